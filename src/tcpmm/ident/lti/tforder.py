"""Numerator and denominator degrees for :func:`~tcpmm.ident.lti.tffit.fit_tf`, counted from
the resonances and antiresonances of the data and chosen by an information criterion."""

from __future__ import annotations

import numpy as np

from ...errors import InputError
from ...frfdata import FRF
from ._tfcore import peaks_and_dips
from .tffit import fit_data, fit_tf

__all__ = ["suggest_order"]


def suggest_order(data, max_order: int = 12, n_integrators: int = 0, delay_s=None,
                  prominence_db: float = 3.0, criterion: str = "bic", refine: int = 4,
                  min_coherence: float = 0.5) -> tuple[int, int]:
    """Suggest numerator and denominator degrees for :func:`fit_tf`.

    Rule: every resonance peak of ``|H (j omega)^k|`` (prominence at least
    ``prominence_db``, coherence at least 0.5) needs a complex pole pair and every
    antiresonance dip a complex zero pair, giving ``n_den0 = 2 peaks`` and
    ``n_num0 = 2 dips``; a peak must turn the phase down and a dip turn it up (a valley
    between two resonances is no antiresonance). Candidates ``n_den0 - 1 <= n_den <= n_den0
    + 2`` (at least 1, at most ``max_order``) and ``n_num0 - 1 <= n_num <= min(n_den, n_num0 +
    2)`` (at least 0) are fitted by the linear stage alone (on at most about 500 of the bins);
    the ``refine`` best of them by the
    information criterion of the weighted relative error are fitted in full, and the one with
    the lowest criterion wins, unless it puts a lightly damped mode (damping ratio below 0.2)
    outside the band of the data, where nothing supports it.

    Parameters
    ----------
    data : FRF or tuple
        As for :func:`fit_tf` [-].
    max_order : int
        Largest denominator degree considered [-].
    n_integrators : int
        Known integrators, as for :func:`fit_tf` [-].
    delay_s : None, float or "fit"
        Delay handling, as for :func:`fit_tf` [s].
    prominence_db : float
        Least prominence of a peak or dip [dB].
    criterion : {"bic", "aic"}
        Information criterion [-].
    refine : int
        Number of candidates fitted in full [-].
    min_coherence : float
        Bins of an FRF below this coherence are left out, as in :func:`fit_tf` [-].

    Returns
    -------
    tuple of int
        ``(n_num, n_den)`` [-].
    """
    if criterion not in ("bic", "aic"):
        raise InputError(f"criterion must be 'bic' or 'aic', got {criterion!r}")
    f, H, w = fit_data(data, None, min_coherence)
    n_num0, n_den0 = _counted_order(data, f, H, int(n_integrators), prominence_db, max_order)
    kw = dict(n_integrators=n_integrators, delay_s=delay_s, min_coherence=min_coherence)
    cands = _screened(f, H, w, n_num0, n_den0, max_order, criterion, kw)
    # refine the most promising candidates by the full fit (ties: lower order first)
    cands.sort()
    return _best_refined(data, f, cands[:refine], criterion, kw)


def _counted_order(data, f, H, k: int, prominence_db: float, max_order: int) -> tuple:
    """``(n_num0, n_den0)``: a complex pole pair per resonance peak and a complex zero pair
    per antiresonance dip of the bins ``f, H`` kept from ``data`` [-]."""
    if isinstance(data, FRF):
        sel = np.isin(data.freq_hz, f)
        coh, rel = data.coherence[sel], data.rel_std[sel]
    else:
        coh, rel = np.ones(f.size), None
    peaks, dips = peaks_and_dips(f, H, coh, k, prominence_db, rel_std=rel)
    n_den0 = min(max(2 * len(peaks), 1), max_order)
    n_num0 = min(2 * len(dips), n_den0)
    return n_num0, n_den0


def _screened(f, H, w, n_num0: int, n_den0: int, max_order: int, criterion: str,
              kw: dict) -> list:
    """``(criterion, n_den, n_num)`` of every candidate order around the counted one, fitted
    by the linear stage alone on at most ~500 of the bins, with the delay of one fit at the
    counted order [-]."""
    screen = dict(kw)
    stride = max(1, f.size // 500)
    screen_data = (f[::stride], H[::stride], w[::stride])
    if kw["delay_s"] == "fit":
        screen["delay_s"] = fit_tf(screen_data, n_num0, n_den0, **kw).delay_s
    cands = []
    for n_den in range(max(1, n_den0 - 1), min(max_order, n_den0 + 2) + 1):
        for n_num in range(max(0, min(n_num0, n_den) - 1), min(n_den, n_num0 + 2) + 1):
            try:
                fit = fit_tf(screen_data, n_num, n_den, nlls=False, **screen)
            except InputError:
                continue
            cands.append((fit.bic if criterion == "bic" else fit.aic, n_den, n_num))
    if not cands:
        raise InputError("too few frequency bins to fit any candidate order")
    return cands


def _best_refined(data, f, cands: list, criterion: str, kw: dict) -> tuple:
    """``(n_num, n_den)`` of the best full fit of the candidates by the criterion; a lightly
    damped mode outside the band is not supported by the data: such candidates only count
    if no other is left [-]."""
    fitted = []
    for _, n_den, n_num in sorted(cands, key=lambda c: (c[1], c[2])):
        fit = fit_tf(data, n_num, n_den, **kw)
        ic = fit.bic if criterion == "bic" else fit.aic
        fn, zeta = fit.natural_freq_hz, fit.damping
        outside = np.any((zeta < 0.2) & ((fn < f[0]) | (fn > f[-1])))
        # a fit that folded far poles into the gain is the lower order it kept
        fitted.append((bool(outside), ic, fit.n_den, fit.n_num))
    best = min(fitted, key=lambda c: (c[0], c[1]))
    return best[3], best[2]
