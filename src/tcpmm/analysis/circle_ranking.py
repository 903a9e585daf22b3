"""What each error term of a circle fit contributes to the circle's form, and the curves,
radial deviations and circular deviations of the circles fitted.

A term's contribution is the peak-to-valley of the radial error it makes alone over the
angles the circles cover, about the nominal centre, the directions together (as G(b) takes
them: a lateral play of p makes p between the directions); that of
the reversal spikes is the largest spike of the residual. Each term is ranked by its
contribution and given its share of their sum and its share of G (G(b) for a pair): what
of G the term alone would make. A centre offset makes ``2 |c|`` of radial error about the
nominal centre, which the contour error sees, but nothing of G, which is taken about the
least-squares centre: its share of G is 0.
"""

from __future__ import annotations

import numpy as np

from .circle_design import design
from .circle_display import ranking_rows, rename_axes
from .circle_model import is_full, servo_remainder
from .circle_passes import circle_deviation, lsq_circle

#: Reported name of a fitted column group
GROUP_NAMES = {"servo_angle": "servo_mismatch"}


def arc_grid(angle, n=3600):
    """Angles to evaluate a fitted circle on: a full turn, or the arc covered [rad]."""
    if is_full(angle):
        return np.linspace(0, 2 * np.pi, n, endpoint=False)
    return np.linspace(min(angle[0], angle[-1]), max(angle[0], angle[-1]), n)


def tool_angle(command, s, mu):
    """The tool's angle where the command is at the angle ``command``, on the path of
    :func:`.circle_model.servo_remainder` (X at its place, Y lagging it by ``mu`` along
    the travel): each axis stays on its own sine, so the tool is behind the command by up
    to ``mu`` where Y moves fastest and on it where Y reverses [rad].

    Parameters
    ----------
    command : ndarray
        Angle of the command CCW from the first axis [rad].
    s : float
        +1 CCW, -1 CW [-].
    mu : float
        Servo mismatch angle of this circle, ``w (ty - tx)`` [rad].
    """
    u = np.asarray(command, float)
    if mu == 0.0 or not np.isfinite(mu):
        return u
    lag = np.arctan2(np.sin(u - s * mu), np.cos(u)) - u
    return u + np.angle(np.exp(1j * lag))


def model_curve(fit, arcs, i, radius, shared, angle=None, e=None, take_up=True):
    """The fitted radial error of arc ``i`` over ``angle`` (default its own samples), the
    servo mismatch's remainder included, each backlash taken up over its width (a step
    without ``take_up``); undetermined terms count as 0 [m]."""
    arc = arcs[i]
    a = arc.angle if angle is None else angle
    pos = arc.positions(radius, a, e) if e is not None else None
    A = design(arc, i, len(arcs), radius, shared, fit.mu, fit.waves, a, pos,
               fit.centres[i] if fit.centres else (0.0, 0.0), fit.tail,
               fit.take_up if take_up else (0.0, 0.0))
    return (A @ np.nan_to_num(fit.coef)
            + servo_remainder(a, arc.s, radius, arc.ratio * fit.mu))


def per_circle_terms(fit, arcs, radius, shared, directions):
    """``(curves, grids)``: per direction ``(angle, e, model)`` on the samples and the
    model over a whole turn of the command's angle, whose mean is the fitted circle's
    radius less the nominal
    (on an arc, the mean over the arc also held the centre offset and the ellipses: a
    centre 5 um off read a radial deviation of -1.5 um) [rad, m]."""
    curves, grids = {}, {}
    turn = np.linspace(0, 2 * np.pi, 3600, endpoint=False)
    for i, (d, arc) in enumerate(zip(directions, arcs, strict=True)):
        curves[d] = (arc.angle, arc.e, model_curve(fit, arcs, i, radius, shared, e=arc.e))
        # the circle's radius, the reversals' transients aside as from the spikes: a
        # backlash's take-up would read as its radius (4 and 6 um of dead band, -0.04 um).
        # The mean is over the command's angle, as the samples come at a steady feed: a
        # lagging axis moves the tool's angle along the ellipse, and a mean over the
        # tool's angle weighs the ellipse's inside by R mu^2 / 4 more than the samples do
        grid = tool_angle(turn, arc.s, arc.ratio * fit.mu)
        grids[d] = model_curve(fit, arcs, i, radius, shared, angle=grid, take_up=False)
    return curves, grids


def deviations(paths, radius):
    """Circular deviation G per circle, and for two G(b) and the hysteresis H over the
    angles both cover; NaN for one circle [m]."""
    xy = [(radius + e) * np.array([np.cos(a), np.sin(a)]) for a, e in paths]
    g = [circle_deviation(*p)[0] for p in xy]
    if len(xy) < 2:
        return g, float("nan"), float("nan")
    both = np.hstack(xy)
    cx, cy, _ = lsq_circle(*both)
    rb = [np.hypot(p[0] - cx, p[1] - cy) for p in xy]
    allr = np.concatenate(rb)
    on = []
    grid = _common_grid([np.arctan2(p[1] - cy, p[0] - cx) for p in xy])
    for p, r in zip(xy, rb, strict=True):
        a = np.unwrap(np.arctan2(p[1] - cy, p[0] - cx))
        order = np.argsort(a)
        a, r = a[order], r[order]
        shift = np.round((grid[0] - a[0]) / (2 * np.pi)) * 2 * np.pi
        period = 2 * np.pi if np.ptp(a) > 2 * np.pi * (1 - 1e-2) else None
        on.append(np.interp(grid, a + shift if period is None else a, r, period=period))
    return g, float(allr.max() - allr.min()), float(np.max(np.abs(on[0] - on[1])))


def _common_grid(angles, n=3600):
    """Angles both circles cover: a full turn, or the overlap of two arcs [rad]."""
    spans = [np.ptp(np.unwrap(a)) for a in angles]
    if min(spans) > 2 * np.pi * (1 - 1e-2):
        return np.linspace(0, 2 * np.pi, n, endpoint=False)
    ua = [np.unwrap(a) for a in angles]
    lo = [u.min() for u in ua]
    shift = np.round((lo[0] - lo[1]) / (2 * np.pi)) * 2 * np.pi
    a0, a1 = max(lo[0], lo[1] + shift), min(ua[0].max(), ua[1].max() + shift)
    return np.linspace(a0, a1, n) if a1 > a0 else np.array([a0])


def contributions(fit, arcs, radius, shared, spikes):
    """Per term ``(peak-to-valley radial error it makes alone over the circles together,
    the G it alone makes)``; NaN for a term not determined (module docstring) [m]."""
    groups = {"centre_offset": [f"centre_{a}_{i}" for i in range(len(arcs)) for a in "XY"]}
    groups.update({GROUP_NAMES.get(t, t): [t] for t in shared})
    for axis, k in zip("XY", fit.waves, strict=True):
        if k is not None:
            groups[f"cyclic_{axis}"] = [f"cyclic_sin_{axis}", f"cyclic_cos_{axis}"]
    out = {}
    grids = [arc_grid(arc.angle) for arc in arcs]
    # every term's curve is its coefficient's share of the same columns
    matrices = [design(arc, i, len(arcs), radius, shared, fit.mu, fit.waves, a,
                       centre=fit.centres[i] if fit.centres else (0.0, 0.0),
                       tail=fit.tail, widths=fit.take_up)
                for i, (arc, a) in enumerate(zip(arcs, grids, strict=True))]
    for name, cols in groups.items():
        idx = [fit.names.index(c) for c in cols]
        if all(np.isnan(fit.coef[j]) for j in idx):
            out[name] = (float("nan"), float("nan"))
            continue
        coef = np.zeros_like(fit.coef)
        coef[idx] = np.nan_to_num(fit.coef[idx])
        curves = []
        for arc, a, A in zip(arcs, grids, matrices, strict=True):
            curve = A @ coef
            if name == "servo_mismatch":
                curve = curve + servo_remainder(a, arc.s, radius, arc.ratio * fit.mu)
            curves.append((a, curve))
        # over the circles together, as G(b) is: a term that differs between the
        # directions (lateral play) makes its size between them, not within one
        # a centre offset is a shift of the circle, no G at all (only its rounding)
        out[name] = (float(np.ptp(np.concatenate([c for _, c in curves]))),
                     0.0 if name == "centre_offset" else _g_alone(curves, radius))
    finite = [abs(v) for v in spikes if v == v]
    top = max(finite) if finite else float("nan")
    out["reversal_spikes"] = (top, top)
    return out


def _g_alone(curves, radius) -> float:
    """The G a term's radial error alone makes: about its own least-squares centre (a
    bow's part that is a shift of the circle makes none: a bow of 2 um makes G 1 um, not
    the 4 um of its peak to valley about the nominal centre), G(b) of a pair [m]."""
    g, gb, _ = deviations(curves, radius)
    return float(gb) if len(curves) == 2 else float(g[0])


def rank_terms(fit, arcs, radius, shared, terms, axes, names=None, unranked=()):
    """The terms ranked by their contribution (:func:`.circle_display.ranking_rows`), the
    axes named as the plane's [m, -].

    Parameters
    ----------
    fit : TermFit
        The fit [-].
    arcs : list of Arc
        The circles fitted [-].
    radius : float
        Nominal radius [m].
    shared : sequence of str
        The fitted terms [-].
    terms : dict
        The reported terms, whose ``spike_*`` are the residual's spikes [SI].
    axes : tuple of str
        The plane's axes [-].
    names : dict, optional
        Reported name of a term where it differs from its column's [-].
    unranked : sequence of str
        Terms left out, by their reported names, with the axes named X and Y or the
        plane's (:func:`.circle_tails.sign_open`) [-].
    """
    spikes = [v for k, (v, _) in terms.items() if k.startswith("spike_")]
    c = contributions(fit, arcs, radius, shared, spikes)
    c = {(names or {}).get(k, k): v for k, v in c.items()}
    # a term not determined (n/a: a cyclic error at the longest period searched, say) is
    # no source to rank, whatever its column takes up in the fit
    left = set(unranked) | {k.replace("cyclic_amplitude_", "cyclic_")
                            for k, (v, _) in terms.items() if not np.isfinite(v)}
    c = {k: v for k, v in c.items() if k not in left and rename_axes(k, axes) not in left}
    g = [v for k, (v, _) in terms.items() if k.startswith("circularity_")]
    rows = ranking_rows(c, terms.get("circularity_pair", (max(g),))[0])
    for r in rows:
        r["term"] = rename_axes(r["term"], axes)
    return rows
