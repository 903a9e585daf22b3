"""How far the predicted reversal spikes move over what the records leave open.

Where the friction runs do not determine how the friction divides between guideway and
screw, a prior share is used, and a warning that says so does not tell a user whether it
matters. Guideway friction reverses the nut force that drives the structure at a quadrant
point and screw friction does not, so on some axes the share moves the TCP spikes by
micrometres and on others by nothing. :func:`share_spike_range` simulates a circular test
in the plane of the axis (R 35 mm, 5000 mm/min, counter-clockwise, started between two
quadrant points) with the share at both ends of its plausible range and gives the largest
change of a TCP spike.
"""

from __future__ import annotations

import math

from ..model import Machine

__all__ = ["share_spike_range", "with_share"]

#: Circle of the check: radius [m], feed [m/s], start angle [rad].
CIRCLE = (0.035, 5000.0 / 60e3, math.radians(45.0))


def _scaled(contact, k: float):
    """A friction contact with its levels times ``k`` (LuGre bristles as identification
    gives them: stiffness in proportion, damping with its square root)."""
    upd = {q: getattr(contact, q) * k for q in ("fc_pos", "fc_neg", "fs_pos", "fs_neg")}
    if hasattr(contact, "sigma0"):
        upd.update(sigma0=contact.sigma0 * k, sigma1=contact.sigma1 * math.sqrt(k))
    return contact.model_copy(update=upd)


def with_share(friction, share: float):
    """The friction of an axis with its Coulomb and static levels split anew, the total per
    direction kept: ``share`` of it on the guideway [-]; ``None`` when one contact is
    missing (nothing to split)."""
    g, s = friction.guideway, friction.screw
    if g is None or s is None or not 0.0 < share < 1.0:
        return None
    now = g.fc_pos / (g.fc_pos + s.fc_pos) if g.fc_pos + s.fc_pos > 0 else 0.5
    if not 0.0 < now < 1.0:
        return None
    return friction.model_copy(update={"guideway": _scaled(g, share / now),
                                       "screw": _scaled(s, (1.0 - share) / (1.0 - now))})


def share_spike_range(machine: Machine, name: str, shares) -> float | None:
    """Largest change of a TCP reversal spike of a circle in the plane of axis ``name`` as
    its guideway share goes over ``shares``.

    Parameters
    ----------
    machine : Machine
        The identified machine [SI].
    name : str
        The axis [-].
    shares : sequence of float
        Guideway shares to compare, within (0, 1) [-].

    Returns
    -------
    float or None
        The change [m]; ``None`` when the machine has no second axis for a circle or the
        axis has no two contacts to split.
    """
    from ..analysis.circular import analyse_circle
    from ..path.circle import circle_command
    from ..simulate import simulate

    other = next((n for n in machine.axes if n != name), None)
    a = machine.axes[name]
    if other is None or a.friction is None:
        return None
    variants = [with_share(a.friction, s) for s in shares]
    if any(v is None for v in variants):
        return None
    radius, feed, start = CIRCLE
    cmd = circle_command(radius, feed, start_angle_rad=start, plane_axes=(name, other))
    spikes = []
    for fr in variants:
        m = machine.with_axis(name, a.replace(friction=fr))
        run = simulate(m.model_copy(update={"axes": {k: m.axes[k] for k in (name, other)}}),
                       cmd)
        spikes.append(analyse_circle(run, radius, plane=(name, other)).passes[0]
                      .sensors["tcp"].spikes)
    return max(abs(spikes[0][q] - spikes[-1][q]) for q in spikes[0])
