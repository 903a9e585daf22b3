"""Compiled corner geometry of corner blending (:mod:`tcpmm.path.blendrows`): arrays in,
arrays out, a corner at a time.

Each value is the C library's ``acos``, ``sin``, ``tan`` and ``cos`` of one number, as
Python's :mod:`math` gives it, with the products and quotients in the order written,
sums over the coordinates first to last (as :mod:`tcpmm._rows`) and no fused
multiply-add: the bits are those of the same formulas in Python, on any CPU. A spiral of
short blocks under ``G64`` turns at every block end, and these formulas over lists of
Python floats and columns of arrays took about a second and a half a million corners.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True)
def corner_turns(a0, a1, b0, b1, tols, bend_tol):
    """Which corners of the line ``a0 -> a1`` into ``b0 -> b1`` (rows) turn, and for those
    the half-angle of the turn and the tangent length the tolerance allows.

    A corner turns where the cross product of the unit tangents is at least 1e-12 long
    and their difference at least ``bend_tol``.

    Parameters
    ----------
    a0, a1, b0, b1 : numpy.ndarray
        Start and end of the lines before and after each corner, ``(n, 3)`` [m].
    tols : numpy.ndarray
        Each corner's contour tolerance [m].
    bend_tol : float
        A change of the unit tangent below this is no turn [-].

    Returns
    -------
    tuple of numpy.ndarray
        1 where a corner turns, else 0 [-]; where it turns its half-angle ``h`` [rad] and
        the tangent length ``tol sin(h) / (2 sin(h / 2)^2)`` at which its blend passes
        the corner at its tolerance [m], else 0.
    """
    n = a0.shape[0]
    turns = np.zeros(n, np.uint8)
    h = np.zeros(n)
    d = np.zeros(n)
    u = np.empty(3)
    w = np.empty(3)
    for i in range(n):
        _unit(a1[i], a0[i], u)
        _unit(b1[i], b0[i], w)
        c0 = u[1] * w[2] - u[2] * w[1]
        c1 = u[2] * w[0] - u[0] * w[2]
        c2 = u[0] * w[1] - u[1] * w[0]
        e0, e1, e2 = w[0] - u[0], w[1] - u[1], w[2] - u[2]
        if not (math.sqrt(c0 * c0 + c1 * c1 + c2 * c2) >= 1e-12
                and math.sqrt(e0 * e0 + e1 * e1 + e2 * e2) >= bend_tol):
            continue
        c = min(max(u[0] * w[0] + u[1] * w[1] + u[2] * w[2], -1.0), 1.0)
        turns[i] = 1
        h[i], d[i] = _halves(c, tols[i])
    return turns, h, d


@njit(cache=True, inline="always")
def _unit(end, start, out):
    """``end - start`` over its length, into ``out``; NaN for a point [-]."""
    v0, v1, v2 = end[0] - start[0], end[1] - start[1], end[2] - start[2]
    n = math.sqrt(v0 * v0 + v1 * v1 + v2 * v2)
    if n == 0.0:
        out[0] = out[1] = out[2] = math.nan
        return
    out[0], out[1], out[2] = v0 / n, v1 / n, v2 / n


@njit(cache=True, inline="always")
def _halves(c, tol):
    """Half-angle of a turn of cosine ``c`` and the tangent length ``tol`` allows
    (:func:`corner_turns`) [rad], [m]."""
    hi = 0.5 * math.acos(c)
    s = math.sin(0.5 * hi)
    return hi, tol * math.sin(hi) / (2.0 * (s * s))


@njit(cache=True)
def blend_reach(h, dk):
    """Distance ``dk / tan(h) / cos(h)`` from each corner to the centre of its blend, of
    half-angle ``h`` and tangent length ``dk``.

    Parameters
    ----------
    h : numpy.ndarray
        Half of each corner's turn [rad].
    dk : numpy.ndarray
        Tangent length of each blend [m].

    Returns
    -------
    numpy.ndarray
        The distance along the bisector [m].
    """
    out = np.empty(h.size)
    for i in range(h.size):
        out[i] = dk[i] / math.tan(h[i]) / math.cos(h[i])
    return out
