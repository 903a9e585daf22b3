"""A tool lagging its command by more than the window in which each sample's closest
command point is sought: the window is widened where it is the default, and one the user
gave is refused. Measured within too short a window, a run's contour error was its
following error, with exit 0: a square on a 3/s position loop without feed-forward read
11.5 mm for 7.8 mm, a 1 ms window 220 um for 56 um."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

from tcpmm.analysis.contour import contour_error
from tcpmm.analysis.contour_lag import WIDEST_S, WINDOW_S, outside_closer
from tcpmm.analysis.contour_stream import stream_contour
from tcpmm.cli import main
from tcpmm.errors import InputError
from tcpmm.io.runfile import read_run
from tcpmm.result import AxisRun, Run

#: the samples' period [s]
DT = 1e-3


def delayed(delay_s: float, speed: float = 0.05) -> Run:
    """An L-shaped path at ``speed`` [m/s] with a rest at each end, the tool following
    the command ``delay_s`` late: every actual point lies on the commanded path, so the
    contour error is nil wherever each point is measured against the command it follows
    [-]."""
    t = np.arange(0.0, 2.5 + 2 * delay_s, DT)
    s = np.clip(speed * (t - 0.2), 0.0, 0.08)  # 40 mm along X, then 40 along Y
    x, y = np.minimum(s, 0.04), np.maximum(s - 0.04, 0.0)
    lag = np.maximum(t - delay_s, 0.0)
    xs, ys = np.interp(lag, t, x), np.interp(lag, t, y)
    return Run(t, {"X": AxisRun(cmd=x, motor=xs, scale=xs, tcp=xs),
                   "Y": AxisRun(cmd=y, motor=ys, scale=ys, tcp=ys)})


@pytest.mark.parametrize("delay_s", [0.05, 0.35, 1.5])
def test_a_delayed_tool_on_its_path_has_no_contour_error(delay_s):
    """Whatever the delay the default window is widened to, the tool lies on the path."""
    res = contour_error(delayed(delay_s), plane=("X", "Y"))
    assert res.window_s >= min(delay_s, WINDOW_S)
    assert res.window_s == (WINDOW_S if delay_s < WINDOW_S else res.window_s)
    for s in res.summary().values():
        assert s["max_abs_m"] < 1e-9


def test_a_window_given_shorter_than_the_lag_is_refused():
    """It said 10 mm, the distance the tool follows the window's first point by."""
    run = delayed(0.35)
    with pytest.raises(InputError, match=r"more than the window of 0\.2 s.*--window-s"):
        contour_error(run, plane=("X", "Y"), window_s=0.2)
    assert contour_error(run, plane=("X", "Y"), window_s=0.5).window_s == 0.5


def test_a_tool_that_does_not_follow_is_refused():
    with pytest.raises(InputError, match="do not follow the command"):
        contour_error(delayed(WIDEST_S * 1.2, speed=0.01), plane=("X", "Y"))


def wobbled(delay_s: float) -> Run:
    """:func:`delayed`, the tool's X off its path by up to 2 um [-]."""
    run = delayed(delay_s)
    run.axes["X"].tcp = run.axes["X"].tcp + 2e-6 * np.sin(np.arange(run.time_s.size) * 0.01)
    return run


def test_the_widened_window_measures_what_a_wide_one_does():
    """Widening changes the window, not what a window long enough measures: the errors
    are those of a window of 3 s to the bit, the corner included."""
    run = wobbled(0.35)
    auto, wide = contour_error(run, plane=("X", "Y")), contour_error(run, plane=("X", "Y"),
                                                                     window_s=3.0)
    assert auto.window_s == 0.4
    for s in auto.errors:
        np.testing.assert_array_equal(auto.errors[s], wide.errors[s])


def test_a_sample_on_the_window_edge_by_a_tie_is_not_cut():
    """Two segments meeting at the closest vertex give its distance to the rounding: no
    cut. The segment before is only a cut where it lies closer."""
    p = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    q = np.array([[1.0, 0.5], [0.5, 0.5]])  # closest at the vertex; before the window
    lo, hi = np.array([1, 1]), np.array([2, 2])
    dist = np.hypot(q[:, 0] - 1.0, q[:, 1])
    both = (np.ones(2, bool), np.ones(2, bool))
    assert outside_closer(q, p, lo, hi, both, dist, lo).tolist() == [False, True]
    # a window a feed move bounds on purpose is no cut
    kept = (np.zeros(2, bool), np.ones(2, bool))
    assert outside_closer(q, p, lo, hi, kept, dist, lo).tolist() == [False, False]


def test_streamed_and_whole_widen_alike(tmp_path):
    """In chunks as whole (the running RMS to the rounding of its sums)."""
    path = tmp_path / "lag.parquet"
    wobbled(0.35).write(path)
    whole = contour_error(read_run(path), plane=("X", "Y"))
    streamed = stream_contour(path, ("X", "Y"), True, rows=97)
    assert streamed.window_s == whole.window_s == 0.4
    assert whole.summary()["tcp"]["max_abs_m"] > 1e-6
    for s, want in whole.summary().items():
        got = streamed.summary()[s]
        assert got["max_abs_m"] == want["max_abs_m"]
        assert got["rms_m"] == pytest.approx(want["rms_m"], rel=1e-12)
    with pytest.raises(InputError, match=r"window of 0\.2 s .*the first at"):
        stream_contour(path, ("X", "Y"), True, 0.2, rows=97)


def test_a_slow_position_loop_is_measured_whole_and_said(tmp_path, capsys):
    """A square on the built-in machine with K_pp 3/s and no feed-forward lags by a third
    of a second: the contour is that of a window long enough, said on stderr and in
    --json; --window-s 0.2 is refused with exit 2 and no traceback."""
    model = tmp_path / "m.yaml"
    assert main(["machine", "export", "vmc", "-o", str(model)]) == 0
    text = re.sub(r"K_pp: [0-9.e+-]+", "K_pp: 3.0", model.read_text())
    model.write_text(re.sub(r"k_ff: [0-9.e+-]+", "k_ff: 0.0", text))
    nc = tmp_path / "sq.nc"
    nc.write_text("G90 G17 G21\nG1 X0 Y0 F5000\nX40\nY40\nX0\nY0\nG4 P2\nM30\n")
    run = tmp_path / "run.csv"
    assert main(["simulate", str(model), "--gcode", str(nc), "-o", str(run)]) == 0
    capsys.readouterr()
    got = {}
    for extra in ([], ["--window-s", "5"]):
        assert main(["contour", str(run), "--json", *extra]) == 0
        cap = capsys.readouterr()
        got[bool(extra)] = json.loads(cap.out)
        assert ("sought within 0.8 s" in cap.err) == (not extra)
    assert got[False]["window_s"] == 0.8
    assert got[False]["sensors"] == got[True]["sensors"]
    assert got[False]["sensors"]["tcp"]["max_abs_um"] < 8000  # 11 487 um within 0.2 s
    assert main(["contour", str(run), "--window-s", "0.2"]) == 2
    err = capsys.readouterr().err
    assert "lags its command by more than the window of 0.2 s" in err
    assert "Traceback" not in err


def zigzag_off_its_pass() -> Run:
    """Two 2 mm passes at 5 mm/s, 0.05 mm apart, the tool following the command in time
    but 0.03 mm off the first pass towards the second: the second pass comes back past
    each point of the first a little later, at 1.5 mm just after 0.2 s [-]."""
    t = np.arange(0.0, 1.0, DT)
    s = np.clip(0.005 * t, 0.0, 0.004)  # 2 mm out, 2 back
    x = np.where(s < 0.002, s, 0.004 - s)
    y = np.where(s < 0.002, 0.0, 50e-6)
    tool = y + np.where(s < 0.002, 30e-6, 0.0)
    return Run(t, {"X": AxisRun(cmd=x, motor=x, scale=x, tcp=x),
                   "Y": AxisRun(cmd=y, motor=tool, scale=tool, tcp=tool)})


def test_a_pass_coming_back_near_is_no_lag():
    """A CAM zig-zag's next pass, 20 um from a tool 30 um off its own, just after the
    window: `contour` said the tool lagged its command by more than 0.2 s (it lags by
    none) and refused --window-s 0.2 so. It widens the default as before, and says why."""
    run = zigzag_off_its_pass()
    assert contour_error(run, plane=("X", "Y")).window_s > WINDOW_S
    with pytest.raises(InputError, match="closer to the command just after the window") as e:
        contour_error(run, plane=("X", "Y"), window_s=0.2)
    assert "lags its command" not in str(e.value) and "comes back near" in str(e.value)
    with pytest.raises(InputError, match="lags its command by more than the window"):
        contour_error(delayed(0.35), plane=("X", "Y"), window_s=0.2)
