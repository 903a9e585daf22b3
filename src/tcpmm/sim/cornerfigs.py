"""Compiled arithmetic of the corner metrics (:mod:`tcpmm.analysis.contour_corners`): a
run with a corner every few blocks (a CAM finishing pattern) has hundreds of thousands
of them, and a corner's few dozen samples cost more in numpy's calls than in their
arithmetic.

Each function does what the numpy expression it replaces does, in the same order
(coordinates summed first to last, a median the mean of the two middle values), so the
figures are the same to the bit.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True)
def median(x):
    """Median of ``x`` as :func:`numpy.median` gives it: NaN if any value is NaN, the mean
    of the two middle values of an even count [-]."""
    for v in x:
        if math.isnan(v):
            return math.nan
    y = np.sort(x)
    h = y.size // 2
    if y.size % 2:
        return y[h]
    return (y[h - 1] + y[h]) / 2.0


@njit(cache=True)
def _pymax(a, b):
    """Python's ``max(a, b)``: ``a`` unless ``b`` is larger (NaN and -0.0 kept)."""
    return b if b > a else a


@njit(cache=True)
def _held(dv, tol):
    """How far outside the path a point lies where it holds on the outgoing leg: the
    median of the last quarter of ``dv`` where that quarter stays within ``tol`` of it
    and lies outside the band ``tol``, else 0 (a point still moving about is not at rest;
    within the band it has settled) [m]."""
    tail = dv[dv.size - max(dv.size // 4, 1):]
    if tail.size < 4:
        return 0.0
    level = median(tail)
    top = 0.0
    for v in tail:
        d = abs(v - level)
        if math.isnan(d):
            return 0.0
        top = max(top, d)
    return level if level > tol and top <= tol else 0.0


@njit(cache=True)
def corner_shape(t, dist, dev, past, b0, b1, end, tol):
    """Overshoot and rounding of one sensor at a corner, from its samples near the corner.

    Parameters
    ----------
    t, dist, dev : ndarray, shape (n,)
        Times [s], distances to the corner point [m] and how far outside the path [m].
    past : ndarray of uint8, shape (n,)
        1 where the sample lies past the corner [-].
    b0, b1 : float
        The samples the corner owns: from ``b0`` to ``b1`` [s].
    end : int
        1 at the end of the path: the overshoot is the travel past the end point less the
        deflection it settles at [-].
    tol : float
        Band within which the error has settled [m].

    Returns
    -------
    ndarray, shape (2,)
        Overshoot and rounding (NaN and NaN if the corner owns no sample) [m].
    """
    out = np.full(2, math.nan)
    own = (t >= b0) & (t <= b1)
    if not own.any():
        return out
    rounding = math.inf
    for k in np.flatnonzero(own):
        if math.isnan(dist[k]):
            rounding = math.nan
            break
        rounding = min(rounding, dist[k])
    if end:
        dv = dev[own]
        tail = dv[dv.size - max(dv.size // 4, 1):]
        level = _pymax(median(tail), 0.0)
    else:
        dv = dev[own & (past != 0)]
        level = _held(dv, tol)
    over = 0.0
    if dv.size:
        top = -math.inf
        for v in dv:
            x = v - level
            if math.isnan(x):
                top = math.nan
                break
            top = max(top, x)
        over = _pymax(top, 0.0)
    out[0], out[1] = over, rounding
    return out


@njit(cache=True)
def corner_shapes(t, dist, dev, past, cut, b0, b1, end, tol):
    """:func:`corner_shape` of every sensor, their samples one after the other: sensor
    ``k``'s are rows ``cut[k]:cut[k + 1]``; shape (sensors, 2) [m]."""
    out = np.empty((cut.size - 1, 2))
    for k in range(cut.size - 1):
        a, b = cut[k], cut[k + 1]
        out[k] = corner_shape(t[a:b], dist[a:b], dev[a:b], past[a:b], b0, b1, end, tol)
    return out


@njit(cache=True)
def settle_rows(rows, cols, tol):
    """Per column of ``cols``: the first row from which the column stays within ``tol`` of
    its level at the end (the median of its last quarter of rows), -1 where the last row
    lies outside (it does not settle) [-]."""
    size = rows.shape[0]
    out = np.empty(cols.size, np.int64)
    for j in range(cols.size):
        col = rows[:, cols[j]]
        level = median(col[size - size // 4:])
        if abs(col[size - 1] - level) > tol:
            out[j] = -1
            continue
        k = 0
        for i in range(size - 1, -1, -1):
            if abs(col[i] - level) > tol:
                k = i + 1
                break
        out[j] = k
    return out


@njit(cache=True)
def near_rows(q, lf, s, p, c, n, s_i, span, s_on, s_first, end):
    """Which of the points ``q`` lie near a corner, and their figures.

    Parameters
    ----------
    q : ndarray, shape (m, d)
        Points measured [m].
    lf : ndarray of int64, shape (m,)
        The segment of ``p`` closest to each; negative where it is dropped (before every
        corner not yet found) [-].
    s : ndarray, shape (k,)
        Path length at each vertex of ``p`` [m].
    p : ndarray, shape (k, d)
        The command polyline [m].
    c, n : ndarray, shape (d,)
        Corner point [m] and the direction an overshoot runs in [-].
    s_i, span, s_on, s_first : float
        Path length at the corner, the corner span, to which the outgoing leg runs on, at
        the first vertex of the corner's rest [m].
    end : int
        1 at the end of the path [-].

    Returns
    -------
    idx : ndarray of int64
        The rows of ``q`` near the corner [-].
    dist, dev : ndarray
        Their distances to the corner point and how far outside the path they lie [m].
    past : ndarray of uint8
        1 where past the corner [-].
    """
    m, d = q.shape
    keep = np.zeros(m, np.bool_)
    for r in range(m):
        if lf[r] >= 0:
            at = s[lf[r]]
            keep[r] = at >= s_i - span and (at <= s_i + span or at <= s_on)
    idx = np.flatnonzero(keep)
    dist, dev = np.empty(idx.size), np.empty(idx.size)
    past = np.ones(idx.size, np.uint8)
    for k in range(idx.size):
        r = idx[k]
        dc = (q[r, 0] - c[0]) * (q[r, 0] - c[0])
        for j in range(1, d):
            dc = dc + (q[r, j] - c[j]) * (q[r, j] - c[j])
        dist[k] = math.sqrt(dc)
        if end:
            x = (q[r, 0] - c[0]) * n[0]
            for j in range(1, d):
                x = x + (q[r, j] - c[j]) * n[j]
            dev[k] = x
            continue
        g = lf[r]
        ln2 = (p[g + 1, 0] - p[g, 0]) * (p[g + 1, 0] - p[g, 0])
        w = (q[r, 0] - p[g, 0]) * (p[g + 1, 0] - p[g, 0])
        for j in range(1, d):
            ln2 = ln2 + (p[g + 1, j] - p[g, j]) * (p[g + 1, j] - p[g, j])
            w = w + (q[r, j] - p[g, j]) * (p[g + 1, j] - p[g, j])
        f = w / ln2 if ln2 > 0 else 0.0
        if f < 0.0:
            f = 0.0
        if f > 1.0:
            f = 1.0
        x = (q[r, 0] - (p[g, 0] + f * (p[g + 1, 0] - p[g, 0]))) * n[0]
        for j in range(1, d):
            x = x + (q[r, j] - (p[g, j] + f * (p[g + 1, j] - p[g, j]))) * n[j]
        dev[k] = x
        past[k] = s[g] + f * math.sqrt(ln2) >= s_first - 1e-12
    return idx, dist, dev, past


@njit(cache=True)
def first_bend(p, s, j0, t_out, after_m, cos_straight):
    """:func:`tcpmm.analysis.corners.first_bend`, -1 for none: the first segment from
    ``j0`` on beyond the path length ``after_m`` whose direction leaves ``t_out`` by more
    than the angle of cosine ``cos_straight`` [-]."""
    d = p.shape[1]
    for j in range(j0, p.shape[0] - 1):
        ln2 = (p[j + 1, 0] - p[j, 0]) * (p[j + 1, 0] - p[j, 0])
        w = (p[j + 1, 0] - p[j, 0]) * t_out[0]
        for k in range(1, d):
            ln2 = ln2 + (p[j + 1, k] - p[j, k]) * (p[j + 1, k] - p[j, k])
            w = w + (p[j + 1, k] - p[j, k]) * t_out[k]
        ln = math.sqrt(ln2)
        if w < cos_straight * ln and ln > 0 and s[j] > after_m:
            return j
    return -1
