"""A run of plain arcs (:data:`tcpmm.path.gcode_scan.ARC` lines) executed in two compiled
passes, with the interpreter's arithmetic in its order
(:func:`tcpmm.path.gcode_arcs.arc_run` calls them).

The interpreter measures a chord and an arc's two radii with Python's ``math.hypot``,
whose algorithm is CPython's own and not the C library's: the passes leave those
lengths to the caller. :func:`arc_ends` finds each block's end point, its motion mode
and feed, the centre of an arc given by I, J and K, and the legs whose lengths are
needed; :func:`arc_centres` takes those lengths, finds the centre of an arc given by R
and stops where the interpreter would refuse an arc. Both are called through
:mod:`tcpmm._compiled`, so that a command parses without numba.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .gcode_scan import block_end, block_feed

#: the state :func:`arc_ends` starts from and its layout: position, motion code (-1
#: none), feed (NaN none), unit, absolute (1 or 0), centre words absolute (G90.1: 1 or
#: 0), the plane's two axes (0 X, 1 Y, 2 Z), the words not allowed (bits as the scan's),
#: the largest feed and coordinate [SI]
STATE_FIELDS = ("x", "y", "z", "motion", "feed", "unit", "absolute", "arc_absolute", "ia",
                "ib", "other", "max_feed", "max_coordinate")
#: columns of the scan's values: the centre words I, J, K and R [-]
_I, _R = 4, 7


@njit(cache=True)
def _in_range(w, v, unit, max_c):
    """The centre words and radius within the largest coordinate [-]."""
    for j in range(_I, _R + 1):
        if w & (1 << j) and not abs(v[j] * unit) <= max_c:
            return False
    return True


@njit(cache=True)
def _centre_words(w, v, s, ia, ib, unit, arc_absolute, out):
    """The centre of an arc given by its centre words into ``out``, False where the
    interpreter refuses them [-]."""
    has_a, has_b = w & (1 << (_I + ia)), w & (1 << (_I + ib))
    if arc_absolute:
        if not (has_a and has_b):
            return False
        out[ia], out[ib] = v[_I + ia] * unit, v[_I + ib] * unit
    else:
        out[ia] = s[ia] + (v[_I + ia] * unit if has_a else 0.0)
        out[ib] = s[ib] + (v[_I + ib] * unit if has_b else 0.0)
    return True


@njit(cache=True)
def arc_ends(codes, vals, state):
    """The blocks of a run of plain arcs up to the first the interpreter refuses before
    it measures a length.

    Parameters
    ----------
    codes, vals : ndarray
        :func:`tcpmm.path.gcode_scan.scan_lines`' rows of the run [-].
    state : ndarray
        The modal state before it, laid out as :data:`STATE_FIELDS` [SI].

    Returns
    -------
    n : int
        Blocks that pass [-].
    ends, centres : ndarray, shape (n, 3)
        End point of each, and the centre of an arc given by its centre words (the
        height axis's coordinate its start's) [m].
    motions : ndarray of int64
        Motion code of each (2 clockwise, 3 counter-clockwise) [-].
    feeds : ndarray
        Feed of each [m/s].
    legs : ndarray, shape (n, 4)
        The legs to measure: the chord (an arc given by R; then zeros), or the radii to
        its start and to its end [m].
    """
    n = codes.shape[0]
    ends, centres, legs = np.empty((n, 3)), np.empty((n, 3)), np.zeros((n, 4))
    motions, feeds = np.empty(n, dtype=np.int64), np.empty(n)
    pos = state[0:3].copy()
    motion, feed, unit, absolute = int(state[3]), state[4], state[5], state[6] != 0.0
    arc_absolute, ia, ib, other = state[7] != 0.0, int(state[8]), int(state[9]), int(state[10])
    max_feed, max_c, ih = state[11], state[12], 3 - int(state[8]) - int(state[9])
    i = 0
    while i < n:
        w, v = codes[i, 2], vals[i]
        fe = block_feed(w, v, feed, unit, max_feed)
        mo = motion if codes[i, 1] < 0 else codes[i, 1]
        if fe < 0.0 or mo < 2 or np.isnan(fe) or w & other:
            break
        ok, x, y, z = block_end(w, v, pos[0], pos[1], pos[2], unit, absolute, max_c)
        if not (ok and _in_range(w, v, unit, max_c)):
            break
        ends[i, 0], ends[i, 1], ends[i, 2] = x, y, z
        has_c = (w & (1 << (_I + ia))) != 0 or (w & (1 << (_I + ib))) != 0
        if has_c == ((w & (1 << _R)) != 0):  # both, or neither
            break
        e = ends[i]
        if has_c:
            if not _centre_words(w, v, pos, ia, ib, unit, arc_absolute, centres[i]):
                break
            legs[i, 0], legs[i, 1] = pos[ia] - centres[i, ia], pos[ib] - centres[i, ib]
            legs[i, 2], legs[i, 3] = e[ia] - centres[i, ia], e[ib] - centres[i, ib]
        else:
            legs[i, 0], legs[i, 1] = e[ia] - pos[ia], e[ib] - pos[ib]
        centres[i, ih] = pos[ih]
        motions[i], feeds[i] = mo, fe
        pos[0], pos[1], pos[2], motion, feed = e[0], e[1], e[2], mo, fe
        i += 1
    return i, ends[:i], centres[:i], motions[:i], feeds[:i], legs[:i]


@njit(cache=True)
def arc_centres(codes, vals, state, ends, centres, motions, lengths, tols):
    """The centres of the arcs given by R, and where the interpreter refuses an arc for
    its lengths.

    Parameters
    ----------
    codes, vals, state : ndarray
        As :func:`arc_ends` took them [-].
    ends, centres, motions : ndarray
        :func:`arc_ends`' results; ``centres`` is completed [m].
    lengths : ndarray, shape (n, 2)
        ``math.hypot`` of the legs: the chord, or the radii to the start and the end [m].
    tols : ndarray
        The shortest chord, the absolute and the relative tolerance of a radius [m, m, -].

    Returns
    -------
    int
        Blocks that pass [-].
    """
    n = ends.shape[0]
    unit, ia, ib = state[5], int(state[8]), int(state[9])
    full, abs_tol, rel_tol = tols[0], tols[1], tols[2]
    for i in range(n):
        s = state[0:3] if i == 0 else ends[i - 1]
        e, w = ends[i], codes[i, 2]
        if w & (1 << _R):
            da, db = e[ia] - s[ia], e[ib] - s[ib]
            chord = lengths[i, 0]
            r = vals[i, _R] * unit
            if chord < full or r == 0.0:
                return i
            half = 0.5 * chord
            h2 = r * r - half * half
            if h2 < 0.0:
                if half - abs(r) > max(abs_tol, rel_tol * abs(r)):
                    return i
                h2 = 0.0
            h = math.sqrt(h2)
            side = (1.0 if motions[i] == 3 else -1.0) * (1.0 if r > 0 else -1.0)
            centres[i, ia] = s[ia] + 0.5 * da - side * h * db / chord
            centres[i, ib] = s[ib] + 0.5 * db + side * h * da / chord
        else:
            r0, r1 = lengths[i, 0], lengths[i, 1]
            if r0 <= abs_tol or r1 <= abs_tol or abs(r1 - r0) > max(abs_tol, rel_tol * r0):
                return i
    return n
