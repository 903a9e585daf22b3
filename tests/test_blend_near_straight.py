"""Corners under G64 P that hardly turn: two G1 lines straight but for the rounding of
their coordinates, and a straight line written as many blocks of 6 decimals. Blended on
radii of kilometres, the blend's sweep, worked out from its centre that far, made it some
80 µm longer than its ends are apart, and the command stepped back by that at its end:
7.5 µm in a period between periods of 83 µm, 62 m/s² on an axis of 1."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

from tcpmm.cli import main
from tcpmm.path.blend import blend_corners
from tcpmm.path.geometry import evaluate, to_arrays
from tcpmm.path.segments import Blend, Line

#: two lines that turn by 3.4e-8 rad (2e-6 deg): straight, but for 6-decimal rounding
TWO_LINES = ("G21 G90 G17\nG0 X18.22635 Y2.763278\nG64 P0.01\n"
             "G1 X15.768894 Y1.042549 F5000\nG1 X9.215678 Y-3.546062\nM30\n")
#: a straight line at 37 deg of 60 blocks of 2 mm, the points to 6 decimals
SIXTY_BLOCKS = "G21 G90 G17\nG0 X0 Y0\nG64 P0.01\nG1 F5000\n" + "".join(
    f"G1 X{2 * k * math.cos(math.radians(37)):.6f} Y{2 * k * math.sin(math.radians(37)):.6f}\n"
    for k in range(1, 61)) + "M30\n"
#: the programmed feed's step in one 1 ms period [mm]
FEED_STEP_MM = 5000.0 / 60.0 * 1e-3


def _command(tmp_path, text: str, *options: str) -> tuple:
    """The command of ``tcpmm path`` on ``text`` (table, CSV text) and what it said [-]."""
    prog, csv = tmp_path / "p.nc", tmp_path / f"c{len(options)}.csv"
    prog.write_text(text)
    assert main(["path", str(prog), "-o", str(csv), *options]) == 0
    return pd.read_csv(csv), csv.read_text()


@pytest.mark.parametrize("text", [TWO_LINES, SIXTY_BLOCKS], ids=["two_lines", "sixty_blocks"])
def test_a_straight_path_under_g64_p_steps_the_feed_every_period(tmp_path, capsys, text):
    """Between speeding up and slowing down the command steps the programmed feed's 83.3
    µm each period, no period shorter or longer (the blend's overshoot stepped 7.5 µm
    between them, and the 6-decimal line 90 µm and 81 µm), and no axis is said to go
    beyond its acceleration; in pieces of 7 blocks the command is the whole one's."""
    table, whole = _command(tmp_path, text)
    said = " ".join(capsys.readouterr().out.split())
    p = table[["x_mm", "y_mm"]].to_numpy()
    feed = (table["rapid"].to_numpy()[1:] == 0) & (table["rapid"].to_numpy()[:-1] == 0)
    step = np.linalg.norm(np.diff(p, axis=0), axis=1)[feed]
    assert step.max() <= FEED_STEP_MM * (1 + 1e-6)
    at = np.flatnonzero(step >= FEED_STEP_MM * (1 - 1e-6))
    cruise = step[at[0]:at[-1] + 1]  # between speeding up and slowing down
    assert np.abs(cruise - FEED_STEP_MM).max() <= 1e-6 * FEED_STEP_MM
    assert cruise.size > 40
    assert "beyond an axis's acceleration" not in said, said
    assert _command(tmp_path, text, "--chunk-blocks", "7")[1] == whole


@pytest.mark.parametrize("turn_rad", [3.4e-8, 9e-7])
def test_a_turn_below_bend_tol_stays_sharp(turn_rad):
    """A corner whose unit tangent turns by less than 1e-6 is a tangent join, as the
    look-ahead takes it: its blend would pass the corner by ``d turn / 4``, nothing."""
    a = Line((0.0, 0.0, 0.0), (0.003, 0.0, 0.0), 0.08, tolerance_m=1e-5)
    b = Line(a.end_m, (0.003 + 0.008 * math.cos(turn_rad), 0.008 * math.sin(turn_rad), 0.0),
             0.08)
    assert blend_corners([a, b]) == [a, b]


@pytest.mark.parametrize("length_m", [0.002, 0.02, 0.2])
@pytest.mark.parametrize("turn_rad", [2e-6, 1e-5])
def test_a_blend_of_a_radius_of_kilometres_ends_where_it_ends(length_m, turn_rad):
    """Two lines of 2 to 200 mm that turn by 2e-6 or 1e-5 rad blend on radii of up to
    100 km: the blend's length is its arc's and its last point its end, within 0.1 nm
    (the 200 mm lines' blend at 2e-6 rad missed its end by 6 µm)."""
    th = 0.3
    a = Line((0.01, 0.02, 0.0), (0.01 + length_m * math.cos(th),
                                 0.02 + length_m * math.sin(th), 0.0), 0.08, tolerance_m=1e-5)
    b = Line(a.end_m, (a.end_m[0] + length_m * math.cos(th + turn_rad),
                       a.end_m[1] + length_m * math.sin(th + turn_rad), 0.0), 0.08)
    segs = blend_corners([a, b])
    [k] = [i for i, s in enumerate(segs) if type(s) is Blend]
    p = to_arrays(segs, (1.0, 1.0, 1.0))
    assert p.length[k] == pytest.approx(segs[k].length_m, rel=1e-8)
    end = evaluate(p, np.array([k]), p.length[k:k + 1])[0]
    assert np.linalg.norm(end - np.array(segs[k].end_m)) <= 1e-10
