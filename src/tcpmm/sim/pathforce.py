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
