"""Runs of plain G1 blocks as arrays (tcpmm.path.runs): a run stands for its Lines, in
the path's arrays, in the corner blender and in the look-ahead's held tail."""

from __future__ import annotations

import numpy as np
import pytest

from tcpmm.path import InterpolatorSettings, parse_gcode
from tcpmm.path.blend import CornerBlender, blend_corners, blended_path
from tcpmm.path.geometry import _segment_columns, to_arrays
from tcpmm.path.runs import LineRun, as_lines, blocks, drop_blocks, path_columns
from tcpmm.path.stream import StreamInterpolator

PROGRAM = "G21 G90 G1 X10 Y0 F3000\n" + "".join(
    f"X{10 * np.cos(0.3 * i):.4f} Y{10 * np.sin(0.3 * i):.4f}\n" for i in range(1, 40)) + \
    "G0 Z5\nG1 X1 Y1 F2000\nX2 Y1.5\nG2 X3 Y2.5 I1 J0\nG1 X4 Y2 F1000\nX5 Y3\nX6 Y2.25\n"


def _runs_of(segments):
    """The Lines of ``segments`` in runs of consecutive Lines where they are 2 or more
    (of one exact stop and tolerance, as the interpreter makes them) [-]."""
    out, lines = [], []
    for s in [*segments, None]:
        if type(s).__name__ == "Line" and (not lines or (
                lines[-1].end_m == s.start_m and lines[-1].exact_stop == s.exact_stop
                and lines[-1].tolerance_m == s.tolerance_m)):
            lines.append(s)
            continue
        if len(lines) > 1:
            a = lines[0]
            out.append(LineRun(a.start_m, np.array([x.end_m for x in lines]),
                               [x.feed_m_per_s for x in lines], a.exact_stop, a.line,
                               a.tolerance_m))
        else:
            out += lines
        lines = [] if s is None or type(s).__name__ != "Line" else [s]
        if s is not None and not lines:
            out.append(s)
    return out


def test_a_run_is_its_lines():
    segments = parse_gcode(PROGRAM)
    runs = _runs_of(segments)
    assert any(type(s) is LineRun for s in runs) and blocks(runs) == len(segments)
    assert repr(as_lines(runs)) == repr(segments)
    for k in range(len(segments) + 1):
        assert repr(as_lines(drop_blocks(runs, k))) == repr(segments[k:])
    a, b = to_arrays(segments, (1.0, 1.0, 1.0)), to_arrays(runs, (1.0, 1.0, 1.0))
    for name in a.__dataclass_fields__:
        x, y = getattr(a, name), getattr(b, name)
        assert (x is None and y is None) or np.array_equal(x, y), name


@pytest.mark.parametrize("tol", [0.0, 1e-5])
@pytest.mark.parametrize("cut", [1, 3, 7, 50])
def test_the_blender_and_the_look_ahead_take_runs_as_their_lines(tol, cut):
    """The blended path a piece at a time, of Lines or of runs, has the columns of the
    whole path's blended at once, to the bit; so has the command."""
    segments = parse_gcode(PROGRAM)
    pieces = [segments[i:i + cut] for i in range(0, len(segments), cut)]
    out = {how: _blended_and_planned([_runs_of(p) if how == "runs" else p for p in pieces],
                                     tol) for how in ("lines", "runs")}
    assert out["runs"] == out["lines"]
    assert out["lines"][0] == _column_bytes(blend_corners(segments, tol))


def _blended_and_planned(pieces, tol) -> tuple:
    """The blender's columns and the look-ahead's command of ``pieces`` given one after
    the other, as bytes, the most blocks the look-ahead held, the blocks it took and
    those the blender holds at the end [-]."""
    blender = CornerBlender(tol)
    ip = StreamInterpolator(InterpolatorSettings(blend_tolerance_m=tol))
    given, command = [], []
    for piece in pieces:
        given += blender.push(piece)
        c = ip.push(piece)
        command += [] if c is None else [c.positions[a] for a in "XYZ"]
    given += blender.push([], final=True)
    c = ip.push([], final=True)
    command += [c.positions[a] for a in "XYZ"]
    return (_column_bytes(given), [x.tobytes() for x in command], ip.most_held,
            ip.segments_in, [blocks([s]) for s in blender.held])


def _column_bytes(segments) -> list:
    """The look-ahead's columns of ``segments``, as bytes [-]."""
    return [c.tobytes() for c in path_columns(segments, _segment_columns)]


@pytest.mark.parametrize(("seed", "default_tol"), [(0, 2e-6), (1, 2e-6), (2, 0.0),
                                                   (3, 0.0)])
def test_a_blended_path_in_pieces_is_the_whole_ones(seed, default_tol):
    """Random straight blocks (turns of every size, collinear stretches, reversals, exact
    stops, tolerances of a block's own, none or 0) with dwells, rapids and arcs between,
    in runs and in pieces of random size: the blender's columns are those of the whole
    path blended at once, to the bit."""
    from tcpmm.path.segments import Arc, Dwell, Line, Rapid

    rng = np.random.default_rng(seed)
    p, segs = np.zeros(3), []
    for i in range(600):
        other = rng.random()
        if other < 0.06:
            if other < 0.02:
                segs.append(Dwell(tuple(p), 0.01, line=i + 1))
                continue
            q = p + rng.normal(size=3) * 1e-3
            c = p + np.array([*rng.normal(size=2) * 1e-3, 0.0])
            a = rng.uniform(0.2, 2.0)
            r = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
            q[:2] = c[:2] + r @ (p[:2] - c[:2])
            segs.append(Rapid(tuple(p), tuple(q), line=i + 1) if other < 0.04 else
                        Arc(tuple(p), tuple(q), tuple(c), ("X", "Y"), "ccw", 0.05,
                            line=i + 1))
            p = q
            continue
        step = rng.normal(size=3) if rng.random() < 0.4 or not segs else np.subtract(
            segs[-1].end_m, segs[-1].start_m) * (1 if rng.random() < 0.8 else -1) \
            if type(segs[-1]) in (Line, Rapid) else rng.normal(size=3)
        q = p + step / np.linalg.norm(step) * 10.0 ** rng.uniform(-5, -2)
        # without a default, stretches of blocks without a tolerance of their own leave
        # whole pieces unblended
        tol = [None, 0.0, 1e-5, 10.0 ** rng.uniform(-7, -3)][rng.integers(4)] if (
            default_tol or i % 200 < 100) else None
        segs.append(Line(tuple(p), tuple(q), 0.05 + 0.01 * rng.integers(3),
                         exact_stop=bool(rng.random() < 0.03), line=i + 1, tolerance_m=tol))
        p = q
    blender, given, i = CornerBlender(default_tol), [], 0
    while i < len(segs):
        k = int(rng.integers(1, 80))
        given += blender.push(_runs_of(segs[i:i + k]))
        i += k
    given += blender.push([], final=True)
    whole = _column_bytes(blend_corners(segs, default_tol))
    assert _column_bytes(given) == whole
    assert sum(type(s).__name__ == "ColumnRun" for s in given) > 1
    assert _column_bytes(blended_path(_runs_of(segs), default_tol)) == whole


#: arcs one after the other (G2 and G3, by I and J and by R), lines between them
ARCS = "G21 G90 G17 G1 X10 Y0 F3000\n" + "".join(
    f"G3 X{10 * np.cos(0.2 * i):.4f} Y{10 * np.sin(0.2 * i):.4f} "
    f"I{-10 * np.cos(0.2 * (i - 1)):.4f} J{-10 * np.sin(0.2 * (i - 1)):.4f}\n"
    for i in range(1, 25)) + "G1 X11 Y-2\nX12 Y-2.5\n" + "".join(
    f"G2 X{12 + 0.5 * i:.4f} Y{-2.5 + 0.25 * (i % 2):.4f} R{1.5 if i % 3 else -1.5}\n"
    for i in range(1, 30)) + "G1 X30 Y0\nG3 X30 Y0 I-2 J0 F2000\n"


@pytest.mark.parametrize("tol", [0.0, 1e-5])
@pytest.mark.parametrize("cut", [1, 4, 9, 200])
def test_the_blender_and_the_look_ahead_take_runs_of_arcs_as_their_arcs(tol, cut):
    """A program of runs of arcs and lines read in chunks: the blender's columns and the
    command are those of its segments one by one, to the bit, and so is the most the
    look-ahead held."""
    from tcpmm.io.text import file_lines
    from tcpmm.path import gcode_stream
    from tcpmm.path.runs import ArcRun

    lines = file_lines(ARCS)
    pieces = []
    for it in gcode_stream.interpret_chunks([lines[i:i + cut] for i in range(0, len(lines), cut)],
                                            "p.nc", (0.0, 0.0, 0.0), runs=True):
        pieces.append(it.segments)
        it.segments = []
    kinds = {type(s) for p in pieces for s in p}
    out = {"runs": _blended_and_planned(pieces, tol),
           "segments": _blended_and_planned([as_lines(p) for p in pieces], tol)}
    assert ArcRun in kinds
    assert out["runs"] == out["segments"]
    assert out["segments"][0] == _column_bytes(blend_corners(parse_gcode(ARCS), tol))
