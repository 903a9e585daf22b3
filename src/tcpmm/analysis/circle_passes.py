"""Where a run holds its circles and arcs.

The reference path (the command when the run has one) is on the circle where its radius
keeps within a tolerance of one level, and that level lies within
:data:`OFFSET_SHARE` of the nominal radius: a controller's acceleration filter after
interpolation pulls a commanded circle inward (33-40 ms of moving average at F10000 take
36-53 um off R 35 mm), a radius offset programmed moves it either way, and both are still
the circle asked for; a path of another radius, or of no constant radius, is not. The
level is the radius at which most of the angle is travelled, so that the samples at rest
before and after the circle do not count. A level within the tolerance is taken as the
nominal radius itself.

A stretch that turns back is split where it does. Full circles are trimmed symmetrically
to whole turns, which cuts off feed-in and feed-out arcs that join the circle
tangentially; a turn of a command whose ends have not settled on the level (a filter's
transient out of a feed-in arc) is the arc of its settled part. A run that holds no full
circle is searched for arcs of :data:`MIN_ARC_DEG` or more (a ballbar's 220 deg arcs in XZ and YZ).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .circle_model import angle_step
from .circle_start import turns_offset

#: The shortest arc analysed [deg]
MIN_ARC_DEG = 30.0
#: Largest distance of the path's radius from the nominal, as a share of it, for the path
#: to count as that circle: 0.7 mm on R 35 mm [-]
OFFSET_SHARE = 0.02
#: Tolerance of a sensor's radius about its own level, as a share of R, where a pass is
#: found in a sensor (a run without its command), and of a command that holds whole turns
#: only within it (a compensated one, :func:`.circle_command.reference_stretches`) [-]
SENSOR_TOL_SHARE = 0.02
#: Fewest samples of a stretch on the circle [-]
_MIN_SAMPLES = 8


@dataclass(frozen=True)
class Stretch:
    """A full circle or an arc of a path.

    Parameters
    ----------
    index : slice
        Its samples [-].
    direction : {"ccw", "cw"}
        Direction of travel [-].
    turns : int
        Whole turns; 0 for an arc [-].
    span_deg : float
        Angle covered [deg].
    """

    index: slice
    direction: str
    turns: int
    span_deg: float


def _level(r, ang) -> float:
    """The radius at which most of the angle is travelled: the median of ``r`` weighted
    by each sample's step of angle [m]."""
    w = np.abs(np.gradient(ang)) if ang.size > 1 else np.ones_like(r)
    if not np.any(w > 0):
        return float(np.median(r))
    order = np.argsort(r)
    cum = np.cumsum(w[order])
    return float(r[order][np.searchsorted(cum, 0.5 * cum[-1])])


def _runs(mask):
    """``(start, stop)`` of the runs of True [-]."""
    edges = np.flatnonzero(np.diff(np.r_[0, mask.astype(int), 0]))
    return list(zip(edges[::2], edges[1::2], strict=True))


def _on_circle(dx, dy, radius, tol, offset):
    """``(start, stop)`` of the stretches on one circle of constant radius near R [-]."""
    r = np.hypot(dx, dy) - radius
    out = []
    for a, b in _runs(np.abs(r) < max(offset, tol)):
        if b - a < _MIN_SAMPLES:
            continue
        level = _level(r[a:b], np.unwrap(np.arctan2(dy[a:b], dx[a:b])))
        level = 0.0 if abs(level) < tol else level
        for a2, b2 in _runs(np.abs(r[a:b] - level) < tol):
            ang = np.unwrap(np.arctan2(dy[a + a2:a + b2], dx[a + a2:a + b2]))
            out += [(a + a2 + c, a + a2 + d) for c, d in _one_way(ang)]
    return out


def _rest_step(steps) -> float:
    """The largest step of a sensor at rest: a twentieth of its travel's steps (their 90th
    percentile), above a dwell's noise [rad]."""
    return 0.05 * float(np.percentile(np.abs(steps), 90))


def _one_way(ang):
    """``(start, stop)`` of the parts of a stretch that turn one way: an arc out and back
    (a ballbar's 220 deg arcs) is two arcs. Steps under a twentieth of the travel's (its 90th
    percentile) are rest, so that a sensor's noise during a dwell does not split a circle;
    the stretch starts with its first turning step and ends with its last: the samples of
    a dwell on the circle, and the end of a radial approach that comes within the
    tolerance of the radius, lie at one angle and are no part of the circle travelled (a
    perfect command fed in from the centre read a G of 32 um) [-]."""
    d = np.diff(ang)
    if d.size == 0:
        return [(0, ang.size)]
    moving = np.flatnonzero(np.abs(d) > max(1e-9, _rest_step(d)))
    if moving.size < 2:
        return [(0, ang.size)]
    way = np.sign(d[moving])
    cut = np.flatnonzero(way[1:] != way[:-1]) + 1  # the first step of each part after one
    first, last = np.r_[0, cut], np.r_[cut - 1, moving.size - 1]
    # each part from its first turning step to the end of its last: a stop between the
    # two directions (a CCW pass, a dwell, then CW) belongs to neither
    return [(int(moving[a]), int(moving[b]) + 2) for a, b in zip(first, last, strict=True)]


#: How far beyond the scatter of its middle half (its median distance from the level)
#: an arc's radius may lie at its ends and still count as the arc [-]; and the least such
#: band, as a share of R [-].
END_SCATTER = 10.0
END_FLOOR = 1e-7


def _steady_ends(dx, dy, radius, a: int, b: int) -> tuple[int, int]:
    """An arc's samples without the ends of a tangential feed-in or feed-out: those that
    come within the tolerance of the radius but whose radius still draws away from the
    level, beyond :data:`END_SCATTER` times the scatter of the arc's middle half (a
    semicircle fed in to a 220 deg arc lies within 0.1 % of R over its last 2.5 deg, and
    the arc read 225 deg with 9 um of backlash) [-]."""
    r = np.hypot(dx[a:b], dy[a:b]) - radius
    n = r.size
    if n < 4 * _MIN_SAMPLES:
        return a, b
    dev = np.abs(r - np.median(r[n // 4:3 * n // 4]))
    band = max(END_SCATTER * float(np.median(dev[n // 4:3 * n // 4])), END_FLOOR * radius)
    inside = np.flatnonzero(dev <= band)
    if inside.size < _MIN_SAMPLES:
        return a, b
    return a + int(inside[0]), a + int(inside[-1]) + 1


def find_stretches(x, y, radius, centre, tol=None, turns=None, offset=None,
                   settled: bool = False) -> list:
    """Full circles in a path, else its arcs (module docstring).

    Parameters
    ----------
    x, y : ndarray
        Reference path, the command if there is one [m].
    radius : float
        Nominal radius [m].
    centre : tuple
        Nominal centre [m].
    tol : float, optional
        Radius tolerance about the path's own level; default 0.1 % of R [m].
    turns : float, optional
        Turns per pass; default the whole number of turns each stretch covers [-].
    offset : float, optional
        Largest distance of that level from R; default :data:`OFFSET_SHARE` of R [m].
    settled : bool
        The path is a command: a whole turn whose ends it has not settled on (a filter's
        transient out of the feed-in, :func:`_steady_ends`) is an arc of its settled
        part [-].

    Returns
    -------
    list of Stretch
        In path order [-].
    """
    tol = 1e-3 * radius if tol is None else tol
    offset = OFFSET_SHARE * radius if offset is None else offset
    dx, dy = x - centre[0], y - centre[1]
    full, arcs = [], []
    for a, b in _on_circle(dx, dy, radius, tol, offset):
        if b - a < _MIN_SAMPLES:
            continue
        ang = np.unwrap(np.arctan2(dy[a:b], dx[a:b]))
        span = ang[-1] - ang[0]
        direction = "ccw" if span > 0 else "cw"
        n_turns = turns if turns is not None else np.floor(abs(span) / (2 * np.pi) + 1e-3)
        if n_turns < 1:
            a, b = _steady_ends(dx, dy, radius, a, b)
            arcs += _arc(a, b, direction, np.unwrap(np.arctan2(dy[a:b], dx[a:b])))
            continue
        keep = _whole_turns(ang, n_turns)
        if keep is None:
            arcs += _arc(a, b, direction, ang) if n_turns == 1 else []
            continue
        if keep.size < _MIN_SAMPLES:
            continue
        lo, hi = a + keep[0], a + keep[-1] + 1
        if settled and _steady_ends(dx, dy, radius, lo, hi) != (lo, hi):
            whole, part = _on_settled(dx, dy, radius, a, b, direction, int(n_turns))
            full, arcs = full + whole, arcs + part
            continue
        full.append(Stretch(slice(lo, hi), direction, int(n_turns), 360.0 * int(n_turns)))
    return full or arcs


def _whole_turns(ang, n_turns):
    """Indices of ``n_turns`` whole turns taken symmetrically out of a stretch of unwrapped
    angle ``ang`` [rad]; None where it falls short of them. Short by up to a sample's angle
    (a circle sampled at 1 kHz at F10000 ends 0.13 deg short) is whole, as
    :func:`~tcpmm.analysis.circle_model.is_full` takes it [-]."""
    span = abs(ang[-1] - ang[0])
    excess = (span - 2 * np.pi * n_turns) / 2
    if excess < -max(1e-3, angle_step(ang)):
        return None
    lo = turns_offset(ang, excess := max(excess, 0.0))  # symmetric, or clear of reversals
    rel = np.abs(ang - ang[0])
    hi = span - excess if lo == excess else lo + span - 2 * excess
    return np.flatnonzero((rel >= lo) & (rel <= hi))


def _on_settled(dx, dy, radius, a: int, b: int, direction: str, n_turns: int) -> tuple:
    """``(full, arcs)`` of the part of a stretch a command has settled on: its whole turns
    where it still holds them, else its arc. A command filtered after interpolation
    (33-40 ms of moving average at F10000) leaves the circle's level over the first and
    last degrees out of a feed-in arc or into a stop, 1-16 um on R 35 mm, and those samples
    read as squareness, scale and backlash [-]."""
    a, b = _steady_ends(dx, dy, radius, a, b)
    if b - a < _MIN_SAMPLES:
        return [], []
    ang = np.unwrap(np.arctan2(dy[a:b], dx[a:b]))
    keep = _whole_turns(ang, n_turns)
    if keep is not None and keep.size >= _MIN_SAMPLES:
        return [Stretch(slice(a + keep[0], a + keep[-1] + 1), direction, n_turns,
                        360.0 * n_turns)], []
    return [], _arc(a, b, direction, ang)


def _arc(a: int, b: int, direction: str, ang) -> list:
    """The samples ``a`` to ``b`` as an arc of the unwrapped angle ``ang`` they cover
    [rad], if it spans :data:`MIN_ARC_DEG` or more [-]."""
    span = float(np.degrees(abs(ang[-1] - ang[0]))) if ang.size > 1 else 0.0
    return [Stretch(slice(a, b), direction, 0, span)] if span >= MIN_ARC_DEG else []


def find_passes(x, y, radius, centre, tol=None, turns=None, offset=None):
    """Index ranges of full circles, else of arcs: ``(slice, direction, turns)`` each, the
    turns 0 for an arc (:func:`find_stretches`) [-]."""
    return [(s.index, s.direction, s.turns)
            for s in find_stretches(x, y, radius, centre, tol, turns, offset)]


def rate(t, ang):
    """Mean angular speed over a pass [rad/s]; NaN without a time span.

    Parameters
    ----------
    t : ndarray
        Time [s].
    ang : ndarray
        Angle of the path about the nominal centre, unwrapped [rad].
    """
    span = t[-1] - t[0]
    return float(abs(ang[-1] - ang[0]) / span) if span > 0 else float("nan")


#: Most sample steps the speed of a pass is taken over at a time (:func:`steady_rate`) [-]
STEADY_STEPS = 25


def steady_rate(t, ang):
    """Median angular speed over a pass's stretches of :data:`STEADY_STEPS` sample steps
    (a fiftieth of the pass where that is fewer), the arguments as :func:`rate`'s: the
    steady feed's, where the mean counts a ramp in or out. Over single steps a recorder's
    jitter of its time stamps stayed in the median: +-0.3 ms about 1 ms moved it by up to
    1 % between two circles, and the servo's ellipse, scaled by it, read as squareness
    [rad/s]; NaN without a time step."""
    k = max(1, min(STEADY_STEPS, (t.size - 1) // 50))
    dt = t[k:] - t[:-k]
    ok = dt > 0
    return (float(np.median(np.abs(ang[k:] - ang[:-k])[ok] / dt[ok])) if ok.any()
            else float("nan"))


def within_span(x, y, sl: slice, centre, ref_ang) -> slice:
    """The samples of a sensor on the circle of a pass: from the first whose own angle
    lies within the angle the reference path covers over the pass, on past the pass's
    end until the sensor's angle reaches the end of that span (or turns back short of
    it). A sensor that lags its command is still on the feed-in arc when the command
    joins the circle (2 mm behind at F5000 without feed-forward: G read 121 um of 48), and
    reaches the circle's end after its command does [-].

    Parameters
    ----------
    x, y : ndarray
        The sensor's whole path [m].
    sl : slice
        The pass's samples, found on the reference path [-].
    centre : tuple
        Nominal centre [m].
    ref_ang : ndarray
        The reference path's unwrapped angle over the pass [rad].
    """
    lo, hi = sl.start or 0, sl.stop
    end = min(x.size, hi + (hi - lo))  # a lag of up to a whole pass
    ang = np.unwrap(np.arctan2(y[lo:end] - centre[1], x[lo:end] - centre[0]))
    ang = ang + 2 * np.pi * np.round((ref_ang[0] - ang[0]) / (2 * np.pi))
    s = 1.0 if ref_ang[-1] >= ref_ang[0] else -1.0
    u, span, n = s * (ang - ref_ang[0]), abs(ref_ang[-1] - ref_ang[0]), hi - lo
    inside = np.flatnonzero((u[:n] >= 0.0) & (u[:n] <= span))
    if inside.size < 2:
        return sl
    first = int(inside[0])
    # past the pass's end, on while the sensor still turns forward short of the span's
    # end: not into the other direction's pass, nor along a radial move off the circle
    step = np.diff(u)
    least = _rest_step(step[:n - 1]) if n > 2 else 0.0
    on = (u[n:] <= span) & (step[n - 1:] > least)
    stop = n + (int(np.argmin(on)) if on.size and not on.all() else on.size)
    return slice(lo + first, lo + stop)


def algebraic_circle(x, y) -> tuple:
    """``(cx, cy, r)``: centre and radius of the circle through the points by linear least
    squares on ``x^2 + y^2`` (Kasa's algebraic fit) [m]."""
    A = np.column_stack([x, y, np.ones_like(x)])
    c = np.linalg.lstsq(A, x**2 + y**2, rcond=None)[0]
    cx, cy = c[0] / 2, c[1] / 2
    return cx, cy, float(np.sqrt(max(c[2] + cx * cx + cy * cy, 0.0)))


def lsq_circle(x, y):
    """Least-squares circle (:func:`algebraic_circle`, then Gauss-Newton on the geometric error).

    Returns
    -------
    cx, cy, r : float
        Centre and radius [m].
    """
    cx, cy, _ = algebraic_circle(x, y)
    for _ in range(5):
        dx, dy = x - cx, y - cy
        r = np.hypot(dx, dy)
        J = np.column_stack([-dx / r, -dy / r, -np.ones_like(r)])
        rr = r.mean()
        step = np.linalg.lstsq(J, -(r - rr), rcond=None)[0]
        cx, cy = cx + step[0], cy + step[1]
    return cx, cy, float(np.hypot(x - cx, y - cy).mean())


def circle_deviation(x, y) -> tuple[float, tuple[float, float]]:
    """Circular deviation G of a path, the spread of its radius about its least squares
    circle (:func:`lsq_circle`), and that circle's centre [m]."""
    cx, cy, _ = lsq_circle(x, y)
    rl = np.hypot(x - cx, y - cy)
    return float(rl.max() - rl.min()), (float(cx), float(cy))
