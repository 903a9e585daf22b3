"""Rational transfer functions fitted to frequency response data.

Model::

    H(s) = B(s) / (A(s) s^k) * exp(-s tau)

with ``deg B = n_num``, ``deg A = n_den``, ``k = n_integrators`` known integrators and an
optional pure delay ``tau``. The fit runs in three stages, all in the normalised frequency
``x = s / omega_0`` with ``omega_0`` the geometric centre of the band, which keeps the
polynomial coefficients of order one:

1. Levy's linearised least squares ``B - H A ~ 0`` followed by Sanathanan-Koerner
   iterations (divide by the previous ``|A|``) on the *relative* error, weighted per bin.
   SK can settle on a poor fixed point and miss a weak mode, so it runs from three starts:
   Levy's ``A = 1``, lightly damped poles spread log-uniformly over the band (as vector
   fitting starts) and poles at the resonance peaks seen in the data.
2. Unstable poles are reflected into the left half plane (``stable=True``).
3. Nonlinear least squares (:func:`scipy.optimize.least_squares`) of the weighted relative
   complex error ``w (H_model / H - 1)`` by variable projection: the denominator is a product
   of second-order sections ``x^2 + exp(p1) x + exp(p0)`` (and one ``x + exp(q)`` if
   ``n_den`` is odd), whose positive coefficients keep every pole stable; for given poles
   the numerator (and gain) is the linear least-squares solution. The delay, if fitted, is
   one more nonlinear parameter, started from the best of a coarse grid. Every start whose
   linear cost is within ``REFINE_RATIO`` of the best refined cost is refined; the lowest
   cost wins.

Weights default to ``1 / sqrt(rel_std^2 + 0.01^2)`` from the FRF's coherence-based random
error, so a bin counts by how well it was measured, and no bin counts more than a 1 %
measurement would (model error dominates below that).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..._threads import limit_blas_threads
from ...errors import InputError
from ...frfdata import FRF
from ...pade import with_delay
from ._tfcore import (
    _extrema,
    _model,
    _numerator,
    _pairs,
    _peak_poles,
    _refine,
    _reflect,
    _relative_cost,
    _sk,
    _spread_poles,
)
from .goodness import fit_percent, rel_error

__all__ = ["TFFit", "fit_tf", "suggest_order"]

#: Relative error floor added to the FRF's random error when weighting bins.
WEIGHT_FLOOR = 0.01
#: Starts of the linear stage this many times costlier than the best fit are not refined.
REFINE_RATIO = 3.0
#: Poles farther than this multiple of the top of the band are folded into the gain.
FAR_POLE = 1e8


@dataclass(frozen=True)
class TFFit:
    """A transfer function fitted to frequency response data.

    Parameters
    ----------
    num : ndarray
        Numerator coefficients in s, highest power first [SI].
    den : ndarray
        Denominator coefficients in s, highest power first, leading coefficient 1,
        including the ``s^k`` of the integrators [SI].
    delay_s : float
        Pure delay [s].
    n_num : int
        Numerator degree [-].
    n_den : int
        Degree of the denominator without the integrators [-].
    n_integrators : int
        Known integrators ``1/s^k`` [-].
    fit_percent : float
        NRMSE fit ``100 (1 - ||H - H_model|| / ||H - mean(H)||)`` against the data fitted,
        unweighted [%].
    rel_error : float
        RMS of ``|H_model / H - 1|`` over the bins fitted, unweighted [-].
    cost : float
        Weighted sum of squared relative residuals (real and imaginary parts) [-].
    n_params : int
        Number of real parameters fitted [-].
    freq_hz : ndarray
        Frequencies of the bins fitted (those of weight > 0) [Hz].
    H : ndarray
        Data fitted [SI].
    weight : ndarray
        Weight of each bin fitted [-].
    omega0 : float
        Frequency scale used internally [rad/s].
    bn : ndarray
        Numerator coefficients in ``x = s/omega0``, lowest power first [-].
    pn : ndarray
        Poles in ``x`` without the integrators; the denominator in ``x`` is
        ``prod(x - pn) x^k`` [-].
    """

    num: np.ndarray
    den: np.ndarray
    delay_s: float
    n_num: int
    n_den: int
    n_integrators: int
    fit_percent: float
    rel_error: float
    cost: float
    n_params: int
    freq_hz: np.ndarray
    H: np.ndarray
    weight: np.ndarray
    omega0: float
    bn: np.ndarray
    pn: np.ndarray

    def freqresp(self, f_hz) -> np.ndarray:
        """Complex response of the fitted model.

        Parameters
        ----------
        f_hz : array_like
            Frequencies [Hz].

        Returns
        -------
        ndarray
            Response [SI].
        """
        f = np.asarray(f_hz, dtype=float)
        return _model(f, self.bn, self.pn, self.omega0, self.n_integrators, self.delay_s)

    @property
    def poles(self) -> np.ndarray:
        """Poles including integrators, sorted by magnitude [rad/s]."""
        p = np.concatenate([self.pn * self.omega0, np.zeros(self.n_integrators)])
        return p[np.argsort(np.abs(p))]

    @property
    def zeros(self) -> np.ndarray:
        """Zeros, sorted by magnitude [rad/s]."""
        z = np.roots(np.trim_zeros(self.bn[::-1], "f")) * self.omega0
        return z[np.argsort(np.abs(z))]

    @property
    def is_stable(self) -> bool:
        """True if no pole lies in the open right half plane (integrators allowed) [-]."""
        return bool(np.all(self.pn.real < 0))

    @property
    def natural_freq_hz(self) -> np.ndarray:
        """Undamped natural frequencies of the complex pole pairs, ascending [Hz]."""
        p = _pairs(self.poles)
        return np.abs(p) / (2 * np.pi)

    @property
    def damping(self) -> np.ndarray:
        """Damping ratios of the complex pole pairs, same order as natural_freq_hz [-]."""
        p = _pairs(self.poles)
        return -p.real / np.abs(p)

    @property
    def aic(self) -> float:
        """Akaike information criterion of the weighted fit [-]."""
        m = 2 * self.freq_hz.size
        return m * np.log(self.cost / m) + 2 * self.n_params

    @property
    def bic(self) -> float:
        """Bayesian information criterion of the weighted fit [-]."""
        m = 2 * self.freq_hz.size
        return m * np.log(self.cost / m) + self.n_params * np.log(m)

    def to_control(self, pade_order="auto"):
        """The fit as a :class:`control.TransferFunction`, its delay included.

        Parameters
        ----------
        pade_order : int or "auto"
            Order of the Pade approximation of the delay; ``"auto"`` takes the smallest
            that holds the relative error below 1e-3 over the band fitted
            (:func:`~tcpmm.pade.pade_order`); 0 leaves the delay out (read it
            from ``delay_s``) [-].

        Returns
        -------
        control.TransferFunction
            Continuous-time transfer function [SI].
        """
        import control  # python-control is slow to import and needed only here

        tf = control.TransferFunction(self.num, self.den)
        return with_delay(tf, self.delay_s, float(self.freq_hz[-1]), pade_order)

    def to_pandas(self):
        """Pole table: one row per real pole or complex pair.

        Returns
        -------
        pandas.DataFrame
            Columns ``kind, freq_hz, damping, real_rad_s, imag_rad_s`` [-].
        """
        import pandas as pd

        rows = []
        for p in self.poles:
            if p.imag < 0:
                continue
            w = abs(p)
            rows.append(
                {
                    "kind": "pair" if p.imag > 0 else ("integrator" if w == 0 else "real"),
                    "freq_hz": w / (2 * np.pi),
                    "damping": -p.real / w if w > 0 else np.nan,
                    "real_rad_s": p.real,
                    "imag_rad_s": p.imag,
                }
            )
        return pd.DataFrame(
            rows, columns=["kind", "freq_hz", "damping", "real_rad_s", "imag_rad_s"]
        )


def _parse_data(data, weight, min_coherence=0.0):
    """Frequencies, response and weights of the bins to fit (weight > 0), sorted."""
    if isinstance(data, FRF):
        f, H = data.freq_hz, data.H
        if weight is None:
            w = 1.0 / np.sqrt(data.rel_std**2 + WEIGHT_FLOOR**2)
            w = np.where(data.coherence >= min_coherence, w, 0.0)
        else:
            w = weight
    else:
        try:
            parts = tuple(data)
        except TypeError:
            raise InputError("fit_tf needs an FRF or a tuple (freq_hz, H[, weight])") from None
        if len(parts) not in (2, 3):
            raise InputError("fit_tf needs an FRF or a tuple (freq_hz, H[, weight])")
        f, H = parts[0], parts[1]
        w = parts[2] if len(parts) == 3 else weight
    f = np.asarray(f, dtype=float)
    H = np.asarray(H, dtype=complex)
    if f.ndim != 1 or H.shape != f.shape:
        raise InputError(f"frequency ({f.shape}) and response ({H.shape}) must be matching 1-D")
    w = np.ones(f.size) if w is None else np.asarray(w, dtype=float)
    if w.shape not in ((), f.shape):
        raise InputError(f"{w.size} weights for {f.size} bins", column="weight")
    w = np.broadcast_to(w, f.shape).copy()
    for name, a in (("freq_hz", f), ("weight", w)):
        bad = np.flatnonzero(~np.isfinite(a))
        if bad.size:
            raise InputError(f"{name} is not finite at bin {bad[0]}", column=name)
    if np.any(f <= 0):
        raise InputError("frequencies must be > 0", column="freq_hz")
    if np.any(w < 0) or not np.any(w > 0):
        raise InputError("weights must be >= 0 and not all zero", column="weight")
    bad = np.flatnonzero((w > 0) & ~np.isfinite(H))
    if bad.size:
        raise InputError(
            f"H is not finite at bin {bad[0]}; remove the bin or give it weight 0", column="H"
        )
    keep = w > 0
    f, H, w = f[keep], H[keep], w[keep]
    if np.any(H == 0):
        raise InputError(
            "the response is exactly zero at some bins: a relative fit cannot use them", column="H"
        )
    order = np.argsort(f)
    return f[order], H[order], w[order]


# ----------------------------------------------------------------------------- fitting


def fit_tf(
    data,
    n_num: int,
    n_den: int,
    n_integrators: int = 0,
    delay_s=None,
    weight=None,
    stable: bool = True,
    iterations: int = 30,
    nlls: bool = True,
    max_delay_s: float | None = None,
    max_nfev: int = 200,
    min_coherence: float = 0.5,
) -> TFFit:
    """Fit ``B(s) / (A(s) s^k) exp(-s tau)`` to a frequency response.

    Parameters
    ----------
    data : FRF or tuple
        An :class:`~tcpmm.ident.frf.response.FRF`, or ``(freq_hz, H)`` or ``(freq_hz, H, weight)``
        with frequencies [Hz], complex response [SI] and bin weights [-].
    n_num : int
        Numerator degree [-].
    n_den : int
        Denominator degree, not counting the integrators [-].
    n_integrators : int
        Known integrators ``1/s^k`` factored out of the data before fitting [-].
    delay_s : None, float or "fit"
        Pure delay: None (none), a known value [s], or ``"fit"`` to estimate it [s].
    weight : array_like, optional
        Bin weights overriding the default (from the FRF's ``rel_std``, else uniform); bins
        of weight 0 are left out [-].
    stable : bool
        Keep every pole of ``A`` in the left half plane [-].
    iterations : int
        Maximum Sanathanan-Koerner iterations [-].
    nlls : bool
        Refine by nonlinear least squares after the linear stage [-].
    max_delay_s : float, optional
        Largest delay tried when ``delay_s="fit"``; default ``1 / f_max`` (one full turn
        of phase at the top of the band) [s].
    max_nfev : int
        Largest number of residual evaluations of the nonlinear least squares [-].
    min_coherence : float
        With an FRF and default weights, bins of lower coherence are left out: their
        relative error is no longer small, and dividing by a noisy ``H`` misleads [-].

    Returns
    -------
    TFFit
        The fitted model and its quality [-].
    """
    limit_blas_threads()
    f, H, w = _parse_data(data, weight, min_coherence)
    n_num, n_den, k = int(n_num), int(n_den), int(n_integrators)
    fit_delay = _check_structure(n_num, n_den, k, delay_s)
    n_params = n_num + 1 + n_den + int(fit_delay)
    if 2 * f.size <= n_params:
        raise InputError(f"{f.size} weighted bins cannot determine {n_params} parameters")
    omega0 = 2 * np.pi * float(np.sqrt(f[0] * f[-1]))
    s = 2j * np.pi * f
    x = s / omega0
    Hk = H * x**k

    starts = _linear_starts(f, H, x, k, n_num, n_den, omega0)

    def linear_stage(tau, start, sel=slice(None), n_iter=iterations):
        Hd = Hk[sel] * np.exp(s[sel] * tau)
        bn, an = _sk(x[sel], Hd, w[sel], start[1], n_den, n_iter, start[0])
        pn = np.roots(an[::-1])
        if stable:
            pn = _reflect(pn)
        bn = _numerator(x[sel], Hd, w[sel], pn, n_num)
        return bn, pn, _relative_cost(f[sel], H[sel], w[sel], bn, pn, omega0, k, tau)

    if fit_delay:
        tau = _coarse_delay(f, max_delay_s, starts, linear_stage, iterations)
    else:
        tau = 0.0 if delay_s is None else float(delay_s)
    # refine the starts in order of their linear cost; a start more than REFINE_RATIO times
    # worse than the best refined fit so far is not worth refining
    linear = sorted((linear_stage(tau, st) for st in starts), key=lambda c: c[2])
    best = (*linear[0][:2], tau, linear[0][2])
    if nlls and (n_den > 0 or fit_delay):
        best = None
        for bn, pn, cost in linear:
            if best is not None and cost > REFINE_RATIO * best[3]:
                continue
            cand = _refine(
                f, H, w, omega0, k, n_num, stable, fit_delay, bn, pn, tau, cost, max_nfev
            )
            if best is None or cand[3] < best[3]:
                best = cand
    bn, pn, tau, cost = best
    return _result(f, H, w, bn, pn, omega0, k, tau, n_num, n_den, n_params, cost)


def _coarse_delay(f, max_delay_s, starts, linear_stage, iterations: int) -> float:
    """Coarse search of the delay on at most ~400 bins with a few SK steps each: the best
    of eleven delays up to ``max_delay_s`` (default one period of the top bin) [s]."""
    tmax = 1.0 / f[-1] if max_delay_s is None else float(max_delay_s)
    grid = np.linspace(0.0, tmax, 11)
    sub = slice(None, None, max(1, f.size // 400))
    costs = [
        min(linear_stage(t, st, sub, min(iterations, 6))[2] for st in starts) for t in grid
    ]
    return float(grid[int(np.argmin(costs))])


def _check_structure(n_num: int, n_den: int, k: int, delay_s) -> bool:
    """Raise for negative orders, more zeros than poles, or a delay that is neither
    ``None``, a time nor ``"fit"``; whether the delay is fitted [-]."""
    if n_num < 0 or n_den < 0 or k < 0:
        raise InputError("orders and number of integrators must be >= 0")
    if n_num > n_den + k:
        raise InputError(
            f"{n_num} zeros over {n_den + k} poles make an improper model (its response grows "
            "without bound and it has no state space); fit at most as many zeros as poles"
        )
    fit_delay = isinstance(delay_s, str)
    if fit_delay and delay_s != "fit":
        raise InputError(f"delay_s must be None, a number or 'fit', got {delay_s!r}")
    if not fit_delay and delay_s is not None and (not np.isfinite(delay_s) or delay_s < 0):
        raise InputError(f"delay must be >= 0 s, got {delay_s}")
    return fit_delay


def _linear_starts(f, H, x, k: int, n_num: int, n_den: int, omega0: float) -> list:
    """Starts of the linear stage as (start poles, numerator degree of the SK
    iterations): Levy's (A = 1), spread poles, poles at resonance peaks, and Levy's with
    two zeros fewer (surplus zeros can lead SK into a basin with a spurious pole-zero
    pair) [-]."""
    starts = [(None, n_num)]
    if n_den > 0:
        starts.append((_spread_poles(n_den, x[0].imag, x[-1].imag), n_num))
    if n_den >= 2:
        starts.append((_peak_poles(f, H, k, n_den, omega0), n_num))
    if n_num >= 2 and n_den > 0:
        starts.append((None, n_num - 2))
    return starts


def _proper(f, H, w, bn, pn, omega0, k, tau, n_num, n_den, n_params, cost):
    """Fold poles far beyond the band into the gain and keep the model proper.

    Such a pole acts as a constant gain over the band, but dropping it (or a pole the
    linear stage lost to a vanishing leading coefficient) leaves fewer poles under a
    numerator of the same degree: an improper model, with no state space. The numerator
    is then fitted again with at most as many zeros as poles are left (integrators
    included), and cost and parameter count follow the model kept.

    Returns
    -------
    tuple
        ``(bn, pn, n_num, n_params, cost)`` [-].
    """
    xmax = 2 * np.pi * f[-1] / omega0
    pn = pn[np.abs(pn) <= FAR_POLE * xmax]
    if pn.size == n_den:
        return bn, pn, n_num, n_params, cost
    new_num = min(n_num, pn.size + k)
    x = 2j * np.pi * f / omega0
    bn = _numerator(x, H * x**k * np.exp(x * omega0 * tau), w, pn, new_num)
    n_params -= (n_den - pn.size) + (n_num - new_num)
    cost = _relative_cost(f, H, w, bn, pn, omega0, k, tau)
    return bn, pn, new_num, n_params, cost


def _result(f, H, w, bn, pn, omega0, k, tau, n_num, n_den, n_params, cost):
    bn, pn, n_num, n_params, cost = _proper(
        f, H, w, bn, pn, omega0, k, tau, n_num, n_den, n_params, cost
    )
    n_den = pn.size
    # conjugate pairs exactly conjugate, real poles exactly real
    pn = np.where(np.abs(pn.imag) <= 1e-12 * np.abs(pn), pn.real + 0j, pn)
    pn = pn[np.lexsort((pn.imag, np.abs(pn)))]
    h = _model(f, bn, pn, omega0, k, tau)
    fit = fit_percent(H, h)
    rel = rel_error(H, h)
    # physical coefficients: x = s / omega0, B(x) / (prod(x - pn) x^k)
    num = (bn * omega0 ** -np.arange(bn.size))[::-1]
    den = np.r_[np.real(np.poly(pn * omega0)), np.zeros(k)]
    num = num * omega0 ** (pn.size + k)
    num = np.trim_zeros(num, "f") if np.any(num) else np.zeros(1)
    return TFFit(
        num=num,
        den=den,
        delay_s=float(tau),
        n_num=n_num,
        n_den=n_den,
        n_integrators=k,
        fit_percent=float(fit),
        rel_error=rel,
        cost=float(cost),
        n_params=n_params,
        freq_hz=f,
        H=H,
        weight=w,
        omega0=omega0,
        bn=bn,
        pn=pn,
    )


# ----------------------------------------------------------------------------- order


def suggest_order(
    data,
    max_order: int = 12,
    n_integrators: int = 0,
    delay_s=None,
    prominence_db: float = 3.0,
    criterion: str = "bic",
    refine: int = 4,
    min_coherence: float = 0.5,
) -> tuple[int, int]:
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
    f, H, w = _parse_data(data, None, min_coherence)
    if isinstance(data, FRF):
        sel = np.isin(data.freq_hz, f)
        coh, rel = data.coherence[sel], data.rel_std[sel]
    else:
        coh, rel = np.ones(f.size), None
    peaks, dips = _extrema(f, H, coh, int(n_integrators), prominence_db, rel_std=rel)
    n_den0 = min(max(2 * len(peaks), 1), max_order)
    n_num0 = min(2 * len(dips), n_den0)
    kw = dict(n_integrators=n_integrators, delay_s=delay_s, min_coherence=min_coherence)
    # screen on at most ~500 of the bins, with the delay of one fit at the counted order
    screen = dict(kw)
    stride = max(1, f.size // 500)
    screen_data = (f[::stride], H[::stride], w[::stride])
    if delay_s == "fit":
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
    # refine the most promising candidates by the full fit (ties: lower order first)
    cands.sort()
    # a lightly damped mode outside the band is not supported by the data: such candidates
    # only count if no other is left
    fitted = []
    for _, n_den, n_num in sorted(cands[:refine], key=lambda c: (c[1], c[2])):
        fit = fit_tf(data, n_num, n_den, **kw)
        ic = fit.bic if criterion == "bic" else fit.aic
        fn, zeta = fit.natural_freq_hz, fit.damping
        outside = np.any((zeta < 0.2) & ((fn < f[0]) | (fn > f[-1])))
        # a fit that folded far poles into the gain is the lower order it kept
        fitted.append((bool(outside), ic, fit.n_den, fit.n_num))
    best = min(fitted, key=lambda c: (c[0], c[1]))
    return best[3], best[2]
