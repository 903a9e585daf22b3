"""LuGre friction along a recorded motion (compiled; arrays in, arrays out).

Identification needs the friction force a LuGre contact would exert along a measured
velocity trace, without simulating the axis: the bristle deflection is driven by the
displacement of each sample, and its equation ``dz/dx = sign(dx) - sigma0 z / g(v)`` is
linear over a sample at frozen ``g``, so each sample is advanced exactly whatever its length
(no stiffness limit on the sample period).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..mechanics.friction import P_FV_NEG, P_FV_POS, P_SIGMA0
from .friction import _micro_damping, stribeck_level

__all__ = ["lugre_path_force"]


@njit(cache=True)
def lugre_path_force(v, dt, params, z0):
    """Friction force of a LuGre contact moved with velocity ``v``.

    Parameters
    ----------
    v : ndarray
        Velocity of the contact at each sample, held over the sample [m/s].
    dt : float
        Sample period [s].
    params : ndarray
        LuGre parameter vector of :func:`tcpmm.mechanics.friction.friction_params_array`
        (its viscous part is included) [-].
    z0 : float
        Bristle deflection at the first sample [m].

    Returns
    -------
    ndarray
        Friction force against the motion at the end of each sample [N].
    """
    n = v.size
    out = np.empty(n)
    s0 = params[P_SIGMA0]
    z = z0
    for k in range(n):
        vk = v[k]
        dx = vk * dt
        z_old = z
        if dx != 0.0:
            g = stribeck_level(vk, params)
            zs = g / s0 if dx > 0.0 else -g / s0
            z = zs + (z - zs) * math.exp(-s0 * abs(dx) / g)
        zdot = (z - z_old) / dt
        fv = params[P_FV_POS] if vk >= 0.0 else params[P_FV_NEG]
        out[k] = s0 * z + _micro_damping(vk, params) * zdot + fv * vk
    return out
