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

#: The end of a path is approached along the chord back over the span, or over the
#: stretch before the end within this angle of the last segment's direction where the path
#: curves nearer the end (a slot's end on an arc of 0.1 mm): the direction of travel
#: past the end point [-].
_END_COS = math.cos(math.radians(1.0))


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
def pymax(a, b):
    """Python's ``max(a, b)``: ``a`` unless ``b`` is larger (NaN and -0.0 kept)."""
    return b if b > a else a


@njit(cache=True)
def _held(dv, tol):
    """How far outside the path a point lies where it holds on the outgoing leg: the
    median of the last quarter of ``dv`` where that lies outside the band ``tol`` and the
    point holds there: the quarter stays within ``tol`` of it, or lies wholly outside the
    band with the median of the quarter before within ``tol`` of it (a ringing about a
    sag of the tool: its level holds, its swings need not fit in the band); else 0 (a
    point still moving about is not at rest; within the band it has settled) [m]."""
    q = max(dv.size // 4, 1)
    tail = dv[dv.size - q:]
    if tail.size < 4:
        return 0.0
    level = median(tail)
    top, low = 0.0, math.inf
    for v in tail:
        d = abs(v - level)
        if math.isnan(d):
            return 0.0
        top = max(top, d)
        low = min(low, v)
    if not level > tol:
        return 0.0
    if top <= tol:
        return level
    before = median(dv[dv.size - 2 * q:dv.size - q])
    return level if low > tol and abs(before - level) <= tol else 0.0


@njit(cache=True)
def corner_shape(t, dist, dev, past, b0, b1, end, tol):
    """Overshoot and rounding of one sensor at a corner, from its samples near the corner.

    Parameters
    ----------
    t, dist, dev : ndarray, shape (n,)
        Times [s], distances to the corner point [m] and how far outside the path [m].
    past : ndarray of uint8, shape (n,)
        1 where the sample lies past the corner; at the end of the path, where the
        command has arrived (before, a path that curves into its end, a slot's, may lie
        beyond the end point along the direction it ends in) [-].
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
    if end:  # the level from the whole stretch, the travel from the command's arrival
        dv = dev[own]
        tail = dv[dv.size - max(dv.size // 4, 1):]
        level = pymax(median(tail), 0.0)
        dv = dev[own & (past != 0)]
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
        over = pymax(top, 0.0)
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
    its level at the end (the median of its last quarter of rows), -1 where it leaves
    that band anywhere in the last quarter (it has not settled within the rows: a ringing
    signal's last row falls in the band or out of it by chance) [-]."""
    size = rows.shape[0]
    quarter = size - size // 4
    out = np.empty(cols.size, np.int64)
    for j in range(cols.size):
        col = rows[:, cols[j]]
        level = median(col[quarter:])
        k = 0
        for i in range(size - 1, -1, -1):
            if not abs(col[i] - level) <= tol:
                k = i + 1
                break
        out[j] = k if k <= quarter else -1
    return out


@njit(cache=True)
def corner_figures(rows, lims, t, dist, dev, past, cut, end):
    """Every sensor's figures at a corner: :func:`corner_shapes`, and the settling of
    each from its stretch of ``rows`` (time, command path length, per sensor the error;
    as :func:`tcpmm.sim.cornerfeed.feed_many` gives them) from ``lims[0]`` to ``lims[1]`` (time).

    Parameters
    ----------
    lims : ndarray, shape (5,)
        The times from and to which the corner owns the samples, the time ``t0`` and path
        length from which settling is counted [s], [s], [s], [m]; the settling band [m].

    Returns
    -------
    ndarray, shape (sensors, 4)
        Overshoot, rounding, time and path length to settle (NaN where the stretch
        is too short or the error does not settle within it, :func:`settle_rows`) [m],
        [m], [s], [m].
    """
    b0, b1, t0, sp0, tol = lims
    out = np.full((cut.size - 1, 4), math.nan)
    out[:, :2] = corner_shapes(t, dist, dev, past, cut, b0, b1, end, tol)
    a0 = np.searchsorted(rows[:, 0], b0, side="left")
    a1 = np.searchsorted(rows[:, 0], b1, side="right")
    if a1 - a0 < 4:
        return out
    k = settle_rows(rows[a0:a1], np.arange(2, 1 + cut.size), tol)
    for j in range(k.size):
        if k[j] >= 0:
            out[j, 2] = rows[a0 + k[j], 0] - t0
            out[j, 3] = rows[a0 + k[j], 1] - sp0
    return out


@njit(cache=True)
def corner_figures_many(rows, rowcut, lims, t, dist, dev, past, cut, end):
    """:func:`corner_figures` of several corners, one after the other: corner ``j``'s
    rows are ``rows[rowcut[j]:rowcut[j + 1]]``, its limits ``lims[j]``, its samples near
    it ``cut[j, 0]`` to ``cut[j, -1]`` of the next four, sensor ``k``'s from ``cut[j, k]``,
    and ``end[j]`` 1 at the end of the path; shape (corners * sensors, 4), a corner's
    sensors one after the other [m], [m], [s], [m]."""
    ns = cut.shape[1] - 1
    out = np.empty((lims.shape[0] * ns, 4))
    for j in range(lims.shape[0]):
        a, b = cut[j, 0], cut[j, ns]
        out[j * ns:(j + 1) * ns] = corner_figures(
            rows[rowcut[j]:rowcut[j + 1]], lims[j], t[a:b], dist[a:b], dev[a:b],
            past[a:b], cut[j] - a, end[j])
    return out


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


@njit(cache=True)
def first_bends(p, s, j0, t_out, after_m, cos_straight):
    """:func:`first_bend` of several corners: from segment ``j0[j]`` on, beyond the path
    length ``after_m[j]``, leaving ``t_out[j]``; -1 for none [-]."""
    out = np.empty(j0.size, np.int64)
    for j in range(j0.size):
        out[j] = first_bend(p, s, j0[j], t_out[j], after_m[j], cos_straight)
    return out


@njit(cache=True)
def interp_at(x, xp, fp, a, b):
    """:func:`numpy.interp` of ``x`` on ``xp[a:b]``, ``fp[a:b]``: the same arithmetic
    (the largest ``j`` with ``xp[j] <= x``, the value at ``j`` where ``x`` is on it, else
    the slope from ``j``, or from ``j + 1`` where that gives NaN) [-]."""
    if math.isnan(x):
        return x
    if x < xp[a]:
        return fp[a]
    if x > xp[b - 1]:
        return fp[b - 1]
    return interp_on(x, xp, fp, bracket(x, xp, a, b), b)


@njit(cache=True)
def bracket(x, xp, a, b):
    """The largest ``j`` in ``a:b`` with ``xp[j] <= x``, for ``xp[a] <= x`` [-]."""
    lo, hi = a, b  # it lies in [lo, hi)
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if xp[mid] <= x:
            lo = mid
        else:
            hi = mid
    return lo


@njit(cache=True)
def interp_on(x, xp, fp, j, b):
    """:func:`interp_at`'s value of an ``x`` within ``xp[a:b]`` whose largest ``j`` with
    ``xp[j] <= x`` is known [-]."""
    if j == b - 1 or xp[j] == x:
        return fp[j]
    slope = (fp[j + 1] - fp[j]) / (xp[j + 1] - xp[j])
    y = slope * (x - xp[j]) + fp[j]
    if math.isnan(y):
        y = slope * (x - xp[j + 1]) + fp[j + 1]
        if math.isnan(y) and fp[j] == fp[j + 1]:
            y = fp[j]
    return y


@njit(cache=True)
def dot(a, b):
    """``a . b``, the coordinates summed first to last [-]."""
    x = a[0] * b[0]
    for k in range(1, a.size):
        x = x + a[k] * b[k]
    return x


@njit(cache=True)
def unit(v):
    """``v`` over its length, or ``v`` itself where that is 0 [-]."""
    ln = math.sqrt(dot(v, v))
    return v / (ln if ln != 0.0 else 1.0)


@njit(cache=True)
def corner_frame(p, s, tc, i, turn, span):
    """Where the rest the corner ``p[i]`` ends begins (the command stands there from it
    to ``i``), the path length at the command's time of the corner (at the end of the
    path, ``turn`` NaN: of its arrival), the direction an overshoot runs in (across the
    outgoing leg, to the side the incoming direction points to; at the end of the path or
    a reversal the incoming direction) and the outgoing direction, the directions taken
    over the chords of ``span`` before and after the corner (at the end of the path, over
    the straight stretch before it where that is shorter: :func:`_straight_back`).

    Returns
    -------
    ndarray, shape (2 + 2 d,)
        The first vertex of the rest [-], the path length [m], the outward and the
        outgoing directions [-].
    """
    d = p.shape[1]
    first = 0
    for j in range(i - 1, -1, -1):
        if (p[j] != p[i]).any():
            first = j + 1
            break
    out = np.empty(2 + 2 * d)
    out[0] = first
    t0 = tc[first] if math.isnan(turn) else tc[i]
    out[1] = interp_at(t0, tc, s, 0, tc.size)
    x0, x1 = s[i] - span, s[i] + span
    if math.isnan(turn):
        x0 = max(x0, _straight_back(p, s, first, x0))
    a = max(np.searchsorted(s, min(x0, x1), side="left") - 1, 0)
    b = np.searchsorted(s, max(x0, x1), side="right") + 1
    b = min(b, s.size)
    back, ahead = np.empty(d), np.empty(d)
    for k in range(d):
        back[k] = interp_at(x0, s, p[:, k], a, b)
        ahead[k] = interp_at(x1, s, p[:, k], a, b)
    t_in = unit(p[i] - back)
    out[2:2 + d], out[2 + d:] = t_in, t_in
    if math.isnan(turn):
        return out
    t_out = unit(ahead - p[i])
    n = t_in - dot(t_in, t_out) * t_out
    ln = math.sqrt(dot(n, n))
    out[2:2 + d] = t_in if ln < 1e-6 else n / ln
    out[2 + d:] = t_out
    return out


@njit(cache=True)
def _straight_back(p, s, first, least):
    """Path length at the first vertex of the stretch that ends at ``p[first]`` within
    :data:`_END_COS` of its last moving segment's direction (its rests passed over), or
    ``least`` where it reaches that far back [m]."""
    j = first - 1
    while j >= 0 and (p[j] == p[first]).all():
        j -= 1
    if j < 0:
        return s[0]
    u = unit(p[first] - p[j])
    k = j
    while k > 0 and s[k] > least:
        v = p[k] - p[k - 1]
        if (v != 0.0).any() and dot(unit(v), u) < _END_COS:
            break
        k -= 1
    return s[k]


@njit(cache=True)
def corner_frames(p, s, tc, idx, turns, span):
    """:func:`corner_frame` of each corner ``p[idx[j]]`` of turn ``turns[j]``, a row each:
    the corners found in a piece of command in one call [-]."""
    out = np.empty((idx.size, 2 + 2 * p.shape[1]))
    for j in range(idx.size):
        out[j] = corner_frame(p, s, tc, idx[j], turns[j], span)
    return out
