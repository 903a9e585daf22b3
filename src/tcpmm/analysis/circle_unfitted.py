"""How far a pair of arcs' terms move under a cyclic error the arcs cannot fit.

Over part of a turn a cyclic error's columns are nearly those of the centre, the bows and
the other terms (:data:`.circle_stable.CYCLIC_WHY`), so a pair of arcs shorter than
:data:`.circle_stable.CYCLIC_ARC_DEG` is not searched for one and the fit takes it as 0.
Where the machine has one all the same, the terms carry it: over 270 deg in YZ, a pitch
error of Y of 0.22 µm and 14 mm read a scale mismatch of 88 ± 6 ppm for 124, and over
220 deg a spike's sign turned. The move of each fitted column per unit of a cyclic error's
amplitude is its least-squares fit by the fitted columns, as for a term left out
(:func:`.circle_model.alias_slopes`), here for each period a full circle's scan would
search (:func:`.circle_cyclic.search_periods`) and for its sine and cosine; the reported
terms' largest move over the periods and phases is their dependence on it
(:func:`.circle_alias.alias_terms`).
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import solve_triangular

from .circle_cyclic import search_periods
from .circle_fit import FitProblem
from .circle_model import cyclic_columns, radial_weights
from .circle_stable import cyclic_on

#: Most periods the moves are worked out at, evenly spaced in wavenumber over the scan's
#: range: the moves change over a wavenumber step of one over the arc's length, coarser
#: than the scan's [-].
MOST_PERIODS = 256


def cyclic_slopes(fit, arcs, radius: float, shared) -> dict:
    """Per axis (``"X"``, ``"Y"``) a list, one per period and phase (sine, cosine), of
    how each fitted column moves per unit amplitude of a cyclic error of that axis;
    empty where the arcs are searched for cyclic errors, are full turns, or give no
    terms [SI/m].

    Parameters
    ----------
    fit : TermFit
        The arcs' fit [-].
    arcs : list of Arc
        The arcs fitted [-].
    radius : float
        Nominal radius [m].
    shared : sequence of str
        The shared terms fitted [-].
    """
    if cyclic_on(arcs) or fit.waves != (None, None):  # full turns are searched too
        return {}
    pb = FitProblem(arcs, radius, shared)
    if fit.mu:
        pb.reversals_at(fit.mu)
    pb.centres, pb.widths, pb.lost = list(fit.centres), fit.widths, fit.lost
    A = pb.matrix(fit.mu, (None, None))
    kept = np.isfinite(fit.coef)
    if kept.size != A.shape[1] or not kept[3 * len(arcs):].any():
        return {}
    longest, shortest = search_periods(pb)
    ks = np.arange(1.0 / longest, 1.0 / shortest, 1.0 / (4.0 * radius))
    if ks.size > MOST_PERIODS:
        ks = ks[np.linspace(0, ks.size - 1, MOST_PERIODS).round().astype(int)]
    names = [n for n, k in zip(fit.names, kept, strict=True) if k]
    q, r = np.linalg.qr(A[:, kept])
    return {axis: _per_period(pb, fit.mu, j, ks, q, r, names)
            for j, axis in enumerate("XY")}


def _per_period(pb, mu: float, axis: int, ks: np.ndarray, q, r, names) -> list:
    """For each wavenumber of ``ks`` and each phase, the fitted columns' moves per unit of
    the cyclic error of ``axis`` (0 the first), from the QR factors of the fitted
    columns [SI/m]."""
    pos = np.concatenate([p[axis] for p in pb.pos])
    w = np.concatenate([radial_weights(a.angle[m], a.s, a.ratio, mu)[axis]
                        for a, m in zip(pb.arcs, pb.masks, strict=True)])
    out = []
    for k in ks:
        B = np.column_stack(cyclic_columns(pos, w, k))
        slopes = solve_triangular(r, q.T @ B)
        out += [dict(zip(names, map(float, slopes[:, j]), strict=True)) for j in range(2)]
    return out
