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


def _unit(a: Line) -> np.ndarray:
    d = np.subtract(a.end_m, a.start_m)
    return d / np.linalg.norm(d)


def blend_arc(a: Line, b: Line, d: float) -> Blend:
    """The arc tangent to ``a`` and ``b`` at the distance ``d`` from their corner [-]."""
    u1, u2 = _unit(a), _unit(b)
    p = np.asarray(a.end_m, float)
    h = 0.5 * math.acos(float(np.clip(np.dot(u1, u2), -1.0, 1.0)))
    rho = d / math.tan(h)
    bis = (u2 - u1) / np.linalg.norm(u2 - u1)
    centre = p + bis * (rho / math.cos(h))
    return Blend(tuple(p - d * u1), tuple(p + d * u2), tuple(centre),
                 min(a.feed_m_per_s, b.feed_m_per_s), line=b.line)


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
    blend after it; block ``first - 1`` gives the blend its start is joined to [-]."""
    out = []
    last = None  # the segment the blended path has so far ended with
    for i in range(max(first - 1, 0), stop):
        s = segs[i]
        mine = []
        if type(s) is Line and (d[i] or d[i + 1]):
            u = _unit(s)
            start = np.asarray(s.start_m, float) + d[i] * u
            end = np.asarray(s.end_m, float) - d[i + 1] * u
            if last is not None and d[i]:
                start = np.asarray(last.end_m)  # exactly where the blend ends
            if np.linalg.norm(end - start) > 1e-12 * max(s.length_m, 1e-3):
                mine.append(Line(tuple(start), tuple(end), s.feed_m_per_s, s.exact_stop,
                                 s.line, s.tolerance_m))
        else:
            mine.append(s)
        if d[i + 1]:
            mine.append(blend_arc(s, segs[i + 1], d[i + 1]))
        if mine:
            last = mine[-1]
        if i >= first:
            out.extend(mine)
    return out


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
