"""The result of a rational fit: :class:`TFFit`, built from the poles and numerator in the
normalised frequency ``x = s / omega_0`` by :func:`tf_result`, which also keeps the model
proper when poles far beyond the band are folded into the gain."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...pade import with_delay
from ._tfcore import fit_numerator, relative_cost, tf_response, upper_pairs
from .goodness import fit_percent, rel_error

__all__ = ["FAR_EFFECT", "TFFit", "tf_result"]

#: A pole (a pair together) that changes the response at the top of the band by less than
#: this part of it acts there as a constant and is folded into the gain [-]. Kept, it lets
#: the numerator hold as many more zeros, which no bin sees: between the band and the pole
#: the response grows with them, by the square of the pole's distance for a pair (a pair
#: 6.5e4 times above the band, damping 1e-4, grew the fit 700-fold a decade above it).
#: 1e-4 is below the noise of any measured bin (a coherence of 0.9999 over 10 averages
#: leaves 2e-3), so the response over the band keeps all the data tell.
FAR_EFFECT = 1e-4


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
        return tf_response(f, self.bn, self.pn, self.omega0, self.n_integrators, self.delay_s)

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
        p = upper_pairs(self.poles)
        return np.abs(p) / (2 * np.pi)

    @property
    def damping(self) -> np.ndarray:
        """Damping ratios of the complex pole pairs, same order as natural_freq_hz [-]."""
        p = upper_pairs(self.poles)
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
    pn = pn[_in_band_effect(pn, 2j * np.pi * f[-1] / omega0) >= FAR_EFFECT]
    if pn.size == n_den:
        return bn, pn, n_num, n_params, cost
    new_num = min(n_num, pn.size + k)
    x = 2j * np.pi * f / omega0
    bn = fit_numerator(x, H * x**k * np.exp(x * omega0 * tau), w, pn, new_num)
    n_params -= (n_den - pn.size) + (n_num - new_num)
    cost = relative_cost(f, H, w, bn, pn, omega0, k, tau)
    return bn, pn, new_num, n_params, cost


def _in_band_effect(pn, x):
    """How much each pole changes the response at ``x``: ``|D(x) - 1|`` of its factor
    ``D = 1 - x / p``, or of the pair's ``(1 - x / p)(1 - x / conj(p))``, whose first-order
    terms cancel to the damping's [-]."""
    with np.errstate(divide="ignore", invalid="ignore"):
        single = np.abs(x / pn)
        pair = np.abs((1 - x / pn) * (1 - x / np.conj(pn)) - 1)
    effect = np.where(np.abs(pn.imag) > 1e-12 * np.abs(pn), pair, single)
    # a pole at the origin (an integrator the linear stage found) is no far pole
    return np.where(np.isfinite(effect), effect, np.inf)


def tf_result(f, H, w, bn, pn, omega0, k, tau, n_num, n_den, n_params, cost):
    bn, pn, n_num, n_params, cost = _proper(
        f, H, w, bn, pn, omega0, k, tau, n_num, n_den, n_params, cost
    )
    n_den = pn.size
    # conjugate pairs exactly conjugate, real poles exactly real
    pn = np.where(np.abs(pn.imag) <= 1e-12 * np.abs(pn), pn.real + 0j, pn)
    pn = pn[np.lexsort((pn.imag, np.abs(pn)))]
    h = tf_response(f, bn, pn, omega0, k, tau)
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
