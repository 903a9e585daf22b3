"""The free step of one axis: the exactly discretised plant's state update, the part
every step of :mod:`tcpmm.sim.kernel` shares (compiled, inlined into it)."""

from __future__ import annotations

from numba import njit

from .layout import FP_CARRIAGE_FORCE, FP_MOTOR_TORQUE, FP_SCREW_TORQUE, NX


@njit(cache=True, inline="always")
def free_step(AdT, BdT, c, x, xn, u0, u4):
    """``xn = Ad x + Bd u``, see :func:`free_end`."""
    y = free_end(AdT, BdT, c, x, u0, u4)
    for i in range(NX):
        xn[i] = y[i]


@njit(cache=True, inline="always")
def free_end(AdT, BdT, c, x, u0, u4):
    """The tuple ``Ad x + Bd u``: the current ``u0``, the constant inputs (their sum ``c``),
    the nut force ``u4``, then the states in order. The sums are carried in a tuple,
    i.e. in registers: through ``xn`` the compiler must assume that each store may change
    ``AdT``, and the product takes twice as long."""
    y = (BdT[0, 0] * u0 + c[0], BdT[0, 1] * u0 + c[1], BdT[0, 2] * u0 + c[2],
         BdT[0, 3] * u0 + c[3], BdT[0, 4] * u0 + c[4], BdT[0, 5] * u0 + c[5],
         BdT[0, 6] * u0 + c[6], BdT[0, 7] * u0 + c[7], BdT[0, 8] * u0 + c[8],
         BdT[0, 9] * u0 + c[9], BdT[0, 10] * u0 + c[10])
    if u4 != 0.0:
        y = (y[0] + BdT[4, 0] * u4, y[1] + BdT[4, 1] * u4, y[2] + BdT[4, 2] * u4,
             y[3] + BdT[4, 3] * u4, y[4] + BdT[4, 4] * u4, y[5] + BdT[4, 5] * u4,
             y[6] + BdT[4, 6] * u4, y[7] + BdT[4, 7] * u4, y[8] + BdT[4, 8] * u4,
             y[9] + BdT[4, 9] * u4, y[10] + BdT[4, 10] * u4)
    for j in range(NX):
        xj = x[j]
        if xj != 0.0 or j < NX - 1:  # no current loop: the last state is 0 and adds nothing
            y = (y[0] + AdT[j, 0] * xj, y[1] + AdT[j, 1] * xj, y[2] + AdT[j, 2] * xj,
                 y[3] + AdT[j, 3] * xj, y[4] + AdT[j, 4] * xj, y[5] + AdT[j, 5] * xj,
                 y[6] + AdT[j, 6] * xj, y[7] + AdT[j, 7] * xj, y[8] + AdT[j, 8] * xj,
                 y[9] + AdT[j, 9] * xj, y[10] + AdT[j, 10] * xj)
    return y


@njit(cache=True)
def constant_inputs(BdT, fp, c):
    """``c`` = the part of ``Bd u`` from the constant inputs of ``fp``: the motor torque,
    the screw torque and the carriage force."""
    for i in range(NX):
        c[i] = (BdT[1, i] * fp[FP_MOTOR_TORQUE] + BdT[2, i] * fp[FP_SCREW_TORQUE]
                + BdT[3, i] * fp[FP_CARRIAGE_FORCE])


@njit(cache=True, inline="always")
def rel(x, idx, ref):
    """Velocity ``x[idx]``, relative to ``x[ref]`` when ``ref >= 0``."""
    if ref >= 0:
        return x[idx] - x[ref]
    return x[idx]
