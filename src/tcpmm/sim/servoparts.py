"""The servo's pieces of a step of the axis kernel (:mod:`tcpmm.sim.kernel`), compiled and
inlined into its loop: the quantisation of a sensor, the current-setpoint filter cascade,
the difference velocity from the encoder's angles and a column of the record."""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True, inline="always")
def quantise(v, q):
    """``v`` rounded to the nearest multiple of the resolution ``q``; as it is where ``q``
    is not positive [SI]."""
    if q > 0.0:
        return np.floor(v / q + 0.5) * q
    return v


@njit(cache=True)
def filter_rest(fsec, fst, i0):
    """Filter states at rest under a constant input ``i0``."""
    u = i0
    for q in range(fsec.shape[0]):
        b0, b1, b2, a1, a2 = fsec[q, 0], fsec[q, 1], fsec[q, 2], fsec[q, 3], fsec[q, 4]
        y = u * (b0 + b1 + b2) / (1.0 + a1 + a2)
        fst[q, 0] = y - b0 * u
        fst[q, 1] = b2 * u - a2 * y
        u = y


@njit(cache=True, inline="always")
def filter_step(fsec, fst, u):
    """One step of the filter cascade (transposed direct form II); its output."""
    for q in range(fsec.shape[0]):
        y = fsec[q, 0] * u + fst[q, 0]
        fst[q, 0] = fsec[q, 1] * u - fsec[q, 3] * y + fst[q, 1]
        fst[q, 1] = fsec[q, 2] * u - fsec[q, 4] * y
        u = y
    return u


@njit(cache=True, inline="always")
def diff_velocity(hist, c_h, th_q, vtaps, T_v):
    """Motor speed from the FIR of encoder differences, newest first [rad/s]."""
    n_taps = vtaps.size
    w_fb = 0.0
    newer = th_q
    for i in range(n_taps):
        older = hist[(c_h - i) % (n_taps + 1)]
        w_fb += vtaps[i] * (newer - older)
        newer = older
    return w_fb / T_v


@njit(cache=True, inline="always")
def record(rec, r, x, i_app, R, c_k, i_peak):
    """Column ``r`` of the record: ``th_m, X_LS, X_TCP, w_m, i_c, R th_m, cmd, i_peak``."""
    rec[0, r] = x[0]
    rec[1, r] = x[2] - x[3]
    rec[2, r] = x[2] - x[4]
    rec[3, r] = x[5]
    rec[4, r] = i_app
    rec[5, r] = R * x[0]
    rec[6, r] = c_k
    rec[7, r] = i_peak
