"""Compiled response ``c (z_k I - H)^-1 b`` of an upper Hessenberg ``H`` at many shifts.

Arrays in, arrays out: the frequency response of a sampled loop
(:func:`tcpmm.servo.freqresp.loop_response`) at every shift ``z_k`` on the unit circle.
Gaussian elimination with partial pivoting along the one sub-diagonal, ``O(n^2)`` per shift,
in real arithmetic on the real and imaginary parts (no fused multiply-add), and the product
with ``c`` summed in the states' order: a shift gives the same bits alone or among others,
on any CPU.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True, inline="always")
def _quotient(ar, ai, br, bi):
    """``(ar + j ai) / (br + j bi)`` by Smith's scaling; over zero an infinity or NaN per
    part, as numpy gives it, and no exception [-]."""
    if br == 0.0 and bi == 0.0:
        return _over_zero(ar), _over_zero(ai)
    if abs(br) >= abs(bi):
        rat = bi / br
        scl = 1.0 / (br + bi * rat)
        return (ar + ai * rat) * scl, (ai - ar * rat) * scl
    rat = br / bi
    scl = 1.0 / (bi + br * rat)
    return (ar * rat + ai) * scl, (ai * rat - ar) * scl


@njit(cache=True, inline="always")
def _over_zero(v):
    """``v / 0`` as IEEE arithmetic gives it: an infinity of ``v``'s sign, NaN for 0 or
    NaN [-]."""
    if v == 0.0 or v != v:
        return math.nan
    return math.copysign(math.inf, v)


@njit(cache=True)
def hessenberg_response(H, z_re, z_im, b, c):
    """``c (z_k I - H)^-1 b`` for each shift ``z_k``.

    Parameters
    ----------
    H : numpy.ndarray
        Upper Hessenberg matrix, ``(n, n)`` [-].
    z_re, z_im : numpy.ndarray
        Real and imaginary parts of the shifts, ``(m,)`` each [-].
    b, c : numpy.ndarray
        Input and output vectors, ``(n,)`` each [-].

    Returns
    -------
    tuple of numpy.ndarray
        Real and imaginary parts of the response, ``(m,)`` each; a shift on an eigenvalue
        gives infinities or NaN [-].
    """
    n = H.shape[0]
    m = z_re.shape[0]
    y_re = np.empty(m)
    y_im = np.empty(m)
    ar = np.empty((n, n))
    ai = np.empty((n, n))
    xr = np.empty(n)
    xi = np.empty(n)
    for j in range(m):
        for r in range(n):
            # from the sub-diagonal on: the elimination reads nothing below it
            for col in range(max(r - 1, 0), n):
                ar[r, col] = -H[r, col]
                ai[r, col] = 0.0
            ar[r, r] = z_re[j] - H[r, r]
            ai[r, r] = z_im[j]
            xr[r] = b[r]
            xi[r] = 0.0
        _eliminate(ar, ai, xr, xi)
        _substitute(ar, ai, xr, xi)
        sr = 0.0
        si = 0.0
        for r in range(n):
            sr += c[r] * xr[r]
            si += c[r] * xi[r]
        y_re[j] = sr
        y_im[j] = si
    return y_re, y_im


@njit(cache=True, inline="always")
def _eliminate(ar, ai, xr, xi):
    """Reduce ``A x = b`` to upper triangular form in place, a row pivot at each step [-]."""
    n = ar.shape[0]
    for k in range(n - 1):
        # the pivot by |re| + |im|, as LAPACK's complex elimination takes it: no square
        # root, and the same choice wherever the two moduli differ by more than 41 %
        if abs(ar[k + 1, k]) + abs(ai[k + 1, k]) > abs(ar[k, k]) + abs(ai[k, k]):
            for c in range(k, n):
                ar[k, c], ar[k + 1, c] = ar[k + 1, c], ar[k, c]
                ai[k, c], ai[k + 1, c] = ai[k + 1, c], ai[k, c]
            xr[k], xr[k + 1] = xr[k + 1], xr[k]
            xi[k], xi[k + 1] = xi[k + 1], xi[k]
        mr, mi = _quotient(ar[k + 1, k], ai[k + 1, k], ar[k, k], ai[k, k])
        for c in range(k + 1, n):
            ar[k + 1, c] -= mr * ar[k, c] - mi * ai[k, c]
            ai[k + 1, c] -= mr * ai[k, c] + mi * ar[k, c]
        xr[k + 1] -= mr * xr[k] - mi * xi[k]
        xi[k + 1] -= mr * xi[k] + mi * xr[k]


@njit(cache=True, inline="always")
def _substitute(ar, ai, xr, xi):
    """Back substitution of the triangular system in place [-]."""
    n = ar.shape[0]
    for k in range(n - 1, -1, -1):
        xr[k], xi[k] = _quotient(xr[k], xi[k], ar[k, k], ai[k, k])
        for r in range(k):
            xr[r] -= ar[r, k] * xr[k] - ai[r, k] * xi[k]
            xi[r] -= ar[r, k] * xi[k] + ai[r, k] * xr[k]
