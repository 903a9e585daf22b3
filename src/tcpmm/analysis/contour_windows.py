"""The time windows in which the contour seeks each sample's closest command point,
reaching over the command's rests: a window of ``window_s`` holds that much of the
command's motion either side of the sample, however long the command dwells between; and
the search of every segment of each window, in numpy."""

from __future__ import annotations

import numpy as np

from .._rows import dot_rows
from ..result import motion_time

#: rows of actual points handled at once [-]
_CHUNK = 256
#: segments within this relative distance of the closest, plus :data:`NEAR_ABS`, tie:
#: :data:`tcpmm.path.nearest.NEAR_REL` and ``NEAR_ABS``, which this module does not
#: import (they come with numba) [-], [m]
NEAR_REL = 1e-9
NEAR_ABS = 1e-9


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


def whole_windows(q, p, seg, ln2, tdir, lo, hi, signed, t_q, t_p):
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
        near = dd <= dd.min(axis=1, keepdims=True) * (1 + NEAR_REL) + NEAR_ABS
        gap = np.maximum(np.maximum(t_p[j] - t_q[k, None], t_q[k, None] - t_p[j + 1]), 0.0)
        best = _tie(near, np.abs(cross), j, gap)
        rows = np.arange(k.size)
        dist[k] = dd[rows, best]
        foot[k] = j[rows, best]
        if signed:
            dist[k] *= np.where(cross[rows, best] < 0, -1.0, 1.0)
    return dist, foot


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
