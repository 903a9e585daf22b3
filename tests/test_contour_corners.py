"""Corner figures of NC programs on the built-in machine, where the figures of one corner
must not depend on what the program does after it: the dwell that ends it, and the move
that follows the leg. The streamed contour gives each the whole run's to the bit."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from tcpmm.analysis.contour import contour_error
from tcpmm.io.runfile import read_run
from tcpmm.path.program import program_to_command
from tcpmm.sim.simulate import simulate

SENSORS = ("motor", "scale", "tcp")


def assert_same_corners(got, want):
    """Every figure of every corner equal to the bit, NaN to NaN."""
    assert len(got) == len(want)
    for g, w in zip(got, want, strict=True):
        for s in SENSORS:
            assert np.array_equal(list(g[s].values()), list(w[s].values()),
                                  equal_nan=True), (w["number"], s)


def corners_of(vmc, tmp_path, lines):
    """The corners of a program run on ``vmc`` (its run file), whole and streamed in
    chunks of 97 rows (which must agree to the bit)."""
    from tcpmm.analysis.contour_stream import stream_contour

    text = "\n".join(["G21 G17 G90", *lines, "M30"]) + "\n"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        path = tmp_path / f"run{len(list(tmp_path.iterdir()))}.parquet"
        simulate(vmc, program_to_command(text)).write(path)
        whole = contour_error(read_run(path))
        streamed = stream_contour(path, whole.axes, whole.signed, rows=97)
    assert_same_corners(streamed.corners, whole.corners)
    return whole.corners


def test_a_corner_and_the_end_do_not_depend_on_the_closing_dwell(vmc, tmp_path):
    """X30 then Y30 at F3000 and a dwell of 0.5 s or 2 s: the motion up to the end point is
    the same, and so must be the corner's figures (its samples end halfway along the
    15 mm leg; a boundary taken halfway to the end of the dwell gave the corner the stop
    at the end point: tcp 213 ms and 1310 ms / 30 mm), and the end's settling counted
    from the command's arrival (scale 98 ms, and 675 ms with the 2 s dwell)."""
    got = {d: corners_of(vmc, tmp_path, ["G0 X0 Y0", "G1 X30 F3000", "Y30", f"G4 P{d}"])
           for d in (0.5, 2.0)}
    short, long = got[0.5], got[2.0]
    assert len(short) == len(long) == 2 and np.isnan(long[1]["turn_rad"])
    for s in SENSORS:
        assert short[0][s] == long[0][s], s
        assert not long[0][s]["settle_m"] > 0.015  # settled within its half of the leg
    for s in ("motor", "scale"):
        assert long[1][s]["settle_s"] == pytest.approx(short[1][s]["settle_s"], abs=2e-3)
        assert long[1][s]["settle_s"] < 0.15


def test_a_dwell_on_the_next_corner_is_no_part_of_a_corners_stretch(vmc, tmp_path):
    """The same corner with a dwell of 1 s on the next one or none: its figures are the
    same (halfway to the command's leaving the next corner, the stretch took in the stop
    there)."""
    got = [corners_of(vmc, tmp_path, ["G0 X0 Y0", "G1 X30 F3000", "Y30", *dwell, "X0",
                                      "G4 P0.5"]) for dwell in ([], ["G4 P1"])]
    assert len(got[0]) == len(got[1]) == 3
    for s in SENSORS:
        assert got[0][0][s] == got[1][0][s], s
