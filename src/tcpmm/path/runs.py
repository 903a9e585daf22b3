"""Runs of consecutive G1 blocks or arcs as arrays, the segments of the stream's plain
moves.

The interpreter of a streamed program hands the interpolator a run of plain G1 blocks as
one :class:`LineRun` (their points, feeds and lines as arrays) rather than a
:class:`~tcpmm.path.segments.Line` per block, and a run of plain arcs as one
:class:`ArcRun`: the look-ahead reads the arrays as they are
(:func:`tcpmm.path.geometry.to_arrays`), and so does corner blending, which hands
the look-ahead the lines and blend arcs of a blended stretch as one :class:`ColumnRun`.
A run stands for its Lines or Arcs exactly (:func:`as_lines`): the same points, feeds,
exact stop, lines and tolerance.
"""

from __future__ import annotations

import dataclasses
from collections import deque
from dataclasses import dataclass
from itertools import repeat

import numpy as np

from .segments import ARC, AXIS_INDEX, Arc, Line


def slot_setters(cls) -> tuple:
    """The slot setters of a frozen dataclass's fields in order: its ``__init__`` sets each
    field through ``object.__setattr__``, which costs twice as much as the setters [-]."""
    return tuple(getattr(cls, f.name).__set__ for f in dataclasses.fields(cls))


#: the slot setters of Line's fields (:func:`slot_setters`)
LINE_SETTERS = slot_setters(Line)


class BlockRun:
    """What a run of blocks, each starting where the one before ends, has of its own: its
    length and its blocks' start points."""

    __slots__ = ()

    def __len__(self) -> int:
        return len(self.feed_m_per_s)

    def starts(self) -> np.ndarray:
        """Start point of each block [m]."""
        return np.vstack([np.array(self.start_m, float)[None, :], self.end_m[:-1]])


@dataclass(frozen=True, slots=True, eq=False)
class LineRun(BlockRun):
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


#: the slot setters of Arc's fields (:func:`slot_setters`)
ARC_SETTERS = slot_setters(Arc)


@dataclass(frozen=True, slots=True, eq=False)
class ArcRun(BlockRun):
    """Consecutive arcs (G2, G3) in one plane, each starting where the one before ends.

    Parameters
    ----------
    start_m : tuple of float
        Start point of the first (X, Y, Z) [m].
    end_m, centre_m : ndarray, shape (n, 3)
        End point and centre of each [m].
    plane_axes : tuple of str
        The plane's two axes, e.g. ``("X", "Y")`` [-].
    ccw : ndarray of bool
        Each turns counter-clockwise (G3) [-].
    feed_m_per_s : list of float
        Programmed feed of each [m/s].
    exact_stop : bool
        Come to rest at the end of each (G61) [-].
    line : int
        Source line of the first; the others follow line by line [-].
    """

    start_m: tuple
    end_m: np.ndarray
    centre_m: np.ndarray
    plane_axes: tuple
    ccw: np.ndarray
    feed_m_per_s: list
    exact_stop: bool
    line: int

    def cut(self, a: int, b: int) -> ArcRun:
        """Arcs ``a`` to ``b - 1`` as a run of their own [-]."""
        start = self.start_m if a == 0 else tuple(self.end_m[a - 1].tolist())
        return ArcRun(start, self.end_m[a:b], self.centre_m[a:b], self.plane_axes,
                      self.ccw[a:b], self.feed_m_per_s[a:b], self.exact_stop, self.line + a)

    def arcs(self) -> list:
        """The run as Arcs [-]."""
        ends = list(map(tuple, self.end_m.tolist()))
        starts = [self.start_m, *ends[:-1]]
        new, n = object.__new__, len(ends)
        segs = list(map(new, repeat(Arc, n)))
        turn = ("cw", "ccw")
        for setter, values in zip(ARC_SETTERS, (
                starts, ends, map(tuple, self.centre_m.tolist()), repeat(self.plane_axes),
                [turn[c] for c in self.ccw.tolist()], self.feed_m_per_s, repeat(0),
                repeat(self.exact_stop), range(self.line, self.line + n)), strict=True):
            deque(map(setter, segs, values), maxlen=0)
        return segs

    def columns(self) -> tuple:
        """The look-ahead's columns of the arcs (those of :func:`path_columns`) [SI]."""
        n = len(self)
        return (np.full(n, ARC, np.int64), self.starts(), np.array(self.end_m, float),
                np.array(self.centre_m, float), np.array(self.feed_m_per_s, float),
                np.zeros(n, bool), np.full(n, self.exact_stop), np.zeros(n),
                np.arange(self.line, self.line + n, dtype=np.int64),
                np.tile(np.array([AXIS_INDEX[a] for a in self.plane_axes], np.int64), (n, 1)),
                np.array(self.ccw, bool), np.zeros(n, np.int64))


def blocks(segments) -> int:
    """Blocks in ``segments``, a run counting its blocks [-]."""
    return sum(len(s) if type(s) in RUNS else 1 for s in segments)


def as_lines(segments) -> list:
    """``segments`` with every run of blocks made Lines and Arcs [-]."""
    out = []
    for s in segments:
        if type(s) is LineRun:
            out += s.lines()
        elif type(s) is ArcRun:
            out += s.arcs()
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
        t = type(s)
        parts.append(_run_columns(s) if t is LineRun else s.columns() if t is ArcRun
                     else s.columns)
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
RUNS = (LineRun, ArcRun, ColumnRun)


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
