"""The G0 rapids of a run made from an NC program, left out of its contour error.

A rapid is moved in the air at rapid traverse: its servo lag and its corners are no
contour error of the part. A run that records which samples' commands are in a rapid (its
``rapid`` column, :mod:`tcpmm.path.blocktrack`; a dwell after a rapid counts as one) has
those samples left out of the error summary, and the corners whose legs take in a rapid
(a rapid within the corner span of the corner, along the commanded path) left out of the
corner table; a sample out of a rapid is measured from its own feed move alone
(:func:`~tcpmm.analysis.contour_windows.feed_windows`). A
run without the column is measured whole, and nothing is said of rapids.
"""

from __future__ import annotations

import numpy as np

from .corner_rows import CornerRows
from .corners import path_length

#: command rows taken at a time [-]
_BLOCK = 1 << 15


class RapidStretches:
    """The command samples near a rapid: within ``span_m`` of path length of a rapid's
    samples, as intervals of sample index, gathered as the command comes (whole, or a
    chunk of rows at a time, to the same numbers) [-].

    Parameters
    ----------
    span_m : float
        How far along the path a rapid reaches [m].
    """

    def __init__(self, span_m: float):
        self.span = float(span_m)
        self.spans: list = []  # [first, last] sample near each rapid
        # the spans whose last sample is not known yet, with the path length it may
        # reach (None while their rapid goes on)
        self.pending: list = []
        self.tail = (np.zeros(0, np.int64), np.zeros(0))  # samples within the span, s
        self.n, self.last, self.s_last, self.in_rapid = 0, None, 0.0, False

    def add_command(self, p, flags) -> None:
        """The next command samples: points, shape (m, d) [m], and their rapid flags [-]."""
        p, flags = np.asarray(p, float), np.asarray(flags)
        # a block of rows at a time: the path lengths' temporaries stay small beside the
        # rows a streamed run holds, and the intervals do not depend on the blocks
        for k in range(0, p.shape[0], _BLOCK):
            self._add(p[k:k + _BLOCK], flags[k:k + _BLOCK])

    def _add(self, p, flags) -> None:
        s = (path_length(p) if self.last is None else
             path_length(np.vstack([self.last, p]), self.s_last)[1:])
        idx = np.concatenate([self.tail[0], self.n + np.arange(s.size)])
        at = np.concatenate([self.tail[1], s])
        on = flags != 0
        if self.in_rapid and not on[0]:  # the rapid ended with the chunk before
            self.pending[-1][1] = self.s_last + self.span
        edge = np.flatnonzero(np.diff(np.concatenate([[False], on, [False]])))
        for a, b in zip(edge[::2].tolist(), edge[1::2].tolist(), strict=True):
            if not (a == 0 and self.in_rapid):  # else the rapid of the chunk before goes on
                first = int(idx[np.searchsorted(at, s[a] - self.span, side="left")])
                self.spans.append([first, first])
                self.pending.append([self.spans[-1], None])
            if b < s.size:  # the rapid ends in this chunk
                self.pending[-1][1] = float(s[b - 1]) + self.span
        for item in list(self.pending):
            span, reach = item
            span[1] = int(idx[-1] if reach is None else
                          idx[np.searchsorted(at, reach, side="right") - 1])
            if reach is not None and at[-1] > reach:
                self.pending.remove(item)
        keep = int(np.searchsorted(at, s[-1] - self.span, side="left"))
        # of a rest only its first sample (where a rapid's reach begins) and the last
        # (where one that reaches past it ends, so far): a long standstill is not held
        first = np.concatenate([[True], at[keep + 1:] != at[keep:-1]])
        first[-1] = True
        self.tail = (idx[keep:][first], at[keep:][first])
        self.n += s.size
        self.last, self.s_last, self.in_rapid = p[-1:].copy(), float(s[-1]), bool(on[-1])

    def near(self, index: int) -> bool:
        """Whether the command sample ``index`` lies within the span of a rapid [-]."""
        return any(lo <= index <= hi for lo, hi in self.spans)

    def near_many(self, indices) -> np.ndarray:
        """:meth:`near` of each of ``indices`` at once (a run may have a corner every few
        blocks): a sample lies within a span where the furthest reach of the spans that
        begin at it or before does not end before it [-]."""
        idx = np.asarray(indices, dtype=np.int64)
        if not self.spans or not idx.size:
            return np.zeros(idx.shape, bool)
        spans = np.array(self.spans, dtype=np.int64)
        order = np.argsort(spans[:, 0], kind="stable")
        lo, reach = spans[order, 0], np.maximum.accumulate(spans[order, 1])
        j = np.searchsorted(lo, idx, side="right") - 1
        return (j >= 0) & (reach[np.maximum(j, 0)] >= idx)


def feed_only(flags, counted_rapids: bool, corners: CornerRows, stretches):
    """What the contour error counts of a run's samples and corners.

    Parameters
    ----------
    flags : ndarray or None
        Per sample, nonzero in a rapid; ``None`` for a run that does not record it [-].
    counted_rapids : bool
        Count the rapids all the same [-].
    corners : CornerRows
        The corners found, each with its command sample ``index`` [-].
    stretches : RapidStretches
        The command's rapids, reaching as far as the corner span [-].

    Returns
    -------
    counted : ndarray of bool or None
        The samples counted; ``None`` for all [-].
    corners : CornerRows
        The corners counted [-].
    rapids : dict or None
        :func:`left_out`'s figures; ``None`` without ``flags`` [-].
    """
    if flags is None:
        return None, corners, None
    air = np.asarray(flags) != 0
    kept, info = left_out(int(np.count_nonzero(air)), air.size, counted_rapids, corners,
                          stretches)
    return (None if info["counted"] else ~air), kept, info


def left_out(samples: int, rows: int, counted_rapids: bool, corners: CornerRows,
             stretches) -> tuple:
    """The corners counted and the figures of the rapids of a run of ``rows`` samples,
    ``samples`` of them in rapids: ``counted`` (whether the rapids are counted: asked, or
    the run is all rapids), ``samples`` and ``share`` of the run in rapids, ``corners``
    whose legs take in a rapid (:meth:`RapidStretches.near`) [-].

    Parameters
    ----------
    samples, rows : int
        Samples in rapids, and all [-].
    counted_rapids, corners, stretches
        As :func:`feed_only` [-].
    """
    near = stretches.near_many(corners.indices()).tolist()
    counted = bool(counted_rapids or samples == rows)
    info = {"counted": counted, "samples": int(samples),
            "share": samples / rows if rows else 0.0, "corners": int(sum(near))}
    if counted:
        return corners, info
    return corners.kept([not x for x in near]), info


def rapids_json(rapids: dict | None) -> dict | None:
    """:func:`left_out`'s figures as ``--json`` gives them: the share in per cent, as the
    text says it, under a key that says so (``share_percent``) [-]."""
    if rapids is None:
        return None
    return {("share_percent" if k == "share" else k): (v * 100.0 if k == "share" else v)
            for k, v in rapids.items()}


def since_rapid(t, air, last_t: float = float("nan")) -> tuple:
    """Per sample the time since the last sample in a rapid, NaN before the first; and the
    time of the last one, to carry into the next chunk of a streamed run.

    Parameters
    ----------
    t : ndarray
        Sample times [s].
    air : ndarray of bool
        Per sample, whether it is in a rapid [-].
    last_t : float
        Time of the last sample in a rapid before these; NaN for none [s].
    """
    t = np.asarray(t, float)
    idx = np.maximum.accumulate(np.where(air, np.arange(t.size), -1)) if t.size else t
    last = np.where(idx >= 0, t[np.maximum(idx, 0).astype(np.int64)], last_t)
    return t - last, float(last[-1]) if t.size else last_t


def rapid_note(rapids: dict | None) -> str | None:
    """The note that says what was left out, ``None`` where nothing was [-]."""
    if rapids is None or not rapids["samples"]:
        return None
    if rapids["counted"]:
        return None if rapids["share"] < 1.0 else "note: the run is all G0 rapids; counted"
    corners = rapids["corners"]
    return (f"note: G0 rapids left out: {rapids['samples']} samples, "
            f"{rapids['share'] * 100:.1f} % of the run, {corners} "
            f"corner{'' if corners == 1 else 's'}; --rapids counts them")


class MoveTravel:
    """Per axis the largest travel of the command within one feed move, a run of samples
    out of G0 rapids, gathered as the command comes (whole, or a chunk of rows at a time,
    to the same numbers): the plane the path is cut in. A Z that moves only in G0 between
    passes at two depths moves in no feed move, though the feed samples span both; a
    pattern of plunges whose X and Y move only in G0 is cut along Z alone [m].
    """

    def __init__(self):
        self.lo: dict = {}  # the open move's least and largest position per axis
        self.hi: dict = {}
        self.best: dict = {}
        self.open = False

    def add(self, cols: dict, feed) -> None:
        """The next samples: position per axis, and which are out of the rapids (None:
        all) [m], [-]."""
        n = next(iter(cols.values())).size if cols else 0
        if n == 0:
            return
        on = np.ones(n, bool) if feed is None else np.asarray(feed, bool)
        if self.open and not on[0]:  # the move the chunk before left open ended
            self.best = self.travel()
            self.open = False
        starts = np.flatnonzero(on & ~np.concatenate([[self.open], on[:-1]]))
        ends = np.flatnonzero(on & ~np.concatenate([on[1:], [False]])) + 1
        cut = np.sort(np.concatenate([starts, ends]))  # each move's samples, one reduce
        if on.any():  # the stretches, the same for every axis
            first = 0 if on[0] and self.open else int(starts[0])
            edges = np.unique(np.concatenate([[first], cut[cut < n]]))
            keep = on[edges]  # the reduced stretches that are moves, not rapids
        for a, v in cols.items():
            self.best.setdefault(a, 0.0)
            if not on.any():
                continue
            lo = np.minimum.reduceat(v, edges)[keep]
            hi = np.maximum.reduceat(v, edges)[keep]
            if on[0] and self.open:  # the move the chunk before left open goes on
                lo[0], hi[0] = min(lo[0], self.lo[a]), max(hi[0], self.hi[a])
            closed = slice(None, -1) if on[-1] else slice(None)
            if (hi - lo)[closed].size:
                self.best[a] = max(self.best[a], float(np.max((hi - lo)[closed])))
            if on[-1]:
                self.lo[a], self.hi[a] = float(lo[-1]), float(hi[-1])
        self.open = bool(on[-1])

    def travel(self) -> dict:
        """The largest travel within one feed move per axis, the open move's included [m]."""
        out = dict(self.best)
        if self.open:
            for a in self.lo:
                out[a] = max(out[a], self.hi[a] - self.lo[a])
        return out


def feed_commands(run, counted_rapids: bool):
    """The run's command's travel within its feed moves alone (:class:`MoveTravel`), as
    two samples per axis, to find the plane it contours in: a program's rapids (a Z
    retracting between XY passes) are left out of it as the contour error leaves them;
    the run itself where it records none, is all rapids or all feed, or they are counted
    [-].

    Parameters
    ----------
    run : Run
        The run [SI].
    counted_rapids : bool
        ``--rapids``: the rapids count [-].
    """
    from ..result import AxisRun, Run

    if run.rapid is None or counted_rapids:
        return run
    feed = np.asarray(run.rapid) == 0
    if feed.all() or not feed.any():
        return run
    moves = MoveTravel()
    moves.add({a: np.asarray(r.cmd, float) for a, r in run.axes.items() if r.cmd is not None},
              feed)
    return Run(np.array([0.0, 1.0]), {a: AxisRun(cmd=np.array([0.0, v]))
                                      for a, v in moves.travel().items()})
