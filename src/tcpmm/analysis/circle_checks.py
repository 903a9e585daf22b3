"""What the circular-test analysis says about a run it cannot fully use: a sensor of one
axis only, quadrant points a circle or arc does not hold, no circle of the radius asked
for."""

from __future__ import annotations

import warnings

import numpy as np

from ..errors import InputError, InputWarning
from .circle_passes import MIN_ARC_DEG, OFFSET_SHARE
from .circle_spikes import QUADRANTS


def warn_uncrossed(names, direction: str, arc_deg: float = 360.0, gapped: bool = False) -> None:
    """Warn (:class:`InputWarning`) that quadrant points are left out of a circle.

    Parameters
    ----------
    names : list of str
        The points left out, e.g. ``["A"]``; nothing is said when empty [-].
    direction : {"ccw", "cw"}
        Direction of travel [-].
    arc_deg : float
        Angle the pass covers; under 360 an arc, whose points outside it are no news [deg].
    gapped : bool
        The pass's samples break off somewhere (:func:`warn_gaps` says where) [-].
    """
    if not names:
        return
    pts = ", ".join(f"{n} ({QUADRANTS[n]:g} deg)" for n in names)
    one = len(names) == 1
    if gapped:
        warnings.warn(InputWarning(
            f"no reversal spike is reported at quadrant point{'' if one else 's'} {pts} of "
            f"the {direction.upper()} pass: {'its' if one else 'their'} reversal window (30 "
            "deg before to 20 deg after) is not whole, where the samples break off or the "
            "pass starts or ends"), stacklevel=3)
        return
    if arc_deg < 360.0:
        warnings.warn(InputWarning(
            f"the {direction.upper()} arc of {arc_deg:.0f} deg does not hold quadrant "
            f"point{'' if one else 's'} {pts} with 30 deg before and 20 deg after "
            f"{'it' if one else 'them'}, so no reversal spike is reported there"),
            stacklevel=3)
        return
    warnings.warn(InputWarning(
        f"the {direction.upper()} circle starts or ends at quadrant point{'' if one else 's'} "
        f"{pts} or within {'its' if one else 'their'} reversal window (30 deg before to 20 "
        f"deg after), so no reversal spike is reported at {', '.join(names)}; start the "
        f"circle between quadrant points (e.g. at 45 deg) to measure {'it' if one else 'them'}"),
        stacklevel=3)


def present_sensors(run, axes, sensors) -> list:
    """The sensors both plane axes have; a sensor of one axis only is warned of [-]."""
    (ax, X), (ay, Y) = ((a, run.axes[a]) for a in axes)
    present = []
    for s in sensors:
        have = [a for a, r in ((ax, X), (ay, Y)) if r.sensor(s) is not None]
        if len(have) == 2:
            present.append(s)
        elif have:
            lack = ay if have[0] == ax else ax
            warnings.warn(InputWarning(
                f"the {s} signal is present for {have[0]} but not for {lack}; the {s} "
                "sensor is left out of the circular test"), stacklevel=3)
    if not present:
        raise InputError(f"the run has no position signals for both {ax} and {ay}")
    return present


def not_found_error(radius_m, centre_m, axes, ref, direction) -> InputError:
    """The error of a run without the circle asked for [-]."""
    ax, ay = axes
    what = f" {direction.upper()}" if direction else ""
    where = (f"({centre_m[0] * 1e3:g}, {centre_m[1] * 1e3:g}) mm" if (ax, ay) == ("X", "Y")
             else f"{ax} {centre_m[0] * 1e3:g} mm, {ay} {centre_m[1] * 1e3:g} mm")
    return InputError(
        f"no full{what} circle of radius {radius_m * 1e3:g} mm about {where} in the "
        f"{ax}{ay} plane found in the {ref} signals, nor an arc of {MIN_ARC_DEG:g} deg or "
        f"more (a path of constant radius within {OFFSET_SHARE * radius_m * 1e3:.3g} mm of "
        "it); check --radius, --centre and --plane")


#: the share of its steady angular speed below which a pass's reference is taken as still
#: speeding up or already slowing down [-]
STEADY_SHARE = 0.99


def warn_unsteady(t, ang, direction: str, arc_deg: float) -> None:
    """Warn (:class:`InputWarning`) where a pass's reference path (the command) is still
    speeding up at its start or slows down before its end: the figures take a steady feed,
    and the servo's transient after a change of feed reads as their terms, for longer than
    the change itself (a 90 deg arc cut 2 deg before the end of a run's feed ramp read as a
    scale mismatch of 1608 ppm and cyclic errors of 15 and 28 um, 152 % of G).

    Parameters
    ----------
    t : ndarray
        Time of the pass's samples [s].
    ang : ndarray
        Angle of its reference path (the command) about the nominal centre, unwrapped
        (a pass's ``angle_rad``) [rad].
    direction : {"ccw", "cw"}
        Direction of travel [-].
    arc_deg : float
        Angle the pass covers [deg].
    """
    dt = np.diff(t)
    if ang.size < 8 or not np.all(dt > 0):
        return
    w = np.abs(np.diff(ang)) / dt
    level = np.median(w)
    said = []
    # the second step from either end: the first or last may be a part of a step (a pass
    # split where the path turns back, or cut between samples)
    for k, how in ((1, "is still speeding up at its start"), (-2, "slows down at its end")):
        if w[k] < STEADY_SHARE * level:
            said.append(f"{how} ({100 * w[k] / level:.0f} % of its steady speed)")
    if not said:
        return
    what = "arc" if arc_deg < 360.0 else "circle"
    warnings.warn(InputWarning(
        f"the {direction.upper()} {what}'s command {' and '.join(said)}: its figures take a "
        "steady feed, and the servo's transient after a change of feed reads as error "
        f"terms (scale mismatch, cyclic error, spikes); take the {what} where the feed has "
        "been steady for a while (a ballbar test feeds in and out off it)"), stacklevel=3)


#: Longest sample period at which a circle's reversal spikes are resolved: a spike rises
#: and falls within some 10 ms [s]
SPARSE_S = 0.02


#: A step between samples this many times their median one is a gap in the log [-].
GAP_STEPS = 5.0


def warn_gaps(t, ang, direction: str) -> bool:
    """Warn (:class:`InputWarning`) where a pass's samples break off (a step of
    :data:`GAP_STEPS` median ones or more: a gap in the log), with the time and the angles
    it spans; whether there is one [-].

    Parameters
    ----------
    t : ndarray
        Time of the pass's samples [s].
    ang : ndarray
        Their angle, unwrapped [rad].
    direction : {"ccw", "cw"}
        Direction of travel [-].
    """
    if t.size < 3:
        return False
    dt = np.diff(t)
    gaps = np.flatnonzero(dt > GAP_STEPS * np.median(dt))
    if gaps.size == 0:
        return False
    where = "; ".join(f"{dt[i]:.3g} s from {np.degrees(ang[i]) % 360:.1f} to "
                      f"{np.degrees(ang[i + 1]) % 360:.1f} deg" for i in gaps[:3])
    warnings.warn(InputWarning(
        f"the {direction.upper()} pass's samples break off ({where}"
        f"{'; ...' if gaps.size > 3 else ''}): a gap in the log; nothing is measured there, "
        "and the figures are those of the samples on either side"), stacklevel=3)
    return True


def warn_sparse(t, rate_rad_s: float, radius_m: float, direction: str) -> None:
    """Warn (:class:`InputWarning`) where a pass's samples lie further apart than
    :data:`SPARSE_S`: no servo trace is logged so slowly, the spikes are not resolved, and
    a time logged in milliseconds under ``time_s`` reads so (a servo mismatch of 85.7 ms
    for 0.086 ms, at a feed of 5 mm/min for 5000).

    Parameters
    ----------
    t : ndarray
        Time of the pass's samples [s].
    rate_rad_s : float
        Its angular speed [rad/s].
    radius_m : float
        Nominal radius [m].
    direction : {"ccw", "cw"}
        Direction of travel [-].
    """
    if t.size < 2:
        return
    dt = float(np.median(np.diff(t)))
    if not dt > SPARSE_S:
        return
    feed = abs(rate_rad_s) * radius_m * 6e4
    warnings.warn(InputWarning(
        f"the {direction.upper()} pass's samples are {dt:g} s apart, at a feed of "
        f"{feed:.4g} mm/min: a reversal's spike lasts some milliseconds and is not resolved, "
        "and the servo mismatch reads in the same unit as the time; if time_s was logged in "
        "milliseconds, divide it by 1000"), stacklevel=3)
