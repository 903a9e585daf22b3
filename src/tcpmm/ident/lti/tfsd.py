"""Standard deviations of a fitted transfer function's physical parameters, linearised.

The parameters said are those a user tunes on: each complex pole pair's natural frequency
``f_n`` [Hz] and damping ratio ``zeta`` [-], each real pole's corner frequency ``|p| / 2 pi``
[Hz], the delay [s] where it was fitted, and the static gain ``lim s^k H(s)`` at ``s = 0``
where the numerator has a constant term. The numerator's coefficients are parameters of the
fit as well: they stay in the Jacobian, so that what they trade with a pole widens its
spread, and are reported through the zeros they place (:mod:`~tcpmm.ident.lti.zerosd`).

The model is written in these parameters, ``B(x) / (prod_i (x^2 + 2 zeta_i W_i x + W_i^2)
prod_j (x + R_j) x^k) exp(-s tau)`` with ``x = s / omega_0``, ``W = 2 pi f_n / omega_0`` and
``R = 2 pi f_r / omega_0``, and the Jacobian ``J`` of the weighted residual
``r = w (H_model / H - 1)`` (real and imaginary parts stacked) is taken analytically at the
solution. The weights ``w`` the fit used are not always ``1 / sigma`` (the 1 % weight floor,
the weights by ``|H|``), so the covariance is that of the weighted least-squares estimate
under each residual row's noise ``n = w sigma``::

    C = A+ J^T diag(n^2) J A+,    A = J^T J,

which is ``pinv(J_s^T J_s)`` with ``J_s`` the Jacobian of the residual in noise units where
``w`` is proportional to ``1 / sigma``.

The noise ``sigma`` here is measured on the relative residual, bin by bin (the running
median of the squared residual, each bin's over ``1 - leverage``), then weighted; it is not
taken from the bins' noise the fit weighs by: the roughness that sets that noise counts a
resonance's own curvature as noise, 2.5 times the true noise at a mode of damping 0.03 on
400 bins from 10 Hz to 2 kHz, which would widen exactly the spreads that matter. Where the
fit is worse than the noise, the residual holds the misfit as well: the spread grows by
the local ``chi2`` ratio, bin by bin, as a covariance scaled by the global ``chi2_ratio``
would grow everywhere; a residual at or below the noise leaves the noise.

A parameter is *determined* where its standard deviation is at most :data:`DETERMINED` of
its value: beyond that a ``±`` would span values of another meaning (a mode of half or
twice the frequency, a damping of either sign). With the Jacobian's columns scaled to unit
norm, a singular value below :data:`SINGULAR` of the largest is a direction the bins do
not see; a parameter that moves along it has no finite standard deviation (a pole pair
its own zeros cancel), and one it leaves alone keeps its own (the gain they leave).

Some values are said undetermined whatever their linearised sd, each with the reason in
:attr:`TFDeviations.notes`, since a ``±`` there would be a confident wrong number:

* the delay: refits through other noise at the same order spread about 4 times the
  linearised sd (up to 9 times), so it bounds nothing: it trades with the numerator's
  zeros above the band, which lag like a delay in the right half-plane and lead in the
  left, and which side they take is a choice between solutions that no linearisation
  at one of them sees;
* a mode or real pole whose frequency lies outside the fitted bins: the bins see only the
  tail of its response, which a numerator term gives as well (a 150 Hz mode fitted from
  300 Hz up came out at 256 Hz with a sd of a few Hz);
* a zero outside the fitted bins, likewise (:mod:`~tcpmm.ident.lti.zerosd`);
* the static gain where a pole or zero lies below the band's lowest bin: it is then an
  extrapolation to 0 Hz through a corner no bin saw (the same fit gave -0.077 +- 0.009
  for a gain of 3);
* with the delay held (none, or a value given), a value that moves by more than 3 of its
  sd when the delay is left free, where the data suggest another delay: these sds are
  linearised at the delay held and hold only for it (:mod:`~tcpmm.ident.lti.delayheld`,
  which :func:`~tcpmm.ident.lti.frffit.fit_frf` applies);
* everything where the ``chi2`` ratio exceeds :data:`MISFIT`: the model misses the data by
  ten times the noise, and the spread of a model that does not describe the data is no
  spread of the data's parameters.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ._tfcore import upper_pairs
from ._tfestimate import DETERMINED, Estimate
from .frfnoise import NOISE_WINDOW
from .zerosd import outside_note, zero_estimates

__all__ = ["DETERMINED", "MISFIT", "SINGULAR", "Estimate", "TFDeviations", "tf_deviations"]

#: Relative singular value below which a direction of the Jacobian is not in the data [-].
SINGULAR = 1e-9
#: Component of a parameter in a direction not in the data that leaves it unbounded [-].
IN_NULL = 1e-2
#: ``chi2`` ratio above which a fit is said not to describe the data: a residual ten
#: times the noise is the model's error, not the noise's, and no sd bounds it [-].
MISFIT = 100.0
#: Why the delay carries no sd (refits of 8 draws of a two-mode system with a real pole
#: and a 0.3 ms delay, 2 % noise, all of 5 poles and 4 zeros: 3.8 times the sd; the
#: zeros, 2.3-7 kHz above a band to 2 kHz, lag as a delay does in the right half-plane
#: and lead in the left, and the draws put them on either side) [-].
DELAY_OPEN = ("the delay: not bounded by the linearised fit; it trades with zeros above "
              "the band, which refits through other noise put in either half-plane, and "
              "spreads about 4 times its linearised sd, up to 9 times, at the same order")


@dataclass(frozen=True)
class TFDeviations:
    """Standard deviations of the physical parameters of a fit (see the module).

    Parameters
    ----------
    modes : list of tuple of Estimate
        ``(natural frequency [Hz], damping ratio [-])`` per complex pole pair, ascending as
        :attr:`TFFit.natural_freq_hz` [-].
    real_poles : list of Estimate
        Corner frequency ``|p| / 2 pi`` of each real pole, ascending [Hz].
    delay : Estimate or None
        The delay, where it was fitted [s].
    gain : Estimate or None
        ``lim s^k H(s)`` at ``s = 0``, where the numerator has a constant term
        [unit (rad/s)^k].
    notes : list of str, optional
        Why values are undetermined beyond their sd, each reason once [-].
    describes_data : bool, optional
        False where the ``chi2`` ratio exceeds :data:`MISFIT` [-].
    zeros : list of ZeroEstimate, optional
        Each zero pair's frequency and damping, each real zero's corner, ascending as
        :attr:`TFFit.zeros` (:mod:`~tcpmm.ident.lti.zerosd`) [-].
    """

    modes: list
    real_poles: list
    delay: Estimate | None
    gain: Estimate | None
    notes: list = field(default_factory=list)
    describes_data: bool = True
    zeros: list = field(default_factory=list)

    def by_row(self, kinds) -> list:
        """``(frequency, damping)`` estimates for the rows of a pole table of ``kinds``
        (``"pair"``, ``"real"``, ``"integrator"``, ascending in magnitude as
        :meth:`TFFit.to_pandas` gives them); None where the row has no such estimate [-]."""
        pairs, reals = iter(self.modes), iter(self.real_poles)
        return [next(pairs, (None, None)) if k == "pair" else
                (next(reals, None), None) if k == "real" else (None, None) for k in kinds]

    def to_dict(self) -> dict:
        """``modes``, ``real_poles``, ``zero_pairs``, ``real_zeros``, ``delay``, ``gain`` and
        how the covariance was scaled, each parameter with its sd (None where unbounded) and
        whether it is determined [-]."""
        return {
            "modes": [{**f.to_dict("freq_hz"), **z.to_dict("damping")} for f, z in self.modes],
            "real_poles": [r.to_dict("freq_hz") for r in self.real_poles],
            "zero_pairs": [z.to_dict() for z in self.zeros if z.kind == "pair"],
            "real_zeros": [z.to_dict() for z in self.zeros if z.kind == "real"],
            "delay": None if self.delay is None else self.delay.to_dict("delay_s"),
            "gain": None if self.gain is None else self.gain.to_dict("gain"),
            "uncertainty": {"method": "linearised: sandwich covariance of the weighted fit, "
                                      "the noise measured on the residual",
                            "relative_sd_determined": DETERMINED,
                            "chi2_ratio_misfit": MISFIT,
                            "describes_data": self.describes_data,
                            "notes": list(self.notes)},
        }


def _split_poles(pn: np.ndarray) -> tuple:
    """Upper poles of the complex pairs and the real poles (as reals), each ascending in
    magnitude, in ``x`` [-]."""
    pairs = upper_pairs(pn)
    cplx = np.abs(pn.imag) > 1e-9 * np.maximum(np.abs(pn), 1e-300)
    return pairs, np.sort(-pn[~cplx].real)


def _jacobian(fit, pairs, reals, fit_delay: bool) -> np.ndarray:
    """``d r / d theta`` for ``theta = (f_n, zeta per pair, f_r per real pole, numerator
    coefficients, delay if fitted)``, rows the real then the imaginary parts [-]."""
    f, omega0, k = fit.freq_hz, fit.omega0, fit.n_integrators
    s = 2j * np.pi * f
    x = s / omega0
    h = fit.freqresp(f)
    g = fit.weight * h / fit.H  # d r = g d ln(h)
    cols = []
    for p in pairs:
        W, zeta = abs(p), -p.real / abs(p)
        D = x * x + 2 * zeta * W * x + W * W
        cols += [-g * (2 * zeta * x + 2 * W) / D * (2 * np.pi / omega0), -g * 2 * W * x / D]
    cols += [-g / (x + R) * (2 * np.pi / omega0) for R in reals]
    den = np.prod([x - p for p in fit.pn], axis=0) * x**k * np.exp(s * fit.delay_s)
    with np.errstate(divide="ignore", invalid="ignore"):
        cols += [fit.weight * x**j / (den * fit.H) for j in range(fit.bn.size)]
    if fit_delay:
        cols.append(-g * s)
    J = np.array(cols).T.reshape(f.size, -1)
    return np.vstack([J.real, J.imag])


def _decompose(J: np.ndarray) -> tuple:
    """SVD of ``J`` with its columns scaled to unit norm: ``(U, sv, Vt, keep, norm)``,
    ``keep`` the directions the bins see (:data:`SINGULAR`); a column of zeros, a
    parameter the bins do not move, is scaled by 1 [-]."""
    norm = np.linalg.norm(J, axis=0)
    norm = np.where(norm > 0, norm, 1.0)
    U, sv, Vt = np.linalg.svd(J / norm, full_matrices=False)
    keep = sv > SINGULAR * sv[0] if sv.size and sv[0] > 0 else np.zeros(sv.size, bool)
    return U, sv, Vt, keep, norm


def _residual_noise(fit, U: np.ndarray, keep: np.ndarray) -> np.ndarray:
    """Noise of each residual row (``w`` times that of ``dH / H``), measured on the
    relative residual: each bin's squared residual over ``1 - leverage`` (a fit of ``p``
    parameters leaves less than the noise where they are decided, at the resonances most),
    real and imaginary parts averaged, the running median of :data:`NOISE_WINDOW` bins
    divided by ``ln 2`` (the median of an exponential variate of mean 1), then weighted.
    The median is taken before the weights: weights by ``|H|`` peak at the modes over
    fewer bins than the window, and a median of the weighted residual flattened the peak
    where the modes are decided [-]."""
    from scipy.ndimage import median_filter

    e = fit.freqresp(fit.freq_hz) / fit.H - 1
    lev = np.sum(U[:, keep] ** 2, axis=1).reshape(2, -1)
    free = np.clip(1.0 - lev, 0.05, 1.0)
    v = 0.5 * (e.real**2 / free[0] + e.imag**2 / free[1])
    med = median_filter(v, size=min(NOISE_WINDOW, v.size), mode="nearest")
    return np.tile(fit.weight * np.sqrt(med / np.log(2.0)), 2)


@dataclass(frozen=True)
class _Covariance:
    """The covariance of the parameters in the directions the bins see, ``C``, and those
    they do not, ``null`` (rows, in the parameters scaled by ``norm``) [-]."""

    C: np.ndarray
    null: np.ndarray
    norm: np.ndarray

    def variance(self, grad: np.ndarray) -> float:
        """Variance of a function of the parameters of gradient ``grad``: infinite where
        the gradient has a component along a direction the bins do not see, finite where
        it has none (a gain that a pole and a zero moving together leave alone) [-]."""
        gs = grad / self.norm
        if np.any(np.abs(self.null @ gs) > IN_NULL * np.linalg.norm(gs)):
            return math.inf
        return float(grad @ self.C @ grad)

    def sd(self, grad: np.ndarray) -> float:
        """Standard deviation of a function of gradient ``grad``: the root of
        :meth:`variance`, infinite where that is not a finite non-negative number [-]."""
        var = self.variance(grad)
        return math.sqrt(var) if np.isfinite(var) and var >= 0 else math.inf


def _covariance(fit, J: np.ndarray) -> _Covariance:
    """``A+ J^T diag(n^2) J A+`` for the residual rows' noise ``n`` (see the module), with
    the directions the bins do not see [-]."""
    U, sv, Vt, keep, norm = _decompose(J)
    noise = _residual_noise(fit, U, keep)
    M = (U[:, keep] * noise[:, None]) / sv[keep]
    Vk = Vt[keep].T
    unseen = np.eye(J.shape[1])[np.linalg.norm(J, axis=0) == 0]
    return _Covariance(Vk @ (M.T @ M) @ Vk.T / np.outer(norm, norm),
                       np.vstack([Vt[~keep], unseen]), norm)


def tf_deviations(fit, fit_delay: bool, chi2_ratio: float | None = None) -> TFDeviations:
    """Standard deviations of the physical parameters of ``fit`` (see the module).

    Parameters
    ----------
    fit : TFFit
        The fitted model, with the bins, data and weights it was fitted to [-].
    fit_delay : bool
        Whether the delay was a parameter of the fit [-].
    chi2_ratio : float, optional
        The fit's ``chi2`` per residual against the bins' noise; above :data:`MISFIT`
        every value is undetermined [-].

    Returns
    -------
    TFDeviations
        Modes, real poles, zeros, delay and gain with their standard deviations [-].
    """
    pairs, reals = _split_poles(fit.pn)
    cov = _covariance(fit, _jacobian(fit, pairs, reals, fit_delay))
    sd = np.sqrt(np.abs([cov.variance(e) for e in np.eye(cov.C.shape[0])]))
    to_hz = fit.omega0 / (2 * np.pi)
    n2 = 2 * pairs.size
    modes = [(Estimate(abs(p) * to_hz, sd[2 * i]), Estimate(-p.real / abs(p), sd[2 * i + 1]))
             for i, p in enumerate(pairs)]
    real_poles = [Estimate(R * to_hz, sd[n2 + j]) for j, R in enumerate(reals)]
    delay = Estimate(fit.delay_s, sd[-1]) if fit_delay else None
    devs = TFDeviations(modes, real_poles, delay, _gain(fit, pairs, reals, cov),
                        zeros=zero_estimates(fit, cov, n2 + reals.size))
    return _limited(fit, devs, chi2_ratio)


def _limited(fit, devs: TFDeviations, chi2_ratio: float | None) -> TFDeviations:
    """``devs`` with the values no linearised sd bounds opened, each with its reason (see
    the module) [-]."""
    notes = []

    def why(reason: str) -> str:
        if reason not in notes:
            notes.append(reason)
        return reason

    lo, hi = float(fit.freq_hz[0]), float(fit.freq_hz[-1])
    outside = (f"a mode or real pole outside the fitted band {lo:.4g}-{hi:.4g} Hz: the "
               "bins see only the tail of its response")
    modes = [(f.opened(why(outside)), z.opened(outside)) if not lo <= f.value <= hi
             else (f, z) for f, z in devs.modes]
    reals = [r.opened(why(outside)) if not lo <= r.value <= hi else r
             for r in devs.real_poles]
    delay = None if devs.delay is None else devs.delay.opened(why(DELAY_OPEN))
    zeros = [z.opened(why(outside_note(lo, hi))) if not lo <= z.freq.value <= hi else z
             for z in devs.zeros]
    gain = devs.gain
    corners = np.abs(np.r_[fit.poles, fit.zeros]) / (2 * np.pi)
    corners = corners[corners > 0]
    if gain is not None and corners.size and corners.min() < lo:
        gain = gain.opened(why(
            f"the static gain: an extrapolation to 0 Hz through a pole or zero at "
            f"{corners.min():.4g} Hz, below the band's {lo:.4g} Hz"))
    describes = chi2_ratio is None or not chi2_ratio > MISFIT
    if not describes:
        miss = why(f"every value: the fit does not describe the data (chi2 ratio "
                   f"{chi2_ratio:.3g}, above {MISFIT:g})")
        modes = [(f.opened(miss), z.opened(miss)) for f, z in modes]
        reals = [r.opened(miss) for r in reals]
        zeros = [z.opened(miss) for z in zeros]
        delay, gain = (None if e is None else e.opened(miss) for e in (delay, gain))
    return TFDeviations(modes, reals, delay, gain, notes, describes, zeros)


def _gain(fit, pairs, reals, cov: _Covariance) -> Estimate | None:
    """``lim s^k H(s)`` at ``s = 0`` and its sd from ``cov`` through the gradient of its
    logarithm; None where the numerator has no constant term or a pole sits at 0 [-]."""
    b0 = fit.bn[0] if fit.bn.size else 0.0
    poles = np.r_[pairs, np.conj(pairs), -reals]
    if b0 == 0 or np.any(poles == 0):
        return None
    gain = float(np.real(b0 * fit.omega0**fit.n_integrators / np.prod(-poles)))
    grad = np.zeros(cov.C.shape[0])
    n2, to_hz = 2 * pairs.size, fit.omega0 / (2 * np.pi)
    grad[0:n2:2] = -2.0 / (np.abs(pairs) * to_hz)  # d ln(W^2) / d f_n
    grad[n2:n2 + reals.size] = -1.0 / (reals * to_hz)
    grad[n2 + reals.size] = 1.0 / b0
    return Estimate(gain, abs(gain) * cov.sd(grad))
