"""Rigid axis with friction inside a general discrete cascade servo loop.

Plant (one rigid body on the axis coordinate ``q`` [m])::

    M q'' = gain * (sat(u) + e) - offset - F_friction(q', ...)

Controller, evaluated at every sample ``k`` (period ``T``) from the sampled position::

    qm(k)  = q(kT)                      (optionally quantised to the encoder resolution)
    qf(k)  = sum_i taps[i] * qm(k - i)  (FIR position filter, EMPS: [0.5, 0.5])
    dq(k)  = (qf(k) - qf(k - 1)) / T    (velocity estimate)
    w(k)   = kp * (r(k) - qm(k)) + kff * (r(k) - r(k - 1)) / T
    u(k)   = kv * (w(k) - dq(k)) + ki * T * sum_{j<=k} (w(j) - dq(j))

``u(k)`` reaches the plant ``delay`` samples after ``kT`` (a computation delay, possibly
fractional), is saturated at ``+/- u_max`` and held until the next command arrives. The
external input ``e(k)`` (e.g. force pulses expressed in controller-output units) is added
after the saturation, before the actuator gain, and held over ``[kT, (k+1)T)``.

The mechanics are sub-stepped ``n_sub`` times per sample. With Coulomb/viscous/Stribeck
friction each sub-step is solved in closed form (exact exponential solution of the
viscous linear part under constant force, Coulomb/Stribeck level frozen at the start of
the sub-step) and the instant at which the velocity reaches zero is found exactly: the
body then sticks (velocity exactly ``0.0``) while the applied force stays inside the
static band, or slips into the other direction. With LuGre friction the velocity and
bristle state are advanced together by the linearly implicit step of
``tcpmm.sim.contact.friction_force``.

For comparison with block-diagram simulators the static friction models can also be
integrated the way those tools do without zero-crossing detection
(``integrator="rk4"`` or ``"dopri5"``): an explicit fixed-step Runge-Kutta scheme with
the friction evaluated at each stage velocity, ``sign(0) = 0`` and no rest phase. Such an
integration chatters around zero velocity wherever the body should stick, and converges
to the closed-form solution only as the step shrinks.

``simulate_rigid_servo`` is the Python entry point; ``rigid_servo_kernel`` is the compiled
loop.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit
from pydantic import Field, field_validator

from tcpmm.errors import InputError
from tcpmm.mechanics.friction import (
    MODEL_LUGRE,
    MODEL_NONE,
    P_FS_NEG,
    P_FS_POS,
    P_FV_NEG,
    P_FV_POS,
    P_MODEL,
    P_SIGMA0,
    P_SIGMA1,
    LuGreFriction,
    StribeckFriction,
    _Holder,
    friction_params_array,
)
from tcpmm.sim.contact import (
    friction_force,
    lugre_decay_rate,
    sliding_friction,
    stribeck_level,
)

#: Butcher tableaus ``(a, b)`` of the explicit Runge-Kutta schemes ``simulate_rigid_servo``
#: offers besides the closed-form sub-step: the classical 4th-order scheme and the
#: Dormand-Prince 5th-order one (Simulink's ``ode4`` and ``ode5``; ``ode45`` with its step
#: capped and never rejected takes the same steps).
TABLEAUS = {
    "rk4": ([[], [0.5], [0.0, 0.5], [0.0, 0.0, 1.0]], [1 / 6, 1 / 3, 1 / 3, 1 / 6]),
    "dopri5": (
        [[], [1 / 5], [3 / 40, 9 / 40], [44 / 45, -56 / 15, 32 / 9],
         [19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729],
         [9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656]],
        [35 / 384, 0.0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84],
    ),
}
INTEGRATORS = ("exact", *TABLEAUS)

__all__ = [
    "INTEGRATORS",
    "TABLEAUS",
    "DiscreteServo",
    "RigidAxis",
    "RigidServoResult",
    "rigid_servo_kernel",
    "simulate_rigid_servo",
]


class RigidAxis(_Holder):
    """A rigid axis: one mass with friction and a constant force offset.

    Parameters
    ----------
    mass : float
        Moving mass (or inertia expressed at the axis coordinate) [kg].
    offset : float
        Constant force opposing the actuator (``M q'' = F_act - offset - F_fric``); for
        EMPS it is the offset of the force measurement [N].
    friction : StribeckFriction or LuGreFriction or None
        Friction model; ``None`` for none [-].
    """

    mass: float = Field(gt=0.0)
    offset: float = 0.0
    friction: LuGreFriction | StribeckFriction | None = None


class DiscreteServo(_Holder):
    """Discrete cascade controller: P position loop, P/PI velocity loop.

    Parameters
    ----------
    period : float
        Controller sample time ``T`` [s].
    kp : float
        Position-loop gain [1/s].
    kv : float
        Velocity-loop proportional gain [controller units per m/s, e.g. V s/m].
    ki : float
        Velocity-loop integral gain (``u = kv e + ki * integral(e) dt``) [units per m].
    kff : float
        Velocity feed-forward fraction of the reference's difference quotient [-].
    taps : tuple of float
        FIR position filter before the velocity difference (newest sample first) [-].
    delay : float
        Computation delay from sampling to actuation, may be fractional [samples].
    u_max : float
        Output saturation, ``inf`` for none [controller units].
    gain : float
        Actuator gain from controller output to force [N per controller unit].
    q_resolution : float
        Encoder resolution for quantising the sampled position, 0 for none [m].
    """

    period: float = Field(gt=0.0)
    kp: float = Field(ge=0.0)
    kv: float = Field(ge=0.0)
    ki: float = Field(default=0.0, ge=0.0)
    kff: float = Field(default=0.0, ge=0.0)
    taps: tuple[float, ...] = (0.5, 0.5)
    delay: float = Field(default=1.0, ge=0.0)
    u_max: float = Field(default=math.inf, gt=0.0)
    gain: float = Field(default=1.0, gt=0.0)
    q_resolution: float = Field(default=0.0, ge=0.0)

    @field_validator("taps")
    @classmethod
    def _taps_sum_to_one(cls, v):
        if len(v) == 0 or abs(sum(v) - 1.0) > 1e-9:
            raise ValueError("position filter taps must be non-empty and sum to 1")
        return v


@dataclass(frozen=True)
class RigidServoResult:
    """Sampled outputs of ``simulate_rigid_servo`` (one value per controller sample).

    Parameters
    ----------
    t : numpy.ndarray
        Sample times [s].
    q : numpy.ndarray
        Position at the sample instants [m].
    v : numpy.ndarray
        Velocity at the sample instants [m/s].
    a : numpy.ndarray
        Acceleration just after the sample instants [m/s^2].
    u_cmd : numpy.ndarray
        Saturated controller output computed at each sample [controller units].
    u_applied : numpy.ndarray
        Saturated controller output acting at the end of each sample interval (with a
        delay of one sample this is ``u_cmd`` of the previous sample) [controller units].
    force : numpy.ndarray
        Actuator force at the end of each sample interval, ``gain * (u_applied + e)`` [N].
    friction_state : numpy.ndarray
        Friction state at the sample instants (LuGre bristle deflection) [m].
    """

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    u_cmd: np.ndarray
    u_applied: np.ndarray
    force: np.ndarray
    friction_state: np.ndarray


@njit(cache=True)
def _phi1(x):
    if x < 1e-4:
        return 1.0 - x / 2.0 + x * x / 6.0
    return -math.expm1(-x) / x


@njit(cache=True)
def _phi2(x):
    if x < 1e-3:
        return 0.5 - x / 6.0 + x * x / 24.0
    return (x + math.expm1(-x)) / (x * x)


@njit(cache=True)
def _static_substep(q, v, u, h, m, fp):
    """Closed-form sub-step of a rigid body with Coulomb/viscous/Stribeck friction."""
    t_left = h
    fsp = fp[P_FS_POS]
    fsn = fp[P_FS_NEG]
    for _ in range(8):
        if t_left <= 0.0:
            break
        if v == 0.0:
            if -fsn <= u <= fsp:
                return q, 0.0
            if u > fsp:
                fcs = fsp
                fv = fp[P_FV_POS]
            else:
                fcs = -fsn
                fv = fp[P_FV_NEG]
        elif v > 0.0:
            fcs = stribeck_level(v, fp)
            fv = fp[P_FV_POS]
        else:
            fcs = -stribeck_level(v, fp)
            fv = fp[P_FV_NEG]
        b = (u - fcs) / m
        a = fv / m
        if v != 0.0 and b * v < 0.0:
            # decelerating towards zero: exact instant of v = 0
            y = -a * v / b
            t_star = math.log1p(y) / a if a > 0.0 else -v / b
            if t_star < t_left:
                x = a * t_star
                q += v * t_star * _phi1(x) + b * t_star * t_star * _phi2(x)
                v = 0.0
                t_left -= t_star
                continue
        x = a * t_left
        q += v * t_left * _phi1(x) + b * t_left * t_left * _phi2(x)
        v = v * math.exp(-x) + b * t_left * _phi1(x)
        break
    return q, v


@njit(cache=True)
def _explicit_substep(q, v, u, h, m, fp, rk_a, rk_b):
    """One explicit Runge-Kutta step with the friction of the stage velocity (no stick)."""
    ns = rk_b.shape[0]
    kv = np.empty(ns)
    kq = np.empty(ns)
    for i in range(ns):
        vi = v
        for j in range(i):
            vi += h * rk_a[i, j] * kv[j]
        kq[i] = vi
        kv[i] = (u - sliding_friction(vi, fp)) / m
    for i in range(ns):
        q += h * rk_b[i] * kq[i]
        v += h * rk_b[i] * kv[i]
    return q, v


@njit(cache=True)
def _acceleration(v, z, u, m, fp):
    model = fp[P_MODEL]
    if model == MODEL_NONE:
        return u / m
    if model == MODEL_LUGRE:
        c = lugre_decay_rate(v, fp)
        fv = fp[P_FV_POS] if v >= 0.0 else fp[P_FV_NEG]
        f = fp[P_SIGMA0] * z + fp[P_SIGMA1] * (v - c * z) + fv * v
        return (u - f) / m
    if v == 0.0:
        if -fp[P_FS_NEG] <= u <= fp[P_FS_POS]:
            return 0.0
        f = fp[P_FS_POS] if u > 0.0 else -fp[P_FS_NEG]
        return (u - f) / m
    return (u - sliding_friction(v, fp)) / m


@njit(cache=True, inline="always")
def _applied(u_cmd, mm, n_sub):
    """Command applied at sub-step ``mm`` (after the delay): that of its sample, 0 before
    the first [controller units]."""
    j = mm // n_sub if mm >= 0 else -1
    return u_cmd[j] if j >= 0 else 0.0


@njit(cache=True, inline="always")
def _controller(ref, k, qm, dq, period, kp, kv, ki, kff, integ, u_max):
    """P position and PI velocity control of sample ``k`` with anti-windup and
    saturation; the command and the new integrator [controller units]."""
    w = kp * (ref[k] - qm)
    if kff != 0.0 and k > 0:
        w += kff * (ref[k] - ref[k - 1]) / period
    e = w - dq
    u = kv * e + integ
    if ki != 0.0:
        cand = integ + ki * period * e
        u_try = kv * e + cand
        if abs(u_try) <= u_max or u_try * e < 0.0:
            integ = cand
            u = u_try
    if u > u_max:
        u = u_max
    elif u < -u_max:
        u = -u_max
    return u, integ


@njit(cache=True, inline="always")
def _mech_substep(q, v, z, f, h, mass, fp, is_none, is_lugre, explicit, rk_a, rk_b):
    """One mechanical sub-step under the force ``f``: ``(q, v, z)`` at its end [SI]."""
    if is_none:
        q += v * h + 0.5 * f / mass * h * h
        v += f / mass * h
    elif is_lugre:
        fr, z = friction_force(v, f, z, fp, h, mass)
        v = v + h * (f - fr) / mass
        q += h * v
    elif explicit:
        q, v = _explicit_substep(q, v, f, h, mass, fp, rk_a, rk_b)
    else:
        q, v = _static_substep(q, v, f, h, mass, fp)
    return q, v, z


@njit(cache=True)
def rigid_servo_kernel(
    ref, ext, period, n_sub, mass, offset, fp, kp, kv, ki, kff, taps, delay,
    u_max, gain, q_res, q0, v0, z0, rk_a, rk_b,
):
    """Compiled closed-loop simulation of a rigid axis (see module docstring).

    Parameters
    ----------
    ref : numpy.ndarray
        Position reference per sample [m].
    ext : numpy.ndarray
        External input per sample, added after saturation [controller units].
    period : float
        Sample time [s].
    n_sub : int
        Mechanical sub-steps per sample [-].
    mass : float
        Mass [kg].
    offset : float
        Constant opposing force [N].
    fp : numpy.ndarray
        Friction parameters from ``friction_params_array`` [-].
    kp, kv, ki, kff : float
        Controller gains ([1/s], [units s/m], [units/m], [-]).
    taps : numpy.ndarray
        Position filter taps, newest first [-].
    delay : float
        Computation delay [samples].
    u_max : float
        Saturation level [controller units].
    gain : float
        Actuator gain [N per controller unit].
    q_res : float
        Encoder resolution, 0 for none [m].
    q0, v0, z0 : float
        Initial position, velocity and friction state ([m], [m/s], [m]).
    rk_a, rk_b : numpy.ndarray
        Butcher tableau ``(s, s)`` and weights ``(s,)`` of an explicit scheme for static
        friction, or empty arrays for the closed-form sub-step [-].

    Returns
    -------
    tuple of numpy.ndarray
        ``(q, v, a, u_cmd, u_applied, force, z)`` per sample ([m], [m/s], [m/s^2],
        [units], [units], [N], [m]).
    """
    n = ref.shape[0]
    ntap = taps.shape[0]
    h = period / n_sub
    d_sub = int(delay * n_sub + 0.5)
    q_out = np.empty(n)
    v_out = np.empty(n)
    a_out = np.empty(n)
    u_cmd = np.zeros(n)
    u_app = np.empty(n)
    f_out = np.empty(n)
    z_out = np.empty(n)
    hist = np.empty(ntap)
    q = q0
    v = v0
    z = z0
    qm0 = q0
    if q_res > 0.0:
        qm0 = q_res * np.round(q0 / q_res)
    for i in range(ntap):
        hist[i] = qm0
    qf_prev = qm0
    integ = 0.0
    is_lugre = fp[P_MODEL] == MODEL_LUGRE
    is_none = fp[P_MODEL] == MODEL_NONE
    explicit = rk_b.shape[0] > 0 and not is_lugre
    for k in range(n):
        qm = q
        if q_res > 0.0:
            qm = q_res * np.round(q / q_res)
        for i in range(ntap - 1, 0, -1):
            hist[i] = hist[i - 1]
        hist[0] = qm
        qf = 0.0
        for i in range(ntap):
            qf += taps[i] * hist[i]
        dq = (qf - qf_prev) / period
        qf_prev = qf
        u_cmd[k], integ = _controller(ref, k, qm, dq, period, kp, kv, ki, kff, integ, u_max)
        # record the state at the sample instant
        f0 = gain * (_applied(u_cmd, k * n_sub - d_sub, n_sub) + ext[k]) - offset
        q_out[k] = q
        v_out[k] = v
        z_out[k] = z
        if explicit:
            a_out[k] = (f0 - sliding_friction(v, fp)) / mass
        else:
            a_out[k] = _acceleration(v, z, f0, mass, fp)
        for s in range(n_sub):
            f = gain * (_applied(u_cmd, k * n_sub + s - d_sub, n_sub) + ext[k]) - offset
            q, v, z = _mech_substep(q, v, z, f, h, mass, fp, is_none, is_lugre, explicit,
                                    rk_a, rk_b)
        u_app[k] = _applied(u_cmd, k * n_sub + n_sub - 1 - d_sub, n_sub)
        f_out[k] = gain * (u_app[k] + ext[k])
    return q_out, v_out, a_out, u_cmd, u_app, f_out, z_out


def simulate_rigid_servo(
    ref,
    axis: RigidAxis,
    servo: DiscreteServo,
    ext=None,
    n_sub: int = 20,
    q0: float | None = None,
    v0: float = 0.0,
    z0: float = 0.0,
    integrator: str = "exact",
) -> RigidServoResult:
    """Simulate a rigid axis in closed loop, one controller sample per reference value.

    Parameters
    ----------
    ref : array_like
        Position reference, one value per controller sample [m].
    axis : RigidAxis
        Mass, offset and friction [-].
    servo : DiscreteServo
        Controller, delay, saturation and actuator gain [-].
    ext : array_like, optional
        External input per sample, added after saturation and before the gain
        [controller units].
    n_sub : int
        Mechanical sub-steps per controller sample, >= 1 [-].
    q0 : float, optional
        Initial position; defaults to ``ref[0]`` [m].
    v0 : float
        Initial velocity [m/s].
    z0 : float
        Initial friction state (LuGre bristle deflection) [m].
    integrator : {"exact", "rk4", "dopri5"}
        ``"exact"``: each sub-step solved in closed form with the rest phase. ``"rk4"`` or
        ``"dopri5"``: an explicit step per sub-step with ``sign(0) = 0`` and no rest
        phase, as block-diagram simulators integrate Coulomb friction without
        zero-crossing detection (static friction models only) [-].

    Returns
    -------
    RigidServoResult
        Sampled position, velocity, acceleration, controller outputs and force [-].
    """
    ref = np.ascontiguousarray(ref, dtype=float).ravel()
    if ref.size < 2 or not np.all(np.isfinite(ref)):
        raise InputError("ref must hold at least 2 finite samples", column="ref")
    if ext is None:
        ext = np.zeros_like(ref)
    ext = np.ascontiguousarray(ext, dtype=float).ravel()
    if ext.shape != ref.shape or not np.all(np.isfinite(ext)):
        raise InputError(
            f"ext must be finite and have the length of ref ({ref.size}), got {ext.size}",
            column="ext",
        )
    if int(n_sub) < 1:
        raise InputError("n_sub must be >= 1", column="n_sub")
    if integrator not in INTEGRATORS:
        raise InputError(f"unknown integrator {integrator!r}; use one of {INTEGRATORS}",
                         column="integrator")
    if integrator != "exact" and isinstance(axis.friction, LuGreFriction):
        raise InputError("explicit integrators take static friction only; use "
                         "integrator='exact' with LuGre friction", column="integrator")
    rk_a, rk_b = _tableau(integrator)
    fp = friction_params_array(axis.friction)
    q_init = float(ref[0]) if q0 is None else float(q0)
    out = rigid_servo_kernel(
        ref, ext, servo.period, int(n_sub), axis.mass, axis.offset, fp,
        servo.kp, servo.kv, servo.ki, servo.kff, np.asarray(servo.taps, dtype=float),
        servo.delay, servo.u_max, servo.gain, servo.q_resolution, q_init, float(v0),
        float(z0), rk_a, rk_b,
    )
    t = np.arange(ref.size) * servo.period
    return RigidServoResult(t, *out)


def _tableau(integrator: str) -> tuple[np.ndarray, np.ndarray]:
    """Butcher tableau as arrays; empty ones for the closed-form sub-step."""
    if integrator == "exact":
        return np.zeros((0, 0)), np.zeros(0)
    rows, b = TABLEAUS[integrator]
    a = np.zeros((len(b), len(b)))
    for i, row in enumerate(rows):
        a[i, : len(row)] = row
    return a, np.asarray(b, dtype=float)
