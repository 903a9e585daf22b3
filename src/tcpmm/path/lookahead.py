"""The look-ahead over all blocks (compiled): a backward and a forward pass so every
segment can reach its exit speed. The limits it works from are
:mod:`tcpmm.path.speedlimits`.
"""

from __future__ import annotations

from numba import njit

from .profile import reach
from .speedlimits import (  # noqa: F401  (where they were)
    JUNCTION_CAUSES,
    REVERSAL_TOL,
    SEGMENT_CAUSES,
    junction_limits,
    segment_limits,
)


@njit(cache=True)
def lookahead(length, vj, acc, j):
    """Junction speeds after the backward and forward passes.

    Parameters
    ----------
    length : ndarray
        Segment lengths [m].
    vj : ndarray
        Junction speed limits, ``len(length) + 1`` entries [m/s].
    acc : ndarray
        Tangential acceleration limit per segment [m/s^2].
    j : float
        Path jerk limit, ``inf`` for trapezoid [m/s^3].

    Returns
    -------
    ndarray
        Junction speeds that every segment can connect [m/s].
    """
    n = length.size
    v = vj.copy()
    for i in range(n - 1, -1, -1):
        v[i] = reach(v[i + 1], length[i], acc[i], j, v[i])
    for i in range(n):
        v[i + 1] = reach(v[i], length[i], acc[i], j, v[i + 1])
    return v


@njit(cache=True)
def backward(length, vj, acc, j):
    """Junction speeds after the backward pass alone: from each junction, the highest
    speed from which everything after it can still be reached (within the limits).

    Parameters and result as :func:`lookahead` [m], [m/s], [m/s^2], [m/s^3].
    """
    n = length.size
    v = vj.copy()
    for i in range(n - 1, -1, -1):
        v[i] = reach(v[i + 1], length[i], acc[i], j, v[i])
    return v
