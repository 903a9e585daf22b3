"""The columns of :func:`tcpmm.path.geometry.to_arrays` read from the segments' fields:
a field of every Line (or Arc) in one list and one conversion per column, not a row at a
time (a path of short blocks or short arcs has hundreds of thousands of them)."""

from __future__ import annotations

from itertools import chain
from operator import attrgetter

import numpy as np

from .segments import AXIS_INDEX

#: the columns :func:`line_columns` reads from each Line, in order
_LINE_FIELDS = tuple(map(attrgetter, ("start_m", "end_m", "feed_m_per_s", "exact_stop",
                                      "line")))


def line_columns(segments, is_line, columns) -> None:
    """Fill the rows of the Lines among ``segments`` (``is_line``) in ``columns``: start,
    end, feed, exact stop and line (-1 for none) [SI]."""
    # a list of a field per column and one conversion each: a path of short blocks is
    # almost all Lines, and setting a row at a time cost microseconds a block
    rows = slice(None) if is_line.all() else np.flatnonzero(is_line)
    lines = segments if type(rows) is slice else [segments[i] for i in rows.tolist()]
    if not len(lines):
        return
    for get, col in zip(_LINE_FIELDS, columns, strict=True):
        values = list(map(get, lines))
        if get is _LINE_FIELDS[-1] and None in values:
            values = [-1 if v is None else v for v in values]
        if col.ndim == 2:  # the points' coordinates in one pass, not a tuple at a time
            flat = np.fromiter(chain.from_iterable(values), float)
            values = flat.reshape(-1, 3) if flat.size == 3 * len(values) else values
        col[rows] = values


#: the columns :func:`arc_columns` reads from each Arc, in order
_ARC_FIELDS = tuple(map(attrgetter, ("start_m", "end_m", "centre_m", "feed_m_per_s",
                                     "exact_stop", "plane_axes", "direction", "extra_turns",
                                     "line")))


def arc_columns(segments, is_arc, columns) -> None:
    """Fill the rows of the Arcs among ``segments`` (``is_arc``) in ``columns``: start,
    end, centre, feed, exact stop, plane axes, counter-clockwise, extra turns and
    line (-1 for none) [SI]."""
    rows = np.flatnonzero(is_arc)
    if not rows.size:
        return
    arcs = [segments[i] for i in rows.tolist()]
    start, end, centre, feed, exact, plane, ccw, turns, line = columns
    got = [list(map(get, arcs)) for get in _ARC_FIELDS]
    for values, col in zip(got[:3], (start, end, centre), strict=True):
        col[rows] = np.fromiter(chain.from_iterable(values), float, 3 * rows.size).reshape(-1, 3)
    feed[rows], exact[rows], turns[rows] = got[3], got[4], got[7]
    plane[rows] = [(AXIS_INDEX[a], AXIS_INDEX[b]) for a, b in got[5]]
    ccw[rows] = [d == "ccw" for d in got[6]]
    line[rows] = [-1 if v is None else v for v in got[8]]
