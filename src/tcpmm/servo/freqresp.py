"""Frequency response of a sampled SISO loop, ``C (zI - Phi)^-1 Gam + D`` on the unit circle.

A margin search evaluates one loop at some 4 000-6 000 grid frequencies and then at each
crossing Brent's method brackets, tens of times for each gain a tuning tries. ``Phi`` is
therefore reduced once: balanced by powers of two (exact, and needed: the sampled loop's
states span some sixteen decades, and an orthogonal reduction of the unbalanced matrix loses
the small entries' digits) and brought to upper Hessenberg form by orthogonal similarity.
``zI - H`` is then solved at each frequency by Gaussian elimination with partial pivoting
along the one sub-diagonal, in ``O(n^2)`` instead of the ``O(n^3)`` of a dense solve, all
frequencies at once.
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import hessenberg, matrix_balance

#: Frequencies from which the elimination runs over all of them at once; below, a dense
#: solve each costs less than the elimination's some 50 array operations per row [-].
VECTORISED_FROM = 64


def loop_response(Phi, Gam, C, D, dt: float):
    """The response of a SISO discrete system as a function of frequency.

    Parameters
    ----------
    Phi, Gam, C, D : ndarray
        Discrete system, one input and one output [-].
    dt : float
        Sample period [s].

    Returns
    -------
    callable
        ``response(f_hz)`` -> complex array, ``C (zI - Phi)^-1 Gam + D`` at
        ``z = e^(j 2 pi f dt)`` for each frequency ``f_hz`` [Hz] (array_like).
    """
    Phi = np.asarray(Phi, float)
    if not np.isfinite(Phi).all():  # no numbers to reduce: no response, as a solve gives
        return lambda f_hz: np.full(np.atleast_1d(f_hz).shape, complex(np.nan, np.nan))
    balanced, (scale, _) = matrix_balance(Phi, permute=False, separate=True)
    H, Q = hessenberg(balanced, calc_q=True)
    b = Q.T @ (np.asarray(Gam, float)[:, 0] / scale)
    c = (np.asarray(C, float)[0] * scale) @ Q
    d = float(np.asarray(D, float)[0, 0])

    def response(f_hz) -> np.ndarray:
        f = np.atleast_1d(np.asarray(f_hz, dtype=float))
        z = np.exp(2j * np.pi * f * dt)
        if f.size < VECTORISED_FROM:
            x = np.linalg.solve(z[:, None, None] * np.eye(H.shape[0]) - H, b[:, None])
            return x[..., 0] @ c + d
        return c @ hessenberg_solve(H, z, b) + d

    return response


def hessenberg_solve(H, z, b) -> np.ndarray:
    """``(z_k I - H)^-1 b`` for each ``z_k``, ``H`` upper Hessenberg [-].

    Parameters
    ----------
    H : ndarray, shape (n, n)
        Upper Hessenberg matrix [-].
    z : ndarray, shape (m,)
        Complex shifts [-].
    b : ndarray, shape (n,)
        Right-hand side [-].

    Returns
    -------
    ndarray, shape (n, m)
        The solutions, one column per shift [-].
    """
    n = H.shape[0]
    A = np.empty((n, n, z.size), complex)  # frequencies last: each row operation contiguous
    A[...] = -H[:, :, None]
    A[np.arange(n), np.arange(n), :] = z[None, :] - np.diagonal(H)[:, None]
    x = np.empty((n, z.size), complex)
    x[...] = b[:, None]
    with np.errstate(divide="ignore", invalid="ignore"):  # a shift on an eigenvalue: inf
        for k in range(n - 1):
            swap = np.abs(A[k + 1, k]) > np.abs(A[k, k])
            if swap.any():
                top, low = A[k, k:], A[k + 1, k:]
                top[:, swap], low[:, swap] = low[:, swap], top[:, swap]
                xt, xl = x[k], x[k + 1]
                xt[swap], xl[swap] = xl[swap], xt[swap]
            m = A[k + 1, k] / A[k, k]
            A[k + 1, k + 1:] -= m * A[k, k + 1:]
            x[k + 1] -= m * x[k]
        for k in range(n - 1, -1, -1):
            x[k] /= A[k, k]
            x[:k] -= A[:k, k] * x[k]
    return x
