"""The plain arcs of a chunk of lines (``G2``/``G3`` blocks of X, Y, Z, I, J, K, R and F
in that order, every number exact; :func:`tcpmm.path.gcode_scan.scan_lines` marks them),
executed without the tokeniser.

A CAM program that fits curves with arcs is almost all such blocks, and the tokeniser and
the interpreter take some 50 µs for each. :func:`arc_run` executes a run of them with the
interpreter's arithmetic in the interpreter's order (:meth:`tcpmm.path.gcode.Interpreter.move`
and :class:`tcpmm.path.gcode_geometry.GeometryMixin`), so the arcs are the same to the bit;
it stops at the first block on which the interpreter would fail, which then goes to the
tokeniser and the interpreter for its message, line and column.
"""

from __future__ import annotations

import math

from .gcode_geometry import ARC_ABS_TOL_M, ARC_REL_TOL
from .gcode_words import MAX_COORDINATE_M, MAX_FEED
from .runs import slot_setters
from .segments import AXIS_INDEX, FULL_CIRCLE_TOL_M, PLANES, Arc

#: the status of a plain arc in the scanner's codes, and the bits of its words of an
#: arc's centre or radius, as :mod:`tcpmm.path.gcode_scan` has them (it imports numba,
#: which a command that parses from the compiled module never does)
ARC, ARC_WORDS = 3, 240
#: the columns of the scanner's values and their bits in its words: F, then I, J, K
#: (the centre word of X, Y, Z) and R
_F, _I, _R = 3, 4, 7
#: the slot setters of Arc's fields in order (:func:`tcpmm.path.runs.slot_setters`)
_SETTERS = slot_setters(Arc)


def arc_run(it, scan, k: int, first: int) -> int:
    """Execute the plain arcs from line ``k`` on, as the interpreter would.

    Parameters
    ----------
    it : tcpmm.path.gcode.Interpreter
        The interpreter, which gets the arcs and the position, motion mode and feed after
        them [-].
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
    codes, vals, run_end = scan
    stop = int(run_end[k])  # the run of arcs from k: nothing past it is looked at
    a, b = PLANES[it.plane]
    ia, ib = AXIS_INDEX[a], AXIS_INDEX[b]
    # a centre word out of the plane: the interpreter's message
    other = ARC_WORDS & ~((1 << (_I + ia)) | (1 << (_I + ib)) | (1 << _R))
    pos, motion, feed = it.pos, it.motion, it.feed
    arcs = []
    for (g, w), v in zip(codes[k:stop, 1:].tolist(), vals[k:stop].tolist(), strict=True):
        fe = feed
        if w & (1 << _F):
            if not 0.0 < v[_F] <= MAX_FEED:
                break
            fe = v[_F] * it.unit / 60.0
        mo = motion if g < 0 else g
        # G0/G1 with a centre word, no motion mode or feed yet: the interpreter's messages
        if mo is None or mo < 2 or fe is None or w & other:
            break
        end = _target(it, pos, w, v)
        centre = None if end is None else _centre(it, pos, end, mo, w, v, (ia, ib))
        if centre is None:
            break
        arcs.append((pos, end, centre, "ccw" if mo == 3 else "cw", fe))
        pos, motion, feed = end, mo, fe
    it.segments += _arcs(arcs, (a, b), it.exact_stop, k + first)
    it.pos, it.motion, it.feed = pos, motion, feed
    return k + len(arcs)


def _arcs(rows: list, plane: tuple, exact_stop: bool, line: int) -> list:
    """An :class:`~tcpmm.path.segments.Arc` of each row (start, end, centre, direction,
    feed), the first of line ``line``, the others on the lines after it [-]."""
    out = []
    new = object.__new__
    for (start, end, centre, direction, fe), n in zip(rows, range(line, line + len(rows)),
                                                      strict=True):
        arc = new(Arc)
        for setter, value in zip(_SETTERS, (start, end, centre, plane, direction, fe, 0,
                                            exact_stop, n), strict=True):
            setter(arc, value)
        out.append(arc)
    return out


def _target(it, pos, w: int, v: list):
    """The block's end point, ``None`` where a coordinate or a centre word or radius is
    beyond :data:`~tcpmm.path.gcode_words.MAX_COORDINATE_M` [m]."""
    unit, absolute = it.unit, it.absolute
    end = list(pos)
    for i in range(3):
        if w & (1 << i):
            x = v[i] * unit
            end[i] = x if absolute else end[i] + x
            if not abs(end[i]) <= MAX_COORDINATE_M:
                return None
    for j in range(_I, _R + 1):
        if w & (1 << j) and not abs(v[j] * unit) <= MAX_COORDINATE_M:
            return None
    return tuple(end)


def _centre(it, s, end, mo: int, w: int, v: list, plane):
    """The arc's centre (X, Y, Z), as the interpreter finds it from R or from the centre
    words; ``None`` where the interpreter would refuse the arc [m]."""
    ia, ib = plane
    has_a, has_b = w & (1 << (_I + ia)), w & (1 << (_I + ib))
    if bool(has_a or has_b) == bool(w & (1 << _R)):  # both, or neither
        return None
    unit = it.unit
    if w & (1 << _R):
        da, db = end[ia] - s[ia], end[ib] - s[ib]
        chord = math.hypot(da, db)
        r = v[_R] * unit
        if chord < FULL_CIRCLE_TOL_M or r == 0.0:
            return None
        half = 0.5 * chord
        h2 = r * r - half * half
        if h2 < 0.0:
            if half - abs(r) > max(ARC_ABS_TOL_M, ARC_REL_TOL * abs(r)):
                return None
            h2 = 0.0
        h = math.sqrt(h2)
        side = (1.0 if mo == 3 else -1.0) * (1.0 if r > 0 else -1.0)
        ca, cb = s[ia] + 0.5 * da - side * h * db / chord, s[ib] + 0.5 * db + side * h * da / chord
    elif it.arc_absolute:
        if not (has_a and has_b):
            return None
        ca, cb = v[_I + ia] * unit, v[_I + ib] * unit
    else:
        ca = s[ia] + (v[_I + ia] * unit if has_a else 0.0)
        cb = s[ib] + (v[_I + ib] * unit if has_b else 0.0)
    if not w & (1 << _R):
        r0 = math.hypot(s[ia] - ca, s[ib] - cb)
        r1 = math.hypot(end[ia] - ca, end[ib] - cb)
        if r0 == 0.0 or r1 == 0.0 or abs(r1 - r0) > max(ARC_ABS_TOL_M, ARC_REL_TOL * r0):
            return None
    centre = [0.0, 0.0, 0.0]
    centre[ia], centre[ib] = ca, cb
    centre[3 - ia - ib] = s[3 - ia - ib]
    return tuple(centre)
