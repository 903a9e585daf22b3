"""The contour error of a Parquet run read a row group at a time, in bounded memory.

Each actual sample is matched, as :func:`tcpmm.analysis.contour.distance_to_polyline`
does, with the command samples within the time window around it; the rows are kept from
a window before the first sample not yet measured to a window after the last one
measured (and on to where the command moves again, which a resting segment's direction
needs). The error of every sample is that of the whole run to the bit; the summary's
largest, smallest and largest magnitude too, its RMS to a relative 1e-12 (the sum of the
squares is taken chunk by chunk, not in numpy's pairwise order over the whole run). The
plane is the one the command moves in (:func:`tcpmm.analysis.plane.motion_plane`, from
each axis' travel). The corners are found and measured as the rows come
(:class:`~tcpmm.analysis.contour_corners.CornerStream`), the whole run's to the bit; the
samples of a corner's settling stretch (up to halfway to the next corner) are held, a few
numbers each, until the next corner is found.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .._rows import any_rows
from .._threads import read_ahead, usable_cores
from ..errors import InputError
from ..result import motion_time
from .contour import ContourResult, distances_to_polyline, polyline
from .contour_chords import off_chord
from .contour_corners import CornerStream, end_unreached
from .contour_inputs import SENSORS
from .contour_lag import WINDOW_S, WindowCut, cut_off, window_error, windows
from .contour_parquet import STREAM_ROWS, batches, has_columns, travel_positions
from .contour_passes import Leaps, leaps
from .contour_summary import RunningSummary
from .contour_windows import direction
from .corners import path_length
from .plane import left_out_axes
from .rapids import RapidStretches, left_out, since_rapid

#: calls (two a chunk) the corners may lag behind the search, their chunks held until
#: the corners take them [-]
CORNERS_BEHIND = 2


@dataclass
class StreamedContour:
    """The contour error summary of a streamed run.

    Parameters
    ----------
    axes : tuple of str
        Axes the distance is measured in; two for a plane (signed) [-].
    signed : bool
        Whether the error is signed [-].
    rows : int
        Samples measured [-].
    sums : dict of str to RunningSummary
        Per sensor, the running figures [m].
    most_rows : int
        Most rows held at once [-].
    corners : sequence of dict
        As :attr:`tcpmm.analysis.contour.ContourResult.corners`, kept as columns
        (:class:`~tcpmm.analysis.corner_rows.CornerRows`; ``list(corners)`` for a list) [SI].
    settle_tol_m : float
        The band of the settling figures [m].
    rapids : dict, optional
        As :attr:`tcpmm.analysis.contour.ContourResult.rapids` [-].
    unreached : dict of str to float
        As :attr:`tcpmm.analysis.contour.ContourResult.unreached` [m].
    command_sag_m : float
        As :attr:`tcpmm.analysis.contour.ContourResult.command_sag_m` [m].
    curves : int
        As :attr:`tcpmm.analysis.contour.ContourResult.curves` [-].
    left_out : dict of str to float
        As :attr:`tcpmm.analysis.contour.ContourResult.left_out` [m].
    off_chord : dict of int to tuple
        As :attr:`tcpmm.analysis.contour.ContourResult.off_chord` [m].
    window_s : float
        As :attr:`tcpmm.analysis.contour.ContourResult.window_s` [s].
    leaps : dict
        As :attr:`tcpmm.analysis.contour.ContourResult.leaps` [-, m].
    """

    axes: tuple
    signed: bool
    rows: int = 0
    sums: dict = field(default_factory=dict)
    most_rows: int = 0
    corners: Sequence = field(default_factory=list)
    settle_tol_m: float = 1e-6
    rapids: dict | None = None
    unreached: dict = field(default_factory=dict)
    command_sag_m: float = 0.0
    curves: int = 0
    left_out: dict = field(default_factory=dict)
    off_chord: dict = field(default_factory=dict)
    window_s: float = WINDOW_S
    leaps: dict = field(default_factory=dict)

    @property
    def errors(self) -> dict:
        """The sensors measured (their errors are not kept) [-]."""
        return dict.fromkeys(self.sums)

    def summary(self) -> dict:
        """Per sensor: largest magnitude, RMS, largest and smallest value [m]."""
        return {s: v.result() for s, v in self.sums.items()}

    corner_rows = ContourResult.corner_rows
    corners_table = ContourResult.corners_table
    to_dict = ContourResult.to_dict
    json_rows = ContourResult.json_rows


def stream_contour(path, axes, signed: bool, window_s: float | None = None,
                   rows: int = STREAM_ROWS, each=None, *, corner_deg: float = 30.0,
                   corner_span_m: float = 0.5e-3, settle_tol_m: float = 1e-6,
                   rapids: bool = False, travel: dict | None = None) -> StreamedContour:
    """Contour error summary and corners of a Parquet run file, read ``rows`` rows at a
    time.

    Parameters
    ----------
    path : str or Path
        The Parquet run file [-].
    axes : tuple of str
        The axes measured in [-].
    signed : bool
        Signed in the plane of two axes [-].
    window_s : float, optional
        Time around each sample in which its closest command point is sought, as for
        :func:`~tcpmm.analysis.contour.contour_error` [s].
    rows : int
        Rows read at a time [-].
    each : callable, optional
        Called with the sensor and the errors of each chunk of samples, in order [-], [m].
    corner_deg, corner_span_m, settle_tol_m : float
        The corners' least turn, span and settling band, as for
        :func:`~tcpmm.analysis.contour.contour_error` [deg], [m], [m].
    rapids : bool
        Count the samples and corners in G0 rapids, as for
        :func:`~tcpmm.analysis.contour.contour_error` [-].
    travel : dict of str to ndarray, optional
        Per axis the command's least and largest position (:func:`travel_positions`, with
        ``feed_only`` as ``rapids`` is not); read from the file where not given [m].
    """
    for w in windows(window_s):
        try:
            return _streamed(Path(path), axes, signed, w, rows, each, corner_deg,
                             corner_span_m, settle_tol_m, rapids, travel)
        except WindowCut as exc:
            cut = exc
    raise window_error(w, window_s is not None, cut.first_s, behind=cut.behind)


def _streamed(path, axes, signed, window_s, rows, each, corner_deg, corner_span_m,
              settle_tol_m, rapids, travel) -> StreamedContour:
    """:func:`stream_contour` at the window ``window_s``; :class:`WindowCut` where it
    cuts a sample off its closest command point [-]."""
    cmd_cols = [f"{a.lower()}_cmd_mm" for a in axes]
    want = {"time_s", "rapid", *cmd_cols,
            *(f"{a.lower()}_{s}_mm" for a in axes for s in SENSORS)}
    res = StreamedContour(tuple(axes), signed, settle_tol_m=settle_tol_m, window_s=window_s)
    if signed:  # the axes the plane leaves out, from the travel alone
        res.left_out = left_out_axes(axes, travel or travel_positions(path, not rapids))
    scan = _Scan(res, window_s, cmd_cols, each,
                 CornerStream(corner_deg, corner_span_m, settle_tol_m, window_s),
                 RapidStretches(corner_span_m))
    has_columns(path, cmd_cols, axes)
    scan.clamp = not rapids
    pending = None
    # the next chunk is read (pyarrow lets go of the interpreter lock) while one is measured
    chunks = read_ahead(batches(path, rows, lambda c: c in want))
    try:
        for cols in chunks:
            if pending is not None:
                scan.step(pending, False)
            pending = cols
        if pending is None or not pending["time_s"].size:
            raise InputError("the run has no rows", file=path)
        scan.step(pending, True)
        _finish(res, scan, rapids)
    finally:
        chunks.close()
        scan.close()
    return res


def _finish(res: StreamedContour, scan, rapids: bool) -> None:
    """Fill in ``res`` once every chunk is measured: its corners, less those of the G0
    rapids unless they count, and the end and the curves the corners found [-]."""
    res.corners = scan.finish()
    if scan.air is not None:
        res.corners, res.rapids = left_out(scan.air, res.rows, rapids, res.corners,
                                           scan.stretches)
        res.sums = res.sums if res.rapids["counted"] else scan.feed
    res.unreached = end_unreached(scan.corners, res.corners)
    res.curves = scan.corners.finder.curves
    res.off_chord = off_chord(scan.corners, res.corners)
    res.leaps = scan.leaps.result()


class _Scan:
    """The rows held: from a window before the next sample to measure (``first`` in the
    buffer, whose row 0 is the run's row ``base``) to the last read."""

    def __init__(self, res, w, cmd_cols, each, corners, stretches):
        self.res, self.w, self.cmd_cols, self.each, self.corners = res, w, cmd_cols, each, corners
        self.buf, self.first, self.base = None, 0, 0
        # direction of travel into the buffer's first row, and the command's row before it
        self.before = self.prev = None
        # the corners take the chunks in a thread of their own, in order, while the next
        # chunk is searched; at most CORNERS_BEHIND calls behind
        self.pool = ThreadPoolExecutor(1) if usable_cores() > 1 else None
        self.behind: deque = deque()
        # of a run that records its rapids: the samples in them, the feed's figures, the
        # command samples near them
        self.air, self.feed, self.stretches = None, {}, stretches
        self.last_rapid_t, self.clamp = np.nan, False  # feed_windows (--rapids: not)
        # the path length to the buffer's row 0, the closest point's leaps counted, and
        # per sensor the last sample measured, its error, closest point and path length
        self.s0, self.leaps, self.last = 0.0, Leaps(), {}

    def _to_corners(self, fn, *args) -> None:
        """``fn(*args)`` of the corners, in the corners' thread where there is one [-]."""
        if self.pool is None:
            fn(*args)
            return
        self.behind.append(self.pool.submit(fn, *args))
        while len(self.behind) > CORNERS_BEHIND:
            self.behind.popleft().result()

    def finish(self) -> list:
        """The corners, once they have taken every chunk [-]."""
        while self.behind:
            self.behind.popleft().result()
        return self.corners.finish()

    def close(self) -> None:
        """Let go of the corners' thread [-]."""
        if self.pool is not None:
            self.pool.shutdown(cancel_futures=True)

    def step(self, cols, final: bool) -> None:
        """Add rows ``cols`` and measure the samples whose window (and one more) the
        buffer holds."""
        res, w, cmd_cols = self.res, self.w, self.cmd_cols
        buf = cols if self.buf is None else {c: np.concatenate([self.buf[c], cols[c]])
                                             for c in self.buf}
        self.buf = buf
        t, first = buf["time_s"], self.first
        n = t.size
        cmd = np.column_stack([buf[c] * 1e-3 for c in cmd_cols])
        self._to_corners(self.corners.add_command, cols["time_s"],
                         cmd[n - cols["time_s"].size:])  # the rows just read
        if "rapid" in cols:
            self.stretches.add_command(cmd[n - cols["time_s"].size:], cols["rapid"])
        res.most_rows = max(res.most_rows, n)
        moves = any_rows(np.diff(cmd, axis=0) != 0.0)  # segment i: rows i, i + 1
        tau = motion_time(t, moves)[0]  # the windows reach over the command's rests
        b = n if final else min(int(np.searchsorted(t, t[-1] - 2.0 * w, side="left")),
                                int(np.searchsorted(tau, tau[-1] - 2.0 * w, side="left")))
        window = _window(moves, t, tau, first, b, w, final) if b > first else None
        if window is None:
            return
        c0, c1 = window
        qs = {}
        for s in SENSORS:
            cols_s = [c.replace("_cmd_", f"_{s}_") for c in cmd_cols]
            if all(c in buf for c in cols_s):
                qs[s] = np.column_stack([buf[c][first:b] * 1e-3 for c in cols_s])
        before = direction(cmd, moves, c0 - 1) if c0 > 0 else self.before
        after = direction(cmd, moves, c1 - 1) if c1 < n else None
        # the chords' sag as the whole path's, and the largest the command has so far
        line = polyline(cmd[c0:c1], before, after)
        res.command_sag_m = max(res.command_sag_m, float(np.max(line[4])))
        air = buf["rapid"][c0:c1] if self.clamp and "rapid" in buf else None
        cuts = {}
        found = distances_to_polyline(qs, cmd[c0:c1], t[first:b], t[c0:c1], w, res.signed,
                                      line=line, air=air, cuts=cuts,
                                      prev=cmd[c0 - 1] if c0 > 0 else self.prev)
        feed, since = self._feed(buf, first, b)
        ts = t[first:b]
        cut = cut_off(ts, cuts, feed if self.clamp else None)
        if cut is not None:
            raise WindowCut(*cut)
        s_buf = path_length(cmd, self.s0)  # from the run's start, for the leaps
        self._sum(found, qs, (ts, feed, since), cmd[c0:c1], s_buf[c0:c1])
        got = (qs, {s: v[0] for s, v in found.items()},
               {s: v[1] + self.base + c0 for s, v in found.items()})
        self._to_corners(self.corners.add_samples, t[first:b], *got)
        res.rows += b - first
        drop = min(int(np.searchsorted(t, t[b] - w, side="left")),
                   int(np.searchsorted(tau, tau[b] - w, side="left")), b) if b < n else n
        self.buf = {c: v[drop:].copy() for c, v in buf.items()}
        if 0 < drop < n:
            self.before, self.prev = direction(cmd, moves, drop - 1), cmd[drop - 1]
        self.s0 = float(s_buf[min(drop, n - 1)])
        self.first, self.base = b - drop, self.base + drop

    def _sum(self, found, qs, times, cmd, s_cmd) -> None:
        """Add the errors ``found`` of the samples ``qs`` at ``times`` (their times, which
        are out of rapids and the time since one: :meth:`_feed`) to the running figures
        and the closest point's leaps (:mod:`.contour_passes`; ``cmd`` the command they
        were measured against, ``s_cmd`` its path lengths from the run's start) [-]."""
        ts, feed, since = times
        res = self.res
        for s, (e, seg) in found.items():
            res.sums.setdefault(s, RunningSummary()).add(e, ts)
            if feed is not None:
                self.feed.setdefault(s, RunningSummary()).add(e, ts, since, feed)
            if self.each is not None:
                self.each(s, e)
            flags, self.last[s] = leaps(qs[s], e, seg, cmd, s_cmd, self.last.get(s))
            self.leaps.add(s, flags if feed is None else flags & feed, e)

    def _feed(self, buf, first: int, b: int):
        """The samples ``first:b`` not in a rapid and the time since the last one in a
        rapid, where the run records its rapids (``None`` where it does not); their
        count in rapids added up [-, s]."""
        if "rapid" not in buf:
            return None, None
        feed = buf["rapid"][first:b] == 0
        self.air = (self.air or 0) + int(feed.size - np.count_nonzero(feed))
        since, self.last_rapid_t = since_rapid(buf["time_s"][first:b], ~feed,
                                               self.last_rapid_t)
        return feed, since


def _window(moves, t, tau, first: int, b: int, w: float, final: bool):
    """The command rows ``c0:c1`` that samples ``first:b`` are measured against: their
    windows (in time, and over the command's rests in its time of motion ``tau``), the end
    of the last segment, and on to a segment that moves (a resting segment takes the
    direction of the next moving one; ``moves``: per segment); ``None`` where the buffer
    does not reach that far yet [-]."""
    n = t.size
    c0 = min(int(np.searchsorted(t, t[first] - w, side="left")),
             int(np.searchsorted(tau, tau[first] - w, side="left")))
    c1 = min(max(int(np.searchsorted(t, t[b - 1] + w, side="right")),
                 int(np.searchsorted(tau, tau[b - 1] + w, side="right"))) + 1, n)
    while c1 < n and not moves[c1 - 2]:
        c1 += 1
    if not final and not (moves[c1 - 2] and moves[c1 - 1:].any()):
        return None  # and the turn at the end of the last segment is not known yet
    if final:  # at the end the last moving segment of all stands in for the next
        while c0 > 0 and not moves[c0:c1 - 1].any():
            c0 -= 1
    return c0, c1
