"""A curve posted as short straight blocks (a chain of lines left sharp): the speed its
curvature allows at each corner (:func:`chain_limits`), and the tangential acceleration
left to its lines beside the centripetal acceleration of their corners
(:func:`chain_tangential`), both shared as on an arc."""

from __future__ import annotations

import numpy as np

from .._rows import dot_rows, min_rows, norm_rows
from .geometry import PathArrays
from .segments import LINE


def _corner_plane(t_out, t_in):
    """Per corner: the largest share of a unit vector in the plane of the two tangents
    that falls on each axis, shape (m, 3), and the change of the unit tangent's length
    [-]."""
    du = t_in - t_out
    # the plane of the corner: t_out and the unit vector e2 normal to it towards t_in
    e2 = t_in - dot_rows(t_in, t_out)[:, None] * t_out
    n2 = norm_rows(e2)
    e2 = np.divide(e2, n2[:, None], out=np.zeros_like(e2), where=n2[:, None] > 0.0)
    return np.sqrt(t_out**2 + e2**2), norm_rows(du)


def chain_limits(p: PathArrays, t_out, t_in, acc_normal) -> np.ndarray:
    """Speed limit of each inner junction between two straight blocks from the curvature
    of the chain they belong to [m/s].

    The step rule of :func:`~tcpmm.path.speedlimits._corner_limits` holds each corner
    alone: ``v*|du_k|`` within ``a_step_k*T`` (``du`` the change of the unit tangent,
    ``T`` the filter's spread or one period). Where the blocks are shorter than ``v*T``,
    ``v*T/L`` corners fall within one ``T`` and their steps add up to a steady centripetal
    acceleration ``v^2*|du|/L`` the step rule leaves unbounded (0.02 mm chords of a circle
    at F20000: 5.6 times the axes' limit). It is held here as on an arc, with the local
    curvature ``|du| / Lbar``::

        v <= sqrt(a_n * Lbar / |du|),   a_n = min over k of a_n_k / share_k

    ``a_n_k`` the centripetal share of axis ``k``'s acceleration
    (:func:`~tcpmm.path.speedlimits.normal_accel`: ``a_k/sqrt(2)`` by default, the rest
    left to the tangent as on arcs and blends); ``share_k`` the largest share of a unit
    vector in the plane of the two tangents that falls on axis ``k``, as for blends (1 for
    X and Y of a curve in XY). ``Lbar`` is the mean of the two blocks' lengths: the
    tangent turns by ``du`` between their midpoints, ``Lbar`` apart, so the chords of a
    circle of radius ``r`` give ``|du|/Lbar = 1/r`` and run as its arc, whatever their
    length (the shorter length would make a curve posted in blocks of alternating length
    several times too sharp).

    Against the step rule's speed ``v_s``: the chain's limit is the lower where
    ``Lbar < v_s^2*|du|/a_n = c * v_s*T``, ``c = (v_s*|du|/T) / a_n`` the step's
    acceleration over the centripetal share; with the defaults (``a_step_k = a_k``,
    ``a_n_k = a_k/sqrt(2)``) and a turn in XY, ``c`` is ``sqrt(2)`` to 2: where a corner or
    more falls within about ``T``. Longer blocks keep the step rule and their numbers.
    The lines' tangential acceleration is shared with this centripetal acceleration by
    :func:`chain_tangential`.

    Parameters
    ----------
    p : PathArrays
        The path [-].
    t_out, t_in : ndarray, shape (n - 1, 3)
        Unit tangents before and after each inner junction [-].
    acc_normal : sequence of float
        Centripetal acceleration of X, Y, Z (:func:`~tcpmm.path.speedlimits.normal_accel`)
        [m/s^2].

    Returns
    -------
    ndarray
        ``n - 1`` limits, ``inf`` at junctions that are not between two lines [m/s].
    """
    lines = (p.kind[:-1] == LINE) & (p.kind[1:] == LINE)
    lbar = 0.5 * (p.length[:-1] + p.length[1:])
    share, dun = _corner_plane(t_out, t_in)
    with np.errstate(divide="ignore", invalid="ignore"):
        a_n = min_rows(np.asarray(acc_normal, float)[None, :] / share)
        v = np.where(dun > 0.0, np.sqrt(a_n * lbar / dun), np.inf)
    return np.where(lines, v, np.inf)


def chain_tangential(p: PathArrays, du, vj, acc, acc_axis, acc_normal, start=None,
                     open_end=False):
    """Tangential acceleration limit of each segment, lowered on the lines between corners
    so that with the centripetal acceleration of the corners every axis stays within its
    limit; and that centripetal acceleration per axis at each junction [m/s^2].

    At a corner between two lines the velocity turns by ``v*|du|``, one such step per
    block: over the blocks on either side a centripetal acceleration
    ``c = v^2*|du|/Lbar`` along ``n = du/|du|``, at most ``a_n`` at the junction's speed
    limit ``v`` (:func:`chain_limits`). Axis ``k`` of a line along ``u`` beside it reads
    ``a_t*|u_k| + c*|n_k|`` at most, so the line keeps
    ``a_t <= min_k (a_k - c*|n_k|) / |u_k|``: about the tangential share of an arc where
    short blocks run at the chain's limit; nearly the whole acceleration at a corner
    between long blocks, whose step falls in one period (:func:`~tcpmm.path.speedlimits.
    _corner_limits`), or at a tangent join. The look-ahead only lowers a junction's
    speed, and so ``c``.

    Parameters
    ----------
    p : PathArrays
        The path [-].
    du : ndarray, shape (n - 1, 3), or None
        Change of the unit tangent at each inner junction; ``None`` under two segments [-].
    vj : ndarray
        ``n + 1`` junction speed limits (:func:`~tcpmm.path.speedlimits.junction_limits`)
        [m/s].
    acc : ndarray
        Tangential acceleration limit per segment (:func:`~tcpmm.path.speedlimits.
        segment_limits`) [m/s^2].
    acc_axis, acc_normal : sequence of float
        Acceleration of X, Y, Z, and the centripetal share of it
        (:func:`~tcpmm.path.speedlimits.normal_accel`) [m/s^2].
    start : ndarray, optional
        ``c*|n|`` at the junction before the first segment, where ``p`` continues a path
        planned before (none at its start) [m/s^2].
    open_end : bool
        More segments follow ``p``: the last, if a line, is held as if a corner after it
        took the whole centripetal share ``acc_normal``, the most any corner can [-].

    Returns
    -------
    acc : ndarray
        The tangential acceleration limits [m/s^2].
    load : ndarray, shape (n + 1, 3)
        ``c*|n|`` at each junction [m/s^2].
    """
    n = p.n
    lines = (p.kind == LINE) & ~p.rapid
    load = np.zeros((n + 1, 3))
    if start is not None:
        load[0] = start
    if n >= 2:
        load[1:-1] = _corner_loads(p, du, vj[1:-1], lines[:-1] & lines[1:])
    if open_end and n and lines[-1]:
        load[-1] = np.asarray(acc_normal, float)
    u = np.abs(p.end - p.start) / np.where(p.length > 0, p.length, 1.0)[:, None]
    room = np.asarray(acc_axis, float)[None, :] - np.maximum(load[:-1], load[1:])
    with np.errstate(divide="ignore", invalid="ignore"):
        cap = min_rows(np.where(u > 0.0, np.maximum(room, 0.0) / u, np.inf))
    return np.where(lines, np.minimum(acc, cap), acc), load


def _corner_loads(p: PathArrays, du, v, chained) -> np.ndarray:
    """``c*|n|`` at each inner junction, shape (n - 1, 3): the centripetal acceleration
    ``v^2*|du|/Lbar`` of the corners between two lines (``chained``) at their speed
    limits ``v``, per axis, zero elsewhere (``du`` the change of the unit tangent)
    [m/s^2]."""
    lbar = 0.5 * (p.length[:-1] + p.length[1:])
    with np.errstate(divide="ignore", invalid="ignore"):
        c = np.where(chained & (norm_rows(du) > 0.0), v**2 / lbar, 0.0)
    return c[:, None] * np.abs(du)
