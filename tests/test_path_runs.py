"""Runs of plain G1 blocks as arrays (tcpmm.path.runs): a run stands for its Lines, in
the path's arrays, in the corner blender and in the look-ahead's held tail."""

from __future__ import annotations

import numpy as np
import pytest

from tcpmm.path import InterpolatorSettings, parse_gcode
from tcpmm.path.blend import CornerBlender
from tcpmm.path.geometry import to_arrays
from tcpmm.path.runs import LineRun, as_lines, blocks, drop_blocks
from tcpmm.path.stream import StreamInterpolator

PROGRAM = "G21 G90 G1 X10 Y0 F3000\n" + "".join(
    f"X{10 * np.cos(0.3 * i):.4f} Y{10 * np.sin(0.3 * i):.4f}\n" for i in range(1, 40)) + \
    "G0 Z5\nG1 X1 Y1 F2000\nX2 Y1.5\nG2 X3 Y2.5 I1 J0\nG1 X4 Y2 F1000\nX5 Y3\nX6 Y2.25\n"


def _runs_of(segments):
    """The Lines of ``segments`` in runs of consecutive Lines where they are 2 or more [-]."""
    out, lines = [], []
    for s in [*segments, None]:
        if type(s).__name__ == "Line" and (not lines or lines[-1].end_m == s.start_m):
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
    segments = parse_gcode(PROGRAM)
    pieces = [segments[i:i + cut] for i in range(0, len(segments), cut)]
    out = {}
    for how in ("lines", "runs"):
        blender = CornerBlender(tol)
        ip = StreamInterpolator(InterpolatorSettings(blend_tolerance_m=tol))
        given, command = [], []
        for piece in pieces:
            piece = _runs_of(piece) if how == "runs" else piece
            given += as_lines(blender.push(piece))
            c = ip.push(piece)
            command += [] if c is None else [c.positions[a] for a in "XYZ"]
        given += as_lines(blender.push([], final=True))
        c = ip.push([], final=True)
        command += [c.positions[a] for a in "XYZ"]
        out[how] = (repr(given), [x.tobytes() for x in command], ip.most_held,
                    ip.segments_in, [blocks([s]) for s in blender.held])
    assert out["runs"] == out["lines"]
