"""Frequency response of a sampled SISO loop, ``C (zI - Phi)^-1 Gam + D`` on the unit circle.

A margin search evaluates one loop at some 4 000-6 000 grid frequencies and then at each
crossing Brent's method brackets, tens of times for each gain a tuning tries. ``Phi`` is
therefore reduced once: balanced by powers of two (exact, and needed: the sampled loop's
states span some sixteen decades, and an orthogonal reduction of the unbalanced matrix loses
the small entries' digits) and brought to upper Hessenberg form by orthogonal similarity.
``zI - H`` is then solved at each frequency by Gaussian elimination with partial pivoting
along the one sub-diagonal, in ``O(n^2)`` instead of the ``O(n^3)`` of a dense solve, by the
compiled :func:`tcpmm.sim.hessenberg.hessenberg_response`: one frequency gives the same
bits alone as in a grid.
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import hessenberg, matrix_balance

from .._compiled import hessenberg_response


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
    H = np.ascontiguousarray(H)
    b = np.ascontiguousarray(Q.T @ (np.asarray(Gam, float)[:, 0] / scale))
    c = np.ascontiguousarray((np.asarray(C, float)[0] * scale) @ Q)
    d = float(np.asarray(D, float)[0, 0])

    def response(f_hz) -> np.ndarray:
        f = np.atleast_1d(np.asarray(f_hz, dtype=float))
        z = np.exp(2j * np.pi * f.ravel() * dt)
        re, im = hessenberg_response(H, np.ascontiguousarray(z.real),
                                     np.ascontiguousarray(z.imag), b, c)
        out = np.empty(f.size, dtype=complex)
        out.real, out.imag = re + d, im
        return out.reshape(f.shape)

    return response
