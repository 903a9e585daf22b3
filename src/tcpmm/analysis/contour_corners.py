"""Overshoot, rounding and settling at every corner of a run given a piece at a time (the
definitions are in :mod:`tcpmm.analysis.contour`): the command as it is read, the actual
samples with their contour errors as they are measured.

A corner is found (:class:`~tcpmm.analysis.corners.CornerFinder`) once the command runs
on a corner span past it. From then on every sample measured is taken down on the
corner's tapes: where its closest command point lies near the corner, its distance to the
corner point and how far outside the path it lies; from the corner on, its contour error.
The samples between the corner and the next one found (its settling stretch) are kept so,
a few numbers each; the command and the samples are kept only as far back as a corner not
found yet may reach. A corner is summed up when the next one is found and the samples up
to halfway to it are in: the figures are the whole run's to the bit, whatever the pieces.
"""

from __future__ import annotations

from collections import deque

import numpy as np

from .._compiled import call
from .corners import CornerFinder, first_bend, path_length
from .tape import Tape

#: rows of a settling stretch read back at a time [-]
_BACK_ROWS = 1 << 18
#: a corner's figures per sensor, in :func:`tcpmm.sim.cornerfigs.corner_figures`' order
_FIGURES = ("overshoot_m", "rounding_m", "settle_s", "settle_m")


class _Corner:
    """One corner being measured: its geometry, bounds and tapes."""

    def __init__(self, i, turn, first, t_i, t0, sp0, c, n, t_out, s_i, s_first, b0):
        self.i, self.turn, self.first, self.t_i, self.t0, self.sp0 = i, turn, first, t_i, t0, sp0
        self.c, self.n, self.t_out, self.s_i, self.s_first = c, n, t_out, s_i, s_first
        self.end = bool(np.isnan(turn))
        self.b0, self.b1 = b0, None
        self.s_on = s_i if self.end else np.inf  # path length to which the leg runs on
        self.checked = i  # the first segment not yet looked at for the bend
        self.near, self.after, self.sensors = [], Tape(), []


class CornerStream:
    """The corner metrics of :func:`tcpmm.analysis.contour.contour_error`, accumulated.

    Parameters
    ----------
    corner_deg : float
        Least turn that makes a corner [deg].
    span_m : float
        Path length before and after a point over which its turn is taken [m].
    settle_tol_m : float
        Band within which the error has settled after a corner [m].
    window_s : float
        Time around each sample in which its closest command point was sought [s].
    """

    def __init__(self, corner_deg=30.0, span_m=0.5e-3, settle_tol_m=1e-6, window_s=0.2):
        self.finder = CornerFinder(corner_deg, span_m)
        self.span, self.tol, self.w = span_m, settle_tol_m, window_s
        self.tc = self.p = self.s = None
        self.off = 0  # the command's vertex of row 0 of the buffer
        self.smp = None  # samples kept for corners not found yet: t, actual, errors, feet
        self.open, self.done = deque(), []  # corners being measured; the figures of those done
        self.last = None  # the last corner done
        self.unbent = []  # the open corners whose outgoing leg's bend is not found yet
        self.t_done = -np.inf  # the last sample measured
        self.tc0 = None

    def add_command(self, tc, p) -> None:
        """The next command samples: times [s] and points, shape (m, d) [m]."""
        tc, p = np.asarray(tc, float), np.asarray(p, float)
        if not tc.size:
            return
        if self.p is None:
            self.tc0, self.tc, self.p, self.s = float(tc[0]), tc, p, path_length(p)
        else:
            s = path_length(np.vstack([self.p[-1:], p]), self.s[-1])[1:]
            self.tc, self.p = np.concatenate([self.tc, tc]), np.vstack([self.p, p])
            self.s = np.concatenate([self.s, s])
        self._found(self.finder.step(self.p, self.s, self.off, False))
        self._settle()

    def add_samples(self, t, actual, errors, feet) -> None:
        """The next actual samples, measured: times [s], per sensor the points, shape
        (n, d) [m], contour errors [m] and the command segments closest to them [-]."""
        t = np.asarray(t, float)
        if not t.size:
            return
        new = (t, actual, errors, feet)
        if self.smp is None:
            self.smp = new
        else:
            self.smp = tuple([np.concatenate([self.smp[0], t])] + [
                {k: np.concatenate([old[k], v[k]]) for k in v}
                for old, v in zip(self.smp[1:], new[1:], strict=True)])
        self._bends()
        self._feed(self.open, _stacked(*new))
        self.t_done = float(t[-1])
        self._settle()

    def finish(self) -> list:
        """The corners of the whole run, the end of the path last: per corner ``number``,
        ``index`` (command sample), ``point_m``, ``turn_rad`` and per sensor
        ``overshoot_m``, ``rounding_m``, ``settle_s``, ``settle_m`` [SI]."""
        if self.p is None:
            return []
        self._found(self.finder.step(self.p, self.s, self.off, True))
        if self.open:
            self.open[-1].b1 = float(self.tc[-1])
        self._bends()
        self.t_done = np.inf
        self._settle()
        return list(self.done)

    def _found(self, corners) -> None:
        """Open the corners just found and take down the samples kept for them, once
        each knows where the next begins (else each would take the samples kept up to
        the last: a chunk of a run with a corner every few blocks)."""
        new, d = [], self.p.shape[1]
        frames = call("corner_frames", self.p, self.s, self.tc,
                      np.array([i - self.off for i, _ in corners], np.int64),
                      np.array([t for _, t in corners], float), self.span) if corners else ()
        for (i, turn), frame in zip(corners, frames, strict=True):
            li = i - self.off
            first = int(frame[0])
            t_i, t_in = float(self.tc[li]), float(self.tc[first])
            t0 = t_in if np.isnan(turn) else t_i  # the end: the arrival
            prev = self.open[-1] if self.open else self.last
            # halfway from the command leaving the corner before to its arriving here: a
            # rest here (a dwell, the end's) is no part of the leg the one before owns
            b0 = self.tc0 if prev is None else 0.5 * (prev.t_i + t_in)
            if prev is not None:
                prev.b1 = b0
            c = _Corner(i, turn, first + self.off, t_i, t0, float(frame[1]),
                        self.p[li].copy(), frame[2:2 + d], frame[2 + d:],
                        float(self.s[li]), float(self.s[first]), b0)
            self.open.append(c)
            new.append(c)
            if c.s_on == np.inf:
                self.unbent.append(c)
        self._bends()
        if self.smp is not None and new:
            self._feed(new, _stacked(*self.smp))

    def _bends(self) -> None:
        """Look for the bend that ends each open corner's outgoing leg in the command read
        since (only the corners still without one: a run of many corners finds them
        one after the other)."""
        for c in list(self.unbent):
            j = first_bend(self.p, self.s, c.checked - self.off, c.t_out, c.s_i + self.span)
            if j is None:
                c.checked = self.off + self.s.size - 1
            else:
                c.s_on = float(self.s[j])
                self.unbent.remove(c)

    def _feed(self, corners, batch) -> None:
        """Take down on the corners' tapes the samples of a batch (:func:`_stacked`) that
        concern each: those from the earlier of its start and the halfway point from the
        corner before, up to halfway to the next where that is known (its figures take
        no other); near the corner, and from it on
        (:func:`tcpmm.sim.cornerfeed.feed_many`, every corner in one call). What settles
        is the contour error after a corner, the distance to the end point at the end of
        the path (the command rests there: lag counts too)."""
        if not corners:
            return
        t, q, e, f, names = batch
        lims = np.array([[min(c.b0, c.t0), np.inf if c.b1 is None else c.b1, c.t0, c.s_i,
                          self.span, c.s_on, c.s_first] for c in corners])
        cuts, *near, rowcut, rows = call(
            "feed_many", t, q, e, f, self.off, self.tc, self.s, self.p,
            np.array([c.c for c in corners]), np.array([c.n for c in corners]), lims,
            np.array([int(c.end) for c in corners], np.int64))
        bounds, at = cuts[:, [0, -1]].tolist(), rowcut.tolist()
        for j, c in enumerate(corners):
            a, b = bounds[j]
            # a piece that holds nothing is kept only while no other is: a corner's
            # figures then read its one piece as it is, not joined from several
            if names and (b > a or not c.near):
                piece = (cuts[j] - a, *(x[a:b] for x in near))
                if c.near and not c.near[-1][0][-1]:
                    c.near[-1] = piece
                else:
                    c.near.append(piece)
            c.sensors = names
            c.after.add(rows[at[j]:at[j + 1]])

    def _settle(self) -> None:
        """Sum up the corners whose samples are all in, and let go of what no corner
        needs any more."""
        while self.open and self.open[0].b1 is not None and self.t_done >= self.open[0].b1:
            c = self.open.popleft()
            if c in self.unbent:
                self.unbent.remove(c)
            # a run of many corners keeps only their figures (and the last, to go on from)
            self.done.append(_numbered(len(self.done) + 1, c, _figures(c, self.tol)))
            c.near = None
            c.after.close()
            self.last = c
        if self.p is not None and np.isfinite(self.t_done):
            self._trim()

    def _trim(self) -> None:
        keep = self.finder.keep(self.p, self.s, self.off)
        t_keep = float(self.tc[keep - self.off]) - self.w
        # future samples: their closest segment lies a window before them at the least
        nxt = int(np.searchsorted(self.tc, self.t_done - self.w, side="left")) - 1
        cut = min([keep - self.off, nxt] + [c.checked - self.off for c in self.unbent])
        cut = max(cut, 0)
        if cut:
            self.tc, self.p, self.s = self.tc[cut:], self.p[cut:], self.s[cut:]
            self.off += cut
        if self.smp is not None:
            k = int(np.searchsorted(self.smp[0], t_keep, side="left"))
            if k:
                t, *rest = self.smp
                self.smp = (t[k:], *({n: v[k:] for n, v in d.items()} for d in rest))


def _stacked(t, actual, errors, feet) -> tuple:
    """A batch of samples as :func:`tcpmm.sim.cornerfeed.feed_many` takes them: times,
    and per sensor (a row each) points, contour errors and closest segments; the
    sensors' names [SI]."""
    names = list(actual)
    if not names:
        return (t, np.empty((0, t.size, 1)), np.empty((0, t.size)),
                np.empty((0, t.size), np.int64), names)
    return (t, np.stack([actual[k] for k in names]), np.stack([errors[k] for k in names]),
            np.stack([feet[k] for k in names]).astype(np.int64, copy=False), names)


def _figures(c, tol) -> dict:
    """Per sensor: overshoot, rounding and settling of a corner from its tapes, over the
    samples it owns (halfway from the previous corner to halfway to the next, in time
    from the command leaving one to its arriving at the other) [SI].

    The overshoot (:func:`tcpmm.sim.cornerfigs.corner_shapes`) is taken from where the
    point holds: at the end of the path a static deflection along it is where it settles
    (it is taken off), across the outgoing leg a sag of the tool where it holds there.
    A settling stretch of up to :data:`_BACK_ROWS` rows is measured in the same call
    (:func:`tcpmm.sim.cornerfigs.corner_figures`); a longer one on disk a block at a
    time."""
    if not c.sensors:
        return {}
    cut, *cols = c.near[0] if len(c.near) == 1 else _by_sensor(c.near, len(c.sensors))
    a0, a1 = (0, c.after.n) if not c.after.in_file else (
        c.after.count(c.b0, "left"), c.after.count(c.b1, "right"))
    if not c.after.in_file or a1 - a0 <= _BACK_ROWS:
        rows = c.after.rows(a0, a1) if a1 > a0 else np.empty((0, 2 + len(c.sensors)))
        figs = call("corner_figures", np.ascontiguousarray(rows),
                    np.array([c.b0, c.b1, c.t0, c.sp0, tol]), *cols, cut, int(c.end))
        return {name: dict(zip(_FIGURES, row, strict=True))
                for name, row in zip(c.sensors, figs.tolist(), strict=True)}
    settled = _settling(c.after, a0, a1, range(2, 2 + len(c.sensors)), c.t0, c.sp0, tol)
    shapes = call("corner_shapes", *cols, cut, c.b0, c.b1, int(c.end), tol)
    return {name: {"overshoot_m": over, "rounding_m": rounding, **settle}
            for name, settle, (over, rounding) in zip(c.sensors, settled, shapes.tolist(),
                                                      strict=True)}


def _by_sensor(pieces, sensors: int) -> tuple:
    """The pieces :meth:`CornerStream._feed` took down, joined: each sensor's rows of every
    piece, one sensor after the other, and where each sensor's start [-]."""
    order = [(piece, k) for k in range(sensors) for piece in pieces]
    cols = tuple(np.concatenate([piece[1 + j][piece[0][k]:piece[0][k + 1]]
                                 for piece, k in order]) for j in range(4))
    counts = [sum(int(p[0][k + 1] - p[0][k]) for p in pieces) for k in range(sensors)]
    return (np.concatenate([[0], np.cumsum(counts)]).astype(np.int64), *cols)


def _settling(tape, a0: int, a1: int, cols, t0: float, sp0: float, tol: float) -> list:
    """Per column of ``cols``: time and command path length from ``t0`` (where the path
    length is ``sp0``) until the error in that column of rows ``a0:a1`` of the tape (time,
    path length, errors) stays within ``tol`` of its level at the end of the stretch (the
    median of its last quarter), NaN where it leaves that band in the last quarter [s, m]:
    :func:`tcpmm.sim.cornerfigs.settle_rows` over a stretch too long to hold, read back
    from its end a block at a time, for every column at once."""
    cols = list(cols)
    nan = {"settle_s": float("nan"), "settle_m": float("nan")}
    size = a1 - a0
    if size < 4:
        return [nan] * len(cols)
    quarter = a1 - size // 4
    tail = np.concatenate([tape.rows(lo, min(lo + _BACK_ROWS, a1))[:, cols]
                           for lo in range(quarter, a1, _BACK_ROWS)])
    level = np.median(tail, axis=0)
    # only a column within the band over the whole last quarter settles
    left = set(np.flatnonzero((np.abs(tail - level) <= tol).all(axis=0)).tolist())
    k, hi = dict.fromkeys(left, a0), quarter
    while left and hi > a0:
        lo = max(a0, hi - _BACK_ROWS)
        block = tape.rows(lo, hi)
        for j in list(left):
            out = np.flatnonzero(~(np.abs(block[:, cols[j]] - level[j]) <= tol))
            if out.size:
                k[j] = lo + int(out[-1]) + 1
                left.discard(j)
        hi = lo
    res = []
    for j in range(len(cols)):
        if j not in k:
            res.append(nan)
            continue
        t, sp = tape.rows(k[j], k[j] + 1)[0, :2]
        res.append({"settle_s": float(t - t0), "settle_m": float(sp - sp0)})
    return res


def _numbered(k, c, figures) -> dict:
    return {"number": k, "index": int(c.i), "point_m": c.c.tolist(), "turn_rad": c.turn,
            **figures}
