"""Speed limit of a block transition where the path's curvature jumps (Sinumerik's
``PATH_TRANS_JERK_LIM``, "maximum axial jerk at block transitions in continuous-path mode").

At a tangent transition the velocity keeps its direction, but an axis's acceleration, the
component of ``v^2 * kappa`` (``kappa`` the curvature vector, pointing to the centre of
the osculating circle, of length ``1 / radius``), steps from the end of one block to the
start of the next by ``v^2 * |delta kappa_axis|``. The interpolator takes that step within
one period, or the post-interpolation filter spreads it over ``T``
(:attr:`~tcpmm.path.filters.FilterShape.spread_s`), so the axis's jerk there is
``v^2 * |delta kappa_axis| / T``. The profile along the path (trapezoid or S-curve) does
not see it: it limits the path's own acceleration and jerk. Held to ``j``:

    v <= sqrt(j * T / |delta kappa_axis|)   for every axis.

A line into an arc of radius 35 mm at F5000 steps an axis's acceleration by 0.2 m/s^2,
200 m/s^3 within 1 ms; with ``j`` = 50 m/s^3 the transition runs at no more than
2510 mm/min. Where the curvature is continuous (the blocks of one circle, collinear lines,
the arcs of a spiral that meet with the same radius) the step is zero and nothing is held.

A corner's blend (``G64 P``) steps its curvature at both ends by ``1 / r`` alike, so both
ends hold it to the same speed; it is held to that speed all along (:func:`blend_limits`).
Left to speed up between them, the feed's own ramp on so tight a curve turns the
acceleration fast: ``3 v kappa a_t`` on top of the profile's jerk along the path, which
read 58 m/s^3 on an axis of a spiral posted as G1 blocks under ``G64 P0.005`` planned to
37.5 m/s^3 (a blend of 15 µm radius). Held, its ramps fall on the lines, where the
curvature is 0.
"""

from __future__ import annotations

import numpy as np

from .geometry import ARC, BLEND, PathArrays


def curvatures(p: PathArrays, at_end: bool) -> np.ndarray:
    """Curvature vector at the start or end of every segment, shape (n, 3): 0 on lines
    and dwells, ``1 / radius`` towards the centre on a circle, a helix's and a spiral's
    from their first and second derivatives [1/m].

    Parameters
    ----------
    p : PathArrays
        The path [-].
    at_end : bool
        At the segment's end, else at its start [-].
    """
    d1 = np.zeros((p.n, 3))
    d2 = np.zeros((p.n, 3))
    a = np.flatnonzero(p.kind == ARC)
    if a.size:
        # P(f) = centre + r(f) (cos th, sin th) in the plane, h0 + dh f along its normal,
        # th = theta0 + sweep f, r = r0 + (r1 - r0) f; derivatives in f
        f = 1.0 if at_end else 0.0
        sw, dr = p.sweep[a], p.r1[a] - p.r0[a]
        th = p.theta0[a] + sw * f
        r = p.r0[a] + dr * f
        c, s = np.cos(th), np.sin(th)
        d1[a, p.ia[a]] = dr * c - r * sw * s
        d1[a, p.ib[a]] = dr * s + r * sw * c
        d1[a, p.ih[a]] = p.dh[a]
        d2[a, p.ia[a]] = -2.0 * dr * sw * s - r * sw**2 * c
        d2[a, p.ib[a]] = 2.0 * dr * sw * c - r * sw**2 * s
    b = np.flatnonzero(p.kind == BLEND)
    if b.size:
        ph = (p.sweep[b] if at_end else np.zeros(b.size))[:, None]
        r, sw = p.r0[b][:, None], p.sweep[b][:, None]
        radial = np.cos(ph) * p.e1[b] + np.sin(ph) * p.e2[b]
        d1[b] = r * sw * (-np.sin(ph) * p.e1[b] + np.cos(ph) * p.e2[b])
        d2[b] = -r * sw**2 * radial
    # kappa = (P'' |P'|^2 - P' (P' . P'')) / |P'|^4: the part of P'' normal to the path
    q = np.einsum("ij,ij->i", d1, d1)
    num = d2 * q[:, None] - d1 * np.einsum("ij,ij->i", d1, d2)[:, None]
    return np.divide(num, (q**2)[:, None], out=np.zeros_like(num), where=q[:, None] > 0.0)


def transition_limits(p: PathArrays, jerk_m_per_s3: float | None, spread_s: float) -> np.ndarray:
    """Speed limit of each inner junction, ``n - 1`` of them, that keeps every axis's jerk
    at the step of curvature within ``jerk_m_per_s3`` (module docstring); ``inf`` where
    the curvature does not jump, and everywhere without a limit [m/s].

    Parameters
    ----------
    p : PathArrays
        The path [-].
    jerk_m_per_s3 : float or None
        The axes' jerk at a transition, ``None`` for no limit [m/s^3].
    spread_s : float
        Time over which the interpolator and its filter spread a step of acceleration [s].
    """
    cap = np.full(max(p.n - 1, 0), np.inf)
    if jerk_m_per_s3 is None or p.n < 2:
        return cap
    jump = np.abs(curvatures(p, at_end=False)[1:] - curvatures(p, at_end=True)[:-1])
    most = jump.max(axis=1)  # the axis whose acceleration steps the most sets the limit
    np.divide(jerk_m_per_s3 * spread_s, most, out=cap, where=most > 0.0)
    return np.sqrt(cap)


def blend_limits(p: PathArrays, caps: np.ndarray) -> np.ndarray:
    """Speed limit of every segment from the caps of :func:`transition_limits`: on a
    corner's blend the lower of its two ends' (module docstring), ``inf`` elsewhere [m/s].

    Parameters
    ----------
    p : PathArrays
        The path [-].
    caps : ndarray
        The ``n - 1`` inner junctions' limits (:func:`transition_limits`) [m/s].
    """
    ends = np.concatenate([[np.inf], caps, [np.inf]])
    return np.where(p.kind == BLEND, np.minimum(ends[:-1], ends[1:]), np.inf)
