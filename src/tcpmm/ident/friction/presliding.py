"""Pre-sliding of the identified friction contacts.

Near a velocity reversal a rolling guide or a ball-screw nut does not stick rigidly: the
contact deforms elastically over a pre-sliding displacement, of the order of a micrometre,
before it slides in the other direction. The static Stribeck model sticks rigidly, so the
friction force it predicts flips within the stick band, whereas the real one builds up over
that displacement; on an axis that reverses, that changes the height and the shape of the
reversal spike by micrometres.

Friction runs do not determine the pre-sliding displacement: reversing between two
plateaus at 1 m/s^2 (as the virtual runs do), the table crosses a micrometre in 1-2 ms, one
or two samples of a 1 ms record read through micrometre sensor steps. ``with_presliding`` gives
each identified contact the LuGre bristle stiffness ``sigma0 = Fs / z`` of an assumed
displacement ``z`` (:data:`PRESLIDING`; ``0`` keeps the static model) and the bristle
damping ``sigma1 = 2 zeta sqrt(sigma0 M_t)`` of :data:`BRISTLE_DAMPING_RATIO`, fading with
speed; the levels, the Stribeck curve and the viscous part stay as identified.
"""

from __future__ import annotations

import math

from ...errors import InputError
from ...mechanics.friction import LuGreFriction

__all__ = ["BRISTLE_DAMPING_RATIO", "PRESLIDING", "with_presliding"]

#: Pre-sliding displacement given to identified contacts: the travel over which a contact
#: that has reversed builds up its static level [m]. Half a micrometre sits in the range of
#: preloaded rolling guides and ball screws (a few tenths to a few micrometres).
PRESLIDING = 0.5e-6
#: Damping ratio of the bristles against the table mass. The micro-damping fades with speed
#: as the Stribeck hump does, so it damps pre-sliding without adding to the viscous
#: friction of steady sliding [-].
BRISTLE_DAMPING_RATIO = 0.15


def _contact(c, presliding: float, mass: float, zeta: float):
    """One contact with the bristles of ``presliding`` (``None`` stays ``None``)."""
    if c is None:
        return None
    if not c.slides_both_ways:
        return c  # no sliding friction for the bristles to relax towards: stays static
    fs = max(c.fs_pos, c.fs_neg, c.fc_pos, c.fc_neg)
    base = c.model_dump()
    for k in ("sigma0", "sigma1"):
        base.pop(k, None)
    sigma0 = fs / presliding
    base.pop("sigma1_fades", None)
    return LuGreFriction(**base, sigma0=sigma0, sigma1=2.0 * zeta * math.sqrt(sigma0 * mass),
                         sigma1_fades=True)


def with_presliding(friction, mechanics, presliding: float = PRESLIDING,
                    damping_ratio: float = BRISTLE_DAMPING_RATIO):
    """The friction of an axis with LuGre pre-sliding on guideway and screw.

    Parameters
    ----------
    friction : AxisFriction or None
        Identified friction, static contacts [SI].
    mechanics : AxisMechanics
        Identified mechanics; the table mass ``M_t`` sets the bristle damping [SI].
    presliding : float
        Pre-sliding displacement at the static level; ``0`` returns ``friction`` as it is
        [m].
    damping_ratio : float
        Bristle damping ratio against ``M_t`` [-].

    Returns
    -------
    AxisFriction or None
        The same levels, lost motion and sub-steps, contacts as ``LuGreFriction`` [SI].
    """
    if not (math.isfinite(presliding) and presliding >= 0.0):
        raise InputError(f"the pre-sliding displacement must be 0 or more, got {presliding} m;"
                         " pass 0 for the static friction model", column="presliding")
    if not (math.isfinite(damping_ratio) and damping_ratio >= 0.0):
        raise InputError(f"the bristle damping ratio must be 0 or more, got {damping_ratio}",
                         column="damping_ratio")
    if friction is None or presliding == 0.0:
        return friction
    m = mechanics.M_t
    return friction.model_copy(update={
        "guideway": _contact(friction.guideway, presliding, m, damping_ratio),
        "screw": _contact(friction.screw, presliding, m, damping_ratio)})
