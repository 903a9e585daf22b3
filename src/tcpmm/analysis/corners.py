"""Corners of a commanded path, and what each sensor does there: overshoot, rounding and
settling (the definitions are in :mod:`tcpmm.analysis.contour`).

A corner is measured where it is: only the samples whose closest command point lies within
the corner span of the corner count, so a path that curves on (a spiral, an arc) or comes
back to the same place (a circle's end on its start) adds nothing far from it.
"""

from __future__ import annotations

import itertools

import numpy as np

#: Least share of the turn over the corner span that a corner makes over a quarter of it;
#: a curve of even curvature makes a quarter, a corner (sharp or blended within the quarter
#: span) all of it [-].
_SHARP = 0.5
#: Largest angle between the command's direction and the outgoing one for which the
#: command after a corner still runs straight on [deg].
_STRAIGHT_DEG = 5.0


def _turn(p, s, span_m):
    """Angle between the chords over ``span_m`` before and after each sample [rad]."""
    before = np.stack([np.interp(s - span_m, s, p[:, i]) for i in range(p.shape[1])], 1)
    after = np.stack([np.interp(s + span_m, s, p[:, i]) for i in range(p.shape[1])], 1)
    u, w = p - before, after - p
    cos = np.einsum("ij,ij->i", u, w) / (np.linalg.norm(u, axis=1) * np.linalg.norm(w, axis=1)
                                        + 1e-300)
    return np.arccos(np.clip(cos, -1.0, 1.0))


def find_corners(p, corner_deg=30.0, span_m=0.5e-3):
    """Corners of a polyline: ``(vertex index, turn angle)`` each.

    A corner turns by more than ``corner_deg`` over ``span_m`` before and after, and makes
    most of that turn over a quarter of the span; a curve that turns as much evenly (a small
    arc, the inside of a spiral) is no corner.

    Parameters
    ----------
    p : ndarray, shape (m, d)
        Polyline [m].
    corner_deg : float
        Least turn of the direction over ``span_m`` before and after [deg].
    span_m : float
        Path length over which the direction is taken on either side [m].

    Returns
    -------
    list of tuple
        Vertex index (the last one on the corner point) and turn [rad]; the end of the
        path last, with a turn of NaN [-].
    """
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(p, axis=0), axis=1))])
    if s[-1] <= 0.0:
        return []
    ok = (s >= span_m) & (s <= s[-1] - span_m)
    turn = _turn(p, s, span_m)
    cand = ok & (turn > np.radians(corner_deg)) & (_turn(p, s, span_m / 4) > _SHARP * turn)
    out = []
    for g in np.split(np.flatnonzero(cand), np.flatnonzero(np.diff(np.flatnonzero(cand)) > 1)
                      + 1):
        if g.size:
            i = g[np.argmax(turn[g])]
            # the corner point: the last sample where the command stands there
            while i + 1 < p.shape[0] and np.array_equal(p[i + 1], p[i]):
                i += 1
            out.append((int(i), float(turn[i])))
    # the end of the path: where a step test overshoots and settles
    if not out or out[-1][0] != p.shape[0] - 1:
        out.append((p.shape[0] - 1, float("nan")))
    return out


def _outward(p, s, i, turn, span_m):
    """The direction an overshoot at the corner ``p[i]`` runs in: across the outgoing leg,
    to the side the incoming direction points to; at the end of the path (or a reversal)
    the incoming direction [-]. And the path length to which the command runs on straight
    from the corner [m]."""
    c = p[i]
    at = [np.interp(s[i] + d, s, p[:, k]) for d in (-span_m, span_m) for k in range(p.shape[1])]
    back, ahead = np.reshape(at, (2, p.shape[1]))
    t_in = (c - back) / (np.linalg.norm(c - back) or 1.0)
    if np.isnan(turn):
        return t_in, s[i]
    t_out = (ahead - c) / (np.linalg.norm(ahead - c) or 1.0)
    n = t_in - (t_in @ t_out) * t_out
    n = t_in if np.linalg.norm(n) < 1e-6 else n / np.linalg.norm(n)
    return n, _straight_on(p, s, i, t_out, span_m)


def _straight_on(p, s, i, t_out, span_m):
    """Path length to which the command after the corner ``p[i]`` keeps its outgoing
    direction within ``_STRAIGHT_DEG``, at least the corner span [m]: across a straight
    leg the overshoot is the contour error, across a curve it is not."""
    seg = np.diff(p[i:], axis=0)
    ln = np.linalg.norm(seg, axis=1)
    bent = (seg @ t_out < np.cos(np.radians(_STRAIGHT_DEG)) * ln) & (ln > 0)
    bent &= s[i:-1] > s[i] + span_m  # within the span a blend still turns
    k = np.flatnonzero(bent)
    return s[i + k[0]] if k.size else s[-1]


def _closest(q, p, s, foot):
    """The closest point on segment ``foot`` of the polyline to each point, and its path
    length [m]."""
    a, d = p[foot], p[foot + 1] - p[foot]
    ln2 = np.einsum("ij,ij->i", d, d)
    f = np.clip(np.divide(np.einsum("ij,ij->i", q - a, d), ln2, out=np.zeros(ln2.shape),
                          where=ln2 > 0), 0.0, 1.0)
    return a + f[:, None] * d, s[foot] + f * np.sqrt(ln2)


def _overshoot_rounding(q, p, s, foot, near, i, first, n, turn) -> dict:
    """Overshoot and rounding of one sensor at the corner ``p[i]`` from the samples
    ``near`` it (module docstring of :mod:`tcpmm.analysis.contour`) [m]."""
    if not near.any():
        return {"overshoot_m": float("nan"), "rounding_m": float("nan")}
    c, q = p[i], q[near]
    rounding = float(np.min(np.linalg.norm(q - c, axis=1)))
    if np.isnan(turn):  # the end: the travel past the end point, or past where it rests
        dev = (q - c) @ n
        # a static deflection along the path (the tcp's) is where it settles, no overshoot
        dev = dev - max(float(np.median(dev[-(dev.size // 4 or 1):])), 0.0)
    else:  # a corner: how far outside the path the point lies, once past the corner
        foot_point, at = _closest(q, p, s, foot[near])
        past = at >= s[first] - 1e-12
        dev = (q[past] - foot_point[past]) @ n
    return {"overshoot_m": float(max(np.max(dev), 0.0)) if dev.size else 0.0,
            "rounding_m": rounding}


def corner_metrics(res, corners, t, feet, span_m=0.5e-3) -> list:
    """Overshoot, rounding and settling of every sensor at every corner (module docstring
    of :mod:`tcpmm.analysis.contour`).

    Parameters
    ----------
    res : ContourResult
        Contour errors and command [-].
    corners : list of tuple
        ``(vertex index, turn [rad])`` from :func:`find_corners` [-].
    t : ndarray
        Times of the actual samples [s].
    feet : dict of str to ndarray
        Per sensor, the command segment closest to each actual sample [-].
    span_m : float
        The corner's neighbourhood: path length before and after it [m].
    """
    p, tc, s = res.command, res.command_time_s, res.path_s_m
    idx = [i for i, _ in corners]
    # each corner owns the samples from halfway after the previous to halfway to the next
    bounds = [tc[0]] + [0.5 * (tc[a] + tc[b]) for a, b in itertools.pairwise(idx)] + [tc[-1]]
    out = []
    for k, (i, turn) in enumerate(corners):
        first = i
        while first > 0 and np.array_equal(p[first - 1], p[i]):
            first -= 1
        n, s_on = _outward(p, s, i, turn, span_m)
        own = (t >= bounds[k]) & (t <= bounds[k + 1])
        t0 = tc[first] if np.isnan(turn) else tc[i]  # the end: from the arrival
        after = own & (t >= t0)
        entry = {"number": k + 1, "index": int(i), "point_m": p[i].tolist(), "turn_rad": turn}
        for name, q in res.actual.items():
            at = s[feet[name]]
            near = own & (at >= s[i] - span_m) & (at <= max(s[i] + span_m, s_on))
            entry[name] = {**_overshoot_rounding(q, p, s, feet[name], near, i, first, n, turn),
                           **_settling(_settle_error(res, name, after, p[i], turn), t[after],
                                       t0, tc, s, res.settle_tol_m)}
        out.append(entry)
    return out


def _settle_error(res, name, k, c, turn):
    """What settles: the contour error after a corner, the distance to the end point at the
    end of the path (the command rests there, so lag along the path counts too) [m]."""
    if np.isnan(turn):
        return np.linalg.norm(res.actual[name][k] - c, axis=1)
    return res.errors[name][k]


def _settling(e, t, t0, tc, s, tol) -> dict:
    """Time and command path length from ``t0`` until ``e`` stays within ``tol`` of its
    level at the end of the stretch (the median of its last quarter)."""
    nan = {"settle_s": float("nan"), "settle_m": float("nan")}
    if e.size < 4:
        return nan
    dev = np.abs(e - np.median(e[-(e.size // 4):]))
    if dev[-1] > tol:
        return nan
    out = np.flatnonzero(dev > tol)
    k = 0 if out.size == 0 else out[-1] + 1
    ts = t[k]
    return {"settle_s": float(ts - t0),
            "settle_m": float(np.interp(ts, tc, s) - np.interp(t0, tc, s))}
