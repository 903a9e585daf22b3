"""Compiled taking down of the samples that concern the corners of a run
(:mod:`tcpmm.analysis.contour_corners`): every open corner's share of a batch of
samples in one call, with the arithmetic of the numpy expressions it replaces
(coordinates summed first to last, :func:`numpy.interp` reproduced), so the figures are
the same to the bit."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .cornerfigs import bracket, interp_at, interp_on


@njit(cache=True, inline="always")
def _outside(q, k, i, g, s, p, n, s_first):
    """How far sample ``i`` of sensor ``k`` of ``q`` lies outside the path, from its
    closest point on segment ``g`` of ``p``, and whether that point lies past the
    corner's rest (from path length ``s_first`` on) [m], [-]."""
    d = q.shape[2]
    ln2 = (p[g + 1, 0] - p[g, 0]) * (p[g + 1, 0] - p[g, 0])
    w = (q[k, i, 0] - p[g, 0]) * (p[g + 1, 0] - p[g, 0])
    for j in range(1, d):
        ln2 = ln2 + (p[g + 1, j] - p[g, j]) * (p[g + 1, j] - p[g, j])
        w = w + (q[k, i, j] - p[g, j]) * (p[g + 1, j] - p[g, j])
    f = w / ln2 if ln2 > 0 else 0.0
    if f < 0.0:
        f = 0.0
    if f > 1.0:
        f = 1.0
    x = (q[k, i, 0] - (p[g, 0] + f * (p[g + 1, 0] - p[g, 0]))) * n[0]
    for j in range(1, d):
        x = x + (q[k, i, j] - (p[g, j] + f * (p[g + 1, j] - p[g, j]))) * n[j]
    return x, s[g] + f * math.sqrt(ln2) >= s_first - 1e-12


@njit(cache=True, inline="always")
def _dot_diff(q, k, i, c, v):
    """``(q[k, i] - c) . v``, the coordinates summed first to last [-]."""
    x = (q[k, i, 0] - c[0]) * v[0]
    for j in range(1, q.shape[2]):
        x = x + (q[k, i, j] - c[j]) * v[j]
    return x


@njit(cache=True, inline="always")
def _dist(q, k, i, c):
    """``|q[k, i] - c|``, the squares summed first to last [m]."""
    x = (q[k, i, 0] - c[0]) * (q[k, i, 0] - c[0])
    for j in range(1, q.shape[2]):
        x = x + (q[k, i, j] - c[j]) * (q[k, i, j] - c[j])
    return math.sqrt(x)


@njit(cache=True)
def _window(t, lim):
    """The samples of ``t`` a corner takes (``lim[0]`` to ``lim[1]``) and the first of
    them from its time ``lim[2]`` on [-]."""
    i0 = np.searchsorted(t, lim[0], side="left")
    i1 = max(np.searchsorted(t, lim[1], side="right"), i0)
    a = i0
    while a < i1 and not t[a] >= lim[2]:
        a += 1
    return i0, i1, a


@njit(cache=True, inline="always")
def _is_near(g, s, lo, hi, on):
    """Whether segment ``g`` lies near the corner: within the span about it (path length
    ``lo`` to ``hi``), or on its outgoing leg (up to ``on``) [-]."""
    return g >= 0 and s[g] >= lo and (s[g] <= hi or s[g] <= on)


@njit(cache=True, inline="always")
def _takes(g, s, lo, hi, on, at_end, after, q, k, i, c, span):
    """Whether a corner takes sample ``i`` of sensor ``k`` of ``q``, whose closest point
    lies on segment ``g``: :func:`_is_near`, or at the path's end, once the command has
    arrived (``after``), within the span of the end point while its closest point lies
    wholly before the span (or before the command kept, ``g < 0``): a closed path's end
    meets its start, which lies closer to a tool travelling past the end point than the
    last leg does [-]."""
    if _is_near(g, s, lo, hi, on):
        return True
    return (at_end != 0 and after and (g < 0 or s[g + 1] < lo)
            and _dist(q, k, i, c) <= span)


@njit(cache=True)
def _span(lim):
    """The path lengths :func:`_is_near` takes of a corner's limits: where its span begins
    and ends, and to which its outgoing leg runs on [m]."""
    return lim[3] - lim[4], lim[3] + lim[4], lim[5]


@njit(cache=True)
def _path_at(x, tc, s, v):
    """:func:`tcpmm.sim.cornerfigs.interp_at` of the time ``x`` on the command's times
    ``tc`` and path lengths ``s``, and the largest vertex at or before ``x`` (-1 outside
    the command), looked for forward from ``v``, that of an earlier time (-1 for none):
    the times of a corner's samples follow one another, the vertices with them [s], [m],
    [-]."""
    n = tc.size
    if not (tc[0] <= x and x <= tc[n - 1]):
        return interp_at(x, tc, s, 0, n), -1
    if v < 0:
        v = bracket(x, tc, 0, n)
    while v + 1 < n and tc[v + 1] <= x:
        v += 1
    return interp_on(x, tc, s, v, n), v


@njit(cache=True)
def feed_many(t, q, e, f, off, tc, s, p, c, n, lims, end):
    """What each of several corners takes down of a batch of samples: those from
    ``lims[j, 0]`` to ``lims[j, 1]`` (time); of them, every sensor's that lie near the
    corner, and those from the corner on (its settling stretch).

    Parameters
    ----------
    t : ndarray, shape (m,)
        Times of the samples [s].
    q : ndarray, shape (sensors, m, d)
        Their points [m].
    e : ndarray, shape (sensors, m)
        Their contour errors [m].
    f : ndarray of int64, shape (sensors, m)
        The segment of the command closest to each [-].
    off : int
        The segment of the command that is ``p``'s first: one before it is dropped
        (it lies before every corner not yet found) [-].
    tc, s : ndarray, shape (k,)
        Time [s] and path length [m] at each vertex of the command ``p``, shape (k, d).
    c, n : ndarray, shape (corners, d)
        Corner points [m]; the directions an overshoot runs in [-].
    lims : ndarray, shape (corners, 7)
        Per corner: from and to which time [s], the corner's time ``t0`` [s]; the path
        length at the corner, the corner span, to which the outgoing leg runs on and at
        the first vertex of the corner's rest [m].
    end : ndarray of int64, shape (corners,)
        1 at the end of the path: what settles is the distance to the end point [-].

    Returns
    -------
    cuts : ndarray of int64, shape (corners, sensors + 1)
        Where each corner's samples of each sensor near it begin in the next four [-].
    tn, dist, dev : ndarray
        Their times [s], distances to the corner point and how far outside the path [m].
    past : ndarray of uint8
        1 where past the corner (at the end: from the command's arrival) [-].
    rowcut : ndarray of int64, shape (corners + 1,)
        Where each corner's rows begin in the next [-].
    rows : ndarray, shape (r, 2 + sensors)
        From ``t0`` on: time, the command's path length there and per sensor the
        contour error (the distance to the end point at the end) [s], [m], [m].
    """
    ns, nk = q.shape[0], lims.shape[0]
    cuts, rowcut = np.zeros((nk, ns + 1), np.int64), np.zeros(nk + 1, np.int64)
    # one pass over the windows into arrays as long as all of them, cut to what was
    # taken: a pass that counted first took as long again; a sample is indexed, not
    # viewed (a view of a row made for every sample took more than the arithmetic)
    most = 0
    for j in range(nk):
        i0, i1, a = _window(t, lims[j])
        most += ns * (i1 - i0)
        rowcut[j + 1] = rowcut[j] + i1 - a
    tn, dist, dev = np.empty(most), np.empty(most), np.empty(most)
    past, rows = np.ones(most, np.uint8), np.empty((rowcut[nk], 2 + ns))
    r = _fill(t, q, e, f, off, tc, s, p, c, n, lims, end, cuts, rowcut, tn, dist, dev,
              past, rows)
    return (cuts, tn[:r].copy(), dist[:r].copy(), dev[:r].copy(), past[:r].copy(), rowcut,
            rows)


# Compiled without reference counting (``_nrt=False``): the loop allocates nothing, and the
# counts numba kept on the rows of a corner's numbers and of the samples handed to the
# inlined helpers, up and down for every sample, took two thirds of the call.
@njit(cache=True, _nrt=False)
def _fill(t, q, e, f, off, tc, s, p, c, n, lims, end, cuts, rowcut, tn, dist, dev, past,
          rows):
    """The loop of :func:`feed_many` over the corners, into its arrays ``cuts``, ``tn``,
    ``dist``, ``dev``, ``past`` and ``rows`` (``rowcut`` filled in); how many samples near
    the corners it took [-]."""
    ns, nk = q.shape[0], lims.shape[0]
    r = 0
    for j in range(nk):
        i0, i1, a = _window(t, lims[j])
        lo, hi, on = _span(lims[j])
        cj, nj, s_first, at_end = c[j], n[j], lims[j, 6], end[j]
        t0, span = lims[j, 2], lims[j, 4]
        cuts[j, 0] = r
        for k in range(ns):
            for i in range(i0, i1):
                g = f[k, i] - off
                if not _takes(g, s, lo, hi, on, at_end, t[i] >= t0, q, k, i, cj, span):
                    continue
                tn[r], dist[r] = t[i], _dist(q, k, i, cj)
                if at_end:  # travel past the end once the command is there
                    dev[r], past[r] = _dot_diff(q, k, i, cj, nj), t[i] >= t0
                else:
                    dev[r], past[r] = _outside(q, k, i, g, s, p, nj, s_first)
                r += 1
            cuts[j, k + 1] = r
        v = -1  # the vertex of the sample before, where it lies within the command
        for i in range(a, i1):
            o = rowcut[j] + i - a
            y, v = _path_at(t[i], tc, s, v)
            rows[o, 0], rows[o, 1] = t[i], y
            for k in range(ns):
                rows[o, 2 + k] = _dist(q, k, i, cj) if at_end else e[k, i]
    return r
