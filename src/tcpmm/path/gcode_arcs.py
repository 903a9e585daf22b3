"""The plain arcs of a chunk of lines (``G2``/``G3`` blocks of X, Y, Z, I, J, K, R and F
in that order, every number exact; :func:`tcpmm.path.gcode_scan.scan_lines` marks them),
executed without the tokeniser.

A CAM program that fits curves with arcs is almost all such blocks, and the tokeniser and
the interpreter take some 50 µs for each. :func:`arc_run` executes a run of them with the
interpreter's arithmetic in the interpreter's order (:meth:`tcpmm.path.gcode.Interpreter.move`
and :class:`tcpmm.path.gcode_geometry.GeometryMixin`), compiled
(:mod:`tcpmm.path.gcode_arcscan`) but for Python's ``math.hypot``, so the arcs are the
same to the bit; it stops at the first block on which the interpreter would fail, which
then goes to the tokeniser and the interpreter for its message, line and column.
"""

from __future__ import annotations

import math

import numpy as np

from .. import _compiled as ck
from .gcode_geometry import ARC_ABS_TOL_M, ARC_REL_TOL
from .gcode_words import MAX_COORDINATE_M, MAX_FEED
from .runs import ArcRun
from .segments import AXIS_INDEX, FULL_CIRCLE_TOL_M, PLANES

#: the status of a plain arc in the scanner's codes, and the bits of its words of an
#: arc's centre or radius, as :mod:`tcpmm.path.gcode_scan` has them (it imports numba,
#: which a command that parses from the compiled module never does)
ARC, ARC_WORDS = 3, 240
#: the column of I (the centre word of X) in the scanner's values, and of R
_I, _R = 4, 7
#: the interpreter's shortest chord of an arc given by R, and its tolerances of a radius
_TOLS = np.array([FULL_CIRCLE_TOL_M, ARC_ABS_TOL_M, ARC_REL_TOL])


def arc_run(it, scan, k: int, first: int) -> int:
    """Execute the plain arcs from line ``k`` on, as the interpreter would.

    Parameters
    ----------
    it : tcpmm.path.gcode.Interpreter
        The interpreter, which gets the arcs (an :class:`~tcpmm.path.runs.ArcRun` where
        it takes runs) and the position, motion mode and feed after them [-].
    scan : tuple
        :func:`tcpmm.path.gcode_fast.scan_chunk` of the chunk [-].
    k : int
        0-based index of the first line to try [-].
    first : int
        Program line number of the chunk's first line [-].

    Returns
    -------
    int
        0-based index of the first line not executed here, ``k`` if none was [-].
    """
    codes, vals, run_end = scan.codes, scan.vals, scan.run_end
    stop = int(run_end[k])  # the run of arcs from k: nothing past it is looked at
    a, b = PLANES[it.plane]
    ia, ib = AXIS_INDEX[a], AXIS_INDEX[b]
    # a centre word out of the plane: the interpreter's message
    other = ARC_WORDS & ~((1 << (_I + ia)) | (1 << (_I + ib)) | (1 << _R))
    state = np.array([*it.pos, -1.0 if it.motion is None else it.motion,
                      np.nan if it.feed is None else it.feed, it.unit, float(it.absolute),
                      float(it.arc_absolute), ia, ib, other, MAX_FEED, MAX_COORDINATE_M])
    codes, vals = codes[k:stop], vals[k:stop]
    n, ends, centres, motions, feeds, legs = ck.arc_ends(codes, vals, state)
    if not n:
        return k
    # the interpreter's lengths are Python's hypot, whose algorithm is CPython's own
    hyp = math.hypot
    lengths = np.array([list(map(hyp, legs[:, 0].tolist(), legs[:, 1].tolist())),
                        list(map(hyp, legs[:, 2].tolist(), legs[:, 3].tolist()))]).T.copy()
    n = ck.arc_centres(codes, vals, state, ends, centres, motions, lengths, _TOLS)
    if not n:
        return k
    run = ArcRun(it.pos, ends[:n], centres[:n], (a, b), motions[:n] == 3,
                 feeds[:n].tolist(), it.exact_stop, k + first)
    it.segments += [run] if it.takes_runs else run.arcs()
    it.pos, it.motion = tuple(ends[n - 1].tolist()), int(motions[n - 1])
    it.feed = run.feed_m_per_s[-1]
    return k + n
