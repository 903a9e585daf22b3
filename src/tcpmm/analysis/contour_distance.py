"""The distance from each sample of one or several paths to the command polyline, its
closest point sought within a window of time about the sample
(:mod:`tcpmm.analysis.contour`, module docstring: definitions and signs)."""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .contour_lag import outside_closer
from .contour_search import searched
from .contour_windows import chord_sags, feed_windows, over_rests, travel, whole_windows

#: coordinates the compiled search takes: finite, and far from where their squares
#: overflow [m]
_HUGE = 1e100


def distance_to_polyline(q, p, t_q, t_p, window_s, signed):
    """Shortest distance from points to a polyline, near in time.

    Parameters
    ----------
    q : ndarray, shape (n, d)
        Points [m].
    p : ndarray, shape (m, d)
        Polyline vertices in the order travelled [m].
    t_q, t_p : ndarray
        Times of the points and of the vertices [s].
    window_s : float
        Only segments whose start lies within this time of the point are candidates [s].
    signed : bool
        For ``d == 2``: positive left of the direction of travel [-].

    Returns
    -------
    dist : ndarray
        The distance, signed if asked [m].
    foot : ndarray of int
        Index of the segment the closest point lies on [-].
    """
    return distances_to_polyline({0: q}, p, t_q, t_p, window_s, signed)[0]


def polyline(p, before=None, after=None) -> tuple:
    """The command polyline ``p``'s segments, their squared lengths, directions of travel
    and moving ones (:func:`~tcpmm.analysis.contour_windows.travel`), their chords' sag
    (:func:`~tcpmm.analysis.contour_windows.chord_sags`; ``before``, ``after`` as for
    :func:`distances_to_polyline`) and lengths [m], [m^2], [-], [-], [m], [m]."""
    if p.shape[0] < 2:
        raise InputError("the command needs at least two samples")
    seg, ln2, tdir, moving = travel(p)
    return seg, ln2, tdir, moving, chord_sags(seg, ln2, tdir, before, after), np.sqrt(ln2)


def distances_to_polyline(qs, p, t_q, t_p, window_s, signed, before=None,
                          after=None, line=None, air=None, cuts=None, prev=None) -> dict:
    """:func:`distance_to_polyline` of several paths sampled at the same times (each
    sensor's), the polyline's segments, directions and blocks and the windows worked out
    once for all.

    Parameters
    ----------
    qs : dict of ndarray, shape (n, d)
        Points of each path, at the times ``t_q`` [m].
    p, t_q, t_p, window_s, signed
        As :func:`distance_to_polyline` [m], [s], [s], [s], [-].
    before, after : ndarray, shape (d,), optional
        Where ``p`` is a piece of a longer path, its direction of travel into the first
        vertex and out of the last, for the chords' sag
        (:func:`tcpmm.analysis.contour_windows.chord_sags`) [-].
    line : tuple, optional
        :func:`polyline` of ``p``, ``before`` and ``after``, where the caller has it [-].
    air : ndarray, optional
        The rapid flags of ``p``'s vertices: each point out of a rapid is measured from
        its feed move alone (:func:`~.contour_windows.feed_windows`) [-].
    cuts : dict, optional
        Filled per path with the samples whose window cuts off a closer command point
        (:func:`~tcpmm.analysis.contour_lag.outside_closer`; ``prev`` as there) [-].

    Returns
    -------
    dict of tuple
        Per path, the distance [m] and the segment of the closest point [-].
    """
    m = p.shape[0]
    seg, ln2, tdir, moving, sag, seglen = line or polyline(p, before, after)
    lo = np.searchsorted(t_p, t_q - window_s, side="left")
    hi = np.searchsorted(t_p, t_q + window_s, side="right")
    if moving.size < m - 1:
        lo, hi = over_rests(lo, hi, t_p, t_q, ln2 > 0, window_s)
    kept = (lo, hi)
    if air is not None:
        lo, hi = feed_windows(lo, hi, t_p, t_q, air)
    kept = (lo == kept[0], hi == kept[1])
    fine = p.dtype == np.float64 and np.all(np.abs(p) < _HUGE)
    out, found = {}, {}
    for k, q in qs.items():
        if fine and q.dtype == np.float64 and np.all(np.abs(q) < _HUGE):
            found[k] = out[k] = np.ascontiguousarray(q)  # the compiled search, below
        else:
            out[k] = whole_windows(q, p, seg, ln2, tdir, sag, seglen, lo, hi, signed, t_q,
                                   t_p)
    if found:
        out.update(searched(found, np.ascontiguousarray(p), seg, ln2, tdir, sag, seglen,
                            lo.astype(np.int64), hi.astype(np.int64), bool(signed),
                            np.ascontiguousarray(t_q, float), np.ascontiguousarray(t_p, float)))
    if cuts is not None:
        cuts.update({k: outside_closer(qs[k], p, lo, hi, kept, *v, prev) for k, v in out.items()})
    return out
