"""Post-interpolation acc/dec filter per axis: linear or bell-shaped moving averages.

``linear`` is one causal moving average of length ``T``; ``bell`` is two cascaded
moving averages of length ``T/2`` each (a triangular impulse response of length ``T``).
The filter holds the first value before the command and extends the command by its
length so that the output settles on the final value.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class FilterShape:
    """Numbers of the filter that the speed limits need.

    Parameters
    ----------
    kernel : ndarray
        Impulse response per sample, sums to one [-].
    period_s : float
        Sample period [s].
    tolerance_m : float
        Allowed path deviation caused by the filter [m].
    """

    kernel: np.ndarray
    period_s: float
    tolerance_m: float

    @property
    def delay_s(self) -> float:
        """Group delay (mean of the impulse response) [s]."""
        k = np.arange(self.kernel.size)
        return float(np.dot(k, self.kernel)) * self.period_s

    @property
    def variance_s2(self) -> float:
        """Variance of the impulse response in time [s^2]."""
        k = np.arange(self.kernel.size) * self.period_s
        m = np.dot(k, self.kernel)
        return float(np.dot((k - m) ** 2, self.kernel))

    @property
    def mad_s(self) -> float:
        """Mean absolute deviation of the impulse response from its mean [s]."""
        k = np.arange(self.kernel.size) * self.period_s
        m = np.dot(k, self.kernel)
        return float(np.dot(np.abs(k - m), self.kernel))

    @property
    def spread_s(self) -> float:
        """Time over which a velocity step becomes a ramp at its steepest [s]."""
        return self.period_s / float(np.max(self.kernel))


def filter_shape(kind: str, time_s: float, period_s: float, tolerance_m: float) -> FilterShape:
    """Impulse response of the post-interpolation filter.

    Parameters
    ----------
    kind : {"none", "linear", "bell"}
        Filter kind [-].
    time_s : float
        Total filter length [s].
    period_s : float
        Interpolation period [s].
    tolerance_m : float
        Allowed path deviation caused by the filter [m].

    Returns
    -------
    FilterShape
        The filter [-].
    """
    if kind == "linear":
        n = max(1, round(time_s / period_s))
        h = np.full(n, 1.0 / n)
    elif kind == "bell":
        n = max(1, round(time_s / (2.0 * period_s)))
        box = np.full(n, 1.0 / n)
        h = np.convolve(box, box)
    else:
        h = np.ones(1)
    return FilterShape(kernel=h, period_s=period_s, tolerance_m=tolerance_m)


def apply_filter(x: np.ndarray, shape: FilterShape) -> np.ndarray:
    """Filter one axis, causal, extended until it settles.

    Parameters
    ----------
    x : ndarray
        Command samples [m].
    shape : FilterShape
        The filter [-].

    Returns
    -------
    ndarray
        ``len(x) + len(kernel) - 1`` filtered samples [m].
    """
    h = shape.kernel
    m = h.size
    if m == 1:
        return np.array(x, dtype=float)
    x0, x1 = x[0], x[-1]
    pad = np.concatenate([np.full(m - 1, x0), x - x0, np.full(m - 1, x1 - x0)])
    pad[: m - 1] = 0.0
    return np.convolve(pad, h, mode="valid") + x0
