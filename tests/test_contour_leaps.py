"""The contour error of passes side by side: an error beyond half their spacing is read to
the neighbouring pass, and the leap of the closest point that shows it is said."""

import numpy as np
import pytest

from tcpmm.analysis.contour import contour_error
from tcpmm.analysis.contour_passes import FOLD, leap_between
from tcpmm.analysis.contour_stream import stream_contour
from tcpmm.result import AxisRun, Run

#: passes of 2 mm, 50 um apart, at 50 mm/s sampled at 1 kHz
PASS_M, STEP_M, SPEED, DT = 2e-3, 50e-6, 0.05, 1e-3


def zigzag(passes: int = 12) -> np.ndarray:
    """The vertices of a zig-zag along X, stepping over in Y, sampled along its path [m]."""
    corners = []
    for k in range(passes):
        x0, x1 = (0.0, PASS_M) if k % 2 == 0 else (PASS_M, 0.0)
        corners += [(x0, k * STEP_M), (x1, k * STEP_M)]
    c = np.array(corners)
    s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(c, axis=0).T))])
    at = np.arange(0.0, s[-1], SPEED * DT)
    return np.column_stack([np.interp(at, s, c[:, 0]), np.interp(at, s, c[:, 1])])


def run_off_by(offset_m: float, passes: int = 12) -> Run:
    """The zig-zag commanded, the tool a constant ``offset_m`` off it in +Y [-]."""
    p = zigzag(passes)
    t = np.arange(p.shape[0]) * DT
    return Run(t, {"X": AxisRun(cmd=p[:, 0], tcp=p[:, 0]),
                   "Y": AxisRun(cmd=p[:, 1], tcp=p[:, 1] + offset_m)})


def test_a_tool_off_its_pass_by_more_than_half_the_step_over_is_said():
    """35 um off passes 50 um apart: every pass reads 15 um, to the next pass, with no
    word. The closest point leaps to the next stretch as each pass begins, and that is
    said with the error read there; 10 um off reads 10 um and leaps nowhere."""
    far = contour_error(run_off_by(35e-6), plane="XY")
    assert far.summary()["tcp"]["max_m"] == pytest.approx(15e-6)  # to the next pass
    got = far.leaps["tcp"]
    assert got["leaps"] >= 8
    assert got["max_abs_m"] == pytest.approx(15e-6, abs=1e-6)
    assert far.to_dict(corners=False)["closest_point_leaps"]["tcp"]["leaps"] == got["leaps"]
    near = contour_error(run_off_by(10e-6), plane="XY")
    assert near.leaps == {}


def test_a_path_run_back_over_itself_is_no_leap():
    """Out and back along one line (a circle's CCW then CW): the two stretches coincide,
    and the closest point moving from one to the other loses nothing."""
    x = np.r_[np.linspace(0.0, 0.01, 201), np.linspace(0.01, 0.0, 201)[1:]]
    t = np.arange(x.size) * DT
    lag = np.interp(t - 0.02, t, x)
    run = Run(t, {"X": AxisRun(cmd=x, tcp=lag), "Y": AxisRun(cmd=0 * x, tcp=0 * x + 3e-6)})
    assert contour_error(run, plane="XY").leaps == {}


def test_a_right_angle_corner_is_no_leap():
    """Crossing a corner's inside from one leg to the next moves the closest point along
    the path by 1.4 times the straight line between the two points, well under FOLD."""
    e = np.array([10e-6])
    at = np.zeros((1, 2))
    assert FOLD > 2.0 ** 0.5
    assert not leap_between((at, e, np.array([[-10e-6, 0.0]]), np.zeros(1), np.array([[1.0, 0.0]])),
                            (at, e, np.array([[0.0, 10e-6]]), np.array([20e-6]),
                             np.array([[0.0, 1.0]])))[0]


def test_the_leaps_of_a_run_read_in_chunks_are_the_whole_run_s(tmp_path):
    """Read 37 rows at a time, a chunk's first sample judged against the last one before,
    the run gives the whole run's leaps."""
    run = run_off_by(35e-6, passes=8)
    path = tmp_path / "run.parquet"
    run.write(path)
    whole = contour_error(run, plane="XY").leaps
    for rows in (37, 500):
        assert stream_contour(path, ("X", "Y"), True, rows=rows).leaps == whole


def test_the_command_line_warns_of_the_leaps_and_gives_them_in_json(tmp_path, capsys):
    from tcpmm.cli import main

    run_off_by(35e-6).write_csv(tmp_path / "run.csv")
    assert main(["contour", str(tmp_path / "run.csv"), "--plane", "XY"]) == 0
    err = capsys.readouterr().err
    assert "warning:" in err and "tcp: the closest command point leaps" in err
    assert "up to 15.00 µm" in err
    assert main(["contour", str(tmp_path / "run.csv"), "--plane", "XY", "--json"]) == 0
    import json

    got = json.loads(capsys.readouterr().out)["closest_point_leaps"]["tcp"]
    assert got["leaps"] >= 8 and got["max_abs_um"] == pytest.approx(15.0, abs=1.0)
