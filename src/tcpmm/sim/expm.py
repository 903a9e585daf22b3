"""The matrix exponential of the exact discretisation, compiled (numba): scaling and
squaring of Padé approximants after balancing. Arrays in, arrays out.

A. H. Al-Mohy and N. J. Higham, "A new scaling and squaring algorithm for the matrix
exponential", SIAM J. Matrix Anal. Appl. 31(3), 2009, Algorithm 5.1 without its
triangular refinements, as ``scipy.linalg.expm`` does it: the degree ``m`` of the [m/m]
Padé approximant, 3 to 13, and the number ``s`` of halvings follow the norms of the
matrix's powers ``||A^k||^(1/k)`` rather than its norm, which overstates them for the
plants' far-from-normal matrices, and ``ell`` extra halvings keep the backward error at
the unit roundoff; the result is squared ``s`` times. The matrix is first balanced by
exact powers of two, as LAPACK's ``dgebal`` does it (scaling, no permutation): the
plants' entries span twenty orders of magnitude, and unbalanced their small entries lose
up to seven digits.

Written out in loops (products, and the Padé quotient by Gaussian elimination with
partial pivoting) so that it needs no LAPACK: it is built into the compiled module with
the axis kernel (:mod:`tcpmm._compiled`), and a command that simulates needs neither
numba nor scipy at start-up. ``tcpmm._compiled.expm`` is the entry point; it checks
the argument. Agrees with ``scipy.linalg.expm`` to 1e-12 in every entry of the plants'
matrices (``tests/test_matexp.py``).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

#: Padé coefficients ``b_0 .. b_m``, one row per degree of :data:`DEGREES`, zero-padded
#: (Higham 2005, eq. 2.3) [-].
DEGREES = (3, 5, 7, 9, 13)
PADE = np.zeros((5, 14))
PADE[0, :4] = (120.0, 60.0, 12.0, 1.0)
PADE[1, :6] = (30240.0, 15120.0, 3360.0, 420.0, 30.0, 1.0)
PADE[2, :8] = (17297280.0, 8648640.0, 1995840.0, 277200.0, 25200.0, 1512.0, 56.0, 1.0)
PADE[3, :10] = (17643225600.0, 8821612800.0, 2075673600.0, 302702400.0, 30270240.0,
                2162160.0, 110880.0, 3960.0, 90.0, 1.0)
PADE[4, :] = (64764752532480000.0, 32382376266240000.0, 7771770303897600.0,
              1187353796428800.0, 129060195264000.0, 10559470521600.0, 670442572800.0,
              33522128640.0, 1323241920.0, 40840800.0, 960960.0, 16380.0, 182.0, 1.0)
#: Bounds ``theta_m`` on ``||A^k||^(1/k)`` for which degree ``m`` is accurate to the unit
#: roundoff (Al-Mohy and Higham 2009, Table 3.1; 4.25 for 13 as scipy takes it) [-].
THETA = np.array([1.495585217958292e-2, 2.539398330063230e-1, 9.504178996162932e-1,
                  2.097847961257068e0, 4.25])
#: ``|c_(2m+1)|^-1``, the reciprocal of the Padé error's leading coefficient (eq. 1.2) [-].
C_RECIP = np.array([float(math.comb(2 * m, m) * math.factorial(2 * m + 1)) for m in DEGREES])
UNIT_ROUNDOFF = 2.0**-53
#: Sweeps of the balancing at most: the plants need six; each sweep that changes a scale
#: lowers a sum of norms by 5 %, so a bound only cuts short a matrix whose entries span
#: far more than a double's range, which stays a valid similarity, just less balanced [-].
MAX_BALANCE_SWEEPS = 100


@njit(cache=True)
def expm(A):
    """``exp(A)`` of a square, finite, C-contiguous float64 matrix (not checked here) [-]."""
    n = A.shape[0]
    d = _balance(A)
    B = np.empty((n, n))
    for i in range(n):
        for j in range(n):
            B[i, j] = A[i, j] / d[i] * d[j]
    E = _expm_balanced(B)
    for i in range(n):
        for j in range(n):
            E[i, j] = E[i, j] * d[i] / d[j]
    return E


@njit(cache=True)
def _balance(A):
    """Powers of two ``d`` with ``D^-1 A D`` balanced, LAPACK ``dgebal``'s scaling: per
    state in turn, the power of two that brings its column's and row's 2-norms within a
    factor 2, applied where it lowers their sum by 5 %; until none does, or for
    :data:`MAX_BALANCE_SWEEPS` sweeps. A state whose norm overflows (entries beyond
    1e154) keeps its scale: halving an infinite norm would never end."""
    n = A.shape[0]
    B = A.copy()
    d = np.ones(n)
    for _ in range(MAX_BALANCE_SWEEPS):
        changed = False
        for i in range(n):
            c, r = 0.0, 0.0
            for k in range(n):
                c += B[k, i] * B[k, i]
                r += B[i, k] * B[i, k]
            c, r = math.sqrt(c), math.sqrt(r)
            if c == 0.0 or r == 0.0 or not (math.isfinite(c) and math.isfinite(r)):
                continue
            f, s = 1.0, c + r
            while c < r / 2.0:
                f, c, r = f * 2.0, c * 2.0, r / 2.0
            while c / 2.0 >= r:
                f, c, r = f / 2.0, c / 2.0, r * 2.0
            if c + r >= 0.95 * s:
                continue
            d[i] *= f
            for k in range(n):
                B[i, k] /= f
                B[k, i] *= f
            changed = True
        if not changed:
            break
    return d


@njit(cache=True)
def _mm(X, Y):
    """``X @ Y`` [-]."""
    n = X.shape[0]
    C = np.zeros((n, n))
    for i in range(n):
        for k in range(n):
            x = X[i, k]
            if x != 0.0:
                for j in range(n):
                    C[i, j] += x * Y[k, j]
    return C


@njit(cache=True)
def _norm1(X):
    """Largest column sum of ``|X|`` [-]."""
    n = X.shape[0]
    best = 0.0
    for j in range(n):
        s = 0.0
        for i in range(n):
            s += abs(X[i, j])
        best = max(best, s)
    return best


@njit(cache=True)
def _expm_balanced(A):
    A2 = _mm(A, A)
    A4 = _mm(A2, A2)
    A6 = _mm(A4, A2)
    d4, d6 = _norm1(A4) ** 0.25, _norm1(A6) ** (1.0 / 6.0)
    eta1 = max(d4, d6)
    for q in range(2):  # degrees 3 and 5
        if eta1 <= THETA[q] and _ell(A, q) == 0:
            return _pade(A, A2, q)
    A8 = _mm(A4, A4)
    d8 = _norm1(A8) ** 0.125
    eta3 = max(d6, d8)
    for q in range(2, 4):  # degrees 7 and 9
        if eta3 <= THETA[q] and _ell(A, q) == 0:
            return _pade(A, A2, q)
    eta5 = min(eta3, max(d8, _norm1(_mm(A4, A6)) ** 0.1))
    s = max(int(math.ceil(math.log2(eta5 / THETA[4]))), 0) if eta5 > 0.0 else 0  # noqa: RUF046
    s += _ell(A / 2.0**s, 4)
    R = _pade(A / 2.0**s, A2 / 4.0**s, 4)
    for _ in range(s):
        R = _mm(R, R)
    return R


@njit(cache=True)
def _ell(A, q):
    """Extra halvings that keep the degree's relative backward error within the unit
    roundoff where ``A`` is far from normal (Al-Mohy and Higham 2009, eq. 3.11), from the
    1-norm of ``|A|^(2m+1)``; ``q`` indexes :data:`DEGREES`."""
    norm = _norm1(A)
    if norm == 0.0:
        return 0
    n = A.shape[0]
    P, B = np.eye(n), np.abs(A)
    k = 2 * DEGREES[q] + 1
    while k:  # |A|^(2m+1) by squaring
        if k & 1:
            P = _mm(P, B)
        k >>= 1
        if k:
            B = _mm(B, B)
    alpha = _norm1(P) / (norm * C_RECIP[q])
    if alpha == 0.0:
        return 0
    return max(int(math.ceil(math.log2(alpha / UNIT_ROUNDOFF) / (2 * DEGREES[q]))), 0)  # noqa: RUF046


@njit(cache=True)
def _pade(A, A2, q):
    """The [m/m] Padé approximant of ``exp(A)``, ``(V - U)^-1 (V + U)``; ``A2 = A @ A``,
    ``q`` indexes :data:`DEGREES`."""
    b = PADE[q]
    n = A.shape[0]
    eye = np.eye(n)
    if q < 4:
        Uo, V = b[1] * eye, b[0] * eye
        P = eye
        for j in range(1, DEGREES[q] // 2 + 1):
            P = A2 if j == 1 else _mm(P, A2)
            Uo = Uo + b[2 * j + 1] * P
            V = V + b[2 * j] * P
        U = _mm(A, Uo)
    else:
        A4 = _mm(A2, A2)
        A6 = _mm(A4, A2)
        U = _mm(A, _mm(A6, b[13] * A6 + b[11] * A4 + b[9] * A2)
                + b[7] * A6 + b[5] * A4 + b[3] * A2 + b[1] * eye)
        V = (_mm(A6, b[12] * A6 + b[10] * A4 + b[8] * A2)
             + b[6] * A6 + b[4] * A4 + b[2] * A2 + b[0] * eye)
    return _solve(V - U, V + U)


@njit(cache=True)
def _solve(M, R):
    """``M^-1 R`` by Gaussian elimination with partial pivoting (``M`` and ``R`` are
    overwritten) [-]."""
    n = M.shape[0]
    for k in range(n):
        p = k
        for i in range(k + 1, n):
            if abs(M[i, k]) > abs(M[p, k]):
                p = i
        if p != k:
            for j in range(n):
                M[k, j], M[p, j] = M[p, j], M[k, j]
                R[k, j], R[p, j] = R[p, j], R[k, j]
        for i in range(k + 1, n):
            f = M[i, k] / M[k, k]
            if f != 0.0:
                for j in range(k + 1, n):
                    M[i, j] -= f * M[k, j]
                for j in range(n):
                    R[i, j] -= f * R[k, j]
    for k in range(n - 1, -1, -1):
        for j in range(n):
            s = R[k, j]
            for i in range(k + 1, n):
                s -= M[k, i] * R[i, j]
            R[k, j] = s / M[k, k]
    return R
