"""The matrix exponential by scaling and squaring of Padé approximants, in numpy.

A. H. Al-Mohy and N. J. Higham, "A new scaling and squaring algorithm for the matrix
exponential", SIAM J. Matrix Anal. Appl. 31(3), 2009, Algorithm 5.1 without its
triangular refinements (as ``scipy.linalg.expm``): the degree ``m`` of the [m/m] Padé
approximant, 3 to 13, and the number ``s`` of halvings follow the norms of the matrix's
powers ``||A^k||^(1/k)`` rather than its norm, which overstates them for the plants'
far-from-normal matrices; the result is squared ``s`` times. The matrix is balanced
first by exact powers of two (LAPACK's ``dgebal``): the plants' entries span twenty
orders of magnitude.

It is the exact discretisation's one need of a matrix function, and a command that
simulates otherwise needs nothing of scipy: importing ``scipy.linalg`` takes 0.15 s, a
third of such a command's start-up (``docs/performance.md``). It agrees with
``scipy.linalg.expm`` to 1e-12 in every entry of the plants' matrices
(``tests/test_matexp.py``).
"""

from __future__ import annotations

import math

import numpy as np

#: Padé coefficients ``b_0 .. b_m`` per degree (Higham 2005, eq. 2.3 and Table 2.3) [-].
_PADE = {
    3: (120.0, 60.0, 12.0, 1.0),
    5: (30240.0, 15120.0, 3360.0, 420.0, 30.0, 1.0),
    7: (17297280.0, 8648640.0, 1995840.0, 277200.0, 25200.0, 1512.0, 56.0, 1.0),
    9: (17643225600.0, 8821612800.0, 2075673600.0, 302702400.0, 30270240.0, 2162160.0,
        110880.0, 3960.0, 90.0, 1.0),
    13: (64764752532480000.0, 32382376266240000.0, 7771770303897600.0,
         1187353796428800.0, 129060195264000.0, 10559470521600.0, 670442572800.0,
         33522128640.0, 1323241920.0, 40840800.0, 960960.0, 16380.0, 182.0, 1.0),
}
#: Bounds ``theta_m`` of Al-Mohy and Higham (2009), Table 3.1: the largest ``||A^k||^(1/k)``
#: for which degree ``m`` is accurate to the unit roundoff; 13 as scipy takes it [-].
_THETA = {3: 1.495585217958292e-2, 5: 2.539398330063230e-1, 7: 9.504178996162932e-1,
          9: 2.097847961257068e0, 13: 4.25}
#: ``|c_(2m+1)|^-1``, the reciprocal of the Padé error's leading coefficient (eq. 1.2) [-].
_C_RECIP = {m: float(math.comb(2 * m, m) * math.factorial(2 * m + 1)) for m in _PADE}
_UNIT_ROUNDOFF = 2.0**-53


def _norm1(A: np.ndarray) -> float:
    return float(np.max(np.sum(np.abs(A), axis=0))) if A.size else 0.0


def expm(A) -> np.ndarray:
    """The matrix exponential ``exp(A)``.

    Parameters
    ----------
    A : array_like (n, n)
        A real square matrix, finite [-].

    Returns
    -------
    ndarray (n, n)
        ``exp(A)`` [-].
    """
    A = np.asarray(A, dtype=float)
    if A.ndim != 2 or A.shape[0] != A.shape[1]:
        raise ValueError(f"expm needs a square matrix, not one of shape {A.shape}")
    if not np.all(np.isfinite(A)):
        raise ValueError("expm needs a finite matrix")
    d = balancing_scale(A)
    E = _expm_balanced(A / d[:, None] * d[None, :])
    return E * d[:, None] / d[None, :]


def balancing_scale(A: np.ndarray) -> np.ndarray:
    """Powers of two ``d`` that balance ``A``: ``D^-1 A D`` (``D = diag(d)``) has rows and
    columns of like 2-norms, as LAPACK's ``dgebal`` (scaling, no permutation) makes them.
    The scaling is exact in floating point; without it the plants' matrices, whose
    entries span 20 orders of magnitude, lose up to 7 digits in their small entries.

    Parameters
    ----------
    A : ndarray (n, n)
        The matrix [-].

    Returns
    -------
    ndarray (n,)
        The scale of each state [-].
    """
    B = np.array(A, dtype=float)
    d = np.ones(B.shape[0])
    changed = True
    while changed:
        changed = False
        for i in range(B.shape[0]):
            c, r = float(np.linalg.norm(B[:, i])), float(np.linalg.norm(B[i, :]))
            if c == 0.0 or r == 0.0:
                continue
            f, s = 1.0, c + r
            while c < r / 2.0:
                f, c, r = f * 2.0, c * 2.0, r / 2.0
            while c / 2.0 >= r:
                f, c, r = f / 2.0, c / 2.0, r * 2.0
            if c + r >= 0.95 * s:
                continue
            d[i] *= f
            B[i, :] /= f
            B[:, i] *= f
            changed = True
    return d


def _expm_balanced(A: np.ndarray) -> np.ndarray:
    A2 = A @ A
    A4 = A2 @ A2
    A6 = A4 @ A2
    d4, d6 = _norm1(A4) ** 0.25, _norm1(A6) ** (1 / 6)
    if max(d4, d6) <= _THETA[3] and _ell(A, 3) == 0:
        return _pade(A, A2, 3)
    if max(d4, d6) <= _THETA[5] and _ell(A, 5) == 0:
        return _pade(A, A2, 5)
    A8 = A4 @ A4
    d8 = _norm1(A8) ** 0.125
    eta3 = max(d6, d8)
    for m in (7, 9):
        if eta3 <= _THETA[m] and _ell(A, m) == 0:
            return _pade(A, A2, m)
    eta5 = min(eta3, max(d8, _norm1(A4 @ A6) ** 0.1))
    s = max(math.ceil(math.log2(eta5 / _THETA[13])), 0) if eta5 > 0 else 0
    s += _ell(A / 2.0**s, 13)
    R = _pade(A / 2.0**s, A2 / 4.0**s, 13)
    for _ in range(s):
        R = R @ R
    return R


def _ell(A: np.ndarray, m: int) -> int:
    """Extra halvings that keep the degree-``m`` approximant's relative backward error
    within the unit roundoff where ``A`` is far from normal (Al-Mohy and Higham 2009,
    eq. 3.11), from the 1-norm of ``|A|^(2m+1)``."""
    norm = _norm1(A)
    if norm == 0.0:
        return 0
    P, B, k = np.eye(A.shape[0]), np.abs(A), 2 * m + 1
    while k:  # |A|^(2m+1) by squaring
        if k & 1:
            P = P @ B
        B, k = B @ B, k >> 1
    alpha = _norm1(P) / (norm * _C_RECIP[m])
    if alpha == 0.0:
        return 0
    return max(math.ceil(math.log2(alpha / _UNIT_ROUNDOFF) / (2 * m)), 0)


def _pade(A: np.ndarray, A2: np.ndarray, m: int) -> np.ndarray:
    """The [m/m] Padé approximant of ``exp(A)``: ``(V - U)^-1 (V + U)``; ``A2 = A @ A``."""
    b = _PADE[m]
    eye = np.eye(A.shape[0])
    if m < 13:
        powers = [eye, A2]
        for _ in range(2, m // 2 + 1):
            powers.append(powers[-1] @ A2)
        U = A @ sum(b[2 * j + 1] * P for j, P in enumerate(powers))
        V = sum(b[2 * j] * P for j, P in enumerate(powers))
    else:
        A4 = A2 @ A2
        A6 = A4 @ A2
        U = A @ (A6 @ (b[13] * A6 + b[11] * A4 + b[9] * A2)
                 + b[7] * A6 + b[5] * A4 + b[3] * A2 + b[1] * eye)
        V = (A6 @ (b[12] * A6 + b[10] * A4 + b[8] * A2)
             + b[6] * A6 + b[4] * A4 + b[2] * A2 + b[0] * eye)
    return np.linalg.solve(V - U, V + U)
