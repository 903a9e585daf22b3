"""Compiled friction and lost-motion functions (numba, for per-step simulation loops).

The functions read the parameter vectors built by ``friction_params_array`` and
``backlash_params_array`` of :mod:`tcpmm.mechanics.friction`, whose constants give the
vector layout and the model codes. Every friction force ``F`` is the force the friction
exerts *against* the body's motion, so that the body obeys ``m v' = f_applied - F``,
with ``f_applied`` the sum of every other force on the body along the same coordinate
[N] (the sign convention of :mod:`tcpmm.mechanics.friction`).

Calling conventions
-------------------
Build the parameter vector once, outside the loop, then call the jitted functions with
plain floats inside ``@njit`` code::

    p = friction_params_array(model)          # np.ndarray, float64, length N_FRICTION_PARAMS
    s = 0.0                                   # friction state, one float per contact
    F, s = friction_force(v, f_applied, s, p, dt, m_eff)
    v_end = v + dt * (f_applied - F) / m_eff
    if at_rest(s, p):
        v_end = 0.0

``friction_force(v, f_applied, state, params, dt, m_eff) -> (F, new_state)``
    One time step ``[t, t + dt]`` of a body moving at ``v`` [m/s] at ``t`` with the other
    forces ``f_applied`` [N] held over the step. Returns the friction force ``F`` [N] to
    hold constant over the step and the friction state at ``t + dt``. The step is meant
    to be completed by the caller as ``v_end = v + dt * (f_applied - F) / m_eff``, and
    ``v_end = 0.0`` exactly when ``at_rest(new_state, params)`` (the stop force brings the
    velocity to zero only up to rounding).

    - ``m_eff`` [kg] is the mass of the body as the friction sees it over the step
      (``m_eff = dt / |dv_end/dF|``). For a free body it is its mass. For an exactly
      discretised linear system (ZOH), take ``dv_end/dF`` from the discrete input column
      of the friction force, and pass ``f_applied = m_eff * (v_free - v) / dt`` where
      ``v_free`` is the end-of-step velocity the step would give without friction: the
      returned ``F`` then gives ``v_end = v_free - dt * F / m_eff``.
    - ``state``: LuGre bristle deflection ``z`` [m] (read and returned); for the static
      model a stick flag, ``STUCK`` (1.0) or ``SLIDING`` (0.0), that is only returned.
    - Static model, ``m_eff > 0``: exact stick. If the body is at rest, or if the sliding
      friction would reverse the velocity inside the step, the friction becomes the force
      that stops the body at the end of the step, ``F_stop = f_applied + m_eff * v / dt``,
      provided ``-Fs_- <= F_stop <= Fs_+`` (state ``STUCK``); beyond the static band it
      is clipped to it and the body slips through zero into the other direction (or
      breaks away). Otherwise it is the sliding value ``F(v)``. A body at rest under
      ``|f_applied|`` below the static level stays at exactly zero velocity; a reversal
      lands on zero instead of overshooting, so there is no chattering.
    - Static model, ``m_eff == 0``: Karnopp stick band. For ``|v| <= v_stick``,
      ``F = clip(f_applied, -Fs_-, Fs_+)``; outside it ``F = F(v)``.
    - LuGre model: the bristle equation is stiff (``sigma0`` is large), so ``z`` and
      ``v`` are advanced together by a linearly implicit (backward Euler) step with the
      rate ``sigma0 |v| / g(v)`` frozen at the start of the step; with ``m_eff == 0`` the
      velocity is taken as constant and ``z`` is updated with the exact exponential
      solution of its linear equation. Both updates are stable for any ``dt``.
    - The caller should sub-step (shorter ``dt``) around velocity reversals if it needs
      the reversal instant to better than one step; stick itself needs no sub-stepping.

``friction_step(v, f_applied, state, params, dt, m_eff) -> (v_end, F, new_state)``
    The same step completed for a single free body of mass ``m_eff > 0``.
``at_rest(state, params) -> bool``
    True when a static-model step ended in stick.
``static_stop_or_slide(v, f_stop, params) -> (F, new_state)``
    The static model's step given the force ``f_stop`` that brings the body to rest at
    the end of the step (what ``friction_force`` does with ``m_eff > 0``), for callers
    that have ``f_stop`` more directly.
``backlash_force(delta, delta_dot, params) -> F``
    Force transmitted across a backlash element of relative displacement ``delta`` [m]
    and relative velocity ``delta_dot`` [m/s]; zero inside the gap ``|delta| <= b``,
    ``k (delta - b) + c delta_dot`` beyond ``+b`` (never pulling, i.e. clipped at 0),
    symmetric beyond ``-b``. Parameters from ``backlash_params_array(model)``.

The friction laws at a velocity these steps use (``sliding_friction``, ``static_levels``,
``lugre_steady_state``, ``lugre_rates``: ``micro_damping`` and ``lugre_decay_rate`` at
once, ``stribeck_level``) are :mod:`tcpmm.sim.frictionlaw`'s; they are named here too,
beside the steps (``lugre_decay_rate`` for the callers that take it alone).
"""

from __future__ import annotations

import math

from numba import njit

from tcpmm.mechanics.friction import (
    B_C,
    B_GAP,
    B_K,
    MODEL_LUGRE,
    MODEL_NONE,
    MODEL_STATIC,
    P_FS_NEG,
    P_FS_POS,
    P_MODEL,
    P_SIGMA0,
    P_V_STICK,
    SLIDING,
    STUCK,
)

# the friction laws stay importable from here, where the simulator's callers take them
from .frictionlaw import (
    lugre_decay_rate,
    lugre_rates,
    lugre_steady_state,
    sliding_friction,
    static_levels,
    stribeck_level,
    viscous_coefficient,
)

__all__ = [
    "at_rest",
    "backlash_force",
    "friction_force",
    "friction_step",
    "lugre_decay_rate",
    "lugre_steady_state",
    "sliding_friction",
    "static_levels",
    "static_stop_or_slide",
    "stribeck_level",
]


@njit(cache=True, inline="always")
def _clip(x, lo, hi):
    if x < lo:
        return lo
    if x > hi:
        return hi
    return x


@njit(cache=True, inline="always")
def _stop_or_slip(f_stop, fsn, fsp):
    if -fsn <= f_stop <= fsp:
        return f_stop, STUCK
    return _clip(f_stop, -fsn, fsp), SLIDING


@njit(cache=True, inline="always")
def static_stop_or_slide(v, f_stop, params):
    """Static friction over a step of a body that ``f_stop`` would bring to rest.

    Parameters
    ----------
    v : float
        Velocity at the start of the step [m/s].
    f_stop : float
        Friction force, held over the step, that brings the body to rest at its end
        (``f_applied + m_eff * v / dt``) [N].
    params : numpy.ndarray
        Vector from ``friction_params_array`` of a static model [-].

    Returns
    -------
    tuple of float
        ``(F, new_state)``: the sliding friction if it does not reverse the velocity within
        the step (``SLIDING``); else ``f_stop`` within the static band (``STUCK``), clipped
        to it beyond (``SLIDING``) [N, -].
    """
    f_sl = sliding_friction(v, params)  # 0.0 at v == 0
    if (v > 0.0 and f_sl < f_stop) or (v < 0.0 and f_sl > f_stop):
        return f_sl, SLIDING
    # at rest, or the sliding force reverses v
    return _stop_or_slip(f_stop, params[P_FS_NEG], params[P_FS_POS])


@njit(cache=True, inline="always")
def _static_step(v, f_applied, params, dt, m_eff):
    if m_eff > 0.0:
        return static_stop_or_slide(v, f_applied + m_eff * v / dt, params)
    fsp = params[P_FS_POS]
    fsn = params[P_FS_NEG]
    f_sl = sliding_friction(v, params)  # 0.0 at v == 0
    if abs(v) <= params[P_V_STICK]:
        return _clip(f_applied, -fsn, fsp), SLIDING
    return f_sl, SLIDING


@njit(cache=True, inline="always")
def _lugre_step(v, f_applied, z, params, dt, m_eff):
    s0 = params[P_SIGMA0]
    s1, c = lugre_rates(v, params)
    fv = viscous_coefficient(v, params)
    if m_eff > 0.0:
        # backward Euler on (v, z) with c frozen:
        #   m (v1 - v)/dt = f_applied - F1
        #   z1 = (z + dt v1) / (1 + c dt)
        #   F1 = (s0 - s1 c) z1 + (s1 + fv) v1
        den = 1.0 + c * dt
        k = s0 - s1 * c
        a = m_eff / dt + k * dt / den + s1 + fv
        v1 = (m_eff * v / dt + f_applied - k * z / den) / a
        z1 = (z + dt * v1) / den
        f1 = k * z1 + (s1 + fv) * v1
        return f1, z1
    if c > 0.0:
        z_ss = v / c
        z1 = z_ss + (z - z_ss) * math.exp(-c * dt)
    else:
        z1 = z + v * dt
    zdot = v - c * z1
    return s0 * z1 + s1 * zdot + fv * v, z1


@njit(cache=True, inline="always")
def friction_force(v, f_applied, state, params, dt, m_eff):
    """Friction force over one time step, with exact stick and a stable state update.

    Parameters
    ----------
    v : float
        Velocity of the body at the start of the step [m/s].
    f_applied : float
        Sum of all other forces on the body, held over the step [N].
    state : float
        Friction state at the start of the step: LuGre bristle deflection [m]; for the
        static model a stick flag (``STUCK`` or ``SLIDING``) that is returned, not read
        [-].
    params : numpy.ndarray
        Vector from ``friction_params_array`` [-].
    dt : float
        Step length, > 0 [s].
    m_eff : float
        Mass the friction acts on over the step (``0.0`` if unknown: Karnopp band for the
        static model, constant-velocity state update for LuGre) [kg].

    Returns
    -------
    tuple of float
        ``(F, new_state)``: friction force against the motion to hold over the step [N]
        and the friction state at the end of the step (LuGre: deflection [m]; static:
        ``STUCK`` if the body is at rest at the end of the step, else ``SLIDING`` [-]).
    """
    model = params[P_MODEL]
    if model == MODEL_NONE:
        return 0.0, state
    if model == MODEL_LUGRE:
        return _lugre_step(v, f_applied, state, params, dt, m_eff)
    return _static_step(v, f_applied, params, dt, m_eff)


@njit(cache=True, inline="always")
def at_rest(state, params):
    """Whether a ``friction_force`` step ended in stick (static model only).

    Parameters
    ----------
    state : float
        ``new_state`` returned by ``friction_force`` [-].
    params : numpy.ndarray
        Vector from ``friction_params_array`` [-].

    Returns
    -------
    bool
        True if the body is at rest at the end of the step: the caller sets its velocity
        to exactly ``0.0`` (the returned force already brings it there up to rounding)
        [-].
    """
    return params[P_MODEL] == MODEL_STATIC and state == STUCK


@njit(cache=True)
def friction_step(v, f_applied, state, params, dt, m_eff):
    """One explicit step of a single body with friction, exact at rest.

    Parameters
    ----------
    v : float
        Velocity at the start of the step [m/s].
    f_applied : float
        Other forces on the body, held over the step [N].
    state : float
        Friction state [m or -].
    params : numpy.ndarray
        Vector from ``friction_params_array`` [-].
    dt : float
        Step [s].
    m_eff : float
        Mass of the body, > 0 [kg].

    Returns
    -------
    tuple of float
        ``(v_end, F, new_state)``: velocity at the end of the step (exactly ``0.0`` in
        stick) [m/s], friction force held over the step [N], new friction state [m or -].
    """
    f, s = friction_force(v, f_applied, state, params, dt, m_eff)
    if at_rest(s, params):
        return 0.0, f, s
    return v + dt * (f_applied - f) / m_eff, f, s


@njit(cache=True)
def backlash_force(delta, delta_dot, params):
    """Force across a screw-nut backlash (dead-zone spring with contact damping).

    Parameters
    ----------
    delta : float
        Relative displacement across the element (screw side minus nut side) [m].
    delta_dot : float
        Relative velocity [m/s].
    params : numpy.ndarray
        ``[k, b, c]`` from ``backlash_params_array`` [-].

    Returns
    -------
    float
        Transmitted force, zero inside the gap ``|delta| <= b``; in contact it never
        changes sign against the penetration (the contact only pushes) [N].
    """
    k = params[B_K]
    b = params[B_GAP]
    c = params[B_C]
    if delta > b:
        f = k * (delta - b) + c * delta_dot
        return f if f > 0.0 else 0.0
    if delta < -b:
        f = k * (delta + b) + c * delta_dot
        return f if f < 0.0 else 0.0
    return 0.0
