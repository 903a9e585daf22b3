"""Corners measured over chords that stray off the command (a feature shorter than the
corner span: a notch, a zig-zag's step-over, a small loop) are named, whole and streamed
alike; corners of a square, a G64 square, a spiral and a circle are not."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

from tcpmm.analysis.contour import contour_error
from tcpmm.analysis.contour_stream import stream_contour
from tcpmm.analysis.corners import path_length
from tcpmm.cli import main
from tcpmm.path.program import program_to_command
from tcpmm.sim.simulate import simulate

NOTCH = "G21 G90 G17\nG1 X10 F3000\nY-0.3\nX10.3\nY0\nX20\nG4 P0.5\nM30\n"
ZIGZAG = "\n".join(["G21 G90 G17 G64 P0.02", "G1 X0 Y0 F3000",
                    *[f"G1 X{30 * ((k + 1) // 2 % 2)} Y{0.5 * (k // 2)}" for k in range(1, 8)],
                    "G4 P0.5", "M30"]) + "\n"
LOOPS = "\n".join(["G21 G90 G17", "G1 X1 F2000",
                   *[f"G1 X{k}.0 Y0\nG2 X{k}.0 Y0 I0.25 J0" for k in range(1, 5)],
                   "G1 X6", "G4 P0.3", "M30"]) + "\n"
SQUARE = "G21 G90 G17\nG1 X20 F3000\nY20\nX0\nY0\nG4 P0.5\nM30\n"
SQUARE_G64 = "G21 G90 G17 G64 P0.05\nG1 X20 F3000\nY20\nX0\nY0\nG4 P0.5\nM30\n"
CIRCLE = "G21 G90 G17\nG0 X35 Y0\nG3 X35 Y0 I-35 J0 F2000\nG4 P0.5\nM30\n"


def spiral() -> str:
    a = np.linspace(0.0, 4 * np.pi, 120)[1:]
    r = 10.0 - 0.5 * a
    return "\n".join(["G21 G90 G17 G64 P0.01", "G0 X10 Y0", "G1 F3000",
                      *[f"X{x:.5f} Y{y:.5f}" for x, y in zip(r * np.cos(a), r * np.sin(a),
                                                           strict=True)],
                      "G4 P0.5", "M30"]) + "\n"


def run_of(vmc, program):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return simulate(vmc, program_to_command(program))


def contour(run, span_mm=0.5):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return contour_error(run, corner_span_m=span_mm * 1e-3)


def test_a_notch_shorter_than_the_span_is_named_and_a_shorter_span_clears_it(vmc):
    run = run_of(vmc, NOTCH)
    res = contour(run)
    near = [c["number"] for c in res.corners if np.hypot(*(np.array(c["point_m"]) - [0.01, 0]))
            < 0.2e-3]
    assert near and set(near) <= set(res.off_chord)  # the corner read 56 deg, 1 um
    stray, straight = res.off_chord[near[0]]
    assert stray > 0.5e-3 / 6 and 0.0 < straight < 0.5e-3
    fine = contour(run, 0.1)
    assert fine.off_chord == {}
    c = next(c for c in fine.corners if np.hypot(*(np.array(c["point_m"]) - [0.01, 0])) < 1e-6)
    assert abs(np.degrees(c["turn_rad"]) - 90.0) < 1.0
    assert abs(c["tcp"]["rounding_m"] - 43e-6) < 2e-6


def test_a_uturn_over_a_spans_step_over_is_named(vmc):
    res = contour(run_of(vmc, ZIGZAG))
    uturns = [c["number"] for c in res.corners if c["turn_rad"] > np.radians(170)]
    assert uturns and set(uturns) <= set(res.off_chord)
    assert contour(run_of(vmc, ZIGZAG), 0.2).off_chord == {}


def test_small_loops_are_named(vmc):
    assert contour(run_of(vmc, LOOPS)).off_chord


@pytest.mark.parametrize("program", [SQUARE, SQUARE_G64, CIRCLE, spiral()],
                         ids=["square", "square_g64", "circle", "spiral_g64"])
def test_corners_on_straight_chords_are_not_named(vmc, program):
    res = contour(run_of(vmc, program))
    assert res.off_chord == {}
    assert res.to_dict(corners=False)["corners_off_chord"] == []


@pytest.mark.parametrize("rows", [37, 400])
def test_corners_named_in_chunks_are_the_whole_runs(vmc, tmp_path, rows):
    path = tmp_path / "run.parquet"
    run_of(vmc, NOTCH + "").write(path)
    from tcpmm.io.runfile import read_run

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        whole = contour_error(read_run(path))
        got = stream_contour(path, ("X", "Y"), True, rows=rows)
    assert whole.off_chord and got.off_chord == whole.off_chord


def test_the_cli_names_them_and_json_has_them(vmc, tmp_path, capsys):
    path = tmp_path / "run.csv"
    run_of(vmc, NOTCH).write(path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["contour", str(path)]) == 0
        err = capsys.readouterr().err
        assert "strays from the chords over 0.5 mm" in err and "--corner-span-mm 0.1" in err
        assert main(["contour", str(path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert {r["corner"] for r in out["corners_off_chord"]} >= {1}
    assert all(r["stray_um"] > 500 / 6 for r in out["corners_off_chord"])


def test_the_stray_is_the_vertex_farthest_off_the_chord():
    from tcpmm._compiled import call

    # a step: 0.2 mm on from the corner, then 0.2 mm aside, then on; span 0.5 mm
    p = np.array([[-1.0, 0], [0, 0], [0.2, 0], [0.2, -0.2], [1.0, -0.2]]) * 1e-3
    s = path_length(p)
    got = call("chord_strays", p, s, np.array([1]), 0.5e-3, 1 / 6)[0]
    end = np.array([0.3, -0.2]) * 1e-3  # 0.5 mm along the path
    u = end / np.hypot(*end)
    want = max(abs(v[0] * u[1] - v[1] * u[0]) for v in p[2:4])
    assert got[0] == pytest.approx(want, rel=1e-12)
    assert 0.0 < got[1] < 0.5e-3


#: Counts numba's allocations of one call of the compiled ``chord_strays`` (numba's own
#: build of it, whose runtime counts them) on two corners of a zig-zag: U-turns of 0.2 mm
#: between passes of 2 mm, 200 vertices a pass, all within the corner span of 0.5 mm.
_ALLOCATIONS = """
import numpy as np
from numba.core.runtime import rtsys
from tcpmm.analysis.corners import path_length
from tcpmm.sim.cornerchords import chord_strays
x = np.r_[np.linspace(0, 2e-3, 200), np.full(5, 2e-3), np.linspace(2e-3, 0, 200)]
y = np.r_[np.zeros(200), np.linspace(0, 2e-4, 5), np.full(200, 2e-4)]
p = np.c_[x, y]
s, idx = path_length(p), np.array([200, 204])
chord_strays(p, s, idx, 0.5e-3, 1 / 6)
before = rtsys.get_allocation_stats().alloc
got = chord_strays(p, s, idx, 0.5e-3, 1 / 6)
print(rtsys.get_allocation_stats().alloc - before, int(np.isfinite(got[:, 1]).sum()))
"""


def test_a_corners_strays_allocate_nothing_a_vertex():
    """The strays of a zig-zag's corners made arrays for every vertex within the span
    (its offset from the chord, and for each vertex of the shorter side the chord's
    direction), each counted up and down: most of their time. A corner now takes a few
    arrays (its chords' ends and directions), whatever its vertices: two corners of 200
    vertices each side take 20 allocations at most (7 828 before, some ten a vertex),
    and both run straight on a side, which the count covers too."""
    import os
    import subprocess
    import sys

    out = subprocess.run([sys.executable, "-c", _ALLOCATIONS], capture_output=True,
                         text=True, check=True, env={**os.environ, "NUMBA_NRT_STATS": "1"})
    allocations, straight = (int(v) for v in out.stdout.split())
    assert straight == 2
    assert allocations <= 20
