"""Overshoot, rounding and settling at every corner of a run given a piece at a time (the
definitions are in :mod:`tcpmm.analysis.contour`): the command as it is read, the actual
samples with their contour errors as they are measured.

A corner is found (:class:`~tcpmm.analysis.corners.CornerFinder`) once the command runs
on a corner span past it. From then on every sample measured is taken down for the
corner (:class:`~tcpmm.analysis.corner_store.CornerStore`): where its closest command
point lies near the corner, its distance to the corner point and how far outside the path
it lies; from the corner on, its contour error. The samples between the corner and the
next one found (its settling stretch) are kept so, a few numbers each; the command and the
samples are kept only as far back as a corner not found yet may reach. A corner is summed
up when the next one is found and the samples up to halfway to it are in: the figures are
the whole run's to the bit, whatever the pieces.

A run with a corner every few blocks (a CAM finishing pattern) has hundreds of thousands
of them: the open corners are columns of numbers, and each step (opening the corners
found, looking for their legs' bends, taking down a batch of samples, summing up) is one
compiled call for all the corners it concerns.
"""

from __future__ import annotations

import numpy as np

from .._compiled import call
from .contour_chords import stray_corners
from .corner_rows import CornerRows
from .corner_store import CornerStore, batch_figures
from .corners import CornerFinder, first_bends, path_length

#: rows of a settling stretch read back at a time [-]
_BACK_ROWS = 1 << 18
#: a corner's figures per sensor, in :func:`tcpmm.sim.cornerfigs.corner_figures`' order
_FIGURES = ("overshoot_m", "rounding_m", "settle_s", "settle_m")
#: the open corners' numbers, a row each (``c``, ``n`` and ``t_out`` a vector a row):
#: vertex, turn; time at the corner, from which it settles; path length from which it
#: settles, at the corner, at the first vertex of its rest; the samples it owns from and
#: to (inf until the next corner is found); to which its outgoing leg runs on (inf until
#: its bend is found); the first segment not yet looked at for the bend; 1 at the end of
#: the path; its rows taken down; whether samples of sensors have come to it
_COLUMNS = ("i", "turn", "t_i", "t0", "sp0", "s_i", "s_first", "b0", "b1", "s_on",
            "checked", "end", "rows", "fed", "c", "n", "t_out")


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
        self.open = None  # the corners being measured (:data:`_COLUMNS`), in order
        self.g0 = 0  # the number of the first open corner, from 0
        self.store = CornerStore()
        self.done = CornerRows()  # the figures of the corners done
        self.names = []  # the sensors
        self.last_t_i = None  # the time at the last corner done
        self.t_done = -np.inf  # the last sample measured
        self.tc0 = None
        self.last = None  # the last sample: its time [s] and per sensor its point [m]
        self.unreached = {}  # per sensor still on its way to the path's end point [m]
        # per corner (its command vertex) whose chords stray off the command: how far, and
        # the path length over which the command runs straight from it [m]
        self.strayed = {}

    def add_command(self, tc, p) -> None:
        """The next command samples: times [s] and points, shape (m, d) [m]."""
        tc, p = np.asarray(tc, float), np.asarray(p, float)
        if not tc.size:
            return
        if self.p is None:
            self.tc0, self.tc, self.p, self.s = float(tc[0]), tc, p, path_length(p)
            self.open = _table(p.shape[1])
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
        self._feed(0, _stacked(*new))
        self.t_done = float(t[-1])
        self.last = (self.t_done, {k: np.array(v[-1], float) for k, v in actual.items()})
        self._settle()

    def finish(self) -> CornerRows:
        """The corners of the whole run, the end of the path last (a sequence of dicts,
        :class:`~tcpmm.analysis.corner_rows.CornerRows`): per corner ``number``,
        ``index`` (command sample), ``point_m``, ``turn_rad`` and per sensor
        ``overshoot_m``, ``rounding_m``, ``settle_s``, ``settle_m`` [SI]."""
        if self.p is None:
            return self.done
        self._found(self.finder.step(self.p, self.s, self.off, True))
        if self.open["i"].size:
            self.open["b1"][-1] = self.tc[-1]
        self._bends()
        self.t_done = np.inf
        self._settle()
        return self.done

    def _found(self, corners) -> None:
        """Open the corners just found and take down the samples kept for them, once
        each knows where the next begins (else each would take the samples kept up to
        the last: a chunk of a run with a corner every few blocks)."""
        if corners:
            idx = np.array([i for i, _ in corners], np.int64)
            turn = np.array([t for _, t in corners], float)
            frames = call("corner_frames", self.p, self.s, self.tc, idx - self.off, turn,
                          self.span)
            self.strayed.update(stray_corners(self.p, self.s, idx[~np.isnan(turn)],
                                              self.off, self.span))
            self._opened(idx, turn, frames)
        self._bends()
        if self.smp is not None and corners:
            self._feed(self.open["i"].size - len(corners), _stacked(*self.smp))

    def _opened(self, idx, turn, frames) -> None:
        """Add the corners at the vertices ``idx`` of turns ``turn`` [-], [rad] and frames
        (:func:`tcpmm.sim.cornerfigs.corner_frames`) to the open ones."""
        li, d, o = idx - self.off, self.p.shape[1], self.open
        first = frames[:, 0].astype(np.int64)
        t_i, t_in, end = self.tc[li], self.tc[first], np.isnan(turn)
        prev = o["t_i"][-1] if o["i"].size else self.last_t_i
        # halfway from the command leaving the corner before to its arriving here: a
        # rest here (a dwell, the end's) is no part of the leg the one before owns
        b0 = 0.5 * (np.concatenate([[np.nan if prev is None else prev], t_i[:-1]]) + t_in)
        if prev is None:
            b0[0] = self.tc0
        if o["i"].size:
            o["b1"][-1] = b0[0]
        s_i, n = self.s[li], idx.size
        new = {"i": idx, "turn": turn, "t_i": t_i, "t0": np.where(end, t_in, t_i),
               "sp0": frames[:, 1], "s_i": s_i, "s_first": self.s[first], "b0": b0,
               "b1": np.concatenate([b0[1:], [np.inf]]),
               "s_on": np.where(end, s_i, np.inf),  # the end's leg runs on nowhere
               "checked": idx.copy(), "end": end.astype(np.int64),
               "rows": np.zeros(n, np.int64), "fed": np.zeros(n, bool), "c": self.p[li],
               "n": frames[:, 2:2 + d], "t_out": frames[:, 2 + d:]}
        self.open = {k: np.concatenate([o[k], new[k]]) for k in _COLUMNS}

    def _bends(self) -> None:
        """Look for the bend that ends each open corner's outgoing leg in the command read
        since (only the corners still without one: a run of many corners finds them
        one after the other), every such corner in one call."""
        o = self.open
        u = np.flatnonzero(o["s_on"] == np.inf) if o is not None else ()
        if not len(u):
            return
        j = first_bends(self.p, self.s, o["checked"][u] - self.off, o["t_out"][u],
                        o["s_i"][u] + self.span)
        found = j >= 0
        o["checked"][u[~found]] = self.off + self.s.size - 1
        o["s_on"][u[found]] = self.s[j[found]]

    def _feed(self, a: int, batch) -> None:
        """Take down on the open corners from the ``a``-th on the samples of a batch
        (:func:`_stacked`) that concern each: those from the earlier of its start and the
        halfway point from the corner before, up to halfway to the next where that is
        known (its figures take no other); near the corner, and from it on
        (:func:`tcpmm.sim.cornerfeed.feed_many`, every corner in one call). What settles
        is the contour error after a corner, the distance to the end point at the end of
        the path (the command rests there: lag counts too)."""
        o = self.open
        if o is None or o["i"].size <= a:
            return
        t, q, e, f, names = batch
        k = slice(a, None)
        lims = np.column_stack([np.minimum(o["b0"][k], o["t0"][k]), o["b1"][k], o["t0"][k],
                                o["s_i"][k], np.full(o["i"].size - a, self.span),
                                o["s_on"][k], o["s_first"][k]])
        cuts, *near, rowcut, rows = call(
            "feed_many", t, q, e, f, self.off, self.tc, self.s, self.p,
            np.ascontiguousarray(o["c"][k]), np.ascontiguousarray(o["n"][k]), lims,
            np.ascontiguousarray(o["end"][k]))
        self.names = names
        if names:
            o["fed"][k] = True
            o["rows"][k] += np.diff(rowcut)
            self.store.add(self.g0 + a, cuts, near, rowcut, rows, o["rows"][k])

    def _settle(self) -> None:
        """Sum up the corners whose samples are all in, and let go of what no corner
        needs any more."""
        o = self.open
        if o is not None and o["i"].size:
            ready = (o["b1"] != np.inf) & (self.t_done >= o["b1"])
            m = o["i"].size if ready.all() else int(np.argmin(ready))
            if m:
                self._summed(m)
                self.last_t_i = float(o["t_i"][m - 1])
                self.open = {k: v[m:] for k, v in o.items()}
                self.g0 += m
                # a run of many corners keeps only their figures
                self.store.release(self.g0)
        if self.p is not None and np.isfinite(self.t_done):
            self._trim()

    def _summed(self, m: int) -> None:
        """Add the first ``m`` open corners, numbered, with their figures
        (:func:`_figures`), to the corners done as columns: a run of many corners had
        each made a dict and packed again."""
        o, ns = self.open, len(self.names)
        lims = np.column_stack([o["b0"][:m], o["b1"][:m], o["t0"][:m], o["sp0"][:m],
                                np.full(m, self.tol)])
        fed = o["fed"][:m].copy()
        figs = np.full((m, ns, len(_FIGURES)), np.nan)
        if ns and fed.any():
            figs[fed] = batch_figures(self.store, self.g0, lims, o["end"][:m],
                                      ns).reshape(m, ns, len(_FIGURES))[fed]
        # a corner on a tape, and the end of the path, as a dict of its own
        odd = {g - self.g0 for g in self.store.long if self.g0 <= g < self.g0 + m}
        for j in sorted(odd | set(np.flatnonzero(o["end"][:m]).tolist())):
            if not fed[j]:
                continue
            long = self.store.long.get(self.g0 + j)
            row = (_figures(long, lims[j], int(o["end"][j]), self.names) if long is not None
                   else {n: dict(zip(_FIGURES, figs[j, k].tolist(), strict=True))
                         for k, n in enumerate(self.names)})
            if o["end"][j]:
                self._on_its_way(row, o["c"][j])
            figs[j] = [[row[n][f] for f in _FIGURES] for n in self.names]
        self.done.extend_columns(o["i"][:m], o["c"][:m], o["turn"][:m], fed, figs,
                                 tuple(self.names) if fed.any() else ())

    def _on_its_way(self, row: dict, c) -> None:
        """At the end of the path: where the run leaves a sensor on its way to the end
        point (not settled, further than the band from it at the run's last sample, and
        never closer before, or never near enough to be measured: ringing about a
        deflection comes closer between), it stopped before the machine came to rest, so
        no sensor not settled there has its overshoot and rounding measured (NaN: the
        tool's lead on the motor, say, is not over); their distances at the last sample
        go to :attr:`unreached` [m]."""
        if self.last is None or self.last[0] > self.tc[-1]:
            return  # the run goes on past the command's end: its end stretch is whole
        far = {name: float(np.sqrt(np.sum((q - c) ** 2))) for name, q in self.last[1].items()
               if name in row and np.isnan(row[name]["settle_s"])}
        # a rounding of NaN: no sample came near enough to be measured there at all
        if not any(self.tol < d and not d > row[n]["rounding_m"] + 1e-3 * self.tol
                   for n, d in far.items()):
            return
        for name, d in far.items():
            row[name]["overshoot_m"] = row[name]["rounding_m"] = float("nan")
            self.unreached[name] = d

    def _trim(self) -> None:
        keep = self.finder.keep(self.p, self.s, self.off)
        t_keep = float(self.tc[keep - self.off]) - self.w
        # future samples: their closest segment lies a window before them at the least
        nxt = int(np.searchsorted(self.tc, self.t_done - self.w, side="left")) - 1
        checked = self.open["checked"][self.open["s_on"] == np.inf]
        cut = min([keep - self.off, nxt] + ([int(checked.min()) - self.off]
                                            if checked.size else []))
        cut = max(cut, 0)
        if cut:
            self.tc, self.p, self.s = self.tc[cut:], self.p[cut:], self.s[cut:]
            self.off += cut
        if self.smp is not None:
            k = int(np.searchsorted(self.smp[0], t_keep, side="left"))
            if k:
                t, *rest = self.smp
                self.smp = (t[k:], *({n: v[k:] for n, v in d.items()} for d in rest))


def end_unreached(stream: CornerStream, kept) -> dict:
    """Per sensor the run leaves on its way to the path's end point, its distance from it
    at the last sample (:attr:`CornerStream.unreached`), where the end is among the
    corners ``kept`` (not left out with the G0 rapids) [m]."""
    return dict(stream.unreached) if len(kept) and np.isnan(kept[-1]["turn_rad"]) else {}


def _table(d: int) -> dict:
    """No open corners: the columns of :data:`_COLUMNS`, empty, of points of ``d``
    coordinates [-]."""
    ints = ("i", "checked", "end", "rows")
    out = {k: np.empty(0, np.int64 if k in ints else float) for k in _COLUMNS}
    out["fed"] = np.empty(0, bool)
    for k in ("c", "n", "t_out"):
        out[k] = np.empty((0, d))
    return out


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


def _figures(long, lims, end: int, names) -> dict:
    """Per sensor: overshoot, rounding and settling of a corner whose settling stretch is
    on a tape (:class:`~tcpmm.analysis.corner_store.CornerStore`), from the tape and its
    pieces near it, over the samples it owns (``lims``: from and to which time, the time
    and path length from which it settles, the band) [SI].

    The overshoot (:func:`tcpmm.sim.cornerfigs.corner_shapes`) is taken from where the
    point holds: at the end of the path a static deflection along it is where it settles
    (it is taken off), across the outgoing leg a sag of the tool where it holds there.
    A settling stretch of up to :data:`_BACK_ROWS` rows is measured in one call
    (:func:`tcpmm.sim.cornerfigs.corner_figures`); a longer one a block at a time."""
    tape, pieces = long
    b0, b1, t0, sp0, tol = lims.tolist()
    cut, *cols = pieces[0] if len(pieces) == 1 else _by_sensor(pieces, len(names))
    a0, a1 = tape.count(b0, "left"), tape.count(b1, "right")
    if a1 - a0 <= _BACK_ROWS:
        rows = tape.rows(a0, a1) if a1 > a0 else np.empty((0, 2 + len(names)))
        figs = call("corner_figures", np.ascontiguousarray(rows),
                    np.array([b0, b1, t0, sp0, tol]), *cols, cut, end)
        return {name: dict(zip(_FIGURES, row, strict=True))
                for name, row in zip(names, figs.tolist(), strict=True)}
    settled = _settling(tape, a0, a1, range(2, 2 + len(names)), t0, sp0, tol)
    shapes = call("corner_shapes", *cols, cut, b0, b1, end, tol)
    return {name: {"overshoot_m": over, "rounding_m": rounding, **settle}
            for name, settle, (over, rounding) in zip(names, settled, shapes.tolist(),
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
