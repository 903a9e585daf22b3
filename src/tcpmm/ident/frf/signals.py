"""Signal conditioning for time-domain identification.

Zero-phase Butterworth low-pass (``lowpass_filtfilt``), derivatives by central
differences (``central_difference``) and zero-phase down-sampling (``decimate``) of
uniformly sampled records.

Conventions follow MATLAB's ``filtfilt`` (edge padding of ``3 (n - 1)`` samples) and
``decimate`` (8th-order Chebyshev I, 0.05 dB ripple, cutoff ``0.8 / r`` of Nyquist,
zero-phase, samples kept so that the last one is included), so published IDIM-LS
results are reproduced to their printed digits.
"""

from __future__ import annotations

import numpy as np
from scipy import signal

from tcpmm.errors import InputError

__all__ = ["central_difference", "decimate", "lowpass_filtfilt"]


def as_1d(x, name: str) -> np.ndarray:
    a = np.asarray(x, dtype=float).ravel()
    if a.size == 0 or not np.all(np.isfinite(a)):
        raise InputError(f"{name} must be a non-empty array of finite numbers", column=name)
    return a


def lowpass_filtfilt(x, dt: float, cutoff: float, order: int = 4) -> np.ndarray:
    """Zero-phase Butterworth low-pass (forward-backward), MATLAB ``filtfilt`` padding.

    Parameters
    ----------
    x : array_like
        Signal, uniformly sampled [any].
    dt : float
        Sample time [s].
    cutoff : float
        Cut-off frequency of the single-pass filter [Hz].
    order : int
        Butterworth order of the single-pass filter [-].

    Returns
    -------
    numpy.ndarray
        Filtered signal, same length and unit as ``x`` [any].
    """
    x = as_1d(x, "x")
    nyq = 0.5 / dt
    if not 0.0 < cutoff < nyq:
        raise InputError(
            f"cut-off {cutoff} Hz must lie between 0 and the Nyquist frequency {nyq} Hz",
            column="cutoff",
        )
    b, a = signal.butter(order, cutoff / nyq)
    pad = 3 * (max(len(a), len(b)) - 1)
    if x.size <= pad:
        raise InputError(f"need more than {pad} samples to filter, got {x.size}", column="x")
    return signal.filtfilt(b, a, x, padlen=pad)


def central_difference(x, dt: float) -> np.ndarray:
    """Derivative by central differences, one-sided at both ends.

    Parameters
    ----------
    x : array_like
        Signal, uniformly sampled [any].
    dt : float
        Sample time [s].

    Returns
    -------
    numpy.ndarray
        ``dx/dt``, same length as ``x`` [unit of x per s].
    """
    x = as_1d(x, "x")
    if x.size < 2:
        raise InputError("need at least 2 samples to differentiate", column="x")
    dx = np.empty_like(x)
    dx[1:-1] = (x[2:] - x[:-2]) / (2.0 * dt)
    dx[0] = (x[1] - x[0]) / dt
    dx[-1] = (x[-1] - x[-2]) / dt
    return dx


def decimate(x, factor: int) -> np.ndarray:
    """Zero-phase low-pass and down-sampling, MATLAB ``decimate`` conventions.

    Parameters
    ----------
    x : array_like
        Signal, or a 2-D array whose columns are decimated in parallel [any].
    factor : int
        Keep one sample in ``factor`` (1 returns the input) [-].

    Returns
    -------
    numpy.ndarray
        Decimated signal; the last input sample is always kept [any].
    """
    x = np.asarray(x, dtype=float)
    r = int(factor)
    if r < 1:
        raise InputError("decimation factor must be >= 1", column="decimation")
    if r == 1:
        return x.copy()
    b, a = signal.cheby1(8, 0.05, 0.8 / r)
    pad = 3 * (max(len(a), len(b)) - 1)
    n = x.shape[0]
    if n <= pad:
        raise InputError(f"need more than {pad} samples to decimate, got {n}", column="x")
    y = signal.filtfilt(b, a, x, axis=0, padlen=pad)
    nout = -(-n // r)
    start = r - (r * nout - n) - 1
    return y[start::r]
