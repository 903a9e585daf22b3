"""Stretches of constant velocity in a record of back-and-forth runs.

A sample is steady when the velocity stays within a tolerance of its value over a short
window; consecutive steady samples of one sign form a stretch, split wherever the velocity
drifts by more than the tolerance (:func:`find_plateaus`). Each plateau is trimmed at both
ends and averages the force (or current) that the Stribeck fit
(:mod:`tcpmm.ident.friction.stribeck`) takes as one point of the steady curve.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np

from tcpmm.errors import InputError

from ..frf.signals import as_1d

__all__ = ["Plateau", "find_plateaus"]


@dataclass(frozen=True)
class Plateau:
    """A stretch of (nearly) constant velocity.

    Parameters
    ----------
    start : int
        First sample index (after trimming) [-].
    stop : int
        One past the last sample index [-].
    velocity : float
        Mean velocity [m/s].
    force : float
        Mean force or current on the plateau [N or A].
    force_std : float
        Sample standard deviation of the force on the plateau [N or A].
    """

    start: int
    stop: int
    velocity: float
    force: float
    force_std: float


def find_plateaus(t, v, effort, *, v_min: float | None = None, rel_tol: float = 0.05,
                  min_duration: float = 0.2, trim: float = 0.1) -> list[Plateau]:
    """Detect constant-velocity plateaus in both directions.

    A sample is steady when the velocity stays within ``rel_tol`` of its value over a
    window of ``min_duration / 4``; consecutive steady samples of one sign form a
    plateau, split wherever the velocity drifts by more than ``rel_tol``; plateaus are
    trimmed by ``trim`` of their length at each end and kept if they last at least
    ``min_duration``.

    Parameters
    ----------
    t : array_like
        Time [s].
    v : array_like
        Velocity (e.g. filtered central difference of the position) [m/s].
    effort : array_like
        Force or current to average on each plateau [N or A].
    v_min : float, optional
        Slowest speed treated as motion; default 0.2 % of the largest speed [m/s].
    rel_tol : float
        Relative velocity tolerance [-].
    min_duration : float
        Shortest plateau kept [s].
    trim : float
        Fraction cut at each end of a plateau [-].

    Returns
    -------
    list of Plateau
        Plateaus in time order [-].
    """
    t = as_1d(t, "t")
    v = as_1d(v, "v")
    effort = as_1d(effort, "effort")
    if not (t.size == v.size == effort.size):
        raise InputError("t, v and effort must have the same length", column="effort")
    sgn = np.sign(v) * _steady(t, v, v_min, rel_tol, min_duration)
    out = []
    edges = np.flatnonzero(np.diff(np.r_[0.0, sgn, 0.0]) != 0)
    for i0, i1 in itertools.pairwise(edges):
        if sgn[i0] != 0:
            out += _drift_free(t, v, effort, i0, i1, rel_tol, min_duration, trim)
    return out


def _steady(t, v, v_min, rel_tol: float, min_duration: float) -> np.ndarray:
    """Whether each sample moves faster than ``v_min`` (default 0.2 % of the largest
    speed) [m/s] with the velocity within ``rel_tol`` [-] over a window of
    ``min_duration / 4`` [s] [-]."""
    from scipy.ndimage import maximum_filter1d, minimum_filter1d

    dt = float(np.median(np.diff(t)))
    vmax = float(np.max(np.abs(v)))
    if v_min is None:
        v_min = 2e-3 * vmax
    w = max(round(0.25 * min_duration / dt), 3)
    vhi = maximum_filter1d(v, w)
    vlo = minimum_filter1d(v, w)
    return (np.abs(v) > v_min) & ((vhi - vlo) <= rel_tol * np.abs(v))


def _drift_free(t, v, effort, i0: int, i1: int, rel_tol: float, min_duration: float,
                trim: float) -> list[Plateau]:
    """The plateaus of the steady stretch ``i0:i1``: cut wherever the velocity drifts by
    more than ``rel_tol`` [-] from a piece's first sample, each piece trimmed by ``trim``
    [-] at both ends and kept if it lasts ``min_duration`` [s]."""
    out = []
    i = i0
    while i < i1:
        ref = v[i]
        drift = np.flatnonzero(np.abs(v[i:i1] - ref) > rel_tol * abs(ref))
        j = i1 if drift.size == 0 else i + int(drift[0])
        n = j - i
        cut = int(trim * n)
        a, b = i + cut, j - cut
        if b > a + 1 and (t[b - 1] - t[a]) >= min_duration:
            seg = effort[a:b]
            out.append(Plateau(int(a), int(b), float(np.mean(v[a:b])), float(np.mean(seg)),
                               float(np.std(seg, ddof=1))))
        i = j
    return out
