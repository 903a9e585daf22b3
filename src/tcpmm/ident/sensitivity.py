"""How far the predicted reversal spikes move over what the records leave open.

Where the friction runs do not determine how the friction divides between guideway and
screw, a prior share is used, and a warning that says so does not tell a user whether it
matters. Guideway friction reverses the nut force that drives the structure at a quadrant
point and screw friction does not, so on some axes the share moves the TCP spikes by
micrometres and on others by nothing; so does a lost motion below what the runs resolve.
:func:`spike_range` simulates a circular test in the plane of the axis (R 35 mm,
5000 mm/min, counter-clockwise, started between two quadrant points) with two frictions
and gives the largest change of a TCP spike; :func:`share_spike_range` and
:func:`lost_motion_spike_range` put the ends of a plausible range into it.
"""

from __future__ import annotations

import math

from ..model import Machine

__all__ = ["lost_motion_spike_range", "share_spike_range", "spike_range", "with_share"]

#: Circle of the check: radius [m], feed [m/s], start angle [rad].
CIRCLE = (0.035, 5000.0 / 60e3, math.radians(45.0))


_LEVELS = ("fc_pos", "fc_neg", "fs_pos", "fs_neg")


def _resplit(contact, part: dict):
    """A friction contact with the given levels (LuGre bristles as identification gives
    them: stiffness in proportion to the static level, damping with its square root)."""
    upd = dict(part)
    if hasattr(contact, "sigma0"):
        fs_old = max(contact.fs_pos, contact.fs_neg)
        k = max(part["fs_pos"], part["fs_neg"]) / fs_old if fs_old > 0 else 1.0
        upd.update(sigma0=contact.sigma0 * k, sigma1=contact.sigma1 * math.sqrt(k))
    return contact.model_copy(update=upd)


def with_share(friction, share: float):
    """The friction of an axis with each Coulomb and static level split anew, the total of
    each kept: ``share`` of it on the guideway [-]; ``None`` when one contact is missing
    (nothing to split) or the share is not inside (0, 1)."""
    g, s = friction.guideway, friction.screw
    if g is None or s is None or not 0.0 < share < 1.0:
        return None
    total = {q: getattr(g, q) + getattr(s, q) for q in _LEVELS}
    if not all(v > 0 for v in total.values()):
        return None
    return friction.model_copy(update={
        "guideway": _resplit(g, {q: share * v for q, v in total.items()}),
        "screw": _resplit(s, {q: (1.0 - share) * v for q, v in total.items()})})


def spike_range(machine: Machine, name: str, frictions) -> float | None:
    """Largest change of a TCP reversal spike of a circle in the plane of axis ``name``
    between two frictions of that axis.

    Parameters
    ----------
    machine : Machine
        The identified machine [SI].
    name : str
        The axis [-].
    frictions : sequence of AxisFriction
        The two frictions to compare [SI].

    Returns
    -------
    float or None
        The change [m]; ``None`` when the machine has no second axis for a circle [-].
    """
    from ..analysis.circular import analyse_circle
    from ..path.circle import circle_command
    from ..simulate import simulate

    other = next((n for n in machine.axes if n != name), None)
    if other is None:
        return None
    a = machine.axes[name]
    radius, feed, start = CIRCLE
    cmd = circle_command(radius, feed, start_angle_rad=start, plane_axes=(name, other))
    spikes = []
    for fr in frictions:
        m = machine.with_axis(name, a.replace(friction=fr))
        run = simulate(m.model_copy(update={"axes": {k: m.axes[k] for k in (name, other)}}),
                       cmd)
        spikes.append(analyse_circle(run, radius, plane=(name, other)).passes[0]
                      .sensors["tcp"].spikes)
    return max(abs(spikes[0][q] - spikes[-1][q]) for q in spikes[0])


def share_spike_range(machine: Machine, name: str, shares) -> float | None:
    """:func:`spike_range` as the guideway share of axis ``name`` goes over ``shares``
    (within (0, 1)) [m]; ``None`` also when the axis has no two contacts to split."""
    a = machine.axes[name]
    if a.friction is None:
        return None
    variants = [with_share(a.friction, s) for s in shares]
    if any(v is None for v in variants):
        return None
    return spike_range(machine, name, variants)


def lost_motion_spike_range(machine: Machine, name: str, plays) -> float | None:
    """:func:`spike_range` as the lost motion of axis ``name`` goes over ``plays`` [m]."""
    a = machine.axes[name]
    if a.friction is None:
        return None
    return spike_range(machine, name, [a.friction.model_copy(update={"backlash": float(p)})
                                       for p in plays])
