"""Compiled friction laws at a velocity (numba, for per-step simulation loops): the
Stribeck curve and the LuGre bristle's steady state and decay rate.

The functions read the parameter vector built by ``friction_params_array`` of
:mod:`tcpmm.mechanics.friction`, whose constants give the vector layout and the model
codes; the friction step over time that uses them is :mod:`tcpmm.sim.contact`'s.

``sliding_friction(v, params) -> F``
    Steady-state friction at velocity ``v`` (the Stribeck curve, ``0.0`` at ``v == 0``).
``static_levels(params) -> (Fs_plus, Fs_minus)``
    Break-away levels, both non-negative [N].
``lugre_steady_state(v, params) -> z``
    Bristle deflection in steady sliding at ``v`` [m].
``lugre_decay_rate(v, params) -> rate``
    Rate of the LuGre bristle equation ``z' = v - rate * z`` [1/s].
"""

from __future__ import annotations

import math

from numba import njit

from tcpmm.mechanics.friction import (
    MODEL_NONE,
    P_DELTA,
    P_FC_NEG,
    P_FC_POS,
    P_FS_NEG,
    P_FS_POS,
    P_FV_NEG,
    P_FV_POS,
    P_MODEL,
    P_SIGMA0,
    P_SIGMA1,
    P_SIGMA1_FADES,
    P_VS,
)

__all__ = [
    "lugre_decay_rate",
    "lugre_steady_state",
    "micro_damping",
    "sliding_friction",
    "static_levels",
    "stribeck_level",
    "viscous_coefficient",
]


@njit(cache=True)
def static_levels(params):
    """Break-away levels of a friction parameter vector.

    Parameters
    ----------
    params : numpy.ndarray
        Vector from ``friction_params_array`` [-].

    Returns
    -------
    tuple of float
        ``(Fs_plus, Fs_minus)``, both non-negative [N].
    """
    if params[P_MODEL] == MODEL_NONE:
        return 0.0, 0.0
    return params[P_FS_POS], params[P_FS_NEG]


@njit(cache=True, inline="always")
def stribeck_level(v, params):
    """Coulomb + Stribeck part of the sliding friction, as a magnitude.

    Parameters
    ----------
    v : float
        Velocity, non-zero; its sign selects the direction-dependent levels [m/s].
    params : numpy.ndarray
        Vector from ``friction_params_array`` [-].

    Returns
    -------
    float
        ``g(v) = Fc_d + (Fs_d - Fc_d) exp(-|v / vs|**delta)`` [N].
    """
    fc, fs = _levels(v, params)
    if fs == fc:
        return fc
    return fc + (fs - fc) * _stribeck_shape(v, params)


@njit(cache=True, inline="always")
def _levels(v, params):
    """``(Fc_d, Fs_d)`` of the direction of ``v``, that of ``v < 0`` at rest [N]."""
    if v > 0.0:
        return params[P_FC_POS], params[P_FS_POS]
    return params[P_FC_NEG], params[P_FS_NEG]


@njit(cache=True, inline="always")
def _stribeck_shape(v, params):
    """``exp(-|v / vs|**delta)``, taken as 0 where it is below double precision [-]."""
    x = abs(v) / params[P_VS]
    d = params[P_DELTA]
    if d == 2.0:  # the usual Gaussian form: spare the general power
        p = x * x
    elif d == 1.0:
        p = x
    else:
        p = x**d
    if p > 40.0:  # exp(-40) is below double precision relative to fc
        return 0.0
    return math.exp(-p)


@njit(cache=True, inline="always")
def viscous_coefficient(v, params):
    """Viscous coefficient of the direction of ``v``, that of ``v > 0`` at rest [N s/m]."""
    return params[P_FV_POS] if v >= 0.0 else params[P_FV_NEG]


@njit(cache=True, inline="always")
def sliding_friction(v, params):
    """Steady-state friction at velocity ``v`` (the Stribeck curve).

    Parameters
    ----------
    v : float
        Velocity [m/s].
    params : numpy.ndarray
        Vector from ``friction_params_array`` [-].

    Returns
    -------
    float
        Friction force against the motion, with the sign of ``v``; ``0.0`` at ``v == 0``
        [N].
    """
    if params[P_MODEL] == MODEL_NONE or v == 0.0:
        return 0.0
    g = stribeck_level(v, params)
    return (g if v > 0.0 else -g) + viscous_coefficient(v, params) * v


@njit(cache=True)
def lugre_steady_state(v, params):
    """Bristle deflection of the LuGre model in steady sliding.

    Parameters
    ----------
    v : float
        Velocity [m/s].
    params : numpy.ndarray
        Vector from ``friction_params_array`` of a LuGre model [-].

    Returns
    -------
    float
        ``z_ss = sign(v) g(v) / sigma0``; ``0.0`` at ``v == 0`` [m].
    """
    if v == 0.0 or params[P_SIGMA0] <= 0.0:
        return 0.0
    g = stribeck_level(v, params)
    return (g if v > 0.0 else -g) / params[P_SIGMA0]


@njit(cache=True)
def lugre_decay_rate(v, params):
    """Rate ``sigma0 |v| / g(v)`` of the LuGre bristle equation ``z' = v - rate * z``.

    Parameters
    ----------
    v : float
        Velocity [m/s].
    params : numpy.ndarray
        Vector from ``friction_params_array`` of a LuGre model [-].

    Returns
    -------
    float
        Decay rate, ``0.0`` at ``v == 0`` [1/s].
    """
    if v == 0.0:
        return 0.0
    return params[P_SIGMA0] * abs(v) / stribeck_level(v, params)


@njit(cache=True)
def micro_damping(v, params):
    """LuGre micro-damping at ``v``: ``sigma1``, faded by the Stribeck shape if asked
    [N s/m]."""
    s1 = params[P_SIGMA1]
    if params[P_SIGMA1_FADES] == 0.0 or v == 0.0 or s1 == 0.0:
        return s1
    return s1 * _stribeck_shape(v, params)


@njit(cache=True, inline="always")
def lugre_rates(v, params):
    """``(micro_damping(v), lugre_decay_rate(v))`` with the Stribeck shape taken once:
    the same numbers [N s/m, 1/s]."""
    s1 = params[P_SIGMA1]
    if v == 0.0:
        return s1, 0.0
    fc, fs = _levels(v, params)
    fades = params[P_SIGMA1_FADES] != 0.0 and s1 != 0.0
    shape = _stribeck_shape(v, params) if fades or fs != fc else 0.0
    g = fc if fs == fc else fc + (fs - fc) * shape
    return (s1 * shape if fades else s1), params[P_SIGMA0] * abs(v) / g
