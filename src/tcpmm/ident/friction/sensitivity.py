"""How far the predicted reversal spikes move over what the records leave open.

Where the friction runs do not determine how the friction divides between guideway and
screw, a prior share is used, and a warning that says so does not tell a user whether it
matters. Guideway friction reverses the nut force that drives the structure at a quadrant
point and screw friction does not, so on some axes the share moves the TCP spikes by
micrometres and on others by nothing; so does a lost motion below what the runs resolve,
and so does the pre-sliding distance over the range its fit leaves
(:attr:`tcpmm.ident.friction.preslidingresult.PreslidingFit.presliding_range`).
:func:`spike_range` simulates a circular test in the plane of the axis (R 35 mm,
5000 mm/min, counter-clockwise, started between two quadrant points) with two frictions
and gives the largest change of a TCP spike; :func:`share_spike_range` and
:func:`lost_motion_spike_range` and :func:`presliding_spike_range` put the ends of a
plausible range into it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...analysis.circular import analyse_circle
from ...errors import InputError
from ...io.csvutil import warn_input
from ...model import BACKLASH_MAX_M, Machine
from ...path.circle import circle_command
from ...sim.simulate import simulate, unstable_loops
from .leadbound import lead_voids_bound
from .presliding import with_presliding
from .split import SHARE_WARN_STD

__all__ = ["LostMotionSensitivity", "NoSpikePrediction", "PreslidingSensitivity",
           "ShareSensitivity",
           "coulomb_share", "lost_motion_spike_range", "presliding_spike_range",
           "share_spike_range", "spike_range", "unbounded_lost_motion_words",
           "warn_lost_motion_sensitivity",
           "warn_presliding_sensitivity", "warn_share_sensitivity", "with_share"]

@dataclass(frozen=True)
class ShareSensitivity:
    """How far the TCP spikes of a circle move over the plausible range of a guideway share
    the friction runs leave open.

    Parameters
    ----------
    shares : tuple of float
        Ends of the range simulated [-].
    spike_change_m : float
        Largest change of a TCP reversal spike between them [m].
    """

    shares: tuple
    spike_change_m: float

    def to_dict(self) -> dict:
        """Plain dictionary for the JSON report [-]."""
        return {"shares": list(self.shares), "spike_change_m": self.spike_change_m}


@dataclass(frozen=True)
class LostMotionSensitivity:
    """How far the TCP spikes of a circle move with a lost motion the friction runs would
    not find.

    Parameters
    ----------
    lost_motion_m : tuple of float
        Ends of the range simulated: none, and three standard deviations of the runs'
        estimate (total free play) [m].
    spike_change_m : float
        Largest change of a TCP reversal spike between them [m].
    """

    lost_motion_m: tuple
    spike_change_m: float

    def to_dict(self) -> dict:
        """Plain dictionary for the JSON report [-]."""
        return {"lost_motion_m": list(self.lost_motion_m), "spike_change_m": self.spike_change_m}


@dataclass(frozen=True)
class PreslidingSensitivity:
    """How far the TCP spikes of a circle move over the range of pre-sliding distances
    that the fit to the friction runs leaves.

    Parameters
    ----------
    presliding_m : tuple of float
        Ends of the range simulated [m].
    spike_change_m : float
        Largest change of a TCP reversal spike between them [m].
    """

    presliding_m: tuple
    spike_change_m: float

    def to_dict(self) -> dict:
        """Plain dictionary for the JSON report [-]."""
        return {"presliding_m": list(self.presliding_m), "spike_change_m": self.spike_change_m}


class NoSpikePrediction(Exception):
    """The model's run of the circle of :func:`spike_range` is no prediction, so neither
    are its spikes; the message says why [-]."""


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


def coulomb_share(friction) -> float:
    """The guideway's share of the Coulomb levels of both directions, the share
    :func:`with_share` sets [-]; NaN without Coulomb friction.

    Parameters
    ----------
    friction : AxisFriction
        Friction of the axis [SI].
    """
    g, s = (0.0 if c is None else c.fc_pos + c.fc_neg for c in (friction.guideway,
                                                                 friction.screw))
    return g / (g + s) if g + s > 0.0 else math.nan


def with_share(friction, share: float):
    """The friction of an axis with each Coulomb and static level split anew, the total of
    each kept: ``share`` of it on the guideway [-]; ``None`` without friction or where the
    share is not inside (0, 1). Where all of it sits on one contact, the other takes that
    one's form: an identification that put the whole friction on the guideway (a share
    read at 1) left its open share unvaried, and the prediction's interval without it
    (bench D with the TCP one sample late: spikes 3.2 um off against +-1.6) [-]."""
    g, s = friction.guideway, friction.screw
    if (g is None and s is None) or not 0.0 < share < 1.0:
        return None
    total = {q: sum(getattr(c, q) for c in (g, s) if c is not None) for q in _LEVELS}
    if not all(v > 0 for v in total.values()):
        return None
    return friction.model_copy(update={
        "guideway": _resplit(g if g is not None else s, {q: share * v
                                                         for q, v in total.items()}),
        "screw": _resplit(s if s is not None else g, {q: (1.0 - share) * v
                                                      for q, v in total.items()})})


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

    Raises
    ------
    NoSpikePrediction
        An axis of the plane has an unstable sampled loop, or the run of the circle cannot
        be analysed as one.
    """
    other = next((n for n in machine.axes if n != name), None)
    if other is None:
        return None
    unstable = unstable_loops(machine, (name, other))
    if unstable:  # its run diverges: its circle would be judged as a user's bad file
        raise NoSpikePrediction(f"{'; '.join(unstable)}, so a run of the model diverges")
    a = machine.axes[name]
    radius, feed, start = CIRCLE
    cmd = circle_command(radius, feed, start_angle_rad=start, plane_axes=(name, other))
    spikes = []
    for fr in frictions:
        m = machine.with_axis(name, a.replace(friction=fr))
        run = simulate(m.model_copy(update={"axes": {k: m.axes[k] for k in (name, other)}}),
                       cmd)
        try:
            res = analyse_circle(run, radius, plane=(name, other), settling=False)
        except InputError:  # its checks blame a user's columns; this run is the model's
            faults = "; ".join(f["text"] for f in run.meta.get("faults", ()))
            raise NoSpikePrediction(
                f"the model's run of a circle in the plane of {name} and {other} cannot be "
                "analysed as a circle" + (f" ({faults})" if faults else "")) from None
        spikes.append(res.passes[0].sensors["tcp"].spikes)
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


def presliding_spike_range(machine: Machine, name: str, distances,
                           damping_ratio: float) -> float | None:
    """:func:`spike_range` as the pre-sliding distance of both contacts of axis ``name``
    goes over ``distances`` [m], at the bristle damping ratio ``damping_ratio`` [-]."""
    a = machine.axes[name]
    if a.friction is None:
        return None
    return spike_range(machine, name, [with_presliding(a.friction, a.mechanics, float(z),
                                                       damping_ratio) for z in distances])


#: Smallest undetected lost motion (three standard deviations of a lost motion the runs do
#: not find) worth a simulation of what it would do to the spikes [m].
LOST_MOTION_CHECK_M = 0.2e-6
#: Change of a TCP spike from an undetected lost motion that identify warns about: five
#: times the noise floor of comparing a circle with itself through its sensors [m].
SPIKE_WARN_M = 0.5e-6


def _warn_from(friction, due: bool, message: str) -> None:
    """A sensitivity warning, when ``due``, naming the file of the friction runs it rests
    on (``friction.source``, when there is one) [-]."""
    if not due:
        return

    warn_input(message, file=getattr(friction, "source", None))


def warn_lost_motion_sensitivity(name: str, a, machine, friction) -> None:
    """Where the friction runs find no lost motion but could miss one of three standard
    deviations, say how far that would move the TCP spikes of a circle
    (:func:`lost_motion_spike_range`); noted as ``a.lost_motion_sensitivity``. Where that
    is beyond any screw-nut's, say that the runs cannot bound it.

    Parameters
    ----------
    name : str
        Axis name [-].
    a : AxisIdentification
        The identified axis [-].
    machine : Machine
        The identified machine [SI].
    friction : FrictionRecord or None
        Its friction runs, for the file the warning names [-].
    """
    split = a.friction_split
    if split is None or lead_voids_bound(name, split, machine, friction):
        return
    if split.lost_motion_unbounded:  # a spike range over it would be no machine's
        _warn_from(friction, True, unbounded_lost_motion_words(name, split))
        return
    hidden = split.unfound_backlash
    if not (np.isfinite(hidden) and hidden > LOST_MOTION_CHECK_M):
        return
    moved = lost_motion_spike_range(machine, name, (0.0, hidden))
    if moved is None:
        return
    a.lost_motion_sensitivity = LostMotionSensitivity((0.0, hidden), moved)
    _warn_from(
        friction, moved >= SPIKE_WARN_M,
        f"axis {name}: the friction runs find no lost motion in the nut, but would not "
        f"find one of up to {hidden * 1e6:.2f} um (three standard deviations); that much "
        f"would move the TCP reversal spikes of a circle in its plane (R35 mm, F5000) "
        f"{moved_by(moved)}. A reversal test at low speed, or finer sensors, fixes it")


def unbounded_lost_motion_words(name: str, split) -> str:
    """What to tell where the friction runs find no lost motion and cannot bound one
    (:attr:`~tcpmm.ident.friction.frictionsplit.FrictionSplit.lost_motion_unbounded`) [-]."""
    return (f"axis {name}: the friction runs find no lost motion in the nut, but cannot bound "
            f"one: three standard deviations of their estimate "
            f"({split.unfound_backlash * 1e3:.3g} mm) are beyond the "
            f"{BACKLASH_MAX_M * 1e3:g} mm of any screw-nut, so the model takes none and "
            "names it open. A reversal test at low speed, or friction runs with plateaus at "
            "low speed (0.5 and 2 mm/s), bound it")


def moved_by(moved: float) -> str:
    """``by up to X um``; where the model's run of the circle is no prediction (its
    current held at the limit) and the change is not a number, that it cannot be told
    [m]."""
    if np.isfinite(moved):
        return f"by up to {moved * 1e6:.2f} um"
    return "by an amount the model cannot tell (its run of that circle is no prediction)"


def warn_share_sensitivity(name: str, a, machine, friction) -> None:
    """Where the friction runs leave the guideway share open (a prior, or a standard
    deviation above :data:`SHARE_WARN_STD`), say how far the TCP spikes of a circle move
    over its plausible range (:func:`share_spike_range`), and note it as
    ``a.share_sensitivity``.

    Parameters
    ----------
    name : str
        Axis name [-].
    a : AxisIdentification
        The identified axis [-].
    machine : Machine
        The identified machine [SI].
    friction : FrictionRecord or None
        Its friction runs, for the file the warning names [-].
    """
    split = a.friction_split
    if split is None or split.source == "given":
        return
    sd = split.guideway_share_std
    if split.source == "prior":
        lo, hi = 0.05, 0.95
    elif np.isfinite(sd) and sd > SHARE_WARN_STD:
        lo = min(max(split.guideway_share - 2.0 * sd, 0.02), 0.98)
        hi = min(max(split.guideway_share + 2.0 * sd, 0.02), 0.98)
    else:
        return
    moved = share_spike_range(machine, name, (lo, hi))
    if moved is None:
        return
    a.share_sensitivity = ShareSensitivity((lo, hi), moved)
    _warn_from(
        friction, True,
        f"axis {name}: the guideway share is not determined by the friction runs "
        f"({split.guideway_share:.2f} used); between shares {lo:.2f} and {hi:.2f} the TCP "
        f"reversal spikes of a circle in its plane (R35 mm, F5000) move "
        f"{moved_by(moved)}. Finer sensors, or runs at speeds that do not advance whole "
        "sensor steps per sample, fix the share; --guideway-share sets it")


#: Change of a TCP spike over the pre-sliding range of a fit that identify warns about: the
#: accuracy asked of a predicted spike. A fitted distance always leaves a range, and on
#: the reference machines it moves the spikes by 0.7-2.3 um; the warnings of a prior share
#: or an unfound lost motion (:data:`SPIKE_WARN_M`) are about quantities not measured at all.
PRESLIDING_SPIKE_WARN_M = 1.0e-6


def warn_presliding_sensitivity(name: str, a, machine, friction) -> None:
    """Where the pre-sliding distance was fitted to the friction runs, say how far the TCP
    spikes of a circle move over the range the fit leaves (:func:`presliding_spike_range`)
    when that is more than :data:`PRESLIDING_SPIKE_WARN_M`; noted as
    ``a.presliding_sensitivity`` in any case.

    Parameters
    ----------
    name : str
        Axis name [-].
    a : AxisIdentification
        The identified axis [-].
    machine : Machine
        The identified machine [SI].
    friction : FrictionRecord or None
        Its friction runs, for the file the warning names [-].
    """
    fit = a.presliding_fit
    if fit is None or not fit.determined or not np.all(np.isfinite(fit.presliding_range)):
        return
    lo, hi = fit.presliding_range
    moved = presliding_spike_range(machine, name, (lo, hi), fit.damping_ratio)
    if moved is None:
        return
    a.presliding_sensitivity = PreslidingSensitivity((lo, hi), moved)
    _warn_from(
        friction, moved >= PRESLIDING_SPIKE_WARN_M,
        f"axis {name}: the friction runs' reversals fix the pre-sliding distance only to "
        f"between {lo * 1e6:.2f} and {hi * 1e6:.2f} um ({fit.presliding * 1e6:.2f} used; two "
        "standard deviations of the fit, with the play that keeps the encoder's noise out "
        "of the contacts halved and doubled). Over that range the TCP reversal spikes of a "
        f"circle in its plane (R35 mm, F5000) move {moved_by(moved)}. A finer "
        "encoder, reversals that turn round faster, or a measured distance "
        "(--presliding-um) fixes it")
