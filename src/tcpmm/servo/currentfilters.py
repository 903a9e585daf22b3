"""Current-setpoint filters of the velocity controller: 2nd-order low-pass and notch.

Drives filter the velocity controller's output (the current setpoint) to keep it from
exciting mechanical resonances. Sinumerik (parameters p1656 ff.) offers up to four
filters per axis, each a PT2 low-pass (natural frequency, damping) or a general
second-order filter whose band-stop form is set by its blocking frequency, bandwidth
and notch depth; other drives (Fanuc's HRV filter, Kollmorgen's biquads) parametrise
them the same way. Here the band-stop is

``H(s) = (s^2 + 2 D_z w0 s + w0^2) / (s^2 + 2 D_n w0 s + w0^2)``,

with ``D_n = bandwidth / (2 f0)`` (the -3 dB width of a full notch) and
``D_z = D_n 10^(depth/20)``, so that ``|H(j w0)|`` is the depth exactly.

The filters run at the velocity-loop period ``T_v`` (the rate at which the current
setpoint changes in this model): each is discretised by the bilinear transform
prewarped at its own frequency, so the notch sits at ``f0`` with its designed depth and
the low-pass has its designed gain at ``f0``.
"""

from __future__ import annotations

import math
from typing import Annotated, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from ..mechanics.export import biquad, series

#: Most current-setpoint filters per axis (as Sinumerik's p1656).
MAX_FILTERS = 4


class LowPass(BaseModel):
    """PT2 low-pass ``w0^2 / (s^2 + 2 zeta w0 s + w0^2)``.

    Parameters
    ----------
    f_hz : float
        Natural frequency [Hz].
    zeta : float
        Damping ratio [-].
    """

    model_config = ConfigDict(extra="forbid", frozen=True)

    type: Literal["lowpass"] = "lowpass"
    f_hz: float = Field(gt=0, allow_inf_nan=False)
    zeta: float = Field(0.7, gt=0, le=10, allow_inf_nan=False)

    def continuous(self):
        """Numerator and denominator coefficients in ``s``, highest power first [-]."""
        w = 2 * math.pi * self.f_hz
        return np.array([0.0, 0.0, w * w]), np.array([1.0, 2 * self.zeta * w, w * w])


class Notch(BaseModel):
    """Band-stop as drives set it: blocking frequency, bandwidth and depth.

    Parameters
    ----------
    f_hz : float
        Blocking frequency [Hz].
    bandwidth_hz : float
        -3 dB bandwidth of the full notch, ``2 D_n f0`` [Hz].
    depth_db : float
        Gain at ``f0``, 0 or negative (e.g. -20) [dB].
    """

    model_config = ConfigDict(extra="forbid", frozen=True)

    type: Literal["notch"] = "notch"
    f_hz: float = Field(gt=0, allow_inf_nan=False)
    bandwidth_hz: float = Field(gt=0, allow_inf_nan=False)
    depth_db: float = Field(-20.0, ge=-120.0, le=0.0, allow_inf_nan=False)

    def continuous(self):
        """Numerator and denominator coefficients in ``s``, highest power first [-]."""
        w = 2 * math.pi * self.f_hz
        d_n = self.bandwidth_hz / (2 * self.f_hz)
        d_z = d_n * 10 ** (self.depth_db / 20)
        return np.array([1.0, 2 * d_z * w, w * w]), np.array([1.0, 2 * d_n * w, w * w])


ServoFilter = Annotated[LowPass | Notch, Field(discriminator="type")]


def check_filters(filters, T_v: float) -> None:
    """Raise ``ValueError`` for a filter at or above the Nyquist frequency of ``T_v``.

    Parameters
    ----------
    filters : list of LowPass or Notch
        The filters [-].
    T_v : float
        Period they run at [s].
    """
    nyq = 0.5 / T_v
    for i, f in enumerate(filters):
        if f.f_hz >= 0.95 * nyq:
            raise ValueError(
                f"filter {i + 1} ({f.type}) at {f.f_hz:g} Hz is not below 0.95 times the "
                f"Nyquist frequency {nyq:g} Hz of the velocity loop; lower f_hz")


def _bilinear(p, k: float) -> np.ndarray:
    """``(p0 s^2 + p1 s + p2)(z + 1)^2`` with ``s (z + 1) = k (z - 1)``: coefficients of
    ``z^2, z, 1`` [-]."""
    return np.array([p[0] * k * k + p[1] * k + p[2], -2 * p[0] * k * k + 2 * p[2],
                     p[0] * k * k - p[1] * k + p[2]])


def biquads(filters, T_v: float) -> np.ndarray:
    """Discrete sections of the filters, bilinear transform prewarped at each ``f0``.

    Parameters
    ----------
    filters : list of LowPass or Notch
        The filters [-].
    T_v : float
        Sample period [s].

    Returns
    -------
    numpy.ndarray (n, 5)
        ``b0, b1, b2, a1, a2`` per section: ``y = (b0 + b1 z^-1 + b2 z^-2) /
        (1 + a1 z^-1 + a2 z^-2) x`` [-].
    """
    out = np.zeros((len(filters), 5))
    for i, f in enumerate(filters):
        num, den = f.continuous()
        w0 = 2 * math.pi * f.f_hz
        k = w0 / math.tan(w0 * T_v / 2)  # s = k (z - 1)/(z + 1)
        b, a = _bilinear(num, k), _bilinear(den, k)
        out[i] = [b[0] / a[0], b[1] / a[0], b[2] / a[0], a[1] / a[0], a[2] / a[0]]
    return out


def filters_freqresp(filters, f_hz, T_v: float | None = None) -> np.ndarray:
    """Frequency response of the filter cascade, discrete when ``T_v`` is given [-].

    Parameters
    ----------
    filters : list of LowPass or Notch
        The filters [-].
    f_hz : array_like
        Frequencies [Hz].
    T_v : float, optional
        Sample period of the discrete filters; ``None`` for the continuous ones [s].
    """
    f = np.atleast_1d(np.asarray(f_hz, dtype=float))
    h = np.ones(f.size, dtype=complex)
    if T_v is None:
        s = 2j * np.pi * f
        for flt in filters:
            num, den = flt.continuous()
            h *= np.polyval(num, s) / np.polyval(den, s)
        return h
    zi = np.exp(-2j * np.pi * f * T_v)
    for b0, b1, b2, a1, a2 in biquads(filters, T_v):
        h *= (b0 + b1 * zi + b2 * zi * zi) / (1 + a1 * zi + a2 * zi * zi)
    return h


def continuous_ss(filters):
    """State space of the continuous filter cascade, two states per filter.

    Returns
    -------
    A, b, c, d : ndarray
        ``x' = A x + b u``, ``y = c x + d u`` [-]; empty ``A`` and ``d = 1`` without
        filters.
    """
    if not filters:
        return np.zeros((0, 0)), np.zeros(0), np.zeros(0), 1.0
    sections = [biquad(*f.continuous()) for f in filters]
    ss = sections[0]
    for sec in sections[1:]:
        ss = series(ss, sec)
    return ss.A, ss.B[:, 0], ss.C[0], float(ss.D[0, 0])


def filter_text(f) -> str:
    """One current-setpoint filter as a commissioning engineer types it in [-]."""
    if f.type == "notch":
        return f"notch {f.f_hz:.1f} Hz, {f.bandwidth_hz:.1f} Hz wide, {f.depth_db:.1f} dB"
    return f"low-pass {f.f_hz:.1f} Hz, zeta {f.zeta:.2f}"


def filters_text(filters) -> str:
    """The current-setpoint filters as a commissioning engineer types them in, ``none``
    without any [-]."""
    return "; ".join(filter_text(f) for f in filters) or "none"
