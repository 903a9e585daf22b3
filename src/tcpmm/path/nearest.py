"""The nearest point of a polyline to each of a run of points, among a window of its
segments.

Each point is measured against the segments ``a..b`` of its window. Segments are grouped
in blocks of :data:`BLOCK`, each inside a capsule about its chord (tight where the path
runs straight, as a CAM program's passes do side by side); a block whose capsule lies
further from the point than the closest segment found so far (with a margin far above the
rounding of either distance) cannot hold the closest segment nor one that ties with it,
and is passed
over, and so are the blocks after it within the path length by which it is too far. Every
:data:`PER` blocks lie in a box whose sides run along and across the chord from its first
vertex to its last (in the first two coordinates: their distance is never more than the
whole one); where the box lies that far, its blocks are passed over at once. A zig-zag's
passes lie side by side within the window, each block's capsule only a few hundredths of a
millimetre further than the closest segment: a box takes four blocks of a pass, or the
U-turn between two, at one test. The
search starts at the previous point's segment, so the closest one found so far is close
from the start. Every segment measured is measured with the same operations in
the same order as :func:`tcpmm.analysis.contour.distance_to_polyline`'s whole window, so
the result is that of the whole window to the bit.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .ties import NEAR_ABS, NEAR_REL, pass_run, tie

#: segments per block [-]
BLOCK = 8
#: blocks per box [-]
PER = 4
#: margin of a block's pass-over, relative to the distances involved: rounding errs by
#: some 1e-15 of them [-]
_MARGIN = 1e-10


@njit(cache=True)
def block_capsules(p, block):
    """A capsule around the segments of each block: the chord from the block's first
    vertex to its last, and the furthest any vertex lies from it.

    The distance to a segment is convex, so along each segment of the block it is
    largest at a vertex: every point of the block lies within that radius of the chord.

    Parameters
    ----------
    p : ndarray, shape (m, d)
        Polyline vertices [m].
    block : int
        Segments per block [-].

    Returns
    -------
    start : ndarray, shape (nb, d)
        First vertex of each block [m].
    chord : ndarray, shape (nb, d)
        Its last vertex less its first [m].
    inv2 : ndarray, shape (nb,)
        The chord's inverse squared length, 0 for a chord of no length [1/m^2].
    slack : ndarray, shape (nb,)
        Radius of each block's capsule with a margin for the rounding of a distance to
        its chord [m].
    length : ndarray, shape (nb,)
        Path length of each block, rounded up [m].
    """
    m, d = p.shape
    nb = (m - 2) // block + 1
    start = np.empty((nb, d))
    chord = np.empty((nb, d))
    inv2, slack, length = np.zeros(nb), np.zeros(nb), np.zeros(nb)
    for b in range(nb):
        v0, v1 = b * block, min(b * block + block, m - 1)
        c2 = reach = 0.0
        for c in range(d):
            start[b, c] = p[v0, c]
            chord[b, c] = p[v1, c] - p[v0, c]
            c2 += chord[b, c] * chord[b, c]
            reach += abs(chord[b, c])
        inv2[b] = 1.0 / c2 if c2 > 0 else 0.0
        radius = 0.0
        for v in range(v0, v1 + 1):
            radius = max(radius, _to_chord(p, v, start, chord, inv2, b))
            if v > v0:
                s = 0.0
                for c in range(d):
                    s += (p[v, c] - p[v - 1, c]) ** 2
                length[b] += math.sqrt(s) * (1 + _MARGIN)
        slack[b] = radius * (1 + 2 * _MARGIN) + _MARGIN * reach
    return start, chord, inv2, slack, length


@njit(cache=True)
def block_boxes(p, block, per):
    """A box about the vertices of each run of ``per`` blocks, its sides along and across
    the chord from the run's first vertex to its last, in the first two coordinates (none
    for a path of one).

    Parameters
    ----------
    p : ndarray, shape (m, d)
        Polyline vertices [m].
    block, per : int
        Segments per block, blocks per box [-].

    Returns
    -------
    org : ndarray, shape (nb, 2)
        First vertex of each box [m].
    unit : ndarray, shape (nb, 2)
        Its chord's direction, ``(1, 0)`` for a chord of no length [-].
    ext : ndarray, shape (nb, 4)
        The vertices' least and largest distance along it and across it from the first [m].
    slack : ndarray, shape (nb,)
        A margin for the roundings of the distances to the box [m].
    """
    m, d = p.shape
    ns = ((m - 2) // block) // per + 1 if d >= 2 else 0
    org, unit, ext, slack = np.empty((ns, 2)), np.empty((ns, 2)), np.empty((ns, 4)), np.empty(ns)
    for sb in range(ns):
        v0 = sb * per * block
        v1 = min(v0 + per * block, m - 1)
        cx, cy = p[v1, 0] - p[v0, 0], p[v1, 1] - p[v0, 1]
        size = math.sqrt(cx * cx + cy * cy)
        ux, uy = (cx / size, cy / size) if size > 0 else (1.0, 0.0)
        a0 = a1 = b0 = b1 = 0.0
        for v in range(v0, v1 + 1):
            rx, ry = p[v, 0] - p[v0, 0], p[v, 1] - p[v0, 1]
            a, b = rx * ux + ry * uy, ry * ux - rx * uy
            a0, a1, b0, b1 = min(a0, a), max(a1, a), min(b0, b), max(b1, b)
        org[sb, 0], org[sb, 1], unit[sb, 0], unit[sb, 1] = p[v0, 0], p[v0, 1], ux, uy
        ext[sb, 0], ext[sb, 1], ext[sb, 2], ext[sb, 3] = a0, a1, b0, b1
        slack[sb] = 4 * _MARGIN * (a1 - a0 + b1 - b0 + abs(p[v0, 0]) + abs(p[v0, 1]))
    return org, unit, ext, slack


@njit(cache=True, inline="always")
def _box_far(q, k, org, unit, ext, bslack, sb, level):
    """How much further than ``level`` every point of box ``sb`` lies from point ``k`` at
    the least; not positive where some may not [m]."""
    rx, ry = q[k, 0] - org[sb, 0], q[k, 1] - org[sb, 1]
    a = rx * unit[sb, 0] + ry * unit[sb, 1]
    b = ry * unit[sb, 0] - rx * unit[sb, 1]
    ga = max(ext[sb, 0] - a, a - ext[sb, 1], 0.0)
    gb = max(ext[sb, 2] - b, b - ext[sb, 3], 0.0)
    return math.sqrt(ga * ga + gb * gb) * (1 - _MARGIN) - bslack[sb] - level


@njit(cache=True, inline="always")
def _to_chord(q, k, start, chord, inv2, bi):
    """Distance from point ``k`` of ``q`` to the chord of block ``bi`` [m]."""
    d = q.shape[1]
    dot = 0.0
    for c in range(d):
        dot += (q[k, c] - start[bi, c]) * chord[bi, c]
    f = min(max(dot * inv2[bi], 0.0), 1.0)
    s = 0.0
    for c in range(d):
        s += (q[k, c] - start[bi, c] - f * chord[bi, c]) ** 2
    return math.sqrt(s)


@njit(cache=True, inline="always")
def _segment(q, k, p, seg, ln2, tdir, j):
    """Squared distance from point ``k`` to segment ``j`` and the travel direction's
    cross product with the offset (0 outside a plane) [m^2], [m]."""
    d = q.shape[1]
    # coordinates summed first to last, as the numpy reference does: the same bits on
    # every CPU, where a library's vectorised sum may pair them otherwise
    dot = 0.0
    for c in range(d):
        dot += (q[k, c] - p[j, c]) * seg[j, c]
    f = dot / ln2[j] if ln2[j] > 0 else 0.0
    f = min(max(f, 0.0), 1.0)
    s2 = 0.0
    o0 = o1 = 0.0
    for c in range(d):
        o = (q[k, c] - p[j, c]) - f * seg[j, c]
        s2 += o * o
        if c == 0:
            o0 = o
        elif c == 1:
            o1 = o
    cross = tdir[j, 0] * o1 - tdir[j, 1] * o0 if d == 2 else 0.0
    return s2, cross


@njit(cache=True, inline="always")
def _far(q, k, start, chord, inv2, slack, bi, level):
    """How much further than ``level`` every point of block ``bi`` lies from point ``k``
    at the least; not positive where some may not [m]."""
    return _to_chord(q, k, start, chord, inv2, bi) * (1 - _MARGIN) - slack[bi] - level


@njit(cache=True, inline="always")  # a call a point counts every array it is given
def _measure(q, k, p, seg, ln2, tdir, sag, start, chord, inv2, slack, length, boxes, a, b,
             seed, block, dd, cross, at):
    """Squared distance and cross product (``dd``, ``cross``) of the segments ``a..b`` not
    passed over, in order, their segments in ``at`` (``boxes``: :func:`block_boxes`, with
    their blocks' and boxes' largest ``sag``); how many, and the smallest distance plus
    sag (a distance: the root of the squared one, the smallest of the roots as the root
    rounds monotonically) [m^2], [m]."""
    best2 = _segment(q, k, p, seg, ln2, tdir, seed)[0]
    best = math.sqrt(best2)
    upper = best + sag[seed]
    count = 0
    org, unit, ext, bslack, bsag, sag_b = boxes
    bi = a // block
    while bi <= b // block:
        level = upper * (1 + NEAR_REL) + NEAR_ABS
        if bslack.size and (bi % PER == 0 or bi == a // block):  # a box's first block
            sb = bi // PER
            if _box_far(q, k, org, unit, ext, bslack, sb, level) > bsag[sb]:
                bi = (sb + 1) * PER
                continue
        gap = _far(q, k, start, chord, inv2, slack, bi, level)
        if gap > sag_b[bi]:  # the blocks that follow within that path length are as far
            bi += 1
            run = 0.0
            while bi <= b // block and run + length[bi] + sag_b[bi] < gap:
                run += length[bi]
                bi += 1
            continue
        bi += 1
        for j in range(max(a, bi * block - block), min(b, bi * block - 1) + 1):
            dd[count], cross[count] = _segment(q, k, p, seg, ln2, tdir, j)
            at[count] = j
            if dd[count] < best2:
                best2 = dd[count]
                best = math.sqrt(best2)
                upper = min(upper, best + sag[j])
            elif upper > best:  # a segment of some sag is the closest so far
                upper = min(upper, math.sqrt(dd[count]) + sag[j])
            count += 1
    return count, upper


@njit(cache=True, nogil=True)
def search_blocks(p, sag):
    """The blocks and boxes :func:`nearest_segments` passes over, of the polyline ``p``
    whose segments have the sags ``sag``: worked out once for every run of points searched
    along it (:func:`nearest_segments_in`).

    Parameters
    ----------
    p : ndarray, shape (m, d)
        Polyline vertices, finite, ``m >= 2`` [m].
    sag : ndarray, shape (m - 1,)
        As for :func:`nearest_segments` [m].

    Returns
    -------
    start, chord, inv2, slack, length : ndarray
        :func:`block_capsules` [m], [m], [1/m^2], [m], [m].
    org, unit, ext, bslack : ndarray
        :func:`block_boxes` [m], [-], [m], [m].
    bsag, sag_b : ndarray
        The largest sag of each box and of each block [m].
    """
    start, chord, inv2, slack, length = block_capsules(p, BLOCK)
    org, unit, ext, bslack = block_boxes(p, BLOCK, PER)
    sag_b = np.zeros(start.shape[0])
    for j in range(sag.size):
        sag_b[j // BLOCK] = max(sag_b[j // BLOCK], sag[j])
    bsag = np.zeros(bslack.size)
    for bi in range(min(sag_b.size, bslack.size * PER)):
        bsag[bi // PER] = max(bsag[bi // PER], sag_b[bi])
    return start, chord, inv2, slack, length, org, unit, ext, bslack, bsag, sag_b


@njit(cache=True, nogil=True)  # the paths of a run are searched in threads of their own
def nearest_segments(q, p, seg, ln2, tdir, sag, seglen, lo, hi, signed, t_q, t_p):
    """Distance from each point to the nearest of the segments of its window.

    Parameters
    ----------
    q : ndarray, shape (n, d)
        Points, finite [m].
    p : ndarray, shape (m, d)
        Polyline vertices, finite, ``m >= 2`` [m].
    seg : ndarray, shape (m - 1, d)
        Segment vectors ``p[j + 1] - p[j]`` [m].
    ln2 : ndarray, shape (m - 1,)
        Their squared lengths [m^2].
    tdir : ndarray, shape (m - 1, d)
        Direction of travel on each segment [-].
    sag : ndarray, shape (m - 1,)
        How far each segment may lie from another sampling of the path it samples, not
        negative (:func:`tcpmm.analysis.contour_windows.chord_sags`) [m].
    seglen : ndarray, shape (m - 1,)
        Their lengths, the roots of ``ln2`` [m].
    lo, hi : ndarray of int, shape (n,)
        The window of each point: segments ``lo`` to ``max(hi, lo + 1) - 1``, each taken
        no further than the last [-].
    signed : int
        Not 0: negative where the point lies right of the travel (``d == 2``); an integer,
        as the compiled module of :mod:`tcpmm._compiled` takes it [-].
    t_q, t_p : ndarray, shape (n,) and (m,)
        Times of the points and of the vertices [s].

    Returns
    -------
    dist : ndarray, shape (n,)
        Distance to a segment of the pass the point is on: of the segments that may be
        the closest once their sag is allowed for (their distance less their sag no
        more than the least distance plus sag, within ``NEAR_REL`` and ``NEAR_ABS``),
        their runs along the path (:func:`tcpmm.path.ties.pass_run`), the one
        nearest in time to the point (the first on equal times); in it, the closest
        segment, and among those within ``NEAR_REL`` and ``NEAR_ABS`` of it the run
        nearest in time and in that the first that sees the point most to its side [m].
    foot : ndarray of int, shape (n,)
        That segment [-].
    """
    b = search_blocks(p, sag)
    return nearest_segments_in(q, p, seg, ln2, tdir, sag, seglen, lo, hi, signed, t_q, t_p,
                               b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7], b[8], b[9],
                               b[10])


@njit(cache=True, nogil=True)
def nearest_segments_in(q, p, seg, ln2, tdir, sag, seglen, lo, hi, signed, t_q, t_p, start,
                        chord, inv2, slack, length, org, unit, ext, bslack, bsag, sag_b):
    """:func:`nearest_segments` with the blocks and boxes of :func:`search_blocks` of ``p``
    and ``sag`` given, as its eleven results in order [m], [-]."""
    n = q.shape[0]
    boxes = (org, unit, ext, bslack, bsag, sag_b)
    dist = np.empty(n)
    foot = np.empty(n, np.int64)
    width = 1
    for k in range(n):
        width = max(width, hi[k] - lo[k] + 1)
    dd, cross, at = np.empty(width), np.empty(width), np.empty(width, np.int64)
    _search(q, p, seg, ln2, tdir, sag, seglen, lo, hi, signed, start, chord, inv2, slack,
            length, boxes, dd, cross, at, dist, foot, t_q, t_p)
    return dist, foot


# Compiled without reference counting (``_nrt=False``): the loop allocates nothing, and the
# counts numba kept on every array handed to the inlined helpers, up and down for each
# point, were a fifth of the search's time.
@njit(cache=True, nogil=True, _nrt=False)
def _search(q, p, seg, ln2, tdir, sag, seglen, lo, hi, signed, start, chord, inv2, slack,
            length, boxes, dd, cross, at, dist, foot, t_q, t_p):
    """The loop of :func:`nearest_segments` over the points, on its work arrays: the
    blocks' capsules ``start``, ``chord``, ``inv2``, ``slack``, ``length`` and a window's
    squared distances, cross products and segments ``dd``, ``cross``, ``at``, the
    ``boxes`` of :func:`block_boxes` with the boxes' and blocks' largest sag; the results
    into ``dist`` and ``foot``."""
    n, last = q.shape[0], p.shape[0] - 2
    block = BLOCK
    prev = 0
    for k in range(n):
        a = min(lo[k], last)
        b = min(max(hi[k], lo[k] + 1) - 1, last)
        count, upper = _measure(q, k, p, seg, ln2, tdir, sag, start, chord, inv2,
                                      slack, length, boxes, a, b, min(max(prev, a), b),
                                      block, dd, cross, at)
        # every segment that may tie is among those measured
        i0, i1, best2 = pass_run(dd, at, sag, seglen, count,
                                  upper * (1 + NEAR_REL) + NEAR_ABS, t_q[k], t_p)
        level = math.sqrt(best2) * (1 + NEAR_REL) + NEAR_ABS
        pick = tie(dd, cross, at, sag, i0, i1, upper * (1 + NEAR_REL) + NEAR_ABS, level,
                    t_q[k], t_p)
        d_pick = math.sqrt(dd[pick])
        dist[k] = -d_pick if signed != 0 and cross[pick] < 0 else d_pick
        foot[k] = prev = at[pick]
