"""The look-ahead, time line and sampling of the interpolator over a path that comes in
pieces, with the same numbers as over the whole path.

The backward pass of the look-ahead needs the segments that follow: a segment's speed is
final once the speed a backward pass reaches at its start from a stop at the end of what
is known equals that junction's own limit, for then no later segment can lower it (the
true backward speed is at least as high and at most the limit) and every earlier
junction is computed from the same numbers as over the whole path. A piece is therefore
planned up to the last junction where the look-ahead's speed equals its limit; the
segments after it are held back (the carried tail) and planned again with the next
piece, from the speed carried at that junction. The time line carries the sample index
and the time since the move began; the sampling carries the first sample not yet given
out, and cuts where the next segment, not yet planned, starts.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from .. import _compiled as ck
from .geometry import DWELL, PathArrays, to_arrays
from .interpolate import check_samples
from .speedlimits import path_limits


@dataclass
class PlanState:
    """What one piece of the path hands the next.

    Parameters
    ----------
    v0 : float
        Speed at the start of the first segment held back [m/s].
    cum0 : float
        Path length before it [m].
    sk : int
        Sample index at or before which the current move (or the next block) starts [-].
    soff : float
        Time since then at which the last segment planned ends [s].
    moved : bool
        The last segment planned was motion (the next move waits for the filter) [-].
    load : ndarray or None
        Centripetal acceleration per axis of the corner before the first segment held
        back (:func:`~tcpmm.path.shortblocks.chain_tangential`) [m/s^2].
    next_k : int
        First sample not yet given out [-].
    """

    v0: float = 0.0
    cum0: float = 0.0
    sk: int = 0
    soff: float = 0.0
    moved: bool = False
    next_k: int = 0
    load: np.ndarray | None = None


@dataclass
class Samples:
    """The samples of one piece: global index of the first, segment arrays and, per
    sample, the segment (an index into them) and the distance along it.

    Parameters
    ----------
    first : int
        Index of the first sample in the whole command [-].
    path : PathArrays
        The segments planned in this piece [-].
    seg : ndarray of int
        Segment of each sample [-].
    s : ndarray
        Distance along it [m].
    path_s : ndarray
        Distance along the whole path [m].
    last : bool
        The path ends with these samples [-].
    """

    first: int
    path: PathArrays
    seg: np.ndarray
    s: np.ndarray
    path_s: np.ndarray
    last: bool


def head(p: PathArrays, k: int) -> PathArrays:
    """The first ``k`` segments of ``p`` (contiguous copies) [-]."""
    return PathArrays(**{f.name: np.ascontiguousarray(getattr(p, f.name)[:k])
                         for f in fields(p)})


def settled_speeds(p: PathArrays, settings, filt, st: PlanState, final: bool):
    """Junction speeds of the segments ``p`` after the look-ahead, starting from the
    carried state ``st``, and how many of them are final (module docstring) [m/s], [-];
    ``st.load`` becomes the centripetal acceleration per axis at the first junction held
    back (:func:`~tcpmm.path.shortblocks.chain_tangential`) [m/s^2]."""
    # the last line, its corner after it not known yet, is held as the most any corner
    # can ask: a lower limit only lowers the backward pass, as the stop at the end does
    vmax, acc, _, vj, _, load = path_limits(p, settings, filt, st.load, not final)
    vj[0] = st.v0
    v = ck.lookahead(p.length, vj, acc, settings.jerk())
    n = p.n
    if final:
        return v, vmax, acc, n
    b = ck.backward(p.length, vj, acc, settings.jerk())
    hit = np.flatnonzero(b[1:n] == vj[1:n])
    k = int(hit[-1]) + 1 if hit.size else 0
    if k:
        st.load = load[k]
    return v, vmax, acc, k


def plan_piece(segments: list, settings, filt, st: PlanState, final: bool):
    """Plan, time and sample as much of ``segments`` as is final.

    Parameters
    ----------
    segments : list
        The blended segments held back so far and the new ones [-].
    settings : InterpolatorSettings
        Interpolator settings [-].
    filt : FilterShape
        The post-interpolation filter [-].
    st : PlanState
        Carried from the previous piece; updated [-].
    final : bool
        The path ends with ``segments`` [-].

    Returns
    -------
    samples : Samples or None
        The samples given out, ``None`` where no segment is final yet [-].
    k : int
        Segments planned: ``segments[k:]`` are held back [-].
    """
    if not segments:
        return None, 0
    p = to_arrays(segments, settings.rapid())
    v, vmax, acc, k = settled_speeds(p, settings, filt, st, final)
    if k == 0:
        return None, 0
    q = head(p, k)
    vk = np.ascontiguousarray(v[: k + 1])
    prof = ck.segment_profiles(q.length, vk, np.ascontiguousarray(vmax[:k]),
                               np.ascontiguousarray(acc[:k]), settings.jerk())
    durations = prof[:, 1] + prof[:, 4] + prof[:, 5]
    check_samples(np.where(q.kind == DWELL, q.dwell_s, durations), filt.period_s, q.line,
                  streamed=True)
    nxt = None if final else (int(p.kind[k]), float(v[k]))
    k0, off, dur, k_end, k0n, offn = _timeline(q, durations, vk, filt, st, nxt)
    dt = filt.period_s
    if final:
        stop = max(k_end + 1, 2)
        seg, s = ck.sample(k0 - st.next_k, off, dur, q.length, vk, prof, stop - st.next_k, dt)
    else:
        seg, s = _sample_until(q, k0, off, dur, vk, prof, k0n, offn, st.next_k, dt)
    cum = np.cumsum(np.concatenate([[st.cum0], q.length]))
    out = Samples(st.next_k, q, seg, s, cum[seg] + s, final)
    st.v0, st.cum0, st.next_k = float(v[k]), float(cum[-1]), st.next_k + seg.size
    _carry_time(st, q, k0, off, durations, k0n)
    return out, k


def _timeline(q: PathArrays, durations, v, filt, st: PlanState, nxt):
    """The time line of the segments ``q`` after the carried state, and the start of the
    next segment (its kind and start speed ``nxt``) where there is one [-]."""
    # the carried state enters as a segment before them: a move under way that has run
    # ``soff``, or rest (a dwell of no time)
    kind0 = [0 if st.moved else DWELL]
    tail = [] if nxt is None else [nxt[0]]
    kinds = np.concatenate([kind0, q.kind, tail]).astype(np.int64)
    zero = [0.0] * len(tail)
    dur = np.concatenate([[st.soff if st.moved else 0.0], durations, zero])
    vv = np.concatenate([[0.0], v[:-1], [] if nxt is None else [nxt[1]]])
    dwell = np.concatenate([[0.0], q.dwell_s, zero])
    k0, off, d, k_end = ck.timeline(kinds, dur, vv, dwell, filt.period_s,
                                    filt.kernel.size - 1)
    k0 = k0 + st.sk
    n = q.n
    k0n, offn = (int(k0[n + 1]), float(off[n + 1])) if nxt is not None else (None, None)
    return (np.ascontiguousarray(k0[1:n + 1]), np.ascontiguousarray(off[1:n + 1]),
            np.ascontiguousarray(d[1:n + 1]), int(k_end) + st.sk, k0n, offn)


def _sample_until(q: PathArrays, k0, off, dur, v, prof, k0n: int, offn: float, first: int,
                  dt: float):
    """Samples from index ``first`` until the next segment, which starts at ``k0n`` plus
    ``offn``, takes over: segment and distance along it [-], [m]."""
    n = q.n
    # the next segment enters as one of no length, to find where its samples begin
    k0a = np.append(k0, k0n) - first
    count = k0n + int(np.ceil(offn / dt)) + 2 - first
    seg, s = ck.sample(k0a, np.append(off, offn), np.append(dur, 0.0),
                       np.append(q.length, 0.0), np.append(v, v[-1]),
                       np.vstack([prof, np.zeros((1, prof.shape[1]))]), max(count, 0), dt)
    cut = int(np.searchsorted(seg, n))
    return seg[:cut].copy(), s[:cut].copy()


def _carry_time(st: PlanState, q: PathArrays, k0, off, durations, k0n) -> None:
    """The time line's state after the last segment planned, as :func:`timeline` keeps
    it: after a dwell, rest from where the next block starts; after motion, the move's
    start and the time it has run."""
    if q.kind[-1] == DWELL:
        st.sk, st.soff, st.moved = (st.sk if k0n is None else k0n), 0.0, False
    else:
        st.sk, st.soff, st.moved = int(k0[-1]), float(off[-1] + durations[-1]), True
