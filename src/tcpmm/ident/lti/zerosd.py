"""Standard deviations of a fitted transfer function's zeros, linearised.

A user tuning a notch, or reading whether a response is collocated (an antiresonance
between each two modes) or not, reads the zeros as the poles are read: each complex zero
pair's natural frequency ``f_z`` [Hz] and damping ratio ``zeta_z`` [-], each real zero's
corner frequency ``|z| / 2 pi`` [Hz]. The numerator's coefficients ``b_j`` of
``B(x) = sum_j b_j x^j`` (``x = s / omega_0``) are parameters of the fit, their covariance
that of :mod:`~tcpmm.ident.lti.tfsd`, so each zero's spread follows from it by the delta
method: a simple root ``z`` of ``B`` moves by ``dz / db_j = -z^j / B'(z)``, and ``f_z`` and
``zeta_z`` follow ``|z|`` and ``-Re z / |z|``, the frequency scaled by ``omega_0 / 2 pi``.
A double root (``B'(z) = 0``) has no finite sd: its two roots split either way.

The rules of the poles hold (:data:`~tcpmm.ident.lti.tfsd.DETERMINED`, a direction the
bins do not see, the ``chi2`` ratio above :data:`~tcpmm.ident.lti.tfsd.MISFIT`), and a
zero outside the fitted band is undetermined with the reason :func:`outside_note` gives:
above the band the fit spends its spare numerator degrees there, zeros that trade with
the delay (:data:`~tcpmm.ident.lti.tfsd.DELAY_OPEN`) and are no antiresonance the bins
see; below it the bins see only their tail.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ._tfestimate import Estimate

__all__ = ["ZeroEstimate", "outside_note", "zero_estimates"]


@dataclass(frozen=True)
class ZeroEstimate:
    """A zero of the fit with the standard deviations of what a user reads of it.

    Parameters
    ----------
    root : complex
        The zero, the upper one of a complex pair [rad/s].
    freq : Estimate
        Natural frequency of a pair, corner frequency ``|z| / 2 pi`` of a real zero [Hz].
    damping : Estimate or None
        Damping ratio ``-Re z / |z|`` of a pair (negative in the right half-plane); None
        for a real zero [-].
    """

    root: complex
    freq: Estimate
    damping: Estimate | None = None

    @property
    def kind(self) -> str:
        """``"pair"`` or ``"real"`` [-]."""
        return "real" if self.damping is None else "pair"

    def opened(self, why: str) -> ZeroEstimate:
        """The zero with each value undetermined for the reason ``why`` [-]."""
        damping = None if self.damping is None else self.damping.opened(why)
        return ZeroEstimate(self.root, self.freq.opened(why), damping)

    def to_dict(self) -> dict:
        """A pair's ``freq_hz`` and ``damping``, a real zero's ``freq_hz`` and
        ``real_rad_s`` (its half-plane), each with its sd and whether determined [-]."""
        if self.damping is None:
            return {**self.freq.to_dict("freq_hz"), "real_rad_s": float(self.root.real)}
        return {**self.freq.to_dict("freq_hz"), **self.damping.to_dict("damping")}


def outside_note(lo: float, hi: float) -> str:
    """Why a zero outside the fitted band ``lo``-``hi`` [Hz] is undetermined [-]."""
    return (f"a zero outside the fitted band {lo:.4g}-{hi:.4g} Hz: above it, a spare "
            "numerator degree that trades with the delay, no antiresonance the bins see; "
            "below it, the bins see only its tail")


def zero_estimates(fit, cov, first: int) -> list:
    """The zeros of ``fit`` with their standard deviations from ``cov``.

    Parameters
    ----------
    fit : TFFit
        The fitted model [-].
    cov : tfsd._Covariance
        Covariance of the fit's parameters, the numerator's coefficients ``b_0, b_1, ...``
        (in ``x``) at columns ``first, first + 1, ...`` [-].
    first : int
        Column of ``b_0`` [-].

    Returns
    -------
    list of ZeroEstimate
        Upper zero of each pair and each real zero, ascending in magnitude as
        :attr:`TFFit.zeros` [-].
    """
    b = np.trim_zeros(fit.bn[::-1], "f")  # highest power first, as np.roots takes it
    if b.size < 2:
        return []
    z = np.roots(b)
    z = z[np.argsort(np.abs(z))]
    slope = np.polyval(np.polyder(b), z)
    to_hz = fit.omega0 / (2 * np.pi)
    zeros = []
    for zi, di in zip(z, slope, strict=True):
        pair = abs(zi.imag) > 1e-9 * abs(zi)
        if pair and zi.imag < 0:
            continue
        with np.errstate(divide="ignore", invalid="ignore"):
            dz = -(zi ** np.arange(fit.bn.size)) / di  # d z / d b_j
        zeros.append(_pair(zi, dz, cov, first, to_hz) if pair
                     else _real(zi.real, dz.real, cov, first, to_hz))
    return zeros


def _sd(cov, first: int, dz: np.ndarray) -> float:
    """sd of a value of gradient ``dz`` in the numerator's coefficients; infinite where
    the gradient is not finite (a double root) or leaves the bins' directions [-]."""
    if not np.all(np.isfinite(dz)):
        return math.inf
    grad = np.zeros(cov.C.shape[0])
    grad[first:first + dz.size] = dz
    return cov.sd(grad)


def _pair(z: complex, dz: np.ndarray, cov, first: int, to_hz: float) -> ZeroEstimate:
    """A complex zero ``z`` in ``x`` with ``dz = d z / d b_j``: ``d|z| = Re(conj(z) dz) /
    |z|`` and ``d zeta = -Re(dz) / |z| + Re(z) d|z| / |z|^2`` [-]."""
    w = abs(z)
    dw = (np.conj(z) * dz).real / w
    dzeta = -dz.real / w + z.real * dw / w**2
    return ZeroEstimate(complex(z) * 2 * np.pi * to_hz,
                        Estimate(w * to_hz, _sd(cov, first, dw * to_hz)),
                        Estimate(-z.real / w, _sd(cov, first, dzeta)))


def _real(z: float, dz: np.ndarray, cov, first: int, to_hz: float) -> ZeroEstimate:
    """A real zero ``z`` in ``x``: its corner ``|z|`` moves by ``sign(z) dz`` [-]."""
    return ZeroEstimate(complex(z * 2 * np.pi * to_hz),
                        Estimate(abs(z) * to_hz, _sd(cov, first, np.sign(z) * dz * to_hz)))
