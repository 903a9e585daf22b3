"""Time line of the segments and the distance along the path at every sample.

A move is a run of segments from rest to rest. Every move (and every dwell) starts on
a sample instant, so the samples of a move do not depend on what ran before it: the
same circle gives the same samples whether it is the first move of a program or not.
After the axes come to rest, the next move or dwell waits until the post-interpolation
filter has settled (the in-position wait of an exact stop).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .profile import segment_position

#: slack when rounding a time up to whole periods [-]
_TICK_SLACK = 1e-9


@njit(cache=True)
def timeline(kind, durations, v, dwell_s, period_s, settle):
    """Start of every segment as a sample index plus an offset.

    Parameters
    ----------
    kind : ndarray of int
        Segment kind (2 = dwell) [-].
    durations : ndarray
        Motion time of each segment [s].
    v : ndarray
        Junction speeds; zero at the start of a segment starts a new move [m/s].
    dwell_s : ndarray
        Dwell time of each segment [s].
    period_s : float
        Interpolation period [s].
    settle : int
        Periods to wait after the axes come to rest before anything else starts: the
        in-position wait for the post-interpolation filter to settle [-].

    Returns
    -------
    k0 : ndarray of int
        Sample index at or before which the segment starts [-].
    off : ndarray
        Start of the segment after sample ``k0`` [s].
    dur : ndarray
        Duration of the segment (dwells in whole periods) [s].
    k_end : int
        Index of the last sample, where the path has come to rest [-].
    """
    n = kind.size
    k0 = np.zeros(n, np.int64)
    off = np.zeros(n)
    dur = durations.copy()
    sk = 0
    soff = 0.0
    moved = False  # the previous segment was motion that ended at rest
    for i in range(n):
        if kind[i] == 2:
            k = sk + math.ceil(soff / period_s - _TICK_SLACK) + (settle if moved else 0)
            m = math.ceil(dwell_s[i] / period_s - _TICK_SLACK)
            k0[i] = k
            off[i] = 0.0
            dur[i] = m * period_s
            sk = k + m
            soff = 0.0
            moved = False
            continue
        if v[i] == 0.0:
            k = sk + math.ceil(soff / period_s - _TICK_SLACK) + (settle if moved else 0)
            k0[i] = k
            off[i] = 0.0
            sk = k
            soff = durations[i]
        else:
            k0[i] = sk
            off[i] = soff
            soff += durations[i]
        moved = True
    k_end = sk + math.ceil(soff / period_s - _TICK_SLACK)
    return k0, off, dur, k_end


@njit(cache=True)
def sample(k0, off, dur, length, v, prof, n_samples, period_s):
    """Segment and distance along it at every sample.

    Parameters
    ----------
    k0, off, dur : ndarray
        Time line from :func:`timeline` [-], [s], [s].
    length : ndarray
        Segment lengths [m].
    v : ndarray
        Junction speeds [m/s].
    prof : ndarray, shape (n, 8)
        Segment profiles from :func:`profile.segment_profiles` [-].
    n_samples : int
        Number of samples [-].
    period_s : float
        Interpolation period [s].

    Returns
    -------
    seg : ndarray of int
        Segment of each sample [-].
    s : ndarray
        Distance along that segment [m].
    """
    n = length.size
    seg = np.zeros(n_samples, np.int64)
    s = np.zeros(n_samples)
    if n == 0:
        return seg, s
    _positions(k0, off, dur, length, v, prof, period_s, seg, s)
    return seg, s


# Compiled without reference counting (``_nrt=False``): the loop allocates nothing, and the
# counts numba kept on the row of profile handed on for every sample took a third of the
# sampling.
@njit(cache=True, _nrt=False)
def _positions(k0, off, dur, length, v, prof, period_s, seg, s):
    """The loop of :func:`sample` over the samples, into ``seg`` and ``s`` [-], [m]."""
    n = length.size
    i = 0
    for k in range(seg.size):
        while i + 1 < n and (k - k0[i + 1]) * period_s - off[i + 1] >= 0.0:
            i += 1
        t = (k - k0[i]) * period_s - off[i]
        seg[k] = i
        if length[i] <= 0.0:
            s[k] = 0.0
        elif t >= dur[i]:
            s[k] = length[i]
        else:
            s[k] = segment_position(t, v[i], v[i + 1], length[i], prof[i])
