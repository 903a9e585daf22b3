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
spectrum at its own frequency rather than at zero.

The remainder is not the noise: the fit has taken from it what lies along its columns,
``r = (I - Q Q^T) e`` with ``Q`` an orthonormal basis of them. Its autocovariance at lag
``k`` is then short of the noise's by ``(tr(S_k Q Q^T Sigma) + tr(S_k Sigma Q Q^T) -
tr(S_k Q Q^T Sigma Q Q^T)) / n``, with ``S_k`` the shift by ``k``: about the noise's
power along each column over ``n`` at every lag short of the columns' own periods. A
circle's columns are slow, so over ``L`` lags the shortfall adds up to some ``(2 L + 1)
p / n`` of the noise's density where the terms read it, and where few samples are
independent that is a quarter of it and more (two circles of 1 800 samples under noise
alike over 19, 15 columns: left out, it puts the terms' sigma at 0.59-0.84 of their
scatter). The shortfall is worked out from the autocovariance it corrects, in a few
rounds, and added back (:func:`noise_autocovariances`); for white noise it is the usual
``n / (n - p)``.
"""

from __future__ import annotations

import itertools

import numpy as np
from scipy import fft as sp_fft


def _sample_autocovariance(r) -> np.ndarray:
    """The autocovariance of ``r`` about its mean at every lag, over ``n`` [m^2]."""
    r = np.asarray(r, float) - np.mean(r)
    n = r.size
    f = np.fft.rfft(r, 2 * n)
    return np.fft.irfft(f * np.conj(f))[:n] / n


def _died_out(acov) -> np.ndarray:
    """``acov`` up to where it has died out: the pairs of Geyer's initial positive
    sequence; its first lag alone where it has under four [m^2]."""
    n = acov.size
    if n < 4:
        return acov[:1]
    pairs = acov[: n - n % 2].reshape(-1, 2).sum(axis=1)
    stop = np.flatnonzero(pairs <= 0.0)
    k = 2 * (stop[0] if stop.size else pairs.size)
    return acov[:max(k, 1)]


def autocovariance(r) -> tuple[np.ndarray, float]:
    """The autocovariance of ``r`` over the lags until it has died out (the pairs of
    Geyer's initial positive sequence), and its integrated correlation time in samples: 1
    for white noise [m^2, -]."""
    r = np.asarray(r, float)
    if r.size < 4 or not np.any(r - np.mean(r)):
        return np.array([float(np.mean((r - np.mean(r)) ** 2))]), 1.0
    acov = _died_out(_sample_autocovariance(r))
    tau = 1.0 + 2.0 * acov[1:].sum() / acov[0]
    return acov, float(max(tau, 1.0))


def correlation_length(r) -> float:
    """The integrated autocorrelation time of ``r`` in samples (:func:`autocovariance`)
    [-]."""
    return autocovariance(r)[1]


#: Rounds of the correction of the remainder's autocovariance for what the columns took
#: (:func:`noise_autocovariances`): each works the shortfall out from the last round's
#: noise (two arcs of 900 samples under noise alike over 19: the third moves the terms'
#: sigma by 0.6-0.8 %, a fourth by 0.2 %) [-].
ROUNDS = 3


def noise_autocovariances(A, r, arcs) -> list:
    """Each arc's noise autocovariance, from what the fit with columns ``A`` leaves
    (``r``) with what the columns took of it added back, in :data:`ROUNDS` rounds, each up
    to where it has died out (module docstring) [m^2].

    Parameters
    ----------
    A : ndarray
        Design matrix, rows of every arc in turn [m/unit].
    r : ndarray
        What the fit leaves over per row [m].
    arcs : list of tuple
        First and past-last row of each arc [-].
    """
    q = np.linalg.qr(A)[0]
    raw = [_sample_autocovariance(r[a:b]) for a, b in arcs]
    acovs = [_died_out(x) for x in raw]
    # every product over the samples by the FFT, zero-padded to at least twice an arc
    # (a length the FFT takes fast: an arc's samples may be a prime): the columns'
    # transforms once, Q^T Sigma Q's from Sigma Q's
    size = [sp_fft.next_fast_len(2 * (b - a), real=True) for a, b in arcs]
    fq = [np.fft.rfft(q[a:b], m, axis=0) for (a, b), m in zip(arcs, size, strict=True)]
    for _ in range(ROUNDS):
        fs, g = [], 0.0
        for (a, b), acov, f, m in zip(arcs, acovs, fq, size, strict=True):
            n = b - a
            sq = np.fft.irfft(np.fft.rfft(_circulant(acov, n, m))[:, None] * f,
                              m, axis=0)[:n]  # Sigma Q, Sigma Toeplitz
            fs.append(np.fft.rfft(sq, m, axis=0))
            g = g + q[a:b].T @ sq  # Q^T Sigma Q
        acovs = []
        for (a, b), x, f, h, m in zip(arcs, raw, fq, fs, size, strict=True):
            n = b - a
            # sum_i x[i] . y[i + k] for every lag k, over the columns, of (Sigma Q, Q),
            # (Q, Sigma Q) and (Q G, Q)
            spec = (np.conj(h) * f + np.conj(f) * h - np.conj(f @ g) * f).sum(axis=1)
            x = x + np.fft.irfft(spec, m)[:n] / n
            acovs.append(_died_out(x))
    return acovs


def _circulant(acov, n, m) -> np.ndarray:
    """The first column of the circulant of size ``m`` that holds the Toeplitz matrix of
    ``acov`` for ``n`` rows [m^2]."""
    lags = min(acov.size - 1, n - 1)
    w = np.zeros(m)
    w[:lags + 1] = acov[:lags + 1]
    w[m - np.arange(1, lags + 1)] = acov[1:lags + 1]
    return w


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
    arcs = [(a, b) for a, b in itertools.pairwise(np.cumsum([0, *sizes])) if b > a]
    meat = np.zeros((p, p))
    for (a, b), acov in zip(arcs, noise_autocovariances(A, r, arcs), strict=True):
        meat += toeplitz_form(A[a:b], acov)
    inv = np.linalg.pinv(A.T @ A)
    return inv @ meat @ inv


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
    w = _circulant(acov, n, m)
    spec = np.fft.rfft(A, m, axis=0)
    density = np.clip(np.fft.rfft(w).real, 0.0, None)
    # the one-sided spectrum counts every bin but the first and the Nyquist twice
    density[1:-1] *= 2.0
    return (np.conj(spec).T @ (spec * density[:, None])).real / m
