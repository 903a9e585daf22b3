"""The time windows in which the contour seeks each sample's closest command point,
reaching over the command's rests: a window of ``window_s`` holds that much of the
command's motion either side of the sample, however long the command dwells between; and
the search of every segment of each window, in numpy."""

from __future__ import annotations

import numpy as np

from .._rows import dot_rows
from ..errors import InputError
from ..result import motion_time

#: rows of actual points handled at once [-]
_CHUNK = 256
#: segments within this relative distance of the closest, plus :data:`NEAR_ABS`, tie:
#: :data:`tcpmm.path.ties.NEAR_REL` and ``NEAR_ABS``, which this module does not
#: import (they come with numba) [-], [m]
NEAR_REL = 1e-9
NEAR_ABS = 1e-9
#: a half-turn's sine below this is the rounding of two unit vectors of one direction
#: (some 1e-8), not a turn [-]
_STRAIGHT = 1e-7


def over_rests(lo, hi, t_p, t_q, moves, window_s: float):
    """The windows ``lo:hi`` widened over the command's rests, to hold ``window_s`` of its
    motion either side of each sample: while the command dwells at a corner, the tool
    still on its way there is measured against the path it is on, not against the corner
    (0.5 s dwells at a square's corners read a TCP 19 um short of the corner, along the
    path, as contour error) [-]."""
    tau_p, rest = motion_time(t_p, moves)
    tau_q = t_q - np.interp(t_q, t_p, rest)
    return (np.minimum(lo, np.searchsorted(tau_p, tau_q - window_s, side="left")),
            np.maximum(hi, np.searchsorted(tau_p, tau_q + window_s, side="right")))


def feed_windows(lo, hi, t_p, t_q, air):
    """The windows ``lo:hi`` of the samples out of G0 rapids held to the feed move each is
    on, between the rapids before and after it: a tool still on a rapid's line when the
    cut it leads into begins is measured from the cut, as the lag the rapid carries in
    (a square's first side read 2.6 um there, the distance to the rapid's line, where the
    tool lay 287 um off the side). ``air``: the rapid flags of the command's vertices,
    a segment in a rapid where either end is (the rapid's last step ends on the feed
    move's first vertex: a tool lagging there read its side from the rapid's direction,
    -55 um for +55 um on a circle entered from a G0 along its radius), a sample where the
    command at its time is [-]."""
    p_air = np.asarray(air) != 0
    if not p_air.any():  # one feed move: the windows end at the last segment, no search
        end = np.minimum(hi, p_air.size - 1)
        return lo, np.where(lo >= end, hi, end)
    return searched_feed_windows(lo, hi, t_p, t_q, p_air)


def searched_feed_windows(lo, hi, t_p, t_q, p_air):
    """:func:`feed_windows` found by searching the vertices for the feed move each sample
    is on, whether or not ``p_air`` (the vertices' rapid flags as booleans) holds a rapid
    [-]."""
    seg_air = p_air[1:] | p_air[:-1]
    idx = np.arange(seg_air.size)
    prev = np.maximum.accumulate(np.where(seg_air, idx, -1))
    nxt = np.minimum.accumulate(np.where(seg_air, idx, seg_air.size)[::-1])[::-1]
    i = np.searchsorted(t_p, t_q, side="right") - 1
    # the feed move of vertex i: after the last rapid segment before it, up to the first
    # from it on
    before = np.where(i >= 1, prev[np.clip(i - 1, 0, seg_air.size - 1)], -1)
    a, b = np.maximum(lo, before + 1), np.minimum(hi, nxt[np.clip(i, 0, seg_air.size - 1)])
    keep = p_air[np.clip(i, 0, p_air.size - 1)] | (a >= b)  # in the air: the whole window
    return np.where(keep, lo, a), np.where(keep, hi, b)


def travel(p):
    """The segments of polyline ``p``, their squared lengths, directions of travel (that
    of the next moving segment where one rests, of the last where none follows) and the
    moving ones [m], [m^2], [-], [-]."""
    seg = np.diff(p, axis=0)
    ln2 = dot_rows(seg, seg)
    moving = np.flatnonzero(ln2 > 0)
    if moving.size == 0:
        raise InputError("the command does not move; there is no path to measure from")
    nxt = moving[np.minimum(np.searchsorted(moving, np.arange(seg.shape[0])), moving.size - 1)]
    # rows taken, not gathered by a fancy index: every segment of a chunk is read
    return seg, ln2, np.take(seg, nxt, axis=0) / np.sqrt(ln2.take(nxt))[:, None], moving


def chord_sags(seg, ln2, tdir, before=None, after=None):
    """How far each segment of a sampled path may lie from another sampling of the path
    it samples: a chord of length ``L`` turning by ``phi`` at its ends stands
    ``L sin(phi / 2) / 4`` at most off the curve through its vertices (``L^2 / 8R`` on an
    arc of radius ``R``), the larger turn of its two ends taken. A way out and a way back
    along an arc, sampled at other points, lie that far apart [m].

    Parameters
    ----------
    seg : ndarray, shape (m - 1, d)
        Segment vectors [m].
    ln2 : ndarray, shape (m - 1,)
        Their squared lengths [m^2].
    tdir : ndarray, shape (m - 1, d)
        Direction of travel on each segment (:func:`travel`) [-].
    before, after : ndarray, shape (d,), optional
        Direction of travel into the first vertex and out of the last, where the
        segments are a piece of a longer path (:func:`direction`); default none (the
        path starts or ends there) [-].
    """
    dirs = [tdir]
    if before is not None:
        dirs.insert(0, np.reshape(before, (1, -1)))
    if after is not None:
        dirs.append(np.reshape(after, (1, -1)))
    dirs = np.concatenate(dirs) if len(dirs) > 1 else tdir
    turns = np.sqrt(0.5 * (1.0 - np.clip(dot_rows(dirs[:-1], dirs[1:]), -1.0, 1.0)))
    half = np.zeros(seg.shape[0] + 1)  # sin of half the turn at each vertex
    half[(0 if before is not None else 1):(None if after is not None else -1)] = turns
    half[half < _STRAIGHT] = 0.0
    return np.sqrt(ln2) * np.maximum(half[:-1], half[1:]) * 0.25


def direction(p, moves, j: int):
    """Direction of travel of segment ``j`` of ``p``, as :func:`travel` gives it: that of
    the next moving segment (``moves``: per segment), of the last where none follows [-]."""
    ahead = np.flatnonzero(moves[j:])
    k = j + int(ahead[0]) if ahead.size else int(np.flatnonzero(moves[:j])[-1])
    seg = p[k + 1:k + 2] - p[k:k + 1]
    return (seg / np.sqrt(dot_rows(seg, seg))[:, None])[0]


def whole_windows(q, p, seg, ln2, tdir, sag, seglen, lo, hi, signed, t_q, t_p):
    """:func:`tcpmm.analysis.contour.distance_to_polyline` measuring every segment of each
    window, in numpy: where a point or vertex is not a finite float, or has many
    coordinates (the reference :mod:`tcpmm.path.nearest` is held to) [m], [-]."""
    m = p.shape[0]
    width = int(np.max(hi - lo)) + 1
    dist = np.empty(q.shape[0])
    foot = np.empty(q.shape[0], np.int64)
    for k0 in range(0, q.shape[0], _CHUNK):
        k = np.arange(k0, min(k0 + _CHUNK, q.shape[0]))
        j = np.minimum(lo[k, None] + np.arange(width)[None, :], m - 2)
        valid = (lo[k, None] + np.arange(width)[None, :]) < np.maximum(hi[k, None], lo[k, None] + 1)
        a, d = p[j], seg[j]
        rel = q[k, None, :] - a
        f = np.clip(np.divide(dot_rows(rel, d), ln2[j],
                              out=np.zeros(j.shape), where=ln2[j] > 0), 0.0, 1.0)
        off = rel - f[..., None] * d
        dd = np.where(valid, np.sqrt(dot_rows(off, off)), np.inf)
        cross = _cross(tdir[j], off) if q.shape[1] == 2 else np.zeros(j.shape)
        gap = np.maximum(np.maximum(t_p[j] - t_q[k, None], t_q[k, None] - t_p[j + 1]), 0.0)
        level = (dd + sag[j]).min(axis=1, keepdims=True) * (1 + NEAR_REL) + NEAR_ABS
        run = _pass_run(dd - sag[j] <= level, j, gap, sag, seglen, level[:, 0])
        least = np.where(run, dd, np.inf).min(axis=1, keepdims=True)
        best = _tie(run & (dd <= least * (1 + NEAR_REL) + NEAR_ABS), np.abs(cross), j, gap)
        rows = np.arange(k.size)
        dist[k] = dd[rows, best]
        foot[k] = j[rows, best]
        if signed:
            dist[k] *= np.where(cross[rows, best] < 0, -1.0, 1.0)
    return dist, foot


def _pass_run(near, j, gap, sag, seglen, level):
    """Per row, the ``near`` columns of the run along the path of segments ``j`` that
    :func:`tcpmm.path.nearest.nearest_segments` takes as the pass being run: consecutive
    segments, or apart by no more path than ``2 level`` and their sags; of least time
    ``gap`` to the point, the first on equal gaps [-]."""
    n = near.shape[0]
    pick0, pick1, best = np.full(n, -1), np.full(n, -1), np.full(n, np.inf)
    c0, c1, c_gap, last = np.full(n, -1), np.full(n, -1), np.full(n, np.inf), np.full(n, -2)
    for c in range(near.shape[1]):
        nc = near[:, c]
        new = nc & (c0 < 0)
        for r in np.flatnonzero(nc & (c0 >= 0) & (j[:, c] != last + 1)):
            new[r] = not _along(seglen, last[r], j[r, c],
                                2.0 * level[r] + sag[last[r]] + sag[j[r, c]])
        done = new & (c_gap < best)  # the run before ends
        pick0, pick1 = np.where(done, c0, pick0), np.where(done, c1, pick1)
        best = np.where(done, c_gap, best)
        c0 = np.where(new, c, c0)
        c_gap = np.where(new, gap[:, c], np.where(nc, np.minimum(c_gap, gap[:, c]), c_gap))
        c1 = np.where(nc, c, c1)
        last = np.where(nc, j[:, c], last)
    end = c_gap < best
    pick0, pick1 = np.where(end, c0, pick0), np.where(end, c1, pick1)
    cols = np.arange(near.shape[1])[None, :]
    return near & (cols >= pick0[:, None]) & (cols <= pick1[:, None])


def _along(seglen, last: int, j: int, most: float) -> bool:
    """Whether segment ``j`` follows ``last`` within ``most`` of path, the segments between
    summed in order as the compiled search sums them [-]."""
    run = 0.0
    for k in range(last + 1, j):
        run += seglen[k]
        if run > most:
            return False
    return True


def _tie(near, side, j, gap):
    """Per row, the column :func:`tcpmm.path.nearest.nearest_segments` picks among the
    ``near`` ones: of their runs of consecutive segments ``j``, the one of least time
    ``gap`` to the point (the first on equal gaps), in it the first of largest ``side``;
    a column at a time, every row at once [-]."""
    rows = np.arange(near.shape[0])
    pick, best = np.full(rows.size, -1), np.full(rows.size, np.inf)
    cur, cur_gap, last = np.full(rows.size, -1), np.full(rows.size, np.inf), np.full(rows.size, -2)
    for c in range(near.shape[1]):
        nc = near[:, c]
        new = nc & (j[:, c] != last + 1)
        done = new & (cur_gap < best)  # the run before ends
        pick, best = np.where(done, cur, pick), np.where(done, cur_gap, best)
        on = nc & ~new
        wider = on & (side[:, c] > side[rows, np.maximum(cur, 0)])
        cur = np.where(new | wider, c, cur)
        cur_gap = np.where(new, gap[:, c], np.where(on, np.minimum(cur_gap, gap[:, c]), cur_gap))
        last = np.where(nc, j[:, c], last)
    # a point not finite ties with nothing: the window's first, as NaN
    return np.maximum(np.where(cur_gap < best, cur, pick), 0)


def _cross(t, v):
    return t[..., 0] * v[..., 1] - t[..., 1] * v[..., 0]
