"""Feed profile along the path: acceleration- and jerk-limited speed changes.

A speed change from ``va`` to ``vb`` starts and ends at zero tangential acceleration.
With a jerk limit ``J`` it is the S-curve (jerk +J, constant acceleration, jerk -J);
with ``J = inf`` it is the trapezoid (constant acceleration). Each segment runs
accelerate - cruise - decelerate between the speeds that the look-ahead gives its ends.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True)
def change(va, vb, a, j):
    """Duration, jerk-phase duration and peak acceleration of a speed change.

    Parameters
    ----------
    va, vb : float
        Speed at the start and end [m/s].
    a : float
        Acceleration limit [m/s^2].
    j : float
        Jerk limit, ``inf`` for the trapezoid [m/s^3].

    Returns
    -------
    tuple of float
        Total time [s], time of each jerk phase [s], peak acceleration [m/s^2].
    """
    dv = abs(vb - va)
    if dv == 0.0:
        return 0.0, 0.0, 0.0
    if dv * j >= a * a:
        tj = a / j
        return dv / a + tj, tj, a
    tj = math.sqrt(dv / j)
    return 2.0 * tj, tj, j * tj


@njit(cache=True)
def distance(va, vb, a, j):
    """Path length travelled during the speed change from ``va`` to ``vb`` [m]."""
    return 0.5 * (va + vb) * change(va, vb, a, j)[0]


@njit(cache=True)
def reach(va, length, a, j, cap):
    """Highest speed reachable from ``va`` within ``length``, at most ``cap`` [m/s]."""
    if cap <= va:
        return cap
    if distance(va, cap, a, j) <= length:
        return cap
    if math.isinf(j):
        return min(cap, math.sqrt(va * va + 2.0 * a * length))
    lo, hi = va, cap
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        if distance(va, mid, a, j) <= length:
            lo = mid
        else:
            hi = mid
    return lo


@njit(cache=True)
def peak(v0, v1, vmax, length, a, j):
    """Highest speed inside a segment that still allows ``v0`` -> peak -> ``v1`` [m/s]."""
    lo = max(v0, v1)
    if vmax <= lo:
        return lo
    if distance(v0, vmax, a, j) + distance(vmax, v1, a, j) <= length:
        return vmax
    if math.isinf(j):
        vp = math.sqrt(max(0.0, a * length + 0.5 * (v0 * v0 + v1 * v1)))
        return min(max(vp, lo), vmax)
    hi = vmax
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        if distance(v0, mid, a, j) + distance(mid, v1, a, j) <= length:
            lo = mid
        else:
            hi = mid
    return lo


@njit(cache=True)
def segment_profiles(length, v, vmax, acc, j):
    """Accelerate-cruise-decelerate profile of every segment.

    Parameters
    ----------
    length : ndarray
        Segment lengths [m].
    v : ndarray
        Speed at the junctions, ``len(length) + 1`` entries [m/s].
    vmax : ndarray
        Speed limit of each segment [m/s].
    acc : ndarray
        Tangential acceleration limit of each segment [m/s^2].
    j : float
        Path jerk limit, ``inf`` for trapezoid [m/s^3].

    Returns
    -------
    ndarray, shape (n, 8)
        Per segment: peak speed [m/s], acceleration time [s], its jerk time [s], its
        peak acceleration [m/s^2], cruise time [s], deceleration time [s], its jerk
        time [s], its peak deceleration [m/s^2].
    """
    n = length.size
    out = np.zeros((n, 8))
    for i in range(n):
        if length[i] <= 0.0:
            continue
        v0, v1, a = v[i], v[i + 1], acc[i]
        vp = peak(v0, v1, vmax[i], length[i], a, j)
        ta, tja, apa = change(v0, vp, a, j)
        td, tjd, apd = change(vp, v1, a, j)
        rest = length[i] - 0.5 * (v0 + vp) * ta - 0.5 * (vp + v1) * td
        tc = max(rest, 0.0) / vp if vp > 0.0 else 0.0
        out[i, 0] = vp
        out[i, 1] = ta
        out[i, 2] = tja
        out[i, 3] = apa
        out[i, 4] = tc
        out[i, 5] = td
        out[i, 6] = tjd
        out[i, 7] = apd
    return out


@njit(cache=True)
def change_position(t, va, vb, T, tj, ap):
    """Distance covered after time ``t`` into a speed change (see :func:`change`) [m]."""
    if t <= 0.0:
        return 0.0
    d = 0.5 * (va + vb) * T
    if t >= T:
        return d
    sg = 1.0 if vb >= va else -1.0
    if tj > 0.0 and t < tj:
        return va * t + sg * ap * t * t * t / (6.0 * tj)
    if tj > 0.0 and t > T - tj:
        u = T - t
        return d - vb * u + sg * ap * u * u * u / (6.0 * tj)
    s1 = va * tj + sg * ap * tj * tj / 6.0
    v1 = va + sg * ap * tj / 2.0
    w = t - tj
    return s1 + v1 * w + sg * ap * w * w / 2.0


@njit(cache=True)
def segment_position(t, v0, v1, length, prof):
    """Distance along a segment ``t`` seconds after its start, clamped to its length [m]."""
    vp, ta, tja, apa, tc, td, tjd, apd = prof
    if t >= ta + tc + td:
        return length
    if t <= ta:
        s = change_position(t, v0, vp, ta, tja, apa)
    else:
        da = 0.5 * (v0 + vp) * ta
        if t <= ta + tc:
            s = da + vp * (t - ta)
        else:
            s = da + vp * tc + change_position(t - ta - tc, vp, v1, td, tjd, apd)
    return min(max(s, 0.0), length)
