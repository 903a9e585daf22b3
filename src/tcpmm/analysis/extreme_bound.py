"""The bound on the largest of a window's samples measured from a level that is itself
uncertain.

A reversal spike is the extreme of ``x_i - b`` over a window of ``n`` samples: ``x_i`` the
noise on each, of scatter ``sigma`` read off ``dof`` degrees of freedom, and ``b`` one
shift shared by every sample of the window (the noise on the level before the point, the
terms' own uncertainty), normal with standard deviation ``s``. Whatever the samples'
dependence, the union bound gives

    P(max_i |x_i - b| > T) <= E_b[min(1, n (F(-(T - b) / sigma) + F(-(T + b) / sigma)))]

with ``F`` Student's distribution; :func:`extreme_bound` solves it for ``T``. The shift
cannot be added in quadrature to the extreme's quantile: its tail moves the extreme's
tail by about ``exp(z^2 s^2 / 2 sigma^2)`` at the quantile ``z`` (3.8 for windows of 400
samples), and the quadrature sum let noise alone past a 95 % bound in 8 % of such windows
where the shift is 0.3 of the scatter and in 21 % where it equals it.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq
from scipy.special import ndtri, stdtr, stdtrit

#: The shift's values over which the expectation is taken, in its standard deviations
#: (the integrand is even in it), and their weights: a fine even grid, as the integrand
#: steps from 1 to nearly 0 over a sample's scatter, which a few Gauss-Hermite nodes do
#: not resolve where the shift is several times that scatter (against twice as many
#: nodes the bound moves by 1e-4 of itself at a shift of ten times the scatter, 2e-3 at
#: a hundred) [-].
_NODES = np.linspace(0.0, 8.5, 301)
_WEIGHTS = np.exp(-0.5 * _NODES**2) * np.where(_NODES > 0.0, 2.0, 1.0)
_WEIGHTS = _WEIGHTS / _WEIGHTS.sum()


def extreme_bound(sigma: float, dof: float, n: int, shift_sd: float, beyond: float) -> float:
    """The level ``T`` that the largest ``|x_i - b|`` of a window passes with probability
    ``beyond`` at most (module docstring) [m].

    Parameters
    ----------
    sigma : float
        Scatter of each sample's noise [m].
    dof : float
        Degrees of freedom ``sigma`` is read off [-].
    n : int
        Samples in the window [-].
    shift_sd : float
        Standard deviation of the shift shared by the window's samples [m].
    beyond : float
        Probability the bound is passed [-].
    """
    per_sample = float(stdtrit(dof, 1.0 - 0.5 * beyond / n))
    if sigma <= 0.0:
        return float(shift_sd * ndtri(1.0 - 0.5 * beyond))
    if shift_sd <= 0.0:
        return float(sigma * per_sample)
    b = shift_sd * _NODES

    def excess(T):
        p = n * (stdtr(dof, -(T - b) / sigma) + stdtr(dof, -(T + b) / sigma))
        return float(_WEIGHTS @ np.minimum(p, 1.0)) - beyond

    lo = sigma * per_sample
    hi = lo + shift_sd * ndtri(1.0 - 0.5 * beyond)  # the two bounds added whole
    while excess(hi) > 0.0:
        hi += shift_sd
    return float(brentq(excess, lo, hi, xtol=1e-7 * hi, rtol=1e-7))
