"""FRF from whole periods of a periodic excitation (multisine, repeated chirp).

With an excitation that repeats every ``P`` samples and a system in steady state, the
DFT of one period has no leakage: ``H(f_k) = Y(f_k)/U(f_k)`` is exact at every excited
bin ``f_k = k fs/P``, with no window. With ``K >= 2`` periods the spectra are averaged
over the periods and the noise is estimated from their spread (Pintelon & Schoukens,
*System Identification*, ch. 2): the variance of the averaged ``Y`` is ``s_Y^2 / K``
with ``s_Y^2`` the sample variance across periods, and likewise for ``U`` and their
covariance. When three or more whole periods are recorded, the first is left out as
the system's transient.

**Detection rule** (:func:`detect_period`): the excitation is periodic with period ``P``
when ``P`` is the smallest lag of at least :data:`MIN_PERIOD` samples, with at least two
whole periods in the record, at which the record repeats to within
:data:`PERIOD_TOL` of its RMS (``||u[n+P] - u[n]|| <= tol ||u||``). A measured, noisy
signal does not repeat that well: estimate against the injected excitation.
"""

from __future__ import annotations

import warnings

import numpy as np

from ...errors import InputError, InputWarning
from ...frfdata import FRF

#: Relative RMS difference between successive periods accepted as periodic [-].
PERIOD_TOL = 1e-4
#: Shortest period considered [samples].
MIN_PERIOD = 16
#: Bins whose excitation amplitude is below this fraction of the largest are not excited [-].
EXCITED = 1e-4


def detect_period(u, min_period: int = MIN_PERIOD, tol: float = PERIOD_TOL) -> int | None:
    """Period of a periodic record, or ``None`` (see the module docstring for the rule).

    Parameters
    ----------
    u : array_like
        Excitation samples [SI].
    min_period : int
        Shortest period considered [samples].
    tol : float
        Relative RMS mismatch accepted between successive periods [-].

    Returns
    -------
    int or None
        Period [samples].
    """
    u = np.asarray(u, dtype=float)
    u = u - u.mean()
    n = u.size
    if n < 2 * min_period or not np.any(u):
        return None
    m = 1 << int(np.ceil(np.log2(2 * n)))
    F = np.fft.rfft(u, m)
    R = np.fft.irfft(F * np.conj(F), m)[:n]  # R[P] = sum u[k] u[k+P]
    c = np.concatenate([[0.0], np.cumsum(u * u)])
    lags = np.arange(min_period, n // 2 + 1)
    tail = c[n] - c[lags]  # sum over the later part, u[P:]
    head = c[n - lags]  # sum over u[:-P]
    mismatch = (tail + head - 2 * R[lags]) / (tail + head)
    for p in lags[mismatch <= 4 * tol * tol]:  # candidates; confirmed exactly
        p = int(p)
        d = u[p:] - u[:-p]
        if np.sqrt(d @ d) <= tol * np.sqrt(0.5 * (u[p:] @ u[p:] + u[:-p] @ u[:-p])):
            return p
    return None


def _period_spread(U, Y, Um, Ym, k: int) -> tuple:
    """Relative standard deviation of ``H`` [-] and the coherence it implies [-] from the
    spread of the ``k >= 2`` periods' spectra ``U``, ``Y`` about their means ``Um``, ``Ym``."""
    dY, dU = Y - Ym, U - Um
    vy = np.sum(np.abs(dY) ** 2, axis=0) / (k - 1) / k
    vu = np.sum(np.abs(dU) ** 2, axis=0) / (k - 1) / k
    cyu = np.sum(dY * np.conj(dU), axis=0) / (k - 1) / k
    # complex variance of H/H; |H| and the phase each carry half of it
    rel_var = (vy / np.abs(Ym) ** 2 + vu / np.abs(Um) ** 2
               - 2 * np.real(cyu / (Ym * np.conj(Um))))
    rel_std = np.sqrt(np.maximum(0.5 * rel_var, 0.0))
    coh = 1.0 / (1.0 + 2 * k * rel_std**2)  # the Bendat-Piersol relation, inverted
    return rel_std, coh


def periodic_frf(u, y, fs_hz: float, period: int, fmin_hz=None, fmax_hz=None, **labels):
    """FRF of ``y`` against ``u`` from whole periods (no window).

    Parameters
    ----------
    u, y : ndarray
        Input and output samples [SI].
    fs_hz : float
        Sample rate [Hz].
    period : int
        Period of the excitation [samples].
    fmin_hz, fmax_hz : float, optional
        Band kept [Hz].
    **labels
        ``name``, ``input``, ``output`` of the FRF [-].

    Returns
    -------
    FRF
        ``H`` at the excited bins; ``rel_std`` and ``coherence`` from the spread across
        periods (NaN from a single period, with a warning) [-].
    """
    k_all = u.size // period
    if k_all < 1:
        raise InputError(f"the record ({u.size} samples) is shorter than one period of the "
                         f"excitation ({period} samples); record at least one whole period")
    k = k_all - 1 if k_all >= 3 else k_all
    seg = slice(u.size - k * period, u.size)
    U = np.fft.rfft(u[seg].reshape(k, period), axis=1)
    Y = np.fft.rfft(y[seg].reshape(k, period), axis=1)
    f = np.arange(U.shape[1]) * fs_hz / period
    Um, Ym = U.mean(axis=0), Y.mean(axis=0)
    keep = (np.abs(Um) > EXCITED * np.abs(Um[1:]).max()) & (f > 0) & (f < 0.5 * fs_hz)
    if fmin_hz is not None:
        keep &= f >= fmin_hz
    if fmax_hz is not None:
        keep &= f <= fmax_hz
    if not np.any(keep):
        raise InputError("no excited frequency of the periodic excitation lies in the band")
    f, U, Y, Um, Ym = f[keep], U[:, keep], Y[:, keep], Um[keep], Ym[keep]
    H = Ym / Um
    if k >= 2:
        rel_std, coh = _period_spread(U, Y, Um, Ym, k)
    else:
        warnings.warn("one period of the excitation: the FRF is exact at the excited bins "
                      "but its noise is unknown; record two or more periods to estimate it",
                      InputWarning, stacklevel=3)
        rel_std = np.full(f.size, np.nan)
        coh = np.full(f.size, np.nan)
    return FRF(freq_hz=f, H=H, coherence=coh, n_averages=float(k), rel_std=rel_std,
               name=labels.get("name") or f"{labels.get('output', 'y')}/"
                                          f"{labels.get('input', 'u')}",
               input=labels.get("input", "u"), output=labels.get("output", "y"),
               meta={"periodic": True, "period_samples": period, "n_periods": k,
                     "fs_hz": fs_hz, "window": "none"})
