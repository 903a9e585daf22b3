"""How far the command strays from a corner's chords (:func:`.cornerfigs.corner_frame`'s
straight lines from the corner to the path a span before and after it): a feature shorter
than the span (a notch, a zig-zag's step-over, a small loop) within them makes the
corner's turn and overshoot the feature's (:mod:`tcpmm.analysis.contour_corners`)."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .cornerfigs import interp_at, pymax, unit


# The helpers are inlined and work a coordinate at a time into arrays made once a call
# (the operations of ``dot`` and ``unit``, in their order): a vertex's vector and its
# offset made as arrays, and a call handed its arrays, had their reference counts taken up
# and down for every vertex: most of the time this took on a zig-zag's corners.
@njit(cache=True, inline="always")
def _off_line(p, i, u, k0, k1, step):
    """The largest distance from the line through ``p[i]`` along the unit ``u`` of the
    vertices ``k0, k0 + step, ...`` short of ``k1`` (each ``v - (v . u) u``) [m]."""
    d = p.shape[1]
    worst = 0.0
    k = k0
    while k != k1:
        vu = (p[k, 0] - p[i, 0]) * u[0]
        for c in range(1, d):
            vu = vu + (p[k, c] - p[i, c]) * u[c]
        w = (p[k, 0] - p[i, 0]) - vu * u[0]
        ww = w * w
        for c in range(1, d):
            w = (p[k, c] - p[i, c]) - vu * u[c]
            ww = ww + w * w
        worst = pymax(worst, math.sqrt(ww))
        k += step
    return worst


@njit(cache=True, inline="always")
def _unit_into(u, p, k, i):
    """``unit(p[k] - p[i])`` into ``u`` [-]."""
    d = p.shape[1]
    for c in range(d):
        u[c] = p[k, c] - p[i, c]
    x = u[0] * u[0]
    for c in range(1, d):
        x = x + u[c] * u[c]
    ln = math.sqrt(x)
    den = ln if ln != 0.0 else 1.0
    for c in range(d):
        u[c] = u[c] / den


@njit(cache=True, inline="always")
def _straight_side(p, s, i, k1, step, frac, u):
    """The longest path length from ``p[i]`` to a vertex ``k`` of ``i + step, ...`` short
    of ``k1`` over which the vertices between lie within ``frac`` of it of the chord from
    ``p[i]`` to ``p[k]`` (``inf`` where the last does): where the path runs straight from
    the corner on that side, a corner found a sample past a bend included (``u``: room
    for a direction) [m]."""
    best = 0.0
    k = i + step
    while k != k1:
        ln = abs(s[k] - s[i])
        if ln > 0.0:
            _unit_into(u, p, k, i)
            if _off_line(p, i, u, i + step, k, step) <= frac * ln:
                best = ln if k + step != k1 else math.inf
        k += step
    return best if k1 != i + step else math.inf


@njit(cache=True)
def chord_strays(p, s, idx, span, frac):
    """Per corner ``p[idx[j]]``: how far the command strays from the chords of
    :func:`corner_frame` (the straight lines from the corner to the path ``span`` before
    and after it), the largest distance of a vertex within the span from its side's
    chord; and, where that is over ``frac`` of the span, the path length from the corner
    over which the command runs straight on its shorter side (within ``frac`` of that
    length of the chord over it; ``inf`` where it does over the whole span), else NaN
    [m], a row each."""
    d = p.shape[1]
    out = np.empty((idx.size, 2))
    u = np.empty(d)
    for j in range(idx.size):
        i = idx[j]
        x0, x1 = s[i] - span, s[i] + span
        a = max(np.searchsorted(s, x0, side="left") - 1, 0)
        b = min(np.searchsorted(s, x1, side="right") + 1, s.size)
        back, ahead = np.empty(d), np.empty(d)
        for k in range(d):
            back[k] = interp_at(x0, s, p[:, k], a, b)
            ahead[k] = interp_at(x1, s, p[:, k], a, b)
        # the vertices strictly within the span on either side
        k0 = np.searchsorted(s, x0, side="right")
        k1 = np.searchsorted(s, x1, side="left")
        stray = pymax(_off_line(p, i, unit(p[i] - back), i - 1, k0 - 1, -1),
                       _off_line(p, i, unit(ahead - p[i]), i + 1, k1, 1))
        out[j, 0] = stray
        out[j, 1] = math.nan
        if stray > frac * span:
            out[j, 1] = min(_straight_side(p, s, i, k0 - 1, -1, frac, u),
                            _straight_side(p, s, i, k1, 1, frac, u))
    return out
