"""How far the noise on a circle moves the terms fitted to it.

The terms are a linear least-squares fit, so their covariance follows from the design
matrix and the covariance of what the fit leaves over. That remainder is not white: a
sensor's filter, a ringing axis or a cyclic error too small to be found keep neighbouring
samples alike, and the usual ``s^2 (A^T A)^-1`` then understates the scatter by the square
root of the samples each one repeats (lateral play scattered 0.13 um over circles whose
0.1 um of noise stayed alike over 19 samples, read 0.03 um). The remainder's
autocovariance, estimated per arc up to where it has died out (Geyer's initial positive
sequence), is taken as the noise's; the coefficients' covariance is ``(A^T A)^-1 A^T Sigma
A (A^T A)^-1`` with that Toeplitz ``Sigma``, computed in the frequency domain, so a column
that varies faster than the noise stays alike (a short cyclic error) sees the noise's
spectrum at its own frequency rather than at zero. The remainder is smaller than the noise
by what the columns take of it; the effective samples, the arcs' samples over their
correlation lengths, less the columns correct for that.
"""

from __future__ import annotations

import itertools

import numpy as np


def autocovariance(r) -> tuple[np.ndarray, float]:
    """The autocovariance of ``r`` over the lags until it has died out (the pairs of
    Geyer's initial positive sequence), and its integrated correlation time in samples: 1
    for white noise [m^2, -]."""
    r = np.asarray(r, float) - np.mean(r)
    n = r.size
    if n < 4 or not np.any(r):
        return np.array([float(np.mean(r**2))]), 1.0
    f = np.fft.rfft(r, 2 * n)
    acov = np.fft.irfft(f * np.conj(f))[:n] / n
    pairs = acov[: n - n % 2].reshape(-1, 2).sum(axis=1)
    stop = np.flatnonzero(pairs <= 0.0)
    k = 2 * (stop[0] if stop.size else pairs.size)
    acov = acov[:max(k, 1)]
    tau = 1.0 + 2.0 * acov[1:].sum() / acov[0]
    return acov, float(max(tau, 1.0))


def correlation_length(r) -> float:
    """The integrated autocorrelation time of ``r`` in samples (:func:`autocovariance`)
    [-]."""
    return autocovariance(r)[1]


def coef_covariance(A, r, sizes) -> np.ndarray:
    """Covariance of the least-squares coefficients of ``A c = y`` with remainder ``r``,
    the rows of consecutive arcs ``sizes`` long (module docstring) [SI^2].

    Parameters
    ----------
    A : ndarray
        Design matrix of the fitted columns, rows of every arc in turn [m/unit].
    r : ndarray
        What the fit leaves over per row [m].
    sizes : sequence of int
        Rows of each arc [-].
    """
    p = A.shape[1]
    bounds = np.cumsum([0, *sizes])
    meat = np.zeros((p, p))
    n_eff = 0.0
    for a, b in itertools.pairwise(bounds):
        if b > a:
            acov, tau = autocovariance(r[a:b])
            meat += toeplitz_form(A[a:b], acov)
            n_eff += (b - a) / tau
    inv = np.linalg.pinv(A.T @ A)
    return inv @ meat @ inv * (n_eff / max(n_eff - p, 1.0))


def toeplitz_form(A, acov) -> np.ndarray:
    """``A^T Sigma A`` with ``Sigma`` the Toeplitz matrix of the autocovariance ``acov``
    (zero past its last lag), by the FFT, its spectrum clipped at zero so that the form
    stays positive [m^2 unit^-2].

    Parameters
    ----------
    A : ndarray
        Design matrix of one arc [m/unit].
    acov : ndarray
        Autocovariance from lag 0 [m^2].
    """
    n, lags = A.shape[0], min(acov.size - 1, A.shape[0] - 1)
    if lags == 0:
        return acov[0] * (A.T @ A)
    m = 2 * n
    w = np.zeros(m)
    w[:lags + 1] = acov[:lags + 1]
    w[m - np.arange(1, lags + 1)] = acov[1:lags + 1]
    spec = np.fft.rfft(A, m, axis=0)
    density = np.clip(np.fft.rfft(w).real, 0.0, None)
    # the one-sided spectrum counts every bin but the first and the Nyquist twice
    density[1:-1] *= 2.0
    return (np.conj(spec).T @ (spec * density[:, None])).real / m
