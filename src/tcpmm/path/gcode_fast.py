"""The common block of CAM output, a plain G0/G1 move, without the tokeniser.

A program of short segments is almost all blocks like ``G1 X12.5 Y-3.25`` or
``X12.5 Y-3.25 F3000``. :data:`PLAIN_MOVE` matches such a line as a whole, and
:func:`plain_run` executes a run of them as long as the reference interpreter would do
so without an error or a warning. Anything else (comments, other words, another word order, a feed
or coordinate out of range, a zero-length move, no motion mode or feed yet) is left to
the tokeniser and the interpreter, so every message keeps its text, line and column.

A chunk of lines is lexed once, compiled (:func:`scan_chunk`,
:mod:`tcpmm.path.gcode_scan`), into arrays of what each line says; the blocks are
executed on those arrays and only their segments are made as Python objects. A line
whose numbers the compiled lexer cannot convert exactly goes through :data:`PLAIN_MOVE`
and ``float``. :func:`collector_paused` keeps the garbage collector out of a long parse.
"""

from __future__ import annotations

import contextlib
import gc
import re
from typing import NamedTuple

import numpy as np

from .. import _compiled as ck
from .gcode_arcs import ARC, arc_run
from .gcode_words import MAX_COORDINATE_M, MAX_FEED, NO_POINT, WHOLE_LENGTH, ZERO_MOVE_M
from .runs import LINE_SETTERS, LineRun
from .segments import Line, Rapid

# a number as the tokeniser accepts it; a line the tokeniser would refuse ("X.",
# "X1.2.3", "X1e3") does not match here
_NUMBER = r"[ \t]*([-+]?(?:[0-9]+\.?[0-9]*|\.[0-9]+))[ \t]*"
#: ``G0``/``G1`` (also ``G00``/``G01``), then X, Y, Z, F, each at most once and in that
#: order; groups: motion, X, Y, Z, F [-]
PLAIN_MOVE = re.compile(
    r"[ \t]*(?:[Gg][ \t]*0*([01])[ \t]*)?"
    + "".join(f"(?:[{c}{c.lower()}]{_NUMBER})?" for c in "XYZF")
)

#: plain moves in a row below which the expression runs them rather than the compiled
#: run (a call and a LineRun cost some 50 us; the expression about 5 us a block) [-]
SHORT_RUN = 8
#: statuses of :func:`tcpmm.path.gcode_scan.scan_lines`: executed there, a plain move
#: whose numbers only ``float`` converts exactly, a plain arc (:mod:`tcpmm.path.gcode_arcs`)
_PLAIN, _PLAIN_SLOW, _ARC = 1, 2, ARC
#: the column of the codes that marks a length written without a decimal point
#: (:data:`tcpmm.path.gcode_scan.WHOLE_LONG`) [-]
_WHOLE_LONG = 3


class Scan(NamedTuple):
    """A chunk's lines lexed: per line its codes and values
    (:func:`tcpmm.path.gcode_scan.scan_lines`), and where the run of lines of its status
    ends (a run is executed without looking past it: a program of lines and arcs taken in
    turn would otherwise cost the rest of the chunk at every block). A run also ends
    before the chunk's first line of a length written without a decimal point, which goes
    to the interpreter for its warning until the program has had it [-]."""

    codes: np.ndarray
    vals: np.ndarray
    run_end: np.ndarray


def scan_chunk(lines: list[str]):
    """The chunk's lines lexed, a :class:`Scan`, or ``None`` where a line holds a line break
    of its own [-]."""
    if not lines:
        return None
    # bytes above 127 (any other character) make a line no plain move, as for PLAIN_MOVE
    data = ("\n".join(lines) + "\n").encode("utf-8", "surrogatepass")
    codes, vals = ck.scan_lines(np.frombuffer(data, np.uint8))
    if codes.shape[0] != len(lines):
        return None
    n = codes.shape[0]
    ends = np.flatnonzero(np.diff(codes[:, 0])) + 1
    marked = codes[:, _WHOLE_LONG]
    if marked.any():  # most programs have none, and any() costs a third of a search
        ends = np.union1d(ends, [marked.argmax()])  # the first 1 of the column
    ends = np.r_[ends, n]
    return Scan(codes, vals, ends[np.searchsorted(ends, np.arange(n), side="right")])


def plain_run(it, lines: list[str], k: int, offset: int = 0, scan=None) -> int:
    """Execute the plain moves from ``lines[k]`` on, as the interpreter would.

    Parameters
    ----------
    it : tcpmm.path.gcode.Interpreter
        The interpreter, which gets the segments and the modal state after them [-].
    lines : list of str
        The program's lines [-].
    k : int
        0-based index of the first line to try [-].
    offset : int
        Lines of the program before ``lines[0]`` (when it comes in chunks) [-].
    scan : tuple, optional
        :func:`scan_chunk` of ``lines``; without it every line goes through
        :data:`PLAIN_MOVE` [-].

    Returns
    -------
    int
        0-based index of the first line not executed here, ``k`` if none was: that line
        goes to the tokeniser and the interpreter [-].
    """
    modes = (it.unit, it.absolute, it.exact_stop, it.tolerance)
    if scan is None:  # the expression looks for a length without a point itself
        k, it.pos, it.motion, it.feed = _run(
            lines, k, len(lines), offset + 1, it.segments.append,
            (it.pos, it.motion, it.feed), (*modes, NO_POINT not in it.warned))
        return k
    codes, run_end = scan.codes, scan.run_end
    # a run ends before the chunk's first length without a point, and the lines after it
    # are reached only once the interpreter has warned of it
    modes = (*modes, False)
    while k < len(lines):
        if codes[k, _WHOLE_LONG] and NO_POINT not in it.warned:
            break
        # a line of other words (a comment, a modal code) goes to the tokeniser without a
        # call to the compiled run; a short run of plain moves (between arcs) takes the
        # expression, whose cost is the blocks', not a call's and a run's set-up
        status = codes[k, 0]
        if status == _PLAIN and run_end[k] - k >= SHORT_RUN:
            j = _compiled_run(it, scan, k, offset + 1)
        elif status in (_PLAIN, _PLAIN_SLOW):
            j, it.pos, it.motion, it.feed = _run(
                lines, k, int(run_end[k]), offset + 1, it.segments.append,
                (it.pos, it.motion, it.feed), modes)
        elif status == _ARC:
            j = arc_run(it, scan, k, offset + 1)
        else:
            break
        if j == k:
            break
        k = j
    return k


def _compiled_run(it, scan, k: int, first: int) -> int:
    """The blocks from ``k`` on through :func:`tcpmm.path.gcode_scan.run_plain`, their
    segments appended (a :class:`~tcpmm.path.runs.LineRun` where the interpreter takes
    runs and they are all G1); the index of the first line left [-]."""
    state = np.array([*it.pos, -1.0 if it.motion is None else it.motion,
                      np.nan if it.feed is None else it.feed, it.unit,
                      1.0 if it.absolute else 0.0, MAX_FEED, MAX_COORDINATE_M])
    end = int(scan.run_end[k])  # its outputs sized for the run, not the rest of the chunk
    stop, ends, feeds, motions = ck.run_plain(scan.codes[k:end], scan.vals[k:end], 0, state)
    stop += k
    if stop == k:
        return k
    feeds = feeds.tolist()
    run = LineRun(it.pos, ends, feeds, it.exact_stop, k + first, it.tolerance)
    if it.takes_runs and motions.all():
        it.segments.append(run)
        it.pos = tuple(ends[-1].tolist())
    else:
        segs = run.lines()
        for i in np.flatnonzero(motions == 0).tolist():
            segs[i] = Rapid(segs[i].start_m, segs[i].end_m, k + first + i)
        it.segments += segs
        it.pos = segs[-1].end_m
    it.motion = int(motions[-1])
    it.feed = None if np.isnan(feeds[-1]) else feeds[-1]
    return stop


def _run(lines, k, n, first, append, state, modes):
    """The loop of :func:`plain_run` through :data:`PLAIN_MOVE` over ``lines[k:n]``: the
    index of the first line it leaves, and the position, motion mode and feed after the
    blocks it ran [-]."""
    # modal state in locals and one loop over a run of blocks: attribute look-ups and
    # a call per block cost as much as the block's arithmetic
    fullmatch = PLAIN_MOVE.fullmatch
    pos, motion, feed = state
    unit, absolute, exact, tol, points = modes
    new, (s_start, s_end, s_feed, s_exact, s_line, s_tol) = object.__new__, LINE_SETTERS
    while k < n:
        m = fullmatch(lines[k])
        if m is None:
            break
        g, x, y, z, f = m.groups()
        mo = motion if g is None else int(g)
        fe = feed
        if f is not None:
            fe = float(f)
            if not 0.0 < fe <= MAX_FEED:
                break
            fe = fe * unit / 60.0
        if (x is None and y is None and z is None) or mo is None or mo > 1 or (
                mo == 1 and fe is None) or (points and _no_point(x, y, z)):
            break
        # written out per axis: a helper with a loop took a third of the block's time
        px, py, pz = pos
        px = px if x is None else float(x) * unit if absolute else px + float(x) * unit
        py = py if y is None else float(y) * unit if absolute else py + float(y) * unit
        pz = pz if z is None else float(z) * unit if absolute else pz + float(z) * unit
        # only the axes the block names are checked against the range, as there
        if ((x is not None and not abs(px) <= MAX_COORDINATE_M)
                or (y is not None and not abs(py) <= MAX_COORDINATE_M)
                or (z is not None and not abs(pz) <= MAX_COORDINATE_M)):
            break
        target = (px, py, pz)
        if (abs(px - pos[0]) <= ZERO_MOVE_M and abs(py - pos[1]) <= ZERO_MOVE_M
                and abs(pz - pos[2]) <= ZERO_MOVE_M):  # warns: the interpreter's business
            break
        if mo == 0:
            append(Rapid(pos, target, k + first))
        else:
            seg = new(Line)  # as Line(pos, target, fe, exact, k + first, tol)
            s_start(seg, pos)
            s_end(seg, target)
            s_feed(seg, fe)
            s_exact(seg, exact)
            s_line(seg, k + first)
            s_tol(seg, tol)
            append(seg)
        pos, motion, feed = target, mo, fe
        k += 1
    return k, pos, motion, feed


def _no_point(*numbers) -> bool:
    """Whether a number of those given (``None`` for none) is written without a decimal
    point and reaches :data:`~tcpmm.path.gcode_words.WHOLE_LENGTH` [-]."""
    return any(v is not None and "." not in v and abs(float(v)) >= WHOLE_LENGTH
               for v in numbers)


@contextlib.contextmanager
def collector_paused():
    """Pause the cyclic garbage collector, if it runs, for the block of the ``with``.

    The segments hold no reference cycles, and the collector's passes over the growing
    list of them cost a sixth of the parse of a long program.
    """
    collecting = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if collecting:
            gc.enable()
