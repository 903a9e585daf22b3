"""Speed limits of segments and corners (numpy; the look-ahead over them is compiled, in
:mod:`tcpmm.path.lookahead`).

Segment limits: programmed feed, per-axis velocity, tangential acceleration shared
with the centripetal acceleration on arcs, and the radius loss the post-interpolation
filter causes on arcs. Corner limits: the per-axis velocity step at a corner is at most
``a_axis * T`` (``T`` = the time over which the filter, or one period, spreads it), the
filter must not cut the corner by more than the corner tolerance, and where straight
blocks are so short that several corners fall within ``T`` (a curve posted as short
lines), the centripetal acceleration of the chain is held as on an arc
(:func:`chain_limits`).
"""

from __future__ import annotations

import math

import numpy as np

from .._rows import min_rows
from ..errors import InputError
from .geometry import ARC, BLEND, DWELL, PathArrays, max_abs_trig, tangents
from .shortblocks import chain_limits, chain_tangential
from .transitions import blend_limits, transition_limits

#: unit tangents whose dot product is below -1 + this are a reversal (exact stop) [-]
REVERSAL_TOL = 1e-9
#: a change of the unit tangent below this is a tangent join, not a corner: at 1 m/s it
#: steps an axis by 1 µm/s, far below what any acceleration limit notices [-]
BEND_TOL = 1e-6
#: what sets a segment's speed limit (index = the code :func:`segment_limits` returns)
SEGMENT_CAUSES = ("programmed feed", "axis velocity", "curvature (centripetal acceleration)",
                  "filter tolerance on arcs", "transition jerk (step of curvature)")
#: what sets a junction's speed limit (index = the code :func:`junction_limits` returns)
JUNCTION_CAUSES = ("segment limit", "corner: axis acceleration", "corner: filter tolerance",
                   "exact stop", "curvature of short blocks (centripetal acceleration)",
                   "transition jerk (step of curvature)")
#: index of "exact stop", of the chain of short blocks and of a transition's step of
#: curvature (:mod:`tcpmm.path.transitions`) in ``JUNCTION_CAUSES`` [-]
EXACT_STOP, CHAIN, TRANSITION = 3, 4, 5
#: index of a blend held to its ends' transition limit in ``SEGMENT_CAUSES`` [-]
HELD_BLEND = 4


def segment_limits(p: PathArrays, vel_axis, acc_axis, acc_path, filt):
    """Speed limit and tangential acceleration limit of every segment.

    Parameters
    ----------
    p : PathArrays
        The path [-].
    vel_axis, acc_axis : sequence of float
        Velocity [m/s] and acceleration [m/s^2] limit of X, Y, Z.
    acc_path : float
        Path (tangential) acceleration limit [m/s^2].
    filt : filters.FilterShape
        The post-interpolation filter [-].

    Returns
    -------
    vmax : ndarray
        Speed limit per segment [m/s].
    acc : ndarray
        Tangential acceleration limit per segment [m/s^2].
    cause : ndarray of int
        What sets ``vmax``, an index into ``SEGMENT_CAUSES`` [-].
    """
    vel_axis = np.asarray(vel_axis, float)
    acc_axis = np.asarray(acc_axis, float)
    L = np.where(p.length > 0, p.length, 1.0)
    u = np.abs(p.end - p.start) / L[:, None]
    with np.errstate(divide="ignore", invalid="ignore"):
        v_axis = min_rows(vel_axis[None, :] / u)
        vmax = np.minimum(p.feed, v_axis)
        acc = np.minimum(acc_path, min_rows(acc_axis[None, :] / u))
    cause = np.where(v_axis < p.feed, 1, 0)
    _arc_limits(p, vel_axis, acc_axis, acc_path, filt, vmax, acc, cause)
    _blend_limits(p, vel_axis, acc_axis, acc_path, filt, vmax, acc, cause)
    vmax[p.kind == DWELL] = 0.0
    acc[p.kind == DWELL] = acc_path
    _check_limits(p, vmax)
    return vmax, acc, cause


def _arc_limits(p, vel_axis, acc_axis, acc_path, filt, vmax, acc, cause):
    """Speed and tangential acceleration limits of the arcs, set in place.

    Parameters
    ----------
    p : PathArrays
        The path [-].
    vel_axis, acc_axis : ndarray
        Velocity [m/s] and acceleration [m/s^2] limit of X, Y, Z.
    acc_path : float
        Path (tangential) acceleration limit [m/s^2].
    filt : filters.FilterShape
        The post-interpolation filter [-].
    vmax, acc, cause : ndarray
        Speed limit [m/s], tangential acceleration limit [m/s^2] and what sets the speed
        limit [-] per segment, the arcs' entries overwritten: the axis velocities over the
        angle range, the centripetal acceleration and the filter's radius loss.
    """
    a = np.flatnonzero(p.kind == ARC)
    if not a.size:
        return
    ia, ib, ih = p.ia[a], p.ib[a], p.ih[a]
    La = p.length[a]
    sw = np.abs(p.sweep[a])
    rmax = np.maximum(p.r0[a], p.r1[a])
    dr = np.abs(p.r1[a] - p.r0[a])
    mcos, msin = max_abs_trig(p.theta0[a], p.sweep[a])
    with np.errstate(divide="ignore", invalid="ignore"):
        # axis velocity: first plane axis moves with sin, second with cos
        va = vel_axis[ia] * La / (dr + rmax * sw * msin)
        vb = vel_axis[ib] * La / (dr + rmax * sw * mcos)
        vh = vel_axis[ih] * La / np.abs(p.dh[a])
        a_plane = np.minimum(acc_axis[ia], acc_axis[ib])
        a_t = np.minimum.reduce(
            [
                np.full(a.size, acc_path),
                a_plane / math.sqrt(2.0),
                acc_axis[ih] * La / np.abs(p.dh[a]),
            ]
        )
        a_n = np.sqrt(a_plane**2 - a_t**2)
        kappa = rmax * sw**2 / La**2
        vc = np.sqrt(a_n / kappa)
        vf = np.full(a.size, np.inf)
        if filt.variance_s2 > 0.0:
            # radius loss of a circle through the filter ~ r*omega^2*var/2 <= tol
            omega = np.sqrt(2.0 * filt.tolerance_m / (rmax * filt.variance_s2))
            vf = omega * La / sw
    parts = np.stack([p.feed[a], np.minimum.reduce([va, vb, vh]), vc, vf])
    vmax[a] = parts.min(axis=0)
    cause[a] = np.argmin(parts, axis=0)
    acc[a] = a_t


def _check_limits(p, vmax) -> None:
    """Refuse a motion segment whose speed limit is not positive, naming its line.

    Parameters
    ----------
    p : PathArrays
        The path [-].
    vmax : ndarray
        Speed limit per segment [m/s].
    """
    bad = np.flatnonzero((p.kind != DWELL) & ~(vmax > 0.0))
    if bad.size:  # NaN too: numbers so far apart that doubles cannot resolve the segment
        i = int(bad[0])
        raise InputError(
            f"no speed limit can be computed for a move of this block (length "
            f"{p.length[i]:.4g} m, feed {p.feed[i]:.4g} m/s); its coordinates, arc centre "
            "or radius are beyond "
            "what the interpolator resolves: check them",
            line=None if p.line[i] < 0 else int(p.line[i]))


def _blend_limits(p, vel_axis, acc_axis, acc_path, filt, vmax, acc, cause):
    """Speed and tangential acceleration limits of the corner blends, set in place: an
    axis moves along a blend at most ``sqrt(e1^2 + e2^2)`` times the path's velocity and
    acceleration; the acceleration is shared between tangent and normal as on arcs."""
    b = np.flatnonzero(p.kind == BLEND)
    if not b.size:
        return
    share = np.sqrt(p.e1[b] ** 2 + p.e2[b] ** 2)
    r = p.r0[b]
    with np.errstate(divide="ignore", invalid="ignore"):
        v_axis = min_rows(vel_axis[None, :] / share)
        a_plane = min_rows(acc_axis[None, :] / share)
    a_t = np.minimum(acc_path, a_plane / math.sqrt(2.0))
    vc = np.sqrt(np.sqrt(a_plane**2 - a_t**2) * r)
    vf = np.full(b.size, np.inf)
    if filt.variance_s2 > 0.0:
        vf = np.sqrt(2.0 * filt.tolerance_m / (r * filt.variance_s2)) * r
    parts = np.stack([p.feed[b], v_axis, vc, vf])
    vmax[b] = parts.min(axis=0)
    cause[b] = np.argmin(parts, axis=0)
    acc[b] = a_t


def normal_accel(acc_axis, acc_path: float) -> np.ndarray:
    """Share of each axis's acceleration a curve's centripetal acceleration may take, as on
    the arcs and blends: ``a_t = min(acc_path, a_axis/sqrt(2))`` is left to the tangent,
    ``sqrt(a_axis^2 - a_t^2)`` to the normal [m/s^2].

    Parameters
    ----------
    acc_axis : sequence of float
        Acceleration limit of X, Y, Z the path is planned with
        (:meth:`~tcpmm.path.settings.InterpolatorSettings.axis_accel`: a headroom left to
        a correction is already taken off) [m/s^2].
    acc_path : float
        Path (tangential) acceleration limit [m/s^2].
    """
    a = np.asarray(acc_axis, float)
    a_t = np.minimum(acc_path, a / math.sqrt(2.0))
    return np.sqrt(a**2 - a_t**2)


def junction_limits(p: PathArrays, vmax, acc, acc_axis, filt, acc_normal, turns=None):
    """Speed limit at the start of each segment and at the end of the path [m/s].

    Parameters
    ----------
    p : PathArrays
        The path [-].
    vmax : ndarray
        Speed limit per segment [m/s].
    acc : ndarray
        Tangential acceleration limit per segment [m/s^2].
    acc_axis : sequence of float
        Acceleration of X, Y, Z a corner's velocity step may take over the filter's
        spread (:meth:`~tcpmm.path.settings.InterpolatorSettings.corner_step_accel`)
        [m/s^2].
    filt : filters.FilterShape
        The post-interpolation filter [-].
    acc_normal : sequence of float
        Centripetal acceleration of X, Y, Z a chain of short straight blocks may take
        (:func:`normal_accel`) [m/s^2].
    turns : tuple of ndarray, optional
        ``(t_out, t_in)``, the unit tangents before and after each inner junction, where
        the caller has them (:func:`corner_tangents`) [-].

    Returns
    -------
    vj : ndarray
        ``n + 1`` junction speed limits; the first and last are zero [m/s].
    cause : ndarray of int
        What sets each, an index into ``JUNCTION_CAUSES`` [-].

    Notes
    -----
    With the speed ``v`` at a corner and the tangential acceleration ``a`` on either
    side, the filter pulls the path off the corner point by about
    ``|du|/2 * (v*MAD + a*VAR/2)`` (``du`` change of the unit tangent, ``MAD`` and
    ``VAR`` the mean absolute deviation and variance of the filter's impulse response).
    Where even ``v = 0`` exceeds the tolerance, the corner becomes an exact stop, and
    the next move waits until the filter has settled.
    """
    n = p.n
    vj = np.zeros(n + 1)
    cause = np.full(n + 1, EXACT_STOP)
    if n < 2:
        return vj, cause
    t_out, t_in = corner_tangents(p) if turns is None else turns
    cap, why = _corner_limits(t_in - t_out, vmax, acc, acc_axis, filt)
    chain = chain_limits(p, t_out, t_in, acc_normal)
    why = np.where(chain < cap, CHAIN, why)
    cap = np.minimum(cap, chain)
    stop = ((np.einsum("ij,ij->i", t_in, t_out) < -1.0 + REVERSAL_TOL)
            | (p.kind[:-1] == DWELL) | (p.kind[1:] == DWELL)
            | p.rapid[:-1] | p.rapid[1:] | p.exact_stop[:-1])
    vj[1:-1] = np.where(stop, 0.0, cap)
    cause[1:-1] = np.where(stop, EXACT_STOP, why)
    return vj, cause


def corner_tangents(p: PathArrays) -> tuple[np.ndarray, np.ndarray]:
    """The unit tangents before and after each inner junction, shape (n - 1, 3) each [-]."""
    return tangents(p, at_end=True)[:-1], tangents(p, at_end=False)[1:]


def _corner_limits(du, vmax, acc, acc_axis, filt):
    """Speed limit of each inner junction before exact stops, and what sets it.

    Parameters
    ----------
    du : ndarray, shape (n - 1, 3)
        Change of the unit tangent at each inner junction [-].
    vmax : ndarray
        Speed limit per segment [m/s].
    acc : ndarray
        Tangential acceleration limit per segment [m/s^2].
    acc_axis : sequence of float
        Acceleration of X, Y, Z a corner's velocity step may take [m/s^2].
    filt : filters.FilterShape
        The post-interpolation filter [-].

    Returns
    -------
    cap : ndarray
        The lowest of the two segments' limits, the axis velocity step and the filter
        tolerance [m/s].
    why : ndarray of int
        Which of the three sets it, an index into ``JUNCTION_CAUSES`` [-].
    """
    with np.errstate(divide="ignore", invalid="ignore"):
        adu = np.abs(du)
        step = np.where(adu > BEND_TOL,
                        np.asarray(acc_axis, float)[None, :] * filt.spread_s / adu, np.inf)
        cap = min_rows(step)
        dun = np.linalg.norm(du, axis=1)
        tol = np.full(du.shape[0], np.inf)
        if filt.mad_s > 0.0:
            a_side = np.maximum(acc[:-1], acc[1:])
            room = 2.0 * filt.tolerance_m / dun - 0.5 * a_side * filt.variance_s2
            tol = np.maximum(room, 0.0) / filt.mad_s
    parts = np.stack([np.minimum(vmax[:-1], vmax[1:]), cap, tol])
    return parts.min(axis=0), np.argmin(parts, axis=0)


def path_limits(p: PathArrays, settings, filt, start=None, open_end: bool = False):
    """Every limit the look-ahead works from, with ``settings``' accelerations.

    Parameters
    ----------
    p : PathArrays
        The path [-].
    settings : InterpolatorSettings
        Interpolator settings [-].
    filt : filters.FilterShape
        The post-interpolation filter [-].
    start, open_end : ndarray or None, bool
        Where ``p`` continues a path planned before, and is continued after
        (:func:`~tcpmm.path.shortblocks.chain_tangential`) [m/s^2], [-].

    Returns
    -------
    vmax, acc, seg_cause : ndarray
        Per segment, as :func:`segment_limits` gives them, a blend's ``vmax`` no higher
        than :func:`~tcpmm.path.transitions.blend_limits` allows, ``acc`` shared with the
        corners of chains of short blocks [m/s], [m/s^2], [-].
    vj, junction_cause : ndarray
        Per junction, as :func:`junction_limits` gives them, and no higher than
        :func:`~tcpmm.path.transitions.transition_limits` allows [m/s], [-].
    load : ndarray
        Centripetal acceleration per axis at each junction [m/s^2].
    """
    acc_axis, acc_path = settings.axis_accel(), settings.path_accel_m_per_s2
    acc_normal = normal_accel(acc_axis, acc_path)
    vmax, acc, seg_cause = segment_limits(p, settings.axis_velocity(), acc_axis, acc_path, filt)
    turns = corner_tangents(p) if p.n >= 2 else None
    vj, junction_cause = junction_limits(p, vmax, acc, settings.corner_step_accel(), filt,
                                         acc_normal, turns)
    if p.n >= 2:
        trans = transition_limits(p, settings.transition_jerk_m_per_s3, filt.spread_s)
        lower = np.concatenate([[False], trans < vj[1:-1], [False]])
        vj[lower], junction_cause[lower] = trans[lower[1:-1]], TRANSITION
        held = blend_limits(p, trans)
        lower = held < vmax
        vmax[lower], seg_cause[lower] = held[lower], HELD_BLEND
    du = None if turns is None else turns[1] - turns[0]
    acc, load = chain_tangential(p, du, vj, acc, acc_axis, acc_normal, start, open_end)
    return vmax, acc, seg_cause, vj, junction_cause, load
