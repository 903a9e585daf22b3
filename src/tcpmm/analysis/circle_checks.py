"""What the circular-test analysis says about a run it cannot fully use: a sensor of one
axis only, quadrant points a circle or arc does not hold, a run in another unit
than its columns say (:mod:`.circle_units`)."""

from __future__ import annotations

import warnings

import numpy as np

from ..errors import InputError, InputWarning
from .circle_gaps import warn_gaps
from .circle_passes import circle_deviation
from .circle_spikes import QUADRANTS, end_steps, slower_than
from .circle_units import (
    FASTEST_M_PER_S,
    LARGEST_RADIUS_M,
    SMALLEST_RADIUS_M,
    refuse_other_unit,
)


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
            f"{'it' if one else 'them'} where the feed is steady, so no reversal spike is "
            "reported there"),
            stacklevel=3)
        return
    warnings.warn(InputWarning(
        f"the {direction.upper()} circle starts or ends at quadrant point{'' if one else 's'} "
        f"{pts} or within {'its' if one else 'their'} reversal window (30 deg before to 20 "
        f"deg after, where the feed is steady), so no reversal spike is reported at "
        f"{', '.join(names)}; start the circle between quadrant points (e.g. at 45 deg) to "
        f"measure {'it' if one else 'them'}"),
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
    level = np.median(np.abs(np.diff(ang)) / dt)
    m = end_steps(ang.size)
    # the speed over m steps from the second sample from either end (the first or last
    # step may be a part of one: a pass split where the path turns back, or cut between
    # samples), below the steady share and below what the steady middle's own m-step
    # speeds scatter to (a log's time stamps jitter)
    span = np.abs(ang[m:] - ang[:-m]) / (t[m:] - t[:-m])
    low = slower_than(span, level)
    said = []
    for k, how in ((1, "is still speeding up at its start"), (-2, "slows down at its end")):
        if span[k] < low:
            said.append(f"{how} ({100 * span[k] / level:.0f} % of its steady speed)")
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


#: Samples further apart [s] at a feed below [m/s]: a time in ms under ``time_s`` (1 kHz
#: reads 1 s apart at F5 for F5000, a servo mismatch of 43 ms)
MS_PERIOD_S, SLOWEST_FEED_M_PER_S = 0.05, 1e-3


def check_sampling(t, rate_rad_s: float, radius_m: float, direction: str) -> None:
    """Refuse a pass whose samples lie more than :data:`MS_PERIOD_S` apart at a feed below
    :data:`SLOWEST_FEED_M_PER_S`: no circular test is run and logged so, a time in ms is.
    Else warn (:class:`InputWarning`) where they lie further apart than :data:`SPARSE_S`:
    no servo trace is logged so slowly, the spikes are not resolved, and a time logged in
    milliseconds under ``time_s`` reads so (a servo mismatch of 85.7 ms for 0.086 ms, at a
    feed of 5 mm/min for 5000).

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
    feed = abs(rate_rad_s) * radius_m
    if dt > MS_PERIOD_S and feed < SLOWEST_FEED_M_PER_S:
        raise InputError(
            f"the {direction.upper()} circle's samples are {dt:g} s apart at a feed of "
            f"{feed * 6e4:.3g} mm/min: no circular test is run and logged so; is time_s in "
            "milliseconds? Write seconds (divide it by 1000)", column="time_s")
    if not dt > SPARSE_S:
        return
    warnings.warn(InputWarning(
        f"the {direction.upper()} pass's samples are {dt:g} s apart, at a feed of "
        f"{feed * 6e4:.4g} mm/min: a reversal's spike lasts some milliseconds and is not "
        "resolved, and the servo mismatch reads in the same unit as the time; if time_s was "
        "logged in milliseconds, divide it by 1000"), stacklevel=3)


def warn_scale(rate_rad_s: float, radius_m: float, direction: str) -> None:
    """Warn (:class:`InputWarning`) where a pass's radius or feed lies beyond any machine
    tool's circular test (:data:`LARGEST_RADIUS_M`, :data:`FASTEST_M_PER_S`,
    :data:`SMALLEST_RADIUS_M`): positions logged in metres or micrometres under the
    ``*_mm`` columns, with the radius given in the same unit, read so.

    Parameters
    ----------
    rate_rad_s : float
        The pass's angular speed [rad/s].
    radius_m : float
        Nominal radius [m].
    direction : {"ccw", "cw"}
        Direction of travel [-].
    """
    speed = abs(rate_rad_s) * radius_m
    if (SMALLEST_RADIUS_M <= radius_m <= LARGEST_RADIUS_M
            and not speed > FASTEST_M_PER_S):
        return
    def shown(v):
        return f"{float(f'{v:.4g}'):.10g}"

    warnings.warn(InputWarning(
        f"the {direction.upper()} pass is a circle of radius {shown(radius_m * 1e3)} mm at a "
        f"feed of {shown(speed * 6e4)} mm/min, beyond a machine tool's circular test (radius "
        f"{SMALLEST_RADIUS_M * 1e3:g} mm to {LARGEST_RADIUS_M:g} m, feed up to "
        f"{FASTEST_M_PER_S * 6e4:g} mm/min): if the positions were logged in metres or "
        "micrometres, convert the *_mm columns to millimetres and give --radius in mm; "
        "until then every figure here is off by a factor of 1000"), stacklevel=3)


def warn_pass(t, cp, ang, missing, radius_m) -> None:
    """What a circle pass ``cp`` lacks, in warnings: its log's gaps, the quadrant points it
    gives no spike at, an unsteady feed, samples too sparse for a spike, a radius or feed
    of another unit [-].

    Parameters
    ----------
    t : ndarray
        Time of the pass's samples [s].
    cp : CirclePass
        The pass [-].
    ang : ndarray
        Angle of its reference path, unwrapped [rad].
    missing : list of str
        The quadrant points it gives no spike at [-].
    radius_m : float
        Nominal radius [m].
    """
    d = cp.direction
    gapped = warn_gaps(t, ang, d)
    warn_uncrossed(missing, d, cp.arc_deg, gapped)
    warn_unsteady(t, ang, d, cp.arc_deg)
    check_sampling(t, cp.rate_rad_s, radius_m, d)
    warn_scale(cp.rate_rad_s, radius_m, d)


#: Share of its reference's travel along an axis below which a sensor is said not to follow
#: it: no servo or structure takes half the travel of a circle away [-]
STUCK_SHARE = 0.5


def check_sensor_path(x, y, ref_xy, centre, radius_m, names, direction) -> None:
    """Refuse a sensor an axis of which travels less than :data:`STUCK_SHARE` of its
    reference's (the command's) travel (a column empty or stuck), whose circle turns
    against its reference's, or lies a radius or more from it at the same instants: an
    axis of that sensor negated, or its two axes swapped (a circle mirrored turns the
    other way; turned half a turn it lies a diameter away). No servo lags its command by
    a radius (60 deg of the circle).

    Parameters
    ----------
    x, y : ndarray
        The sensor's path over the pass [m].
    ref_xy : tuple of ndarray
        The reference's path at the same instants [m].
    centre : tuple
        Nominal centre [m].
    radius_m : float
        Nominal radius [m].
    names : tuple of str
        The sensor's and the reference's names, and the plane's axes [-].
    direction : {"ccw", "cw"}
        The reference's direction of travel [-].
    """
    sensor, ref, ax, ay = names
    for v, rv, axis in ((x, ref_xy[0], ax), (y, ref_xy[1], ay)):
        refuse_other_unit(v, rv, f"{axis.lower()}_{sensor}_mm", ref)
        if v.size and not np.ptp(v) > STUCK_SHARE * np.ptp(rv):
            raise InputError(
                f"the {sensor} signal's {axis} travels {np.ptp(v) * 1e3:.4g} mm where the "
                f"{ref}'s travels {np.ptp(rv) * 1e3:.4g} mm: its column "
                f"{axis.lower()}_{sensor}_mm is empty, stuck or another axis's; check it")
    turn = np.unwrap(np.arctan2(y - centre[1], x - centre[0]))
    turned = turn[-1] - turn[0] if turn.size > 1 else 0.0
    against = turned * (1.0 if direction == "ccw" else -1.0) < 0
    apart = float(np.median(np.hypot(x - ref_xy[0], y - ref_xy[1]))) if x.size else 0.0
    if not against and not apart >= radius_m:
        return
    how = (f"turns {'clockwise' if direction == 'ccw' else 'counter-clockwise'} where the "
           f"{ref} turns {direction.upper()}" if against else
           f"lies {apart * 1e3:.4g} mm from the {ref} at the same instants, more than the "
           f"radius of {radius_m * 1e3:g} mm")
    raise InputError(
        f"the {sensor} circle {how}: an axis of the {sensor} signal has the opposite sign, "
        f"or its {ax} and {ay} are swapped; check the signs and the columns "
        f"{ax.lower()}_{sensor}_mm and {ay.lower()}_{sensor}_mm")


#: Share of a figure by which it may move when every other sample is left out before it is
#: said to hang on single samples (the demo's circles at 1 kHz move by up to 5 %, a scale's
#: G by its noise; every 4 or 8 ms, by 11-16 %) [-]
RESOLVED_SHARE = 0.1
#: ... and the least such move said [m]
RESOLVED_M = 0.5e-6


def warn_unresolved(t, cp, radius_m: float, centre) -> None:
    """Warn (:class:`InputWarning`) where a full circle's contour error or circular
    deviation G of a sensor moves by more than :data:`RESOLVED_SHARE` of itself (and
    :data:`RESOLVED_M`) when every other sample is left out: it hangs on single samples,
    a peak that falls between the samples of too sparse a log (the demo's circle every
    8 ms read G 14 % low, with no word) or a sample's noise.

    Parameters
    ----------
    t : ndarray
        Time of the pass's samples [s].
    cp : CirclePass
        The pass, its sensors analysed (each sensor's own samples of it, whose figures the
        table gives); an arc is not judged [-].
    radius_m : float
        Nominal radius [m].
    centre : tuple
        Nominal centre [m].
    """
    if cp.arc_deg < 360.0 or t.size < 8:
        return
    said = []
    for name in (s for s in cp.sensors if s != "cmd"):
        sc = cp.sensors[name]
        r = radius_m + sc.radial_error
        x, y = centre[0] + r * np.cos(sc.angle_rad), centre[1] + r * np.sin(sc.angle_rad)
        whole = _figures(x, y, radius_m, centre)
        halves = [_figures(x[k::2], y[k::2], radius_m, centre) for k in (0, 1)]
        for i, what in enumerate(("contour error", "G")):
            move = max(abs(whole[i] - h[i]) for h in halves)
            if move > max(RESOLVED_SHARE * whole[i], RESOLVED_M):
                said.append(f"{name} {what} {whole[i] * 1e6:.2f} by {move * 1e6:.2f} µm")
    if said:
        dt = float(np.median(np.diff(t)))
        warnings.warn(InputWarning(
            f"the {cp.direction.upper()} circle's figures hang on single samples: left out "
            f"every other of its samples, {dt * 1e3:.3g} ms apart, {', '.join(said)} move; "
            "a peak between the samples (a log too sparse for it) or a sample's noise reads "
            "so, and the figures may be off by about as much"), stacklevel=3)


def _figures(x, y, radius_m: float, centre) -> tuple[float, float]:
    """Contour error about the nominal circle and circular deviation G about the least
    squares circle of a path, as :func:`.circular.analyse_sensor` takes them [m]."""
    e = np.hypot(x - centre[0], y - centre[1]) - radius_m
    return float(np.max(np.abs(e))), circle_deviation(x, y)[0]
