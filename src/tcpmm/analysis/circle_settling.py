"""Whether the servo has settled when a circle pass starts.

After the feed ramp into a circle the position loop's transient outlasts the ramp by some
hundreds of milliseconds; a pass cut from a run that feeds in over too little of the circle
holds it, and the terms and spikes read it as errors of the machine (bench C's true machine
at F10000, a CCW and a CW circle of 1.25 turns from quadrant point A as the bench's own,
reads a centre offset of X of 3.6 um, a bow of Y of -4.0 um and a backlash of X of 3.6 um;
of 1.75 turns, which start further from the feed ramp, 0.0, 0.0 and 7.5 um). The command is
steady there already; the sign is in the following error. Along a settled circle a
sensor's following error, along the path and across it, keeps a steady course: a
constant, the harmonics of one to four a turn that a centre offset and the axes' differing
lags make, and the reversals' spikes (their windows are not judged). A pass whose first
tenth departs from that course by more than twice what its middle half does, by more than
1 um and over 2 deg or more, is said.
"""

from __future__ import annotations

import warnings

import numpy as np

from ..errors import InputWarning
from .circle_model import fit_mask

#: How far a step of the tool's angle may lie from the pass's median step, as a share of
#: it, for the tool to move on steadily [-]
STEADY_STEP = 0.1


def steady_ends(angle, lead_deg=0.0):
    """The samples of a pass from the first to the last at which the tool moves on
    steadily: the steps into and out of it within :data:`STEADY_STEP` of the median step,
    or five times the steps' scatter where that is wider. A pass that starts or stops on
    the circle holds the tool at rest, and the servo's transient, at its ends; the terms
    are those of a steady feed (a pass started and stopped at full feed, with one axis
    1 ms behind, read its squareness -77 um/m for +25, its backlash 26 um for 0, from its
    first and last two samples) [-].

    Parameters
    ----------
    angle : ndarray
        The tool's angle, unwrapped [rad].
    lead_deg : float
        The samples within this of the steady part's ends are left out too: a pass ends
        where its command stops or leaves the circle, and under a servo mismatch the
        leading axis does so that much before the other; a sample between moves along
        one axis alone, 40 um off the circle at F6000 on R 100 mm under 1 ms, a step only
        5 % short (:func:`.circle_model.reversal_lead_deg` of the mismatch) [deg].
    """
    keep = _steady(angle)
    on = np.flatnonzero(keep)
    if lead_deg > 0.0 and on.size:
        a = np.degrees(np.asarray(angle, float))
        keep &= (np.abs(a - a[on[0]]) > lead_deg) & (np.abs(a - a[on[-1]]) > lead_deg)
    return keep


def _steady(angle):
    """:func:`steady_ends` without the lead [-]."""
    d = np.abs(np.diff(angle))
    keep = np.ones(np.size(angle), bool)
    if d.size < 8:
        return keep
    level = float(np.median(d))
    spread = 1.4826 * float(np.median(np.abs(d - level)))
    ok = np.abs(d - level) <= max(STEADY_STEP * level, 5.0 * spread)
    both = np.r_[ok[0], ok[1:] & ok[:-1], ok[-1]]
    on = np.flatnonzero(both)
    if on.size:
        keep[:on[0]] = False
        keep[on[-1] + 1:] = False
    return keep


#: A pass's start departs from the steady course when it does by more than this many
#: times its middle half's largest departure, and by more than :data:`SETTLE_FLOOR_M` [-]
SETTLE_RATIO = 2.0
#: see :data:`SETTLE_RATIO`: a departure of the following error moves the terms by some
#: tenth to a third of it (bench C at F10000: 30 um, and terms 1.5 to 4 um off), so one of
#: 1 um leaves them within about 0.2 um [m]
SETTLE_FLOOR_M = 1e-6
#: Share of the pass at its start that is judged [-]
END_SHARE = 0.1
#: A departure over less of the pass's start than this, a few samples, moves no term by
#: much and is not said (the paper's circle on the built-in machine departs by 2.5 um
#: within its first degree, after the feed-in semicircle of half its radius) [deg]
MIN_EXTENT_DEG = 2.0
#: Shortest pass judged: a full turn (less a sample or two); over an arc the harmonics of
#: the steady course are nearly alike and carry it wrongly to the arc's ends [deg]
MIN_JUDGED_DEG = 350.0


def departures(ang, cmd_xy, sensor_xy) -> np.ndarray:
    """How far the sensor's following error departs from its steady course (module
    docstring), per sample, along the path and across it (two columns); NaN in the
    reversals' windows (5 deg before each quadrant point to 25 deg after), where the
    spikes lie [m].

    Parameters
    ----------
    ang : ndarray
        The command's angle about the nominal centre, unwrapped [rad].
    cmd_xy, sensor_xy : tuple of ndarray
        The command's and the sensor's path over the pass, at the same instants [m].
    """
    dx, dy = cmd_xy[0] - sensor_xy[0], cmd_xy[1] - sensor_xy[1]
    along = dx * -np.sin(ang) + dy * np.cos(ang)
    # and across it: the change of curvature at a feed-in arc's join moves the radial
    # error (the paper's circle after its semicircle of half the radius: by 11 um over
    # its first 10 deg, where the error along the path settles within 1 deg)
    across = dx * np.cos(ang) + dy * np.sin(ang)
    # the constant lag, the harmonics of the centre's offset (1), the axes' differing lags
    # (2), and what the servo and the geometry add at 3 and 4 a turn; the steps a lost
    # motion makes where each axis reverses
    s = 1.0 if ang[-1] >= ang[0] else -1.0
    cols = np.column_stack([np.ones_like(ang), np.sign(-s * np.sin(ang)),
                            np.sign(s * np.cos(ang))]
                           + [f(k * ang) for k in range(1, 5) for f in (np.cos, np.sin)])
    quiet = fit_mask(ang, s, after_deg=(-5.0, 25.0))
    # fitted over the whole pass: a transient over its start bends the course a little,
    # where a course fitted without it would be carried over a sector of no samples
    both = np.column_stack([along, across])
    coef = np.linalg.lstsq(cols[quiet], both[quiet], rcond=None)[0]
    return np.where(quiet[:, None], np.abs(both - cols @ coef), np.nan)


def unsettled_start(ang, cmd_xy, sensor_xy):
    """``(degrees, largest departure, middle's largest)`` where the sensor's following
    error departs from its steady course over the start of a full circle (module
    docstring; ``ang`` the command's unwrapped angle), else None. Only the start is
    judged: the servo's transient follows a change of the command and never leads it,
    and a pass whose command changes before its end is said by
    :func:`tcpmm.analysis.circle_checks.warn_unsteady` [deg, m, m]."""
    n = ang.size
    k = max(1, int(END_SHARE * n))
    said = []
    # along the path and across it, each against its own middle (the radial error's course
    # holds more that the harmonics leave: cyclic errors, bows)
    for dev in np.nan_to_num(departures(ang, cmd_xy, sensor_xy)).T:  # windows not judged
        level = float(np.max(dev[n // 4:n - n // 4]))
        limit = SETTLE_RATIO * level + SETTLE_FLOOR_M
        if not np.max(dev[:k]) > limit:
            continue
        # the settling's extent: to the last sample beyond the limit in the pass's first
        # quarter
        last = int(np.flatnonzero(dev[:n // 4] > limit)[-1])
        extent = abs(float(np.degrees(ang[last] - ang[0])))
        if extent >= MIN_EXTENT_DEG:
            said.append((extent, float(np.max(dev[:k])), level))
    return max(said, key=lambda x: x[1] - SETTLE_RATIO * x[2]) if said else None


def warn_unsettled(X, Y, sl, sensors, ang, direction: str, arc_deg: float) -> None:
    """Warn (:class:`InputWarning`) where a full circle starts before the servo has
    settled, by the sensor that departs most (module docstring); nothing without a
    command, nor for an arc or a pass of fewer than 40 samples.

    Parameters
    ----------
    X, Y : AxisRun
        The plane's axes of the run [m].
    sl : slice
        The pass's samples [-].
    sensors : list of str
        The sensors present, ``cmd`` among them or not [-].
    ang : ndarray
        The reference's angle about the nominal centre over the pass, unwrapped: the
        command's where there is one [rad].
    direction : {"ccw", "cw"}
        Direction of travel [-].
    arc_deg : float
        Angle the pass covers [deg].
    """
    if ("cmd" not in sensors or ang.size < 40
            or abs(float(np.degrees(ang[-1] - ang[0]))) < MIN_JUDGED_DEG):
        return
    cmd = (X.sensor("cmd")[sl], Y.sensor("cmd")[sl])
    found = {s: unsettled_start(ang, cmd, (X.sensor(s)[sl], Y.sensor(s)[sl]))
             for s in sensors if s != "cmd"}
    found = {s: v for s, v in found.items() if v is not None}
    if not found:
        return
    worst = max(found, key=lambda s: found[s][1])
    deg, dev, level = found[worst]
    what = "arc" if arc_deg < 360.0 else "circle"
    warnings.warn(InputWarning(
        f"the {direction.upper()} {what} starts before the servo has settled: the "
        f"{worst}'s following error departs from its steady course by up to "
        f"{dev * 1e6:.3g} µm over its first {deg:.0f} deg, at most {level * 1e6:.3g} µm in "
        f"mid-{what}; the servo's transient reads as error terms and spikes there (some "
        "tenth to a third of it); feed in over more of the circle before it, as a ballbar "
        "test does over half a turn"), stacklevel=3)
