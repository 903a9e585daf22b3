"""The open ranges of an identified axis's friction that its curve and lost motion leave:
the lost motion the runs cannot tell from the scale's rounding, and a static level the runs
do not fix (:mod:`tcpmm.uncertainty.ranges` gathers them with the rest)."""

from __future__ import annotations

import math

from ..ident.friction.hump import HELD_STRIBECK_SPEED
from ..ident.friction.nutstiffness import RESOLUTION_STEPS
from ..model import BACKLASH_MAX_M, OpenRange

__all__ = ["SETTLE_PLAY", "SETTLE_STATIC", "SETTLE_UNBOUNDED_PLAY", "STATIC_RANGE",
           "play_open", "static_open"]

#: Range of an open static level, over the Coulomb level: from no rise at all to the 2 of
#: plastic-lined sliding guides; preloaded rolling guides and ball screws have 1.1 to 1.5
#: (:data:`tcpmm.ident.gates.STATIC_OVER_COULOMB`) [-].
STATIC_RANGE = (1.0, 2.0)

SETTLE_PLAY = "a reversal test at low speed, read by a finer scale or by a TCP device"
SETTLE_UNBOUNDED_PLAY = ("a reversal test at low speed, or friction runs with plateaus at low "
                         "speed (0.5 and 2 mm/s)")
SETTLE_STATIC = ("friction runs with plateaus at low speed (0.1-0.5 mm/s, below the Stribeck "
                 "speed), each held for at least 0.2 s in both directions")


def play_open(a) -> OpenRange | None:
    """The lost motion as an open range where the runs found one of about a scale step, or
    over its whole range (up to :data:`~tcpmm.model.BACKLASH_MAX_M`) where they find none
    and cannot bound one."""
    split = a.friction_split
    if split is None or split.source == "given":
        return None
    if split.lost_motion_unbounded:
        return OpenRange(quantity="backlash", low=0.0, high=BACKLASH_MAX_M,
                         cause=f"the friction runs find no lost motion but cannot bound one "
                               f"(three standard deviations: "
                               f"{split.unfound_backlash * 1e3:.3g} mm, beyond the "
                               f"{BACKLASH_MAX_M * 1e3:g} mm of any screw-nut); none modelled",
                         settle=SETTLE_UNBOUNDED_PLAY)
    res = a.axis.sensors.scale_resolution
    if res <= 0.0:
        return None
    hidden = split.backlash_at_resolution
    if math.isfinite(hidden) and hidden > split.backlash:
        return OpenRange(quantity="backlash", low=0.0, high=hidden,
                         cause=f"the friction runs show a lost motion within "
                               f"{RESOLUTION_STEPS:g} steps of the {res * 1e6:g} um scale, "
                               "which they cannot tell from its rounding; none modelled",
                         settle=SETTLE_PLAY)
    if not split.backlash > 0.0:
        return None
    if split.backlash >= RESOLUTION_STEPS * res:
        return None
    sd = split.backlash_std if math.isfinite(split.backlash_std) else split.backlash
    return OpenRange(quantity="backlash", low=0.0, high=split.backlash + 3.0 * sd,
                     cause=f"the lost motion found ({split.backlash * 1e6:.2f} um) is within "
                           f"{RESOLUTION_STEPS:g} steps of the {res * 1e6:g} um scale",
                     settle=SETTLE_PLAY)


def static_open(a) -> OpenRange | None:
    """The static level as an open range, over the Coulomb level (:data:`STATIC_RANGE`),
    where the runs fix no Stribeck hump and the curve holds it at the Coulomb level
    (:func:`~tcpmm.ident.friction.hump.without_undetermined_hump`)."""
    curve = a.friction
    held = None if curve is None else getattr(curve, "extra", {}).get("static_held")
    if not held or a.axis.friction is None:
        return None
    return OpenRange(quantity="static_level", low=STATIC_RANGE[0], high=STATIC_RANGE[1],
                     cause=f"{held}; held at the Coulomb level, taken up to "
                           f"{STATIC_RANGE[1]:g} times it with a Stribeck speed of "
                           f"{HELD_STRIBECK_SPEED * 1e3:g} mm/s where the runs fix none",
                     settle=SETTLE_STATIC)
