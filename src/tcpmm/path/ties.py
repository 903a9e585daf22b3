"""The tie rule of :func:`tcpmm.path.nearest.nearest_segments`: which of the segments
near a point is the one the point is measured against, where a path comes back near
itself.

The command is a polyline of samples. Along a curve, two passes over the same place (a way
out and a way back, a second lap) are sampled at other points, and each one's chords lie
off the curve by up to their sag (:func:`tcpmm.analysis.contour_windows.chord_sags`). A
segment may be the closest once the sags are allowed for where its distance less its sag
is no more than the least distance plus sag; such segments form runs along the path, and
the point belongs to the run nearest to it in time: the pass being run. In that run the
closest segment, and where several tie with it within :data:`NEAR_REL` and
:data:`NEAR_ABS`, the first of their consecutive runs nearest in time, and in it the
segment that sees the point most to its side.
"""

from __future__ import annotations

import math

from numba import njit

#: a segment within this relative distance of the closest, plus :data:`NEAR_ABS`, ties
#: with it [-]
NEAR_REL = 1e-9
#: see :data:`NEAR_REL`: a run file keeps ten significant digits of a millimetre, which
#: puts the samples of a straight line up to some 1e-13 m off it at 10 mm and 1e-10 m at
#: 1 m, so that a pass back along it would lie nearer or further by that; a hundredth of
#: the 0.1 um a sensor resolves [m]
NEAR_ABS = 1e-9


@njit(cache=True, inline="always")
def pass_run(dd, at, sag, seglen, count, level, t, t_p):
    """Of the ``count`` segments measured, those whose distance less their sag is within
    ``level``: of their runs along the path (consecutive segments, or apart by no more
    path, of lengths ``seglen``, than two such distances: a corner's segment of some sag
    beyond a straight one between), the one nearest in time ``t`` to the point, the first
    on equal times (a closed path's end ties with its start, a second lap with the first,
    a way back with the way out: the sample belongs to the pass being run); its first and
    last (in ``dd``) and its least squared distance [-], [-], [m^2]."""
    i0 = i1 = -1
    gap, least = math.inf, math.inf
    c0, c1, c_gap, c_least, last = -1, -1, math.inf, math.inf, -2
    for i in range(count):
        j = at[i]
        if within(dd[i], sag[j], level):
            g = max(t_p[j] - t, t - t_p[j + 1], 0.0)
            if c0 < 0 or not along(seglen, last, j, 2.0 * level + sag[last] + sag[j]):
                if c0 >= 0 and c_gap < gap:
                    i0, i1, gap, least = c0, c1, c_gap, c_least
                c0, c_gap, c_least = i, g, dd[i]
            else:
                c_gap, c_least = min(c_gap, g), min(c_least, dd[i])
            c1, last = i, j
    if c_gap < gap:
        i0, i1, least = c0, c1, c_least
    return i0, i1, least


@njit(cache=True, inline="always")
def along(seglen, last, j, most):
    """Whether segment ``j`` follows segment ``last`` on the path within ``most`` of path
    length: the segments between, summed in order, no longer [-]."""
    run = 0.0
    for k in range(last + 1, j):
        run += seglen[k]
        if run > most:
            return False
    return True


@njit(cache=True, inline="always")
def tie(dd, cross, at, sag, i0, i1, pass_level, level, t, t_p):
    """Of the segments ``i0..i1`` measured that are of the pass (:func:`pass_run`'s
    ``pass_level``), those within ``level`` of the point: of their runs of consecutive
    segments (a corner's two legs, and the rests between them), the one nearest in time
    ``t`` to the point, the first on equal times; in it the first that sees the point
    most to its side [-]."""
    pick, gap = -1, math.inf
    cur, cur_gap, last = -1, math.inf, -2
    for i in range(i0, i1 + 1):
        if within(dd[i], 0.0, level) and within(dd[i], sag[at[i]], pass_level):
            j = at[i]
            g = max(t_p[j] - t, t - t_p[j + 1], 0.0)
            if j != last + 1:
                if cur >= 0 and cur_gap < gap:
                    pick, gap = cur, cur_gap
                cur, cur_gap = i, g
            else:
                cur_gap = min(cur_gap, g)
                if abs(cross[i]) > abs(cross[cur]):
                    cur = i
            last = j
    if cur_gap < gap:
        pick = cur
    return pick


@njit(cache=True, inline="always")
def within(d2, sag, level):
    """Whether a squared distance ``d2``, less ``sag``, is within ``level``: the root taken
    only where the square may give one (widened far beyond the roundings) [-]."""
    reach = level + sag
    return d2 <= reach * reach * (1 + NEAR_REL) and math.sqrt(d2) - sag <= level
