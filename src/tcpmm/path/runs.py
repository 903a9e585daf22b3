"""A run of consecutive G1 blocks as arrays, the segments of the stream's plain moves.

The interpreter of a streamed program hands the interpolator a run of plain G1 blocks as
one :class:`LineRun` (their points, feeds and lines as arrays) rather than a
:class:`~tcpmm.path.segments.Line` per block: the look-ahead reads the arrays as they
are (:func:`tcpmm.path.geometry.to_arrays`), and so does corner blending, which hands
the look-ahead the lines and blend arcs of a blended stretch as one :class:`ColumnRun`.
A run stands for its Lines exactly (:func:`as_lines`): the same points, feeds, exact
stop, lines and tolerance.
"""

from __future__ import annotations

import dataclasses
from collections import deque
from dataclasses import dataclass
from itertools import repeat

import numpy as np

from .segments import Line


def slot_setters(cls) -> tuple:
    """The slot setters of a frozen dataclass's fields in order: its ``__init__`` sets each
    field through ``object.__setattr__``, which costs twice as much as the setters [-]."""
    return tuple(getattr(cls, f.name).__set__ for f in dataclasses.fields(cls))


#: the slot setters of Line's fields (:func:`slot_setters`)
LINE_SETTERS = slot_setters(Line)


@dataclass(frozen=True, slots=True, eq=False)
class LineRun:
    """Consecutive straight feed moves (G1), each starting where the one before ends.

    Parameters
    ----------
    start_m : tuple of float
        Start point of the first (X, Y, Z) [m].
    end_m : ndarray, shape (n, 3)
        End point of each [m].
    feed_m_per_s : list of float
        Programmed feed of each [m/s].
    exact_stop : bool
        Come to rest at the end of each (G61) [-].
    line : int
        Source line of the first; the others follow line by line [-].
    tolerance_m : float or None
        Contour tolerance of the corners at their ends (G64 P) [m].
    """

    start_m: tuple
    end_m: np.ndarray
    feed_m_per_s: list
    exact_stop: bool
    line: int
    tolerance_m: float | None

    def __len__(self) -> int:
        return len(self.feed_m_per_s)

    def starts(self) -> np.ndarray:
        """Start point of each block [m]."""
        return np.vstack([np.array(self.start_m, float)[None, :], self.end_m[:-1]])

    def cut(self, a: int, b: int) -> LineRun:
        """Blocks ``a`` to ``b - 1`` as a run of their own [-]."""
        start = self.start_m if a == 0 else tuple(self.end_m[a - 1].tolist())
        return LineRun(start, self.end_m[a:b], self.feed_m_per_s[a:b], self.exact_stop,
                       self.line + a, self.tolerance_m)

    def lines(self) -> list:
        """The run as Lines [-]."""
        targets = list(zip(*self.end_m.T.tolist(), strict=True))
        starts = [self.start_m]
        starts += targets[:-1]
        # a Line for every block, the slots set by C loops over the run (map), not per block
        new, (s_start, s_end, s_feed, s_exact, s_line, s_tol) = object.__new__, LINE_SETTERS
        segs = list(map(new, repeat(Line, len(targets))))
        for setter, values in ((s_start, starts), (s_end, targets),
                               (s_feed, self.feed_m_per_s), (s_exact, repeat(self.exact_stop)),
                               (s_line, range(self.line, self.line + len(segs))),
                               (s_tol, repeat(self.tolerance_m))):
            deque(map(setter, segs, values), maxlen=0)
        return segs


def blocks(segments) -> int:
    """Blocks in ``segments``, a run counting its blocks [-]."""
    return sum(len(s) if type(s) in RUNS else 1 for s in segments)


def as_lines(segments) -> list:
    """``segments`` with every run made Lines [-]."""
    out = []
    for s in segments:
        if type(s) is LineRun:
            out += s.lines()
        else:
            out.append(s)
    return out


def drop_blocks(segments: list, k: int) -> list:
    """``segments`` without their first ``k`` blocks (a run cut where they end) [-]."""
    i = 0
    while k > 0 and i < len(segments):
        n = len(segments[i]) if type(segments[i]) in RUNS else 1
        if n > k:
            return [segments[i].cut(k, n), *segments[i + 1:]]
        k -= n
        i += 1
    return segments[i:]


def path_columns(segments, plain_columns) -> tuple:
    """The columns of :func:`tcpmm.path.geometry.to_arrays` (kind, start, end, centre,
    feed, rapid, exact stop, dwell, line, plane axes, ccw, extra turns) of ``segments``
    with runs among them: a run's from its arrays, the others' by ``plain_columns`` [SI]."""
    if not any(type(s) in RUNS for s in segments):
        return plain_columns(segments)
    parts, span = [], []
    for s in segments:
        if type(s) not in RUNS:
            span.append(s)
            continue
        if span:
            parts.append(plain_columns(span))
            span = []
        parts.append(_run_columns(s) if type(s) is LineRun else s.columns)
    if span:
        parts.append(plain_columns(span))
    return tuple(np.concatenate(c) for c in zip(*parts, strict=True))


@dataclass(frozen=True, slots=True, eq=False)
class ColumnRun:
    """Consecutive segments already in the look-ahead's columns, those
    :func:`tcpmm.path.geometry.to_arrays` reads: the lines and blend arcs of a blended
    stretch of a path (:class:`tcpmm.path.blend.CornerBlender`,
    :func:`tcpmm.path.blend.blended_path`).

    Parameters
    ----------
    columns : tuple of ndarray
        Kind, start, end, centre, feed, rapid, exact stop, dwell, line, plane axes, ccw
        and extra turns, a row per segment [SI].
    """

    columns: tuple

    def __len__(self) -> int:
        return self.columns[0].size

    def cut(self, a: int, b: int) -> ColumnRun:
        """Segments ``a`` to ``b - 1`` as a run of their own [-]."""
        return ColumnRun(tuple(c[a:b] for c in self.columns))


#: the segment types that stand for several blocks or segments
RUNS = (LineRun, ColumnRun)


def _run_columns(run: LineRun) -> tuple:
    """The columns of a run's blocks, straight lines (kind 0) [SI]."""
    n = len(run)
    return feed_columns(np.zeros(n, np.int64), run.starts(), np.array(run.end_m, float),
                        np.zeros((n, 3)), np.array(run.feed_m_per_s, float),
                        np.full(n, run.exact_stop),
                        np.arange(run.line, run.line + n, dtype=np.int64))


def feed_columns(kind, start, end, centre, feed, exact, line) -> tuple:
    """The look-ahead's columns (those of :func:`path_columns`) of feed moves that are
    lines or blend arcs: no rapid, dwell, arc plane, direction or extra turn [SI].

    Parameters
    ----------
    kind : ndarray of int
        Kind of each segment (:mod:`tcpmm.path.geometry`: line or blend) [-].
    start, end, centre : ndarray, shape (n, 3)
        Its points; the centre of a blend, zeros for a line [m].
    feed : ndarray
        Its programmed feed [m/s].
    exact : ndarray of bool
        It stops exactly at its end [-].
    line : ndarray of int
        Its source line, -1 for none [-].
    """
    n = kind.size
    return (kind, start, end, centre, feed, np.zeros(n, bool), exact, np.zeros(n), line,
            np.tile(np.array([0, 1], np.int64), (n, 1)), np.zeros(n, bool),
            np.zeros(n, np.int64))
