"""The learning operator of the compensation: the model's linear response from position
command to TCP, and its filtered inverse.

Sampled at the command period the linear part of an axis (friction and play removed) is
time-invariant, because the command period is a multiple of the position-loop period: its
impulse response, simulated once, is the whole linear map from command to TCP. The learning
filter is that map's regularised inverse behind a zero-phase low-pass (the Q-filter), so
that a learning step never asks for content the model cannot be trusted with or the
position loop cannot follow.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..model import Axis
from ..sim.simulate import simulate_axis

#: Step of the impulse that probes the linear map; small enough to stay linear and large
#: enough to stand far above round-off of the positions [m].
PROBE_M = 1e-6

#: Samples before the probe, so that the inverse may look ahead of the command [-].
LEAD_SAMPLES = 20

#: Order of the Butterworth magnitude of the Q-filter [-].
Q_ORDER = 4

#: Regularisation of the inverse where the response is weak: below this gain the inverse
#: stops growing [-].
INVERSE_FLOOR = 0.05


def impulse_response(axis: Axis, period_s: float, n: int = 4096) -> np.ndarray:
    """Response of the TCP to a unit position-command impulse, friction and play removed.

    Parameters
    ----------
    axis : Axis
        The axis [SI].
    period_s : float
        Command period, a multiple or a whole fraction of the position-loop period [s].
    n : int
        Samples simulated [-].

    Returns
    -------
    numpy.ndarray
        ``h[k]``: TCP at sample ``k`` per metre of command at sample
        :data:`LEAD_SAMPLES` [-].
    """
    ratio = period_s / axis.servo.T_p
    whole = abs(ratio - round(ratio)) < 1e-6 and ratio > 0.5
    phases = round(1.0 / ratio) if not whole else 1
    if not whole and abs(1.0 / ratio - phases) > 1e-6:
        raise InputError(f"the command period {period_s:g} s and the position-loop period "
                         f"{axis.servo.T_p:g} s are not multiples of one another; the "
                         "compensation needs one to sample the other whole")
    linear = axis.model_copy(update={"friction": None})
    t = np.arange(n) * period_s
    rest = simulate_axis(linear, t, np.zeros(n), quantise_feedback=False).tcp
    h = np.zeros(n)
    # A position loop slower than the command sees an impulse differently by the phase it
    # falls on; the learning operator takes the mean over the phases.
    for k in range(phases):
        u = np.zeros(n)
        u[LEAD_SAMPLES + k] = PROBE_M
        moved = simulate_axis(linear, t, u, quantise_feedback=False).tcp
        h += np.roll(moved - rest, -k) / PROBE_M
    return h / phases


def lag_samples(h: np.ndarray) -> float:
    """Mean delay of an impulse response: its first moment after the impulse [-]."""
    k = np.arange(h.size) - LEAD_SAMPLES
    return float(np.sum(k * h) / np.sum(h))


def settle_samples(h: np.ndarray, share: float = 1e-3) -> int:
    """Samples after the impulse until the response stays within ``share`` of its peak [-]."""
    big = np.flatnonzero(np.abs(h) > share * np.max(np.abs(h)))
    return int(big[-1] - LEAD_SAMPLES + 1) if big.size else 1


def learning_filter(h: np.ndarray, n_fft: int, period_s: float,
                    cutoff_hz: float) -> np.ndarray:
    """Frequency response of the learning operator: Q-filtered regularised inverse.

    Parameters
    ----------
    h : ndarray
        Impulse response (:func:`impulse_response`) [-].
    n_fft : int
        Length of the transform the filter is applied with [-].
    period_s : float
        Command period [s].
    cutoff_hz : float
        Corner of the Q-filter [Hz].

    Returns
    -------
    numpy.ndarray
        One complex gain per ``numpy.fft.rfftfreq(n_fft)`` bin [-].
    """
    hh = np.zeros(n_fft)
    m = min(h.size - LEAD_SAMPLES, n_fft - LEAD_SAMPLES)
    hh[:m] = h[LEAD_SAMPLES:LEAD_SAMPLES + m]
    hh[-LEAD_SAMPLES:] = h[:LEAD_SAMPLES]
    H = np.fft.rfft(hh)
    f = np.fft.rfftfreq(n_fft, period_s)
    q = 1.0 / np.sqrt(1.0 + (f / cutoff_hz) ** (2 * Q_ORDER))
    return q * np.conj(H) / (np.abs(H) ** 2 + INVERSE_FLOOR ** 2)


def apply_filter(gain: np.ndarray, x: np.ndarray, pad: int) -> np.ndarray:
    """Filter a signal through a frequency response, zero-padded so nothing wraps [-]."""
    n_fft = 2 * (gain.size - 1)
    buf = np.zeros(n_fft)
    buf[pad:pad + x.size] = x
    return np.fft.irfft(np.fft.rfft(buf) * gain, n_fft)[pad:pad + x.size]


def fft_length(n: int, pad: int) -> int:
    """Power of two that holds ``n`` samples with ``pad`` either side [-]."""
    return int(2 ** np.ceil(np.log2(n + 2 * pad)))
