"""Corners of a commanded path, found a piece of the path at a time, and the geometry that
measures them: overshoot, rounding and settling (the definitions are in
:mod:`tcpmm.analysis.contour`, the measuring in :mod:`tcpmm.analysis.contour_corners`).

Two sharp turns with no vertex between them whose turn over the span falls below the
least (a zig-zag's U-turn of a step-over shorter than about the span) are one corner: the
span over which each is taken holds the other, so the finder cannot tell them apart. A
path that turns back within the span (a U-turn on an arc of a tenth of a millimetre) is a
corner however evenly it turns, and a bend too.

A corner is measured where it is: only the samples whose closest command point lies within
the corner span of the corner count, so a path that curves on (a spiral, an arc) or comes
back to the same place (a circle's end on its start) adds nothing far from it.

Every figure is taken sample by sample (the sums over coordinates first to last), so a
path given in pieces gives the whole path's corners to the bit.
"""

from __future__ import annotations

import numpy as np

from .._compiled import call
from .._rows import any_rows, dot_rows, norm_rows

#: Least share of the turn over the corner span that a corner makes over a quarter of it;
#: a curve of even curvature makes a quarter, a corner (sharp or blended within the quarter
#: span) all of it [-].
_SHARP = 0.5
#: Turn over the span at and above which the path turns back within it: a corner however
#: evenly it turns (an even curve turns so far only on a radius under about 0.3 mm) [rad].
_TURNS_BACK = np.radians(150.0)
#: Largest angle between the command's direction and the outgoing one for which the
#: command after a corner still runs straight on [deg].
_STRAIGHT_DEG = 5.0
_COS_STRAIGHT = float(np.cos(np.radians(_STRAIGHT_DEG)))
#: Least turn of a reversal: where the path runs back on itself every vertex within half
#: a span of the turning point turns by pi (the chord ahead points back), up to the
#: roundings of the chords' directions [rad].
_REVERSAL = np.pi - 1e-6


def path_length(p, s0=0.0):
    """Path length at each vertex of a polyline, from ``s0`` at the first [m]."""
    return np.cumsum(np.concatenate([[s0], norm_rows(np.diff(p, axis=0))]))


def _at(p, s, x):
    """The polyline at path lengths ``x``, shape (len(x), d) [m]."""
    out = np.empty((p.shape[1], np.size(x)))
    for k in range(p.shape[1]):
        out[k] = np.interp(x, s, p[:, k])
    return out.T


def turn_at(p, s, idx, span_m):
    """Angle between the chords over ``span_m`` before and after the vertices ``idx``
    [rad]."""
    # every vertex of a piece is judged: rows taken, not gathered by a fancy index
    at, x = np.take(p, idx, axis=0), np.take(s, idx)
    u = at - _at(p, s, x - span_m)
    w = _at(p, s, x + span_m) - at
    cos = dot_rows(u, w) / (norm_rows(u) * norm_rows(w) + 1e-300)
    return np.arccos(np.clip(cos, -1.0, 1.0))


def rest_start(p, i):
    """The first vertex of the rest ``p[i]`` ends: the command stands there from it to
    ``i`` [-]. Looked for back from ``i`` in growing blocks: the rest is short where the
    command moves, and the polyline long."""
    hi, step = i, 64
    while hi > 0:
        lo = max(hi - step, 0)
        moved = np.flatnonzero(np.any(p[lo:hi] != p[i], axis=1))
        if moved.size:
            return lo + int(moved[-1]) + 1
        hi, step = lo, step * 8
    return 0


class CornerFinder:
    """The corners of :func:`find_corners`, found as the polyline grows: each vertex is
    judged once the path runs on ``span_m`` past it, and a run of candidate vertices is
    carried across the pieces until it ends.

    Parameters
    ----------
    corner_deg : float
        Least turn of the direction over ``span_m`` before and after [deg].
    span_m : float
        Path length over which the direction is taken on either side [m].
    """

    def __init__(self, corner_deg=30.0, span_m=0.5e-3):
        self.min_turn, self.span = np.radians(corner_deg), span_m
        self.ev = 0  # the first vertex not judged yet
        # the open run of candidates: [first vertex, best, its turn, first and last vertex
        # of a reversal (None if none), last vertex, whether it holds two sharp turns]
        self.group = None
        self.last = -1  # the last corner's vertex
        self.curves = 0  # runs of bending vertices with no corner among them
        self.curve = (False, False)  # a run open at the last vertex judged; a corner in it

    def step(self, p, s, off: int, final: bool) -> list:
        """Corners among the vertices judged with the polyline ``p`` (from vertex ``off``)
        at hand; at the ``final`` piece the end of the path too [-]."""
        n = off + s.size
        if final:
            hi = n
        else:  # judged only where the path runs on a span: its chord ends there
            far = (s < s[-1] - self.span) & (s + self.span < s[-1])
            hi = off + int(np.count_nonzero(far))
        out = []
        if hi > self.ev:
            out = self._judge(p, s, off, hi, final)
        if final:
            self.curves += int(self.curve[0] and not self.curve[1])
            self.curve = (False, False)
        if final and s[-1] > 0.0 and self.last != n - 1:
            out.append((n - 1, float("nan")))
        return out

    def _judge(self, p, s, off, hi, final) -> list:
        idx = np.arange(self.ev - off, hi - off)
        turn = turn_at(p, s, idx, self.span)
        x = s[idx]
        ok = (x >= self.span) & ((x <= s[-1] - self.span) if final else True)
        bend = ok & (turn > self.min_turn)
        cand = bend.copy()
        k = np.flatnonzero(cand)  # the quarter span's turn only where it decides
        sharp = turn_at(p, s, idx[k], self.span / 4) > _SHARP * turn[k]
        # a path that turns back within the span is a corner at its resolution, however
        # evenly it turns (a U-turn on an arc of 0.1 mm); it is a bend (bend_corners)
        back = np.zeros(idx.size, bool)
        back[k] = ~sharp & (turn[k] >= _TURNS_BACK)
        cand[k] = sharp | back[k]
        self._curves(bend, cand)
        k = np.flatnonzero(cand)
        # non-bending vertices up to each: sharp runs with none between are one bend
        straight = np.cumsum(~bend)
        out = []
        if k.size:  # the runs of candidates, the first and the last as they may go on
            runs = _runs(k, turn, straight, back)
            self._run(p, s, off, idx, turn, [r[0] for r in runs], final, straight, out)
            if runs[0].size > 2:
                self._closed_runs(p, s, off, idx, turn, [r[1:-1] for r in runs], out)
            if runs[0].size > 1:
                self._run(p, s, off, idx, turn, [r[-1] for r in runs], final, straight, out)
        if self.group is not None:  # ends where the path runs straight past its last turn
            at = self.group[4] - self.ev
            if straight[-1] > (straight[at] if at >= 0 else 0):
                self._close(p, s, off, out)
        self.ev = hi
        return out

    def _curves(self, bend, cand) -> None:
        """Count the runs of vertices that bend by more than the least turn over the span
        with none of them a corner: curves, or corners blended over more than a quarter
        span (a square's under ``G64 P0.1``), left out of the corners; a run open at the
        last vertex judged goes on into the next piece [-]."""
        if not bend.size:
            return
        going, held = self.curve
        if going and not bend[0]:
            self.curves += int(not held)
            going = False
        label = np.cumsum(bend & ~np.r_[going, bend[:-1]])
        held_by = np.bincount(label[bend], weights=cand[bend], minlength=label[-1] + 1) > 0
        held_by[0] |= held
        runs = np.unique(label[bend])
        self.curve = (bool(bend[-1]), bool(bend[-1] and held_by[runs[-1]]))
        runs = runs[:-1] if bend[-1] else runs
        self.curves += int(np.count_nonzero(~held_by[runs]))

    def _run(self, p, s, off, idx, turn, run, final, straight, out) -> None:
        """Take in one run of candidates (:func:`_runs`): it goes on from the last piece
        (the path bends on from there to it), or opens; it ends unless the path bends on
        from it to the last vertex judged."""
        first, last, j, rf, rl, split = (int(x) for x in run)
        back = [int(idx[rf]) + off, int(idx[rl]) + off] if rf >= 0 else None
        if self.group is not None and straight[first] == 0:  # goes on from the last piece
            if turn[j] > self.group[2]:
                self.group[1:3] = [idx[j] + off, float(turn[j])]
            if back is not None:
                self.group[3] = back if self.group[3] is None else [self.group[3][0], back[1]]
            # a sharp turn apart from the last one's: the bend holds two
            self.group[5] |= bool(split) or first > 0 or self.group[4] < self.ev - 1
            self.group[4] = idx[last] + off
        else:
            self._close(p, s, off, out)
            self.group = [idx[first] + off, idx[j] + off, float(turn[j]), back,
                          idx[last] + off, bool(split)]
        if straight[-1] != straight[last] or final:
            self._close(p, s, off, out)

    def _closed_runs(self, p, s, off, idx, turn, runs, out) -> None:
        """The corners of runs that open and end within the vertices judged, as
        :meth:`_close` finds each (the vertices of their sharpest turns ``best``, their
        first and last reversal ``rf``, ``rl``, -1 for none), all at once [-]."""
        first, last, best, rf, rl, split = runs
        i, bent = idx[best], turn[best].copy()
        more = []
        for r in np.flatnonzero(rf >= 0).tolist():  # a reversal: the turning points
            at = turning_points(p, s, idx[rf[r]], idx[rl[r]] + 1, self.span / 4)
            i[r] = at[0]
            more += [(k, float(bent[r])) for k in at[1:]]
        r = np.flatnonzero(split & (rf < 0))  # a bend, not a reversal: all at once
        if r.size:
            i[r], bent[r] = bend_corners(p, s, idx[first[r]], idx[last[r]], self.span)
        r = np.flatnonzero(rf < 0)
        if r.size:  # a cusp: the vertex where the path turns back
            at = cusps(p, idx[first[r]], idx[last[r]] + 1)
            i[r] = np.where(at >= 0, at, i[r])
        i = _standing_end(p, np.r_[i, [k for k, _ in more]].astype(np.int64))
        found = sorted(zip(i.tolist(), [*bent.tolist(), *(t for _, t in more)], strict=True))
        out.extend((k + off, t) for k, t in found)
        self.last = found[-1][0] + off

    def _close(self, p, s, off, out) -> None:
        """End the open run: its corner on the last vertex where the command stands at the
        run's sharpest turn; at a reversal, at the turning point: the vertex furthest from
        the first that turns back, which lies half a span before it on the way in (the
        vertex halfway along the path between the first and the last that turn back lay
        samples short of it, the vertices being sparse where the command is fast); else,
        where the run is a bend (two sharp turns, a U-turn), :func:`bend_corners`."""
        if self.group is None:
            return
        i, bent = self.group[1] - off, self.group[2]
        if self.group[3] is not None:
            *before, i = turning_points(p, s, self.group[3][0] - off,
                                        self.group[3][1] - off + 1, self.span / 4)
            out.extend((_stand_on(p, k) + off, bent) for k in before)
        elif self.group[5]:
            at, turns = bend_corners(p, s, np.array([self.group[0] - off]),
                                     np.array([self.group[4] - off]), self.span)
            i, bent = int(at[0]), float(turns[0])
        if self.group[3] is None:  # a cusp: the vertex where the path turns back
            at = int(cusps(p, np.array([self.group[0] - off]),
                           np.array([self.group[4] - off + 1]))[0])
            i = at if at >= 0 else i
        i = _stand_on(p, i)
        out.append((i + off, bent))
        self.last, self.group = i + off, None

    def keep(self, p, s, off: int) -> int:
        """The first vertex a corner not found yet may still need: back over the rest and
        the span before the first vertex it may lie on [-]."""
        c = min(self.group[0] if self.group else self.ev, off + s.size - 1) - off
        j = int(np.searchsorted(s, s[c] - self.span, side="left")) - 1
        return off + max(min(rest_start(p, c), j), 0)


def _stand_on(p, i: int) -> int:
    """The last vertex where the command stands still at vertex ``i``; one corner's, where
    :func:`_standing_end` would look at the whole piece [-]."""
    while i + 1 < p.shape[0] and np.array_equal(p[i + 1], p[i]):
        i += 1
    return i


def _standing_end(p, i):
    """Per vertex ``i``, the last vertex where the command stands still there [-]."""
    moves = np.flatnonzero(any_rows(p[1:] != p[:-1]))  # p[j + 1] off p[j]
    k = np.searchsorted(moves, i, side="left")
    return np.where(k < moves.size, moves[np.minimum(k, moves.size - 1)], p.shape[0] - 1)


def turning_points(p, s, a: int, b: int, apart: float) -> list[int]:
    """The turning points of reversals whose vertices that turn back over the span are
    ``a:b``: each vertex where the path runs back from one segment to the next (a cusp),
    the first of those within ``apart`` of path length of each other (a command that
    dithers about its turning point); where no segment runs back (a turn rounded off),
    the vertex furthest from the first, which lies half a span before it on the way in.
    Two reversals closer than a span are one run: the furthest vertex lay between them,
    or on one of them, and the other was left out [-]."""
    back = a + np.flatnonzero(local_turns(p, np.arange(a, b)) >= _TURNS_BACK)
    if not back.size:
        return [a + int(np.argmax(norm_rows(p[a:b] - p[a])))]
    keep = np.r_[True, np.diff(s[back]) >= apart]
    return back[keep].tolist()


def _runs(k, turn, straight, evenly) -> tuple:
    """The runs of candidate vertices ``k`` (positions among those judged) with no vertex
    between them that does not bend (``straight``, the count of those up to each): two
    sharp turns within a span of each other, as a U-turn's, are one corner, whose span
    each one's turn already takes in. Each run's first and last, the first of its sharpest
    ``turn``, its first and last that turns back (-1 for none), and whether it is a bend
    (1, else 0): more than one sharp turn, or a vertex that is a candidate only as one
    where the path turns back within the span (``evenly``) [-]."""
    cut = np.flatnonzero(np.diff(straight[k]) > 0) + 1
    start, stop = np.r_[0, cut], np.r_[cut, k.size]
    tk, pos = turn[k], np.arange(k.size)
    top = np.repeat(np.maximum.reduceat(tk, start), stop - start)
    best = np.minimum.reduceat(np.where(tk == top, pos, k.size), start)
    back = tk >= _REVERSAL
    rf = np.minimum.reduceat(np.where(back, pos, k.size), start)
    rl = np.maximum.reduceat(np.where(back, pos, -1), start)
    has = rf < k.size
    gaps = np.cumsum(np.r_[0, np.diff(k) > 1])
    even = np.maximum.reduceat(evenly[k].astype(np.int64), start)
    return (k[start], k[stop - 1], k[best], np.where(has, k[np.minimum(rf, k.size - 1)], -1),
            np.where(has, k[np.maximum(rl, 0)], -1),
            ((gaps[stop - 1] > gaps[start]) | (even > 0)).astype(np.int64))


def local_turns(p, at=None):
    """Per vertex of ``p`` (of those ``at``, where given), the angle between the moving
    segments either side of it (the last that ends there or before, the first that
    starts there or after), 0 where there is none on a side [rad]."""
    seg = p[1:] - p[:-1]
    moving = np.flatnonzero(any_rows(seg != 0.0))
    at = np.arange(p.shape[0]) if at is None else np.asarray(at)
    out = np.zeros(at.size)
    after = np.searchsorted(moving, at, side="left")
    ok = np.flatnonzero((after > 0) & (after < moving.size))
    u, w = seg[moving[after[ok] - 1]], seg[moving[after[ok]]]
    cos = dot_rows(u, w) / (norm_rows(u) * norm_rows(w))
    out[ok] = np.arccos(np.clip(cos, -1.0, 1.0))
    return out


def cusps(p, a, b):
    """Per run of vertices ``a[r]:b[r]`` of ``p``, the first vertex where the path turns
    back by :data:`_TURNS_BACK` or more between one segment and the next, -1 where none
    does: a cusp, its turning point (the sharpest turn over the span lies past it where
    one side curves, an arc that turns back onto a line) [-]."""
    lens = b - a
    if lens.sum() == 0:
        return np.full(a.size, -1)
    start = np.r_[0, np.cumsum(lens)[:-1]]
    at = np.repeat(a - start, lens) + np.arange(lens.sum())
    turn = local_turns(p, at)  # the vertices asked alone: a run's few of a long piece
    top = np.maximum.reduceat(turn, start)
    pos = np.minimum.reduceat(np.where(turn == np.repeat(top, lens), np.arange(at.size),
                                       at.size), start)
    return np.where(top >= _TURNS_BACK, at[np.minimum(pos, at.size - 1)], -1)


def bend_corners(p, s, a, b, span) -> tuple:
    """The corners of bends whose sharp turns lie from vertices ``a`` to vertices ``b`` of
    ``p`` (path lengths ``s``), as a U-turn's two, all at once: the vertex halfway along the
    path between them, and the turn between the chords over a quarter of ``span`` [m] into
    ``a`` and out of ``b``: over the whole span they would reach past the turns next to
    the bend (a square notch's bottom, 0.3 mm wide, read 74 deg for its 180) [-, rad]."""
    # the first vertex at or past the half-way length; none before ``a`` is past it
    mid = np.maximum(np.searchsorted(s, 0.5 * (s[a] + s[b]), side="left"), a)
    u = p[a] - _at(p, s, s[a] - span / 4)
    w = _at(p, s, s[b] + span / 4) - p[b]
    cos = dot_rows(u, w) / (norm_rows(u) * norm_rows(w) + 1e-300)
    return np.minimum(mid, b), np.arccos(np.clip(cos, -1.0, 1.0))


def find_corners(p, corner_deg=30.0, span_m=0.5e-3):
    """Corners of a polyline: ``(vertex index, turn angle)`` each.

    A corner turns by more than ``corner_deg`` over ``span_m`` before and after, and makes
    most of that turn over a quarter of the span; a curve that turns as much evenly (a small
    arc, the inside of a spiral) is no corner.

    Parameters
    ----------
    p : ndarray, shape (m, d)
        Polyline [m].
    corner_deg : float
        Least turn of the direction over ``span_m`` before and after [deg].
    span_m : float
        Path length over which the direction is taken on either side [m].

    Returns
    -------
    list of tuple
        Vertex index (the last one on the corner point) and turn [rad]; the end of the
        path last, with a turn of NaN [-].
    """
    p = np.asarray(p, float)
    return CornerFinder(corner_deg, span_m).step(p, path_length(p), 0, True)


def first_bend(p, s, j0, t_out, after_m):
    """The first segment from ``j0`` on, beyond the path length ``after_m``, that leaves the
    outgoing direction by more than ``_STRAIGHT_DEG`` (across a straight leg the overshoot is
    the contour error, across a curve it is not); ``None`` if none of ``p`` does [-].
    Looked for a segment at a time, compiled (:func:`tcpmm.sim.cornerfigs.first_bend`): the
    leg is short where corners follow one another."""
    j = call("first_bend", p, s, int(j0), np.ascontiguousarray(t_out, float),
             float(after_m), _COS_STRAIGHT)
    return None if j < 0 else int(j)


def first_bends(p, s, j0, t_out, after_m):
    """:func:`first_bend` of several legs at once: from segment ``j0[k]`` on, beyond the
    path length ``after_m[k]`` [m], leaving the direction ``t_out[k]`` [-]; -1 where
    none of ``p`` does [-]."""
    return call("first_bends", p, s, np.ascontiguousarray(j0, np.int64),
                np.ascontiguousarray(t_out, float), np.ascontiguousarray(after_m, float),
                _COS_STRAIGHT)
