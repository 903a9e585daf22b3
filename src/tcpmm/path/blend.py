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
stops (G61, G9) and at reversals stay sharp, and so do corners where the unit tangent
turns by less than ``BEND_TOL`` (1e-6): lines straight on but for the rounding of their
coordinates, which the look-ahead takes as a tangent join.
"""

from __future__ import annotations

from itertools import repeat

import numpy as np

from .blendrows import blended_rows, block_table, corner_table
from .geometry import BLEND
from .runs import ArcRun, ColumnRun, LineRun, as_lines, feed_columns
from .segments import Blend, Line


def blend_corners(segments, default_tol_m: float = 0.0) -> list:
    """The path with the corners between straight blocks rounded off (module docstring).

    Parameters
    ----------
    segments : sequence of Line, Rapid, Arc, Dwell, LineRun
        The continuous tool path [-].
    default_tol_m : float
        Contour tolerance of a corner whose block carries none (no ``G64 P``) [m].

    Returns
    -------
    list
        The path with a blend arc at each corner blended; its blocks as they are (a run
        as its Lines) when none is [-].
    """
    segs = as_lines(segments)  # a segment per block: the rows point at the blocks
    rows = _blended(segs, default_tol_m)[1]
    return segs if rows is None else _as_segments(segs, rows)


def blended_path(segments, default_tol_m: float = 0.0) -> list:
    """:func:`blend_corners` for the look-ahead: each blended stretch one run of columns
    (:class:`~tcpmm.path.runs.ColumnRun`) instead of a segment per line and blend [-].

    Parameters
    ----------
    segments : sequence of Line, Rapid, Arc, Dwell, LineRun
        The continuous tool path [-].
    default_tol_m : float
        Contour tolerance of a corner whose block carries none (no ``G64 P``) [m].
    """
    segs = list(segments)
    tb, rows = _blended(segs, default_tol_m)
    return segs if rows is None else _as_runs(segs, tb, rows)


def _blended(segs: list, default_tol_m: float) -> tuple:
    """The table of ``segs`` and the rows of the whole path blended; None for the rows
    where no corner is [-]."""
    tb = block_table(segs)
    corners = corner_table(tb, default_tol_m)
    return tb, (blended_rows(tb, corners, 0, tb.n) if corners[0].any() else None)


def _as_segments(segs: list, rows) -> list:
    """The rows of a blended path as segments: a block left as it was is itself [-]."""
    out = []
    for i, k, a, b, c in zip(rows.src.tolist(), rows.kind.tolist(), rows.start.tolist(),
                             rows.end.tolist(), rows.centre.tolist(), strict=True):
        s = segs[i]
        if k == 1:
            out.append(Line(tuple(a), tuple(b), s.feed_m_per_s, s.exact_stop, s.line,
                            s.tolerance_m))
        elif k == 2:
            nxt = segs[i + 1]
            out.append(Blend(tuple(a), tuple(b), tuple(c),
                             min(s.feed_m_per_s, nxt.feed_m_per_s), line=nxt.line))
        else:
            out.append(s)
    return out


def _as_runs(raw: list, tb, rows) -> list:
    """The rows of a blended path as runs of columns (:class:`ColumnRun`), a block that
    is no straight feed move between them as it is [-]."""
    objects = _other_blocks(raw)
    out = []
    cut = np.flatnonzero(rows.kind < 0).tolist()
    for a, b in zip([-1, *cut], [*cut, rows.kind.size], strict=True):
        if b - a > 1:
            out.append(_columns(tb, rows, a + 1, b))
        if b < rows.kind.size:
            out.append(objects[int(rows.src[b])])
    return out


def _columns(tb, rows, a: int, b: int) -> ColumnRun:
    """Rows ``a`` to ``b - 1`` (lines and blends) as a run of columns [-]."""
    src, blend = rows.src[a:b], rows.kind[a:b] == 2
    nxt = np.where(blend, src + 1, src)
    feed = np.where(blend, np.minimum(tb.feed[src], tb.feed[nxt]), tb.feed[src])
    return ColumnRun(feed_columns(np.where(blend, BLEND, 0).astype(np.int64),
                                  rows.start[a:b], rows.end[a:b], rows.centre[a:b], feed,
                                  tb.exact[src] & ~blend, tb.line[nxt]))


def _other_blocks(raw: list) -> dict:
    """``{block index: segment}`` of the blocks of ``raw`` that are no straight feed
    move (a run counted block by block) [-]."""
    out, i = {}, 0
    for s in raw:
        t = type(s)
        if t is not LineRun and t is not Line:
            out[i] = s
        i += len(s) if t is LineRun else 1
    return out


#: the runs of a block per row, which a piece's last block is cut from
_BLOCK_RUNS = (LineRun, ArcRun)


class CornerBlender:
    """:func:`blend_corners` over a path that comes in pieces: the last block of a piece
    waits for the next piece, whose first block makes the corner at its end. Where
    corners are blended, the path comes out as runs of columns (:class:`ColumnRun`).

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
        # only a Line or a run of them has a tolerance; getattr over the blocks in C
        blend = self.tol > 0.0 or any(map(getattr, raw, repeat("tolerance_m"), repeat(None)))
        if blend and any(type(s) is ArcRun for s in raw):  # the table's row is a segment
            raw = [a for s in raw for a in (s.arcs() if type(s) is ArcRun else (s,))]
        if not blend:  # no corner has a tolerance: none is blended
            raw = _last_block_apart(raw, final)
            first = max(len(self.held) - 1, 0)
            stop = len(raw) if final else len(raw) - 1
            self.held = [_last_block(s) for s in raw[max(stop - 1, 0):]]
            return raw[first:stop] if stop > first else []
        tb = block_table(raw)
        first = max(len(self.held) - 1, 0)
        stop = tb.n if final else tb.n - 1
        self.held = _last_blocks(raw, tb.n - max(stop - 1, 0))
        if stop <= first:
            return []
        rows = blended_rows(tb, corner_table(tb, self.tol), first, stop)
        return _as_runs(raw, tb, rows)


def _last_blocks(raw: list, k: int) -> list:
    """The last ``k`` blocks of ``raw``, each a segment of its own [-]."""
    out = []
    for s in reversed(raw):
        if len(out) == k:
            break
        if type(s) is LineRun:
            n = len(s)
            out += [s.cut(j, j + 1) for j in range(n - 1, max(n - 1 - (k - len(out)), -1), -1)]
        else:
            out.append(s)
    return out[::-1]


def _last_block_apart(raw: list, final: bool) -> list:
    """``raw`` with its last block apart from a run it ends [-]."""
    if final or not raw or type(raw[-1]) not in _BLOCK_RUNS or len(raw[-1]) < 2:
        return raw
    n = len(raw[-1])
    return [*raw[:-1], raw[-1].cut(0, n - 1), raw[-1].cut(n - 1, n)]


def _last_block(s):
    """The last block of a run, else the segment [-]."""
    return s.cut(len(s) - 1, len(s)) if type(s) in _BLOCK_RUNS and len(s) > 1 else s
