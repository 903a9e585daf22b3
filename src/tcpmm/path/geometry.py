"""Path geometry as arrays: lengths, tangents, speed limits and exact point evaluation.

The segment list becomes one structure of arrays so that 100 000 blocks are handled
with vectorised numpy. Arcs are evaluated on the arc (angle and radius), never on chords.
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import repeat
from operator import is_

import numpy as np

from ..errors import InputError
from .runs import path_columns
from .segcolumns import arc_columns, line_columns
from .segments import ARC, BLEND, DWELL, Arc, Blend, Dwell, Line, Rapid, arc_sweep

#: consecutive segments must meet within this distance [m]
CONTINUITY_TOL_M = 1e-9


@dataclass
class PathArrays:
    """The tool path as arrays, one entry per segment (all SI).

    Parameters
    ----------
    kind : ndarray of int
        0 straight line, 1 arc, 2 dwell, 3 corner blend [-].
    start, end : ndarray, shape (n, 3)
        Start and end points (X, Y, Z) [m].
    length : ndarray
        Path length of each segment [m].
    feed : ndarray
        Programmed speed (rapid speed for G0) [m/s].
    rapid, exact_stop : ndarray of bool
        G0 segment; rest at the end of the segment [-].
    dwell_s : ndarray
        Dwell duration (0 for motion) [s].
    line : ndarray of int
        Source line number, -1 where unknown [-].
    ia, ib, ih : ndarray of int
        Arc plane axes and normal axis index (0 for lines) [-].
    ca, cb : ndarray
        Arc centre in the plane [m].
    r0, r1, theta0, sweep : ndarray
        Arc start and end radius [m], start angle and signed sweep [rad].
    h0, dh : ndarray
        Arc normal-axis start coordinate and travel [m].
    centre, e1, e2 : ndarray, shape (n, 3)
        Blend centre [m] and the unit vectors to its start and along its start tangent,
        so that a blend is ``centre + r0 (cos(phi) e1 + sin(phi) e2)``, ``phi`` from 0 to
        ``sweep`` [-].
    """

    kind: np.ndarray
    start: np.ndarray
    end: np.ndarray
    length: np.ndarray
    feed: np.ndarray
    rapid: np.ndarray
    exact_stop: np.ndarray
    dwell_s: np.ndarray
    line: np.ndarray
    ia: np.ndarray
    ib: np.ndarray
    ih: np.ndarray
    ca: np.ndarray
    cb: np.ndarray
    r0: np.ndarray
    r1: np.ndarray
    theta0: np.ndarray
    sweep: np.ndarray
    h0: np.ndarray
    dh: np.ndarray
    centre: np.ndarray | None = None
    e1: np.ndarray | None = None
    e2: np.ndarray | None = None

    @property
    def n(self) -> int:
        """Number of segments [-]."""
        return self.kind.size


def _segment_columns(segments):
    """Per segment: kind, start, end, centre, feed, rapid, exact stop, dwell, line, plane
    axes, ccw and extra turns, as arrays [SI]."""
    n = len(segments)
    kind = np.zeros(n, np.int64)
    start = np.empty((n, 3))
    end = np.empty((n, 3))
    centre = np.zeros((n, 3))
    feed = np.zeros(n)
    rapid = np.zeros(n, bool)
    exact = np.zeros(n, bool)
    dwell = np.zeros(n)
    line = np.full(n, -1, np.int64)
    plane = np.tile(np.array([0, 1], np.int64), (n, 1))
    ccw = np.zeros(n, bool)
    turns = np.zeros(n, np.int64)
    types = list(map(type, segments))
    is_line = np.fromiter(map(is_, types, repeat(Line)), bool, n)
    line_columns(segments, is_line, (start, end, feed, exact, line))
    is_arc = np.fromiter(map(is_, types, repeat(Arc)), bool, n)
    kind[is_arc] = ARC
    arc_columns(segments, is_arc, (start, end, centre, feed, exact, plane, ccw, turns, line))
    for i in np.flatnonzero(~(is_line | is_arc)).tolist():
        s = segments[i]
        t = type(s)
        if t is Blend:
            kind[i] = BLEND
            start[i] = s.start_m
            end[i] = s.end_m
            centre[i] = s.centre_m
            feed[i] = s.feed_m_per_s
        elif t is Rapid:
            start[i] = s.start_m
            end[i] = s.end_m
            rapid[i] = True
        elif t is Dwell:
            kind[i] = DWELL
            start[i] = end[i] = s.position_m
            dwell[i] = s.duration_s
        else:
            raise InputError(f"segment {i}: {type(s).__name__} is not a motion segment")
        if s.line is not None:
            line[i] = s.line
    return kind, start, end, centre, feed, rapid, exact, dwell, line, plane, ccw, turns


def _straight_lengths(start, end, rapid, feed, rapid_m_per_s) -> np.ndarray:
    """Straight distance of each segment; the speed of each rapid set in ``feed``.

    Parameters
    ----------
    start, end : ndarray, shape (n, 3)
        Start and end points [m].
    rapid : ndarray of bool
        G0 segment [-].
    feed : ndarray
        Programmed speed, where each rapid's is set: the fastest along its direction
        that no axis's rapid speed is exceeded [m/s].
    rapid_m_per_s : tuple of float
        Rapid speed of X, Y, Z [m/s].

    Returns
    -------
    ndarray
        Distance from start to end [m].
    """
    diff = end - start
    length = np.linalg.norm(diff, axis=1)
    if np.any(rapid):
        u = np.abs(diff[rapid]) / np.maximum(length[rapid], 1e-300)[:, None]
        with np.errstate(divide="ignore"):
            feed[rapid] = np.min(np.asarray(rapid_m_per_s)[None, :] / u, axis=1)
    return length


def _arc_columns(kind, start, end, centre, plane, ccw, turns, line) -> dict:
    """The arc geometry of every segment, named as the fields of :class:`PathArrays`.

    Parameters
    ----------
    kind : ndarray of int
        Segment kind [-].
    start, end, centre : ndarray, shape (n, 3)
        Start, end and arc centre points [m].
    plane : ndarray of int, shape (n, 2)
        Arc plane axes [-].
    ccw : ndarray of bool
        Counter-clockwise arc [-].
    turns : ndarray of int
        Whole turns an arc makes beyond its sweep [-].
    line : ndarray of int
        Source line of each segment, -1 where unknown [-].

    Returns
    -------
    dict
        ``ia``, ``ib``, ``ih`` [-], ``ca``, ``cb``, ``r0``, ``r1`` [m], ``theta0``,
        ``sweep`` [rad], ``h0``, ``dh`` [m]; the sweep is 0 for all but arcs.
    """
    n = kind.size
    ia, ib = plane[:, 0], plane[:, 1]
    idx = np.arange(n)
    ca, cb = centre[idx, ia], centre[idx, ib]
    xs, ys = start[idx, ia] - ca, start[idx, ib] - cb
    xe, ye = end[idx, ia] - ca, end[idx, ib] - cb
    r0, r1 = np.hypot(xs, ys), np.hypot(xe, ye)
    arc = kind == ARC
    sweep = np.zeros(n)
    if np.any(arc):
        sweep[arc] = arc_sweep(xs[arc], ys[arc], xe[arc], ye[arc], ccw[arc], turns[arc])
        bad = arc & ((r0 <= 0.0) | (r1 <= 0.0))
        if np.any(bad):
            i = int(np.argmax(bad))
            raise InputError(
                f"segment {i}: arc with zero radius; move the centre off the start and end",
                line=_line(line, i),
            )
    ih = 3 - ia - ib
    h0 = start[idx, ih]
    return dict(ia=ia, ib=ib, ih=ih, ca=ca, cb=cb, r0=r0, r1=r1, theta0=np.arctan2(ys, xs),
                sweep=sweep, h0=h0, dh=end[idx, ih] - h0)


def to_arrays(segments, rapid_m_per_s) -> PathArrays:
    """Convert a segment list into :class:`PathArrays`.

    Parameters
    ----------
    segments : sequence of Line, Rapid, Arc, Dwell, LineRun
        The continuous tool path [-].
    rapid_m_per_s : tuple of float
        Rapid speed of X, Y, Z [m/s].

    Returns
    -------
    PathArrays
        The path as arrays [-].
    """
    kind, start, end, centre, feed, rapid, exact, dwell, line, plane, ccw, turns = (
        path_columns(segments, _segment_columns))
    _check(start, end, centre, feed, dwell, kind, rapid, line)
    length = _straight_lengths(start, end, rapid, feed, rapid_m_per_s)
    arcs = _arc_columns(kind, start, end, centre, plane, ccw, turns, line)
    r0, r1, theta0, sweep = arcs["r0"], arcs["r1"], arcs["theta0"], arcs["sweep"]
    length = np.where(kind == ARC, np.hypot(0.5 * (r0 + r1) * sweep, arcs["dh"]), length)
    e1, e2 = _blends(kind == BLEND, start, end, centre, r0, r1, theta0, sweep, length)
    zero = (kind != DWELL) & (length <= 0.0)
    if np.any(zero):
        i = int(np.argmax(zero))
        raise InputError(f"segment {i}: motion of zero length; remove it", line=_line(line, i))
    return PathArrays(kind=kind, start=start, end=end, length=length, feed=feed, rapid=rapid,
                      exact_stop=exact, dwell_s=dwell, line=line, centre=centre, e1=e1, e2=e2,
                      **arcs)


def _blends(bl, start, end, centre, r0, r1, theta0, sweep, length):
    """Radius, sweep and length of the blends set in place; their unit vectors [-]."""
    e1, e2 = np.zeros_like(start), np.zeros_like(start)
    if np.any(bl):
        rs, re = start[bl] - centre[bl], end[bl] - centre[bl]
        r = np.linalg.norm(rs, axis=1)
        a1 = rs / r[:, None]
        along = np.einsum("ij,ij->i", re, a1)
        perp = re - along[:, None] * a1
        across = np.linalg.norm(perp, axis=1)
        a2 = perp / across[:, None]
        # the sweep from the end's parts along and across the start's radius: ``re . a2``
        # adds the radius times a2's rounding tilt off a1, which on the radius of
        # kilometres of lines that hardly turn is micrometres of the blend's length
        th = np.arctan2(across, along)
        e1[bl], e2[bl] = a1, a2
        r0[bl] = r1[bl] = r
        theta0[bl] = 0.0
        sweep[bl] = th
        length[bl] = r * th
    return e1, e2


def _line(line, i):
    return None if line[i] < 0 else int(line[i])


def _check(start, end, centre, feed, dwell, kind, rapid, line):
    finite = np.all(np.isfinite(start) & np.isfinite(end) & np.isfinite(centre), axis=1)
    if not np.all(finite):
        i = int(np.argmax(~finite))
        raise InputError(f"segment {i}: positions and arc centres must be finite numbers",
                         line=_line(line, i))
    gap = np.linalg.norm(start[1:] - end[:-1], axis=1)
    if np.any(gap > CONTINUITY_TOL_M):
        i = int(np.argmax(gap > CONTINUITY_TOL_M)) + 1
        raise InputError(
            f"segment {i} starts {gap[i - 1]:.3g} m away from where segment {i - 1} ends; "
            "a path must be continuous",
            line=_line(line, i),
        )
    badfeed = (kind != DWELL) & ~rapid & ~((feed > 0.0) & np.isfinite(feed))
    if np.any(badfeed):
        i = int(np.argmax(badfeed))
        raise InputError(
            f"segment {i}: feed must be a positive finite speed, got {feed[i]} m/s",
            line=_line(line, i),
        )
    if np.any(~np.isfinite(dwell) | (dwell < 0.0)):
        i = int(np.argmax(~np.isfinite(dwell) | (dwell < 0.0)))
        raise InputError(f"segment {i}: dwell must be >= 0 s", line=_line(line, i))


def evaluate(p: PathArrays, seg: np.ndarray, s: np.ndarray) -> np.ndarray:
    """Points on the path.

    Parameters
    ----------
    p : PathArrays
        The path [-].
    seg : ndarray of int
        Segment index of each point [-].
    s : ndarray
        Distance along that segment, 0..length [m].

    Returns
    -------
    ndarray, shape (len(s), 3)
        Points (X, Y, Z) [m].
    """
    L = p.length[seg]
    f = np.divide(s, L, out=np.zeros_like(s), where=L > 0)
    # a coordinate at a time, each segment's start and run gathered from arrays of one
    # coordinate: rows of three gathered and ``f`` broadcast over them cost some three
    # times as much; each point is ``start + f (end - start)`` all the same (an axis's
    # column is contiguous in the result, the transpose of a C array)
    start, run = p.start.T.copy(), (p.end - p.start).T.copy()
    out = np.empty((start.shape[0], seg.size))
    for c in range(start.shape[0]):
        np.multiply(f, run[c].take(seg), out=out[c])
        out[c] += start[c].take(seg)
    out = out.T
    a = np.flatnonzero(p.kind[seg] == ARC)
    if a.size:
        k, fa = seg[a], f[a]
        th = p.theta0[k] + p.sweep[k] * fa
        r = p.r0[k] + (p.r1[k] - p.r0[k]) * fa
        out[a, p.ia[k]] = p.ca[k] + r * np.cos(th)
        out[a, p.ib[k]] = p.cb[k] + r * np.sin(th)
        out[a, p.ih[k]] = p.h0[k] + p.dh[k] * fa
    b = np.flatnonzero(p.kind[seg] == BLEND)
    if b.size:
        k = seg[b]
        ph = (p.sweep[k] * f[b])[:, None]
        e1, e2 = np.take(p.e1, k, axis=0), np.take(p.e2, k, axis=0)
        out[b] = (np.take(p.centre, k, axis=0)
                  + p.r0[k][:, None] * (np.cos(ph) * e1 + np.sin(ph) * e2))
    return out


def tangents(p: PathArrays, at_end: bool) -> np.ndarray:
    """Unit tangent (direction of travel) at the start or end of every segment [-]."""
    t = p.end - p.start
    a = np.flatnonzero(p.kind == ARC)
    if a.size:
        th = p.theta0[a] + (p.sweep[a] if at_end else 0.0)
        r = p.r1[a] if at_end else p.r0[a]
        dr = p.r1[a] - p.r0[a]
        ta = dr * np.cos(th) - r * p.sweep[a] * np.sin(th)
        tb = dr * np.sin(th) + r * p.sweep[a] * np.cos(th)
        t[a] = 0.0
        t[a, p.ia[a]] = ta
        t[a, p.ib[a]] = tb
        t[a, p.ih[a]] = p.dh[a]
    b = np.flatnonzero(p.kind == BLEND)
    if b.size:
        ph = (p.sweep[b] if at_end else np.zeros(b.size))[:, None]
        t[b] = -np.sin(ph) * p.e1[b] + np.cos(ph) * p.e2[b]
    n = np.linalg.norm(t, axis=1)
    return np.divide(t, n[:, None], out=np.zeros_like(t), where=n[:, None] > 0)


def max_abs_trig(theta0: np.ndarray, sweep: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Largest ``|cos|`` and ``|sin|`` over the angle range ``theta0 .. theta0+sweep`` [-]."""
    lo = np.minimum(theta0, theta0 + sweep)
    hi = np.maximum(theta0, theta0 + sweep)
    end_cos = np.maximum(np.abs(np.cos(lo)), np.abs(np.cos(hi)))
    end_sin = np.maximum(np.abs(np.sin(lo)), np.abs(np.sin(hi)))
    # |cos| peaks at k*pi, |sin| at pi/2 + k*pi: is there such an angle in [lo, hi]?
    has_cos = np.floor(hi / np.pi) >= np.ceil(lo / np.pi)
    has_sin = np.floor(hi / np.pi - 0.5) >= np.ceil(lo / np.pi - 0.5)
    return np.where(has_cos, 1.0, end_cos), np.where(has_sin, 1.0, end_sin)
