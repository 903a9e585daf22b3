"""Corner blending of continuous-path mode (G64 P): an arc rounds off each corner between
two straight blocks, within the contour tolerance.

At a corner turning by ``theta`` the blend is the arc tangent to both lines at the
distance ``d`` from the corner point; its radius is ``d / tan(theta/2)`` and it passes
the corner at ``rho (1/cos(theta/2) - 1)``. ``d`` is the largest that keeps this within
the tolerance, and at most half of either line, so that the blends at both ends of a
line never overlap. A long run of short blocks that approximates a curve thus becomes a
chain of arcs whose radius is the curve's, and the look-ahead limits its speed by the
centripetal acceleration rather than by a velocity step at every block end.

Corners are blended where both blocks are straight feed moves (G1) in continuous-path
mode, in any orientation: the blend is an arc in the plane of the two lines
(:class:`~tcpmm.path.segments.Blend`). Corners next to arcs, rapids and dwells, at exact
stops (G61, G9) and at reversals stay sharp.
"""

from __future__ import annotations

import math
from itertools import repeat

import numpy as np

from .._rows import dot_rows, norm_rows
from .runs import LineRun, as_lines
from .segments import Blend, Line

#: blends shorter than this along either line are not worth a segment [m]
MIN_BLEND_M = 1e-9


def blend_corners(segments, default_tol_m: float = 0.0) -> list:
    """The path with the corners between straight blocks rounded off (module docstring).

    Parameters
    ----------
    segments : sequence of Line, Rapid, Arc, Dwell
        The continuous tool path [-].
    default_tol_m : float
        Contour tolerance of a corner whose block carries none (no ``G64 P``) [m].

    Returns
    -------
    list
        The path with a blend arc at each corner blended; the input when none is [-].
    """
    segs = list(segments)
    d = _tangent_lengths(segs, default_tol_m)
    if not any(d):
        return segs
    return _assemble(segs, d, 0, len(segs))


def _tangent_lengths(segs: list, default_tol_m: float) -> list:
    """``d[i + 1]``: tangent length of the corner at the end of block ``i`` (``d[0]`` and
    ``d[n]`` zero; :func:`_corner_lengths`), 0 where a block is no straight feed move, is
    an exact stop or has no tolerance [m]."""
    n = len(segs)
    d = [0.0] * (n + 1)
    pairs, tols = [], []
    for i in range(n - 1):
        a, b = segs[i], segs[i + 1]
        if type(a) is Line and type(b) is Line and not a.exact_stop:
            tol = default_tol_m if a.tolerance_m is None else a.tolerance_m
            if tol > 0.0:
                pairs.append(i)
                tols.append(tol)
    if pairs:
        found = _corner_lengths([segs[i] for i in pairs], [segs[i + 1] for i in pairs], tols)
        for i, dk in zip(pairs, found, strict=True):
            d[i + 1] = dk
    return d


def _corner_lengths(a: list, b: list, tols: list) -> list:
    """Distance ``d`` from the corner of the line ``a[k]`` into ``b[k]``, of contour
    tolerance ``tols[k]`` > 0, at which its blend starts and ends; 0 where it stays sharp
    (module docstring) [m]. The directions are taken all at once (sums over coordinates
    first to last, the same on every CPU); only where a corner turns are its angle and
    length worked out one by one: a long run of short blocks is mostly straight on."""
    a0, a1, b0, b1 = (np.array([getattr(x, f) for x in lines], float)
                      for lines, f in ((a, "start_m"), (a, "end_m"), (b, "start_m"),
                                       (b, "end_m")))
    with np.errstate(invalid="ignore", divide="ignore"):
        u1, u2 = _units(a1 - a0), _units(b1 - b0)
        c = np.clip(dot_rows(u1, u2), -1.0, 1.0)
        cross = np.stack([u1[:, 1] * u2[:, 2] - u1[:, 2] * u2[:, 1],
                          u1[:, 2] * u2[:, 0] - u1[:, 0] * u2[:, 2],
                          u1[:, 0] * u2[:, 1] - u1[:, 1] * u2[:, 0]], axis=1)
        turns = norm_rows(cross) >= 1e-12  # else straight on, or a reversal
    d = [0.0] * len(a)
    for k in np.flatnonzero(turns).tolist():
        theta = math.acos(float(c[k]))
        if theta < 1e-12:
            continue
        h = 0.5 * theta
        d_tol = tols[k] * math.sin(h) / (2.0 * math.sin(0.5 * h) ** 2)
        dk = min(d_tol, 0.5 * a[k].length_m, 0.5 * b[k].length_m)
        d[k] = dk if dk >= MIN_BLEND_M else 0.0
    return d


def _units(v) -> np.ndarray:
    """Each row of an (n, 3) array over its length [-]."""
    return v / norm_rows(v)[:, None]


def _assemble(segs: list, d: list, first: int, stop: int) -> list:
    """The blended path of blocks ``first`` to ``stop - 1``: each block, trimmed, and the
    blend after it; block ``first - 1`` gives the blend its start is joined to [-].

    The points of the trimmed lines and of the blends are worked out for all corners at
    once (:func:`_trim_and_blend`); the segments are then made in order."""
    lo = max(first - 1, 0)
    touched = [i for i in range(lo, stop) if (d[i] or d[i + 1]) and type(segs[i]) is Line]
    trimmed, blends = _trim_and_blend(segs, d, touched, [i for i in touched if d[i + 1]])
    out = []
    for i in range(first, stop):
        s = segs[i]
        if i in trimmed:
            ends = trimmed[i]
            if ends is not None:
                out.append(Line(ends[0], ends[1], s.feed_m_per_s, s.exact_stop, s.line,
                                s.tolerance_m))
        else:
            out.append(s)
        if d[i + 1]:
            b = segs[i + 1]
            p0, p1, centre = blends[i]
            out.append(Blend(p0, p1, centre, min(s.feed_m_per_s, b.feed_m_per_s),
                             line=b.line))
    return out


def _trim_and_blend(segs: list, d: list, touched: list, corners: list) -> tuple:
    """Ends of the lines ``touched`` trimmed by the tangent lengths ``d`` (None where
    nothing is left of a line), and start, end and centre of the blend at the end of each
    line of ``corners``, as ``{i: points}`` [m].

    Each line's direction is its difference over its length; a trimmed line starts where
    the blend before it ends, ``d`` along it from the corner. The blend at a corner ``p``
    of half-angle ``h`` runs from ``p - d u1`` to ``p + d u2`` about the centre on the
    bisector at ``d / (tan h cos h)``; the angles are taken one corner at a time with
    :mod:`math`, whose results do not depend on the CPU's vector units."""
    rows = sorted(set(touched).union(i + 1 for i in corners))
    if not rows:
        return {}, {}
    at = {i: k for k, i in enumerate(rows)}
    start = np.array([segs[i].start_m for i in rows], float)
    end = np.array([segs[i].end_m for i in rows], float)
    with np.errstate(invalid="ignore", divide="ignore"):
        u = _units(end - start)
    dd = np.asarray(d, float)
    trimmed = {}
    if touched:
        k = np.array([at[i] for i in touched])
        ti = np.array(touched)
        # a line whose corner before is blended starts where that blend ends
        before = np.array([segs[i - 1].end_m if d[i] else segs[i].start_m for i in touched],
                          float)
        t0 = before + dd[ti][:, None] * u[k]
        t1 = end[k] - dd[ti + 1][:, None] * u[k]
        kept = norm_rows(t1 - t0) > 1e-12 * np.maximum(norm_rows(end[k] - start[k]), 1e-3)
        for i, a0, a1, keep in zip(touched, t0.tolist(), t1.tolist(), kept.tolist(),
                                   strict=True):
            trimmed[i] = (tuple(a0), tuple(a1)) if keep else None
    return trimmed, _blends(corners, end, u, at, dd)


def _blends(corners, end, u, at, dd) -> dict:
    """Start, end and centre of the blend at the end of each line of ``corners`` (rows
    ``at`` of its end points ``end`` and directions ``u``; tangent lengths ``dd``) [m]."""
    if not corners:
        return {}
    ka = np.array([at[i] for i in corners])
    kb = np.array([at[i + 1] for i in corners])
    dk = dd[np.array(corners) + 1]
    p, u1, u2 = end[ka], u[ka], u[kb]
    c = np.clip(dot_rows(u1, u2), -1.0, 1.0).tolist()
    reach = []
    for cos_theta, dist in zip(c, dk.tolist(), strict=True):
        h = 0.5 * math.acos(cos_theta)
        reach.append(dist / math.tan(h) / math.cos(h))
    bis = _units(u2 - u1)
    centre = p + bis * np.array(reach)[:, None]
    p0 = p - dk[:, None] * u1
    p1 = p + dk[:, None] * u2
    return {i: (tuple(a), tuple(b), tuple(c)) for i, a, b, c in
            zip(corners, p0.tolist(), p1.tolist(), centre.tolist(), strict=True)}


class CornerBlender:
    """:func:`blend_corners` over a path that comes in pieces: the last block of a piece
    waits for the next piece, whose first block makes the corner at its end.

    Parameters
    ----------
    default_tol_m : float
        Contour tolerance of a corner whose block carries none [m].
    """

    def __init__(self, default_tol_m: float = 0.0):
        self.tol = default_tol_m
        self.held: list = []  # the last block given out (for its blend) and the next one

    def push(self, segments, final: bool = False) -> list:
        """The blended path as far as it is known after ``segments`` [-].

        Parameters
        ----------
        segments : sequence of Line, Rapid, Arc, Dwell
            The next blocks of the path [-].
        final : bool
            They are the last: the path ends with them [-].
        """
        raw = self.held + list(segments)
        # only a Line or a run has a tolerance; getattr over the blocks in C, not a loop
        blend = self.tol > 0.0 or any(map(getattr, raw, repeat("tolerance_m"), repeat(None)))
        # a run is cut so that the blocks held are single ones (a block given out for its
        # blend, the next); where corners are blended, a run's blocks are made Lines
        raw = as_lines(raw) if blend else _last_block_apart(raw, final)
        first = max(len(self.held) - 1, 0)
        stop = len(raw) if final else len(raw) - 1
        self.held = [_last_block(s) for s in raw[max(stop - 1, 0):]]
        if stop <= first:
            return []
        if not blend:
            return raw[first:stop]  # no corner has a tolerance: none is blended
        d = _tangent_lengths(raw, self.tol)
        return _assemble(raw, d, first, stop)


def _last_block_apart(raw: list, final: bool) -> list:
    """``raw`` with its last block apart from a run it ends [-]."""
    if final or not raw or type(raw[-1]) is not LineRun or len(raw[-1]) < 2:
        return raw
    n = len(raw[-1])
    return [*raw[:-1], raw[-1].cut(0, n - 1), raw[-1].cut(n - 1, n)]


def _last_block(s):
    """The last block of a run, else the segment [-]."""
    return s.cut(len(s) - 1, len(s)) if type(s) is LineRun and len(s) > 1 else s
