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

import numpy as np

from ..._threads import limit_blas_threads
from ...errors import InputError
from ...frfdata import FRF
from ._tfcore import (
    fit_numerator,
    peak_poles,
    refine_vp,
    reflect_poles,
    relative_cost,
    sanathanan_koerner,
    spread_poles,
)
from .tfresult import TFFit, tf_result

__all__ = ["TFFit", "fit_data", "fit_tf"]

#: Relative error floor added to the FRF's random error when weighting bins.
WEIGHT_FLOOR = 0.01
#: Starts of the linear stage this many times costlier than the best fit are not refined.
REFINE_RATIO = 3.0


def fit_data(data, weight, min_coherence=0.0):
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


def fit_tf(data, n_num: int, n_den: int, n_integrators: int = 0, delay_s=None, weight=None,
           stable: bool = True, iterations: int = 30, nlls: bool = True,
           max_delay_s: float | None = None, max_nfev: int = 200,
           min_coherence: float = 0.5) -> TFFit:
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
    f, H, w = fit_data(data, weight, min_coherence)
    n_num, n_den, k = int(n_num), int(n_den), int(n_integrators)
    fit_delay, n_params = _check_structure(n_num, n_den, k, delay_s, f)
    omega0 = 2 * np.pi * float(np.sqrt(f[0] * f[-1]))
    starts = _linear_starts(f, H, 2j * np.pi * f / omega0, k, n_num, n_den, omega0)
    linear_stage = _linear_stage(f, H, w, omega0, k, n_num, n_den, stable, iterations)
    if fit_delay:
        tau = _coarse_delay(f, max_delay_s, starts, linear_stage, iterations)
    else:
        tau = 0.0 if delay_s is None else float(delay_s)
    linear = sorted((linear_stage(tau, st) for st in starts), key=lambda c: c[2])
    best = (*linear[0][:2], tau, linear[0][2])
    if nlls and (n_den > 0 or fit_delay):
        best = _best_refined(linear, f, H, w, omega0, k, n_num, stable, fit_delay, tau,
                             max_nfev)
    bn, pn, tau, cost = best
    return tf_result(f, H, w, bn, pn, omega0, k, tau, n_num, n_den, n_params, cost)


def _linear_stage(f, H, w, omega0: float, k: int, n_num: int, n_den: int, stable: bool,
                  iterations: int):
    """The linear stage as a function of the delay, the start, the bins used and the SK
    iterations: Sanathanan-Koerner from the start, poles reflected into the left half
    plane when ``stable``, numerator fitted to them; it returns ``(bn, pn, cost)`` [-]."""
    s = 2j * np.pi * f
    x = s / omega0
    Hk = H * x**k
    # the powers of x the SK iterations weight, per selection of bins: the same for
    # every delay and start
    powers = {}

    def linear_stage(tau, start, sel=slice(None), n_iter=iterations):
        Hd = Hk[sel] * np.exp(s[sel] * tau)
        key = (sel.start, sel.stop, sel.step)
        if key not in powers:
            powers[key] = x[sel][:, None] ** np.arange(max(n_num, n_den) + 1)
        bn, an = sanathanan_koerner(x[sel], Hd, w[sel], start[1], n_den, n_iter, start[0],
                                    powers[key])
        pn = np.roots(an[::-1])
        if stable:
            pn = reflect_poles(pn)
        bn = fit_numerator(x[sel], Hd, w[sel], pn, n_num)
        return bn, pn, relative_cost(f[sel], H[sel], w[sel], bn, pn, omega0, k, tau)

    return linear_stage


def _best_refined(linear: list, f, H, w, omega0: float, k: int, n_num: int, stable: bool,
                  fit_delay: bool, tau: float, max_nfev: int) -> tuple:
    """Refine the linear fits ``(bn, pn, cost)`` in order of their cost by nonlinear least
    squares and keep the best ``(bn, pn, tau, cost)``; a start more than ``REFINE_RATIO``
    times worse than the best refined fit so far is not worth refining [-]."""
    best = None
    for bn, pn, cost in linear:
        if best is not None and cost > REFINE_RATIO * best[3]:
            continue
        cand = refine_vp(f, H, w, omega0, k, n_num, stable, fit_delay, bn, pn, tau, cost, max_nfev)
        if best is None or cand[3] < best[3]:
            best = cand
    return best


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


def check_order_in_range(freq_hz, order: int) -> None:
    """Refuse an order whose powers of the band's frequencies (about its middle) pass the
    largest floating-point number: the fit's matrices would hold inf and NaN, and its
    singular value decomposition fail.

    Parameters
    ----------
    freq_hz : ndarray
        The fitted bins' frequencies, increasing [Hz].
    order : int
        Highest power of the frequency in the model [-].
    """
    decades = np.log10(freq_hz[-1] / freq_hz[0])
    if order * decades / 2 >= 300:  # float64 ends at 1.8e308
        raise InputError(f"{order} poles over {decades:.2g} decades of frequency "
                         f"({freq_hz[0]:g}-{freq_hz[-1]:g} Hz) pass the range of the numbers "
                         f"the fit computes with; at most {int(599 / decades)} poles, or a "
                         "narrower band")


#: Smallest singular value, relative to the largest, of the bins' powers of the frequency
#: (each scaled to unit length) at which the highest power still counts as told apart from
#: the lower ones: about five times the round-off of a double (2.2e-16) [-].
RESOLVED = 1e-15


def _powers_resolved(x, n: int) -> bool:
    """Whether the powers ``x^0 .. x^n`` of the bins are told apart to :data:`RESOLVED` [-]."""
    v = x[:, None] ** np.arange(n + 1)
    m = np.vstack([v.real, v.imag])
    sv = np.linalg.svd(m / np.linalg.norm(m, axis=0), compute_uv=False)
    return sv.size == n + 1 and sv[-1] > RESOLVED * sv[0]


def check_order_resolved(freq_hz, order: int) -> None:
    """Refuse a pole count whose powers of the frequency the bins do not tell apart.

    The fit's linear stage solves for the coefficients of the powers of ``s`` up to the
    order over the bins; beyond some power (about 40 over three decades, whatever the
    number of bins) a power equals a combination of the lower ones to round-off. The
    coefficients are then not determined (on the Sinumerik trace, a fit of 199 poles keeps
    none; one of 80 keeps real poles down to 2e-128 Hz and a static gain of 4e145). Also
    refuses what :func:`check_order_in_range` does, with the count resolved.

    Parameters
    ----------
    freq_hz : ndarray
        The fitted bins' frequencies, increasing [Hz].
    order : int
        Highest power of the frequency in the model [-].
    """
    f = np.asarray(freq_hz, float)
    decades = np.log10(f[-1] / f[0])
    x = 1j * f / np.sqrt(f[0] * f[-1])
    top = min(order, int(599 / decades) if decades > 0 else order, f.size - 1)
    if top in (order, f.size - 1) and _powers_resolved(x, top):
        return  # more poles than the bins hold: the count of parameters refuses them
    lo, hi = 0, top  # the most powers resolved, by bisection: more never resolve again
    while lo < hi:
        mid = (lo + hi + 1) // 2
        lo, hi = (mid, hi) if _powers_resolved(x, mid) else (lo, mid - 1)
    raise InputError(f"{order} poles over {decades:.2g} decades of frequency ({f[0]:g}-"
                     f"{f[-1]:g} Hz): beyond the power {lo} of the frequency, the {f.size} "
                     "bins do not tell the powers the fit solves for apart (a power equals "
                     "a sum of the lower ones to the round-off), so its coefficients are not "
                     f"determined; at most {lo} poles")


def _check_structure(n_num: int, n_den: int, k: int, delay_s, freq_hz) -> tuple:
    """Raise for negative orders, more zeros than poles, a delay that is neither ``None``,
    a time nor ``"fit"``, more parameters than the bins ``freq_hz`` determine, or an order
    past the range of the numbers; whether the delay is fitted and the number of
    parameters [-]."""
    n_bins = freq_hz.size
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
    n_params = n_num + 1 + n_den + int(fit_delay)
    if 2 * n_bins <= n_params:
        raise InputError(f"{n_bins} weighted bins cannot determine {n_params} parameters")
    check_order_in_range(freq_hz, max(n_num, n_den + k))
    return fit_delay, n_params


def _linear_starts(f, H, x, k: int, n_num: int, n_den: int, omega0: float) -> list:
    """Starts of the linear stage as (start poles, numerator degree of the SK
    iterations): Levy's (A = 1), spread poles, poles at resonance peaks, and Levy's with
    two zeros fewer (surplus zeros can lead SK into a basin with a spurious pole-zero
    pair) [-]."""
    starts = [(None, n_num)]
    if n_den > 0:
        starts.append((spread_poles(n_den, x[0].imag, x[-1].imag), n_num))
    if n_den >= 2:
        starts.append((peak_poles(f, H, k, n_den, omega0), n_num))
    if n_num >= 2 and n_den > 0:
        starts.append((None, n_num - 2))
    return starts
