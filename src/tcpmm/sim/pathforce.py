"""Compiled force of a LuGre contact driven along a given displacement path.

Arrays in, arrays out. The contact is moved through the samples of ``s`` at constant
velocity within each sample interval; the bristle state is advanced with the exact
solution of its linear equation at that velocity (``friction_force`` with ``m_eff = 0``),
so the force does not depend on how the path was sampled apart from its samples.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..mechanics.friction import P_SIGMA0
from .contact import friction_force, lugre_steady_state


@njit(cache=True)
def contact_force_along_path(s, h, params):
    """Friction force of one LuGre contact moved along the path ``s``.

    Parameters
    ----------
    s : numpy.ndarray
        Displacement of the contact at the samples, at least two [m].
    h : float
        Sample period [s].
    params : numpy.ndarray
        Vector from ``friction_params_array`` of a LuGre contact [-].

    Returns
    -------
    numpy.ndarray
        Force against the motion at each sample [N]; the first sample holds the
        steady sliding deflection of the first interval's velocity.
    """
    n = s.shape[0]
    out = np.empty(n)
    z = lugre_steady_state((s[1] - s[0]) / h, params)
    out[0] = params[P_SIGMA0] * z
    for k in range(1, n):
        v = (s[k] - s[k - 1]) / h
        f, z = friction_force(v, 0.0, z, params, h, 0.0)
        out[k] = f
    return out


@njit(cache=True)
def play_operator(s, width):
    """The path ``s`` through a play of total ``width``: the output stands still until the
    input has moved ``width / 2`` away from it, then follows at that distance.

    Back-and-forth wiggles of the input narrower than ``width`` (sensor noise on a
    creeping axis) leave the output still; a travel longer than ``width`` comes through
    whole, lagging by ``width / 2``.

    Parameters
    ----------
    s : numpy.ndarray
        Input path, at least one sample [m].
    width : float
        Total width of the play, 0 or more [m].

    Returns
    -------
    numpy.ndarray
        Output path, starting at the first input sample [m].
    """
    out = np.empty_like(s)
    half = 0.5 * width
    y = s[0]
    for k in range(s.shape[0]):
        if s[k] > y + half:
            y = s[k] - half
        elif s[k] < y - half:
            y = s[k] + half
        out[k] = y
    return out
