"""Variants of an identified axis: each uncertain quantity at the two ends of its 90 %
range (a determined one) or of its whole range (an open one; an open guideway share also
inside it), the others as identified."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

from ..ident.friction.presliding import with_presliding
from ..ident.friction.sensitivity import coulomb_share, with_share
from ..ident.physical.loop_timing import OTHER_SENSOR
from ..mechanics.lumped import RANGES
from ..model import Axis
from ..whatif.draws import longer_presliding, scaled_contact
from .driveranges import DRIVE
from .ranges import MODE_DAMPING, MODE_STRUCTURE, mode_damping_bounds, structure_of

__all__ = ["QUANTILE_90", "UNFIXED_LEVEL", "Unbounded", "Variant", "axis_variants"]

#: Standard normal quantile of a two-sided 90 % interval [-].
QUANTILE_90 = 1.6449
#: The mechanics a circle's TCP figures follow: table, nut, head and the torsion that sets
#: the velocity loop's bandwidth [-].
SENSITIVE = ("M_t", "K_t", "C_t", "M_h", "K_h", "C_h", "K_L")
#: What the ``mechanics`` open range scales: the table mass and the structure behind it [-].
STRUCTURE = ("M_t", "M_b", "K_b", "M_h", "K_h")
#: The structural modes' dampings, each moved within the damping ratios of structures [-].
STRUCTURE_DAMPING = tuple(c for c, _, _ in MODE_DAMPING.values())
#: What the ``damping`` open range scales: the axial modes' damping [-].
AXIAL_DAMPING = ("C_t", "C_b", "C_h")
#: What a ``time_base`` open range scales with the square of its factor, and with it [-].
INERTIAS = ("J_m", "J_L", "M_t", "M_b", "M_h")
DAMPINGS = ("B_m", "B_L", "C_t", "C_b", "C_h")


class Unbounded(NamedTuple):
    """A quantity the data do not bound, though no open range names it: what its variant
    moves is no bound on what the quantity may change (the verdict's ``settle``) [-]."""

    quantity: str
    settle: str


#: A friction level the runs do not fix within a thousandfold: moved that far, it still
#: bounds nothing (the steady force could be larger yet) [-].
UNFIXED_LEVEL = Unbounded("friction_level", "friction runs over a wider range of speeds (0.5 to "
                                            "100 mm/s), with longer plateaus")


@dataclass(frozen=True)
class Variant:
    """An axis with one quantity moved to one end of its range.

    Parameters
    ----------
    quantity : str
        What was moved [-].
    open_range : OpenRange or Unbounded or None
        The range the data leave it open over (whole range), or :data:`UNFIXED_LEVEL`
        for a friction level moved a thousandfold and still not bounded; ``None`` for a
        determined quantity at its 90 % bound [-].
    axis : Axis
        The moved axis [SI].
    """

    quantity: str
    open_range: object
    axis: Axis

    @property
    def open(self) -> bool:
        """Whether the data leave the quantity open [-]."""
        return self.open_range is not None


#: The largest log factor a parameter is moved by to the end of its range [-].
MOST_LOG = math.log(1e3)
#: Points inside an open guideway share's range, as fractions of it: a circle's figures
#: are not monotonic in the share, since the contact that sticks first at a reversal
#: changes with it; a contour error can move ten times further at mid-range than at
#: either end [-].
SHARE_INSIDE = (0.25, 0.5, 0.75)


def _mechanics_variants(axis: Axis, u, open_q: set) -> list[Variant]:
    m = axis.mechanics
    # a damping whose mode is open is moved over its open range alone
    shut = {MODE_DAMPING[q][0] for q in open_q if q in MODE_DAMPING}
    out = []
    for p in SENSITIVE:
        v = getattr(m, p)
        if v <= 0.0 or p in shut:
            continue
        rel = u.mechanics.get(p, 0.0) / v
        if rel <= 0.0:
            continue
        # a parameter the data leave wholly open (a relative deviation of hundreds)
        # moved by at most a thousandfold: further, the factor rounds to zero or inf
        # and kept within what a feed axis can have; a structural mode's damping within
        # what structures have, or as far as the fit's own value lies beyond
        low, high, _ = RANGES.get(p, (0.0, math.inf, ""))
        if p in STRUCTURE_DAMPING:
            z_low, z_high = mode_damping_bounds(m, p)
            low, high = max(low, min(v, z_low)), min(high, max(v, z_high))
        for sign in (-1.0, 1.0):
            upd = {p: min(max(v * math.exp(sign * min(QUANTILE_90 * rel, MOST_LOG)), low),
                          high)}
            if p == "C_t":  # the steady viscous force moves to the screw, its total kept
                upd["B_L"] = max(m.B_L + (v - upd[p]) * m.R_L ** 2, 0.0)
            out.append(Variant(p, None, axis.replace(mechanics=m.replace(**upd))))
    return out


def _friction_variants(axis: Axis, u, open_q: set) -> list[Variant]:
    fr = axis.friction
    if fr is None:
        return []
    out = []
    lvl = min(u.friction_level * QUANTILE_90, MOST_LOG)  # a level the runs hardly fix
    unfixed = UNFIXED_LEVEL if lvl >= MOST_LOG else None
    for k in (math.exp(-lvl), math.exp(lvl)) if lvl > 0.0 else ():
        out.append(Variant("friction_level", unfixed, axis.replace(friction=fr.model_copy(
            update={"guideway": scaled_contact(fr.guideway, k),
                    "screw": scaled_contact(fr.screw, k)}))))
    share = coulomb_share(fr)
    if ("guideway_share" not in open_q and math.isfinite(share)
            and math.isfinite(u.guideway_share) and u.guideway_share > 0.0):
        sd = u.guideway_share * QUANTILE_90
        for s in (share - sd, share + sd):
            new = with_share(fr, min(max(s, 0.01), 0.99))
            if new is not None:
                out.append(Variant("guideway_share", None, axis.replace(friction=new)))
    if "backlash" not in open_q and fr.backlash > 0.0 and u.backlash > 0.0:
        sd = u.backlash * QUANTILE_90
        for b in (max(fr.backlash - sd, 0.0), fr.backlash + sd):
            out.append(Variant("backlash", None,
                               axis.replace(friction=fr.model_copy(update={"backlash": b}))))
    if "presliding" not in open_q and u.presliding > 0.0:
        sd = u.presliding * QUANTILE_90
        for k in (math.exp(-sd), math.exp(sd)):
            out.append(Variant("presliding", None, axis.replace(friction=fr.model_copy(
                update={"guideway": longer_presliding(fr.guideway, k),
                        "screw": longer_presliding(fr.screw, k)}))))
    return out


def _static_at(c, ratio: float):
    """A contact whose static levels held at its Coulomb levels are ``ratio`` times them,
    a LuGre contact's pre-sliding distance and bristle damping ratio kept (``sigma0``
    with the static level, ``sigma1`` with its square root); ``None`` stays ``None`` [-]."""
    if c is None:
        return None
    upd = {f"fs_{d}": ratio * getattr(c, f"fc_{d}") for d in ("pos", "neg")
           if getattr(c, f"fs_{d}") == getattr(c, f"fc_{d}")}
    if hasattr(c, "sigma0"):
        old = max(c.fs_pos, c.fs_neg, c.fc_pos, c.fc_neg)
        new = max(*(upd.get(f"fs_{d}", getattr(c, f"fs_{d}")) for d in ("pos", "neg")),
                  c.fc_pos, c.fc_neg)
        k = new / old if old > 0.0 else 1.0
        upd.update(sigma0=c.sigma0 * k, sigma1=c.sigma1 * math.sqrt(k))
    return c.model_copy(update=upd)


def _open_variants(axis: Axis, r) -> list[Variant]:
    """The axis at both ends of an open range ``r`` (:class:`tcpmm.model.OpenRange`), and
    for the guideway share at :data:`SHARE_INSIDE` of the range too."""
    m, fr = axis.mechanics, axis.friction
    out = []
    inside = SHARE_INSIDE if r.quantity == "guideway_share" else ()
    for x in (r.low, r.high, *(r.low + f * (r.high - r.low) for f in inside)):
        if r.quantity == "guideway_share":
            new = with_share(fr, x) if fr is not None else None
            moved = axis.replace(friction=new) if new is not None else None
        elif r.quantity == "backlash":
            moved = axis.replace(friction=fr.model_copy(update={"backlash": x}))
        elif r.quantity == "presliding":
            moved = axis.replace(friction=with_presliding(fr, m, x))
        elif r.quantity == "static_level":
            moved = axis.replace(friction=fr.model_copy(update={
                "guideway": _static_at(fr.guideway, x), "screw": _static_at(fr.screw, x)}))
        elif r.quantity == "mechanics":
            moved = axis.replace(mechanics=m.replace(**{p: getattr(m, p) * x
                                                        for p in STRUCTURE}))
        elif r.quantity == "position_feedback":  # 1: the loop closed on the other sensor
            other = OTHER_SENSOR[axis.servo.position_feedback]
            moved = axis if x < 0.5 else axis.replace(
                servo=axis.servo.model_copy(update={"position_feedback": other}))
        elif r.quantity == "position_gain":  # the gain the sweep reads, or the declared
            moved = axis.replace(servo=axis.servo.model_copy(update={"K_pp": x}))
        elif r.quantity in DRIVE:  # a drive parameter the FRFs leave open, its value
            moved = axis.replace(mechanics=m.replace(**{r.quantity: x}))
        elif r.quantity == "time_base":  # a time x times the stamped one: inertias x^2
            moved = axis.replace(mechanics=m.replace(
                **{p: getattr(m, p) * x * x for p in INERTIAS},
                **{p: getattr(m, p) * x for p in DAMPINGS}))
        elif r.quantity in MODE_STRUCTURE:  # a head or bed on that spring, its mass fitted
            mass = MODE_STRUCTURE[r.quantity][0]  # where determined, else a typical one
            kg = getattr(m, mass) if mass in axis.uncertainty.mechanics else None
            moved = axis.replace(mechanics=m.replace(**structure_of(r.quantity, x, kg)))
        elif r.quantity in MODE_DAMPING:  # the mode's damping ratio, its frequency kept
            c, mass, k = MODE_DAMPING[r.quantity]
            moved = axis.replace(mechanics=m.replace(
                **{c: 2.0 * x * math.sqrt(getattr(m, mass) * getattr(m, k))}))
        elif r.quantity == "damping":  # the steady viscous force kept, as for C_t below
            upd = {p: getattr(m, p) * x for p in AXIAL_DAMPING}
            upd["B_L"] = max(m.B_L + (m.C_t - upd["C_t"]) * m.R_L ** 2, 0.0)
            moved = axis.replace(mechanics=m.replace(**upd))
        else:  # B_m: the motor-bearing share of the steady viscous torque
            moved = axis.replace(mechanics=m.replace(B_m=x, B_L=max(m.B_L - x, 0.0)))
        if moved is not None:
            out.append(Variant(r.quantity, r, moved))
    return out


def axis_variants(axis: Axis) -> list[Variant]:
    """Every variant of an identified axis a prediction's interval is built from.

    Parameters
    ----------
    axis : Axis
        An identified axis with its :class:`~tcpmm.model.AxisUncertainty` [SI].

    Returns
    -------
    list of Variant
        Two per quantity (its low and high end; an open guideway share also inside its
        range); none without an uncertainty [-].
    """
    u = axis.uncertainty
    if u is None:
        return []
    open_q = {r.quantity for r in u.open}
    out = _mechanics_variants(axis, u, open_q) + _friction_variants(axis, u, open_q)
    for r in u.open:
        out += _open_variants(axis, r)
    return out
