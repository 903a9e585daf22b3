"""The scale's rounding in the covariance of the nut fit.

On a stretch of steady motion whose speed advances a whole number of scale steps per
sample, the rounding error of the scale does not average out: it is one unknown constant
per stretch, which :func:`quantisation_cov` adds to the covariance of the least-squares
coefficients of :func:`tcpmm.ident.friction.nutstiffness.estimate_nut`.
"""

from __future__ import annotations

import functools

import numpy as np

from .lostmotion import quantisation_bias_std

__all__ = ["quantisation_cov", "steady_stretches", "stretch_bias_std"]


def steady_stretches(idx, v, rel: float = 0.02):
    """``(start, stop)`` positions in the sample indices ``idx`` [-] of the runs of
    consecutive samples whose speed ``v`` [m/s] stays within ``rel`` [-] of the run's
    first: a plateau is one run, a ramp many."""
    n = idx.size
    # a run's end depends on its own first sample, so the scan stays sequential; on plain
    # floats and a precomputed gap mask it costs a small part of indexing numpy scalars
    gap = [*(np.diff(idx) != 1).tolist(), True]
    speed = np.asarray(v)[idx].tolist()
    out, i0 = [], 0
    v0, lim = (speed[0], rel * abs(speed[0])) if n else (0.0, 0.0)
    for i in range(1, n + 1):
        if gap[i - 1] or abs(speed[i] - v0) > lim:
            out.append((i0, i))
            i0 = i
            if i < n:
                v0, lim = speed[i], rel * abs(speed[i])
    return out


@functools.lru_cache(maxsize=8192)
def stretch_bias_std(t: bytes, x: bytes, quantum: float) -> float:
    """:func:`tcpmm.ident.friction.lostmotion.quantisation_bias_std` of one stretch, given
    by the bytes of its samples, kept: the same stretches come back in every fit of the
    nut (each start, each share, each refit of the mechanics), and working them out again
    would be most of an identification's time [m]."""
    return quantisation_bias_std(np.frombuffer(t), np.frombuffer(x), quantum)


def quantisation_cov(t, use, P, scale, quantum: float, v) -> np.ndarray:
    """Covariance the scale's rounding adds to least-squares coefficients ``P y`` of the
    samples ``use`` of time ``t`` [s], with the recorded ``scale`` [m] of step ``quantum``
    [m].

    On a stretch of steady motion whose speed advances a whole number of sensor steps per
    sample, the rounding error of the scale is one unknown constant (it does not average
    out); it passes the low-pass unchanged into ``y``. Each steady stretch of fitted
    samples (:func:`steady_stretches`, ``v`` the filtered speed [m/s]) gets the variance
    of its mean rounding error
    (:func:`tcpmm.ident.friction.lostmotion.quantisation_bias_std`), and its weight in each
    coefficient is the sum of ``P`` over it.
    """

    k = P.shape[0]
    cov = np.zeros((k, k))
    if quantum <= 0.0:
        return cov
    idx = np.flatnonzero(use)
    for i0, i1 in steady_stretches(idx, v):
        seg = idx[i0:i1]
        sd = stretch_bias_std(np.asarray(t[seg], dtype=float).tobytes(),
                              np.asarray(scale[seg], dtype=float).tobytes(), float(quantum))
        w = P[:, i0:i1].sum(axis=1)
        cov += np.outer(w, w) * sd**2
    return cov
