"""The samples taken down for the corners being measured
(:class:`~tcpmm.analysis.contour_corners.CornerStream`), kept as the batches that took
them: one call of :func:`tcpmm.sim.cornerfeed.feed_many` takes down a batch of samples
for a run of consecutive corners, and a batch is kept as it came until each of its corners
is summed up. The corners summed up together take their samples out of the batches in one
gather (a corner's rows, and per sensor its samples near it, batch after batch: the order
in which they came) and are measured in one call
(:func:`tcpmm.sim.cornerfigs.corner_figures_many`): a run with a corner every few blocks
spends no Python on each corner.

A corner whose settling stretch grows past :data:`tcpmm.analysis.tape.SPILL_ROWS` rows
(a long leg, the path's only corner) goes on a :class:`~tcpmm.analysis.tape.Tape` of its
own, on disk, with its samples near it; the batches then let go of its rows.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._compiled import call
from . import tape as tapes
from .tape import Tape


@dataclass
class _Batch:
    """One batch of samples taken down by the corners ``g0`` to ``g1`` (not included):
    per corner and sensor where its samples near the corner begin in ``near``, per corner
    where its rows begin in ``rows`` (:func:`tcpmm.sim.cornerfeed.feed_many`) [-]."""

    g0: int
    g1: int
    cuts: np.ndarray
    near: tuple
    rowcut: np.ndarray
    rows: np.ndarray

    def piece(self, j: int) -> tuple:
        """Corner ``g0 + j``'s samples near it, with where each sensor's begin [-]."""
        a, b = int(self.cuts[j, 0]), int(self.cuts[j, -1])
        return (self.cuts[j] - a, *(x[a:b] for x in self.near))

    def rows_of(self, j: int) -> np.ndarray:
        """Corner ``g0 + j``'s rows [-]."""
        return self.rows[self.rowcut[j]:self.rowcut[j + 1]]


class CornerStore:
    """The batches of samples of the corners being measured, and the tapes of those whose
    stretch is long: corner ``g`` (numbered from 0 in the order found) ->
    ``(tape, pieces near it)``."""

    def __init__(self):
        self.batches: list = []
        self.long: dict = {}
        self.g0 = 0  # the first corner not summed up

    def add(self, g0: int, cuts, near, rowcut, rows, counts) -> None:
        """A batch taken down by the corners from ``g0`` on, one a row of ``cuts``;
        ``counts`` the rows each of them has taken so far, this batch's too [-]."""
        batch = _Batch(g0, g0 + cuts.shape[0], cuts, tuple(near), rowcut, rows)
        self.batches.append(batch)
        for g, (tape, pieces) in self.long.items():
            if batch.g0 <= g < batch.g1:
                tape.add(batch.rows_of(g - g0))
                pieces.append(batch.piece(g - g0))
        for j in np.flatnonzero(counts > tapes.SPILL_ROWS).tolist():
            if g0 + j not in self.long:
                self._to_tape(g0 + j)
        self._prune()

    def _to_tape(self, g: int) -> None:
        """Put corner ``g``'s rows so far on a tape of its own, and its pieces aside."""
        tape, pieces = Tape(), []
        for b in self.batches:
            if b.g0 <= g < b.g1:
                tape.add(b.rows_of(g - b.g0))
                pieces.append(b.piece(g - b.g0))
        self.long[g] = (tape, pieces)

    def release(self, g0: int) -> None:
        """Let go of what only the corners before ``g0`` (summed up) need."""
        for g in [g for g in self.long if g < g0]:
            self.long.pop(g)[0].close()
        self.g0 = g0
        self._prune()

    def _prune(self) -> None:
        """Keep the batches that a corner not summed up and not on a tape takes from: a
        corner on a tape has its rows and pieces there (a path's one corner, a spiral's
        lead-in, kept every batch to the end of the run)."""
        self.batches = [b for b in self.batches
                        if sum(max(b.g0, self.g0) <= g < b.g1 for g in self.long)
                        < b.g1 - max(b.g0, self.g0)]

    def gathered(self, g0: int, m: int, sensors: int) -> tuple:
        """The corners ``g0`` to ``g0 + m``'s rows one corner after the other and where
        each corner's begin, shape (m + 1,); their samples near them (times, distances,
        deviations, past), corner after corner and within one sensor after sensor, and
        where each begins, shape (m, sensors + 1); a long corner's (:attr:`long`) none
        [-]."""
        rows, near, rsegs, nsegs, base = [], [], [], [], [0, 0]
        for k, b in enumerate(x for x in self.batches if x.g1 > g0 and x.g0 < g0 + m):
            lo, hi = max(g0, b.g0), min(g0 + m, b.g1)
            j = np.arange(lo - b.g0, hi - b.g0)
            on = ~np.isin(np.arange(lo, hi), list(self.long)) if self.long else \
                np.ones(hi - lo, bool)
            g = np.repeat(j + b.g0 - g0, sensors)
            sensor = np.tile(np.arange(sensors), j.size)
            flat = (j[:, None] * (sensors + 1) + np.arange(sensors)[None, :]).ravel()
            c = b.cuts.ravel()
            rsegs.append((j + b.g0 - g0, np.full(j.size, k), b.rowcut[j] + base[0],
                          (b.rowcut[j + 1] - b.rowcut[j]) * on))
            nsegs.append((g * sensors + sensor, np.full(g.size, k), c[flat] + base[1],
                          (c[flat + 1] - c[flat]) * np.repeat(on, sensors)))
            rows.append(b.rows)
            near.append(b.near)
            base = [base[0] + b.rows.shape[0], base[1] + b.near[0].size]
        if not rows:
            return (np.empty((0, 2 + sensors)), np.zeros(m + 1, np.int64),
                    (np.empty(0), np.empty(0), np.empty(0), np.empty(0, np.uint8)),
                    np.zeros((m, sensors + 1), np.int64))
        ri, rowcut = _segments(rsegs, m)
        ni, cs = _segments(nsegs, m * sensors)
        cut = cs[np.arange(m)[:, None] * sensors + np.arange(sensors + 1)[None, :]]
        return (_joined(rows, ri), rowcut,
                tuple(_joined([n[i] for n in near], ni) for i in range(4)), cut)


def _segments(segs, groups: int) -> tuple:
    """From segments ``(group, batch, start, length)`` of several batches: the index that
    reads them group after group, within a group batch after batch, and where each group
    begins, shape (groups + 1,) [-]."""
    group, batch, start, length = (np.concatenate(x) for x in zip(*segs, strict=True))
    order = np.lexsort((batch, group))
    start, length, group = start[order], length[order], group[order]
    ends = np.cumsum(length)
    index = np.repeat(start - (ends - length), length) + np.arange(ends[-1] if ends.size else 0)
    counts = np.bincount(group, weights=length, minlength=groups).astype(np.int64)
    return index, np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)


def _joined(parts: list, index) -> np.ndarray:
    """The rows ``index`` of the arrays ``parts`` one after the other [-]."""
    # rows taken, not gathered by a fancy index (several times faster on rows of a few)
    return np.take(parts[0] if len(parts) == 1 else np.concatenate(parts), index, axis=0)


def batch_figures(store: CornerStore, g0: int, lims, end, sensors: int) -> np.ndarray:
    """Overshoot, rounding, time and path length to settle of the corners ``g0`` to
    ``g0 + len(lims)`` (:func:`tcpmm.sim.cornerfigs.corner_figures`, a row per corner and
    sensor, a long corner's rows to be filled in) from their limits ``lims`` (the time
    from and to which each owns the samples, from which it settles, the path length from
    which it settles, the band) [s], [s], [s], [m], [m] and ``end`` (1 at the end of the
    path) [-]; [m], [m], [s], [m]."""
    rows, rowcut, near, cut = store.gathered(g0, lims.shape[0], sensors)
    return call("corner_figures_many", np.ascontiguousarray(rows), rowcut,
                np.ascontiguousarray(lims), *near, cut, np.ascontiguousarray(end, np.int64))
