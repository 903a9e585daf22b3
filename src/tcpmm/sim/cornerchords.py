"""How far the command strays from a corner's chords (:func:`.cornerfigs.corner_frame`'s
straight lines from the corner to the path a span before and after it): a feature shorter
than the span (a notch, a zig-zag's step-over, a small loop) within them makes the
corner's turn and overshoot the feature's (:mod:`tcpmm.analysis.contour_corners`)."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .cornerfigs import dot, interp_at, pymax, unit


@njit(cache=True)
def _off_line(p, i, u, k0, k1, step):
    """The largest distance from the line through ``p[i]`` along the unit ``u`` of the
    vertices ``k0, k0 + step, ...`` short of ``k1`` (each ``v - (v . u) u``) [m]."""
    worst = 0.0
    k = k0
    while k != k1:
        v = p[k] - p[i]
        w = v - dot(v, u) * u
        worst = pymax(worst, math.sqrt(dot(w, w)))
        k += step
    return worst


@njit(cache=True)
def _straight_side(p, s, i, k1, step, frac):
    """The longest path length from ``p[i]`` to a vertex ``k`` of ``i + step, ...`` short
    of ``k1`` over which the vertices between lie within ``frac`` of it of the chord from
    ``p[i]`` to ``p[k]`` (``inf`` where the last does): where the path runs straight from
    the corner on that side, a corner found a sample past a bend included [m]."""
    best = 0.0
    k = i + step
    while k != k1:
        ln = abs(s[k] - s[i])
        if ln > 0.0:
            u = unit(p[k] - p[i])
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
            out[j, 1] = min(_straight_side(p, s, i, k0 - 1, -1, frac),
                            _straight_side(p, s, i, k1, 1, frac))
    return out
