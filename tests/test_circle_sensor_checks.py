"""A circle's sensors are checked against their command before any figure is taken: a
sensor whose axis is negated or whose axes are swapped is refused, and a run whose
positions are in another unit than its columns say is warned of."""

import warnings

import numpy as np
import pytest

from tcpmm.analysis.circular import analyse_circle
from tcpmm.cli import main
from tcpmm.errors import InputError
from tcpmm.io.runfile import write_run
from tcpmm.result import AxisRun, Run

R = 0.035
DT = 1e-3


def circle(direction="ccw", lag_deg=0.0, turns=1.25, start_deg=45.0, scale=1.0):
    """The command of ``turns`` at 5000 mm/min from ``start_deg`` and a TCP lagging it by
    ``lag_deg``, radii and positions times ``scale`` (a file in another unit) [-]."""
    s = 1.0 if direction == "ccw" else -1.0
    w = (5000 / 60e3) / R
    t = np.arange(0.0, turns * 2 * np.pi / w, DT)
    th = np.radians(start_deg) + s * w * t
    tcp = th - s * np.radians(lag_deg)
    cmd = R * np.c_[np.cos(th), np.sin(th)] * scale
    # the TCP a little inside, as a servo leaves it, with a bump after each quadrant point
    r_tcp = R - 2e-6 + 1e-6 * np.cos(4 * tcp)
    tool = r_tcp[:, None] * np.c_[np.cos(tcp), np.sin(tcp)] * scale
    return t, cmd, tool


def run_of(t, cmd, tcp):
    return Run(t, {"X": AxisRun(cmd=cmd[:, 0], tcp=tcp[:, 0]),
                   "Y": AxisRun(cmd=cmd[:, 1], tcp=tcp[:, 1])})


@pytest.mark.parametrize("direction", ["ccw", "cw"])
@pytest.mark.parametrize("how, says", [
    (lambda p: p * [1.0, -1.0], "turns"),
    (lambda p: p * [-1.0, 1.0], "turns"),
    (lambda p: p[:, ::-1], "turns"),
    (lambda p: -p, "lies"),
])
def test_a_sensor_with_an_axis_negated_or_swapped_is_refused(direction, how, says):
    """Mirrored, the TCP's circle turns against its command; turned half a turn, it lies a
    diameter away: its spikes would be compared with the command's as if they were the
    machine's (a negated Y read spike differences of -56 um on bench C)."""
    t, cmd, tcp = circle(direction)
    with pytest.raises(InputError, match=f"the tcp circle {says}.*opposite sign.*swapped"):
        analyse_circle(run_of(t, cmd, how(tcp)), R)


@pytest.mark.parametrize("direction", ["ccw", "cw"])
@pytest.mark.parametrize("stuck", [[0, 1], [1], [0]], ids=["both", "Y", "X"])
@pytest.mark.parametrize("value", [0.0, 0.012])
def test_a_sensor_column_that_stands_still_is_refused_naming_it(direction, stuck, value):
    """A recorder channel left unconnected writes zeros (or a constant): one circle alone
    reached a failed least-squares fit as an internal error (both TCP axes) or gave a G of
    37 mm with a note that the circle runs the wrong way (Y alone)."""
    t, cmd, tcp = circle(direction)
    tcp[:, stuck] = value
    column = "[xy]" if len(stuck) == 2 else "xy"[stuck[0]]
    with pytest.raises(InputError, match=f"the tcp signal's .* travels 0 mm where the cmd's "
                       f"travels 70 mm: its column {column}_tcp_mm is empty"):
        analyse_circle(run_of(t, cmd, tcp), R)


@pytest.mark.parametrize("direction", ["ccw", "cw"])
@pytest.mark.parametrize("lag_deg", [0.0, 20.0, 50.0])
def test_a_tcp_that_lags_its_command_is_analysed(direction, lag_deg):
    """A slow position loop lags by many degrees (50 deg: a chord of 0.85 R); the TCP is
    still the same circle, turning the same way."""
    t, cmd, tcp = circle(direction, lag_deg)
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        res = analyse_circle(run_of(t, cmd, tcp), R)
    assert not [w for w in got if "circular test" in str(w.message)]
    assert res.passes[0].sensors["tcp"].contour_error == pytest.approx(3e-6, abs=0.1e-6)


def test_compare_refuses_a_measurement_whose_tcp_is_mirrored(tmp_path, capsys):
    t, cmd, tcp = circle()
    write_run(run_of(t, cmd, tcp), tmp_path / "pred.csv")
    write_run(run_of(t, cmd, tcp * [1.0, -1.0]), tmp_path / "meas.csv")
    rc = main(["compare", str(tmp_path / "meas.csv"), str(tmp_path / "pred.csv"),
               "--radius", "35"])
    err = capsys.readouterr().err
    assert rc == 2 and "tcp circle turns clockwise" in err and "y_tcp_mm" in err


@pytest.mark.parametrize("scale, radius_mm, warned", [
    (1.0, 35.0, False),
    (1e3, 35e3, True),    # micrometres under *_mm, the radius in micrometres too
    (1e-3, 0.035, True),  # metres
    (1e2, 3500.0, True),  # a 3.5 m circle at 8333 m/min: no machine runs it
    (1 / 70, 0.5, False),  # a small bore's circle of 0.5 mm, in millimetres
])
def test_a_circle_in_another_unit_is_warned_of(scale, radius_mm, warned):
    """Positions logged in micrometres or metres under the ``*_mm`` columns, with the
    radius in the same unit, read as a circle of 35 m or 35 um: every figure is off by a
    factor of 1000, and is said to be."""
    t, cmd, tcp = circle(scale=scale)
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        analyse_circle(run_of(t, cmd, tcp), radius_mm * 1e-3)
    said = [str(w.message) for w in got if "machine tool's circular test" in str(w.message)]
    assert bool(said) == warned
    if warned:
        assert "off by a factor of 1000" in said[0]


@pytest.mark.parametrize("column, factor, said", [
    ("x_tcp_mm", 1e3, "holds µm, not mm; divide it by 1000"),
    ("x_tcp_mm", 1e-3, "holds m, not mm; multiply it by 1000"),
    ("x_scale_mm", 1 / 25.4, "holds inches, not mm; multiply it by 25.4"),
    (None, 1e3, r"the run holds µm, not mm; divide every \*_mm column by 1000")])
def test_a_column_in_another_unit_is_named_with_it(tmp_path, column, factor, said):
    """Bench C's circle with a sensor's column, or every column in mm, in µm, m or inches
    under its name in mm: refused as the opposite sign or swapped axes (µm), a column
    stuck (m, inches), no circle found (every column), which sent the user to the wrong
    fix. The unit is named with the factor to write it in mm."""
    import pandas as pd

    from conftest import bench_path
    from tcpmm.io.runfile import read_run

    a = pd.read_csv(bench_path("c") / "circle_ccw_meas.csv")
    for c in [column] if column else [c for c in a.columns if c.endswith("_mm")]:
        a[c] *= factor
    a.to_csv(tmp_path / "u.csv", index=False)
    with pytest.raises(InputError, match=said), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        analyse_circle(read_run(tmp_path / "u.csv"), 0.035)


@pytest.mark.parametrize("radius_mm, said", [
    (35000.0, r"--radius 35000 mm is 1000 times that: give --radius in mm \(35\)"),
    (0.035, r"--radius 0.035 mm is 0.001 times that: give --radius in mm \(35\)")])
def test_a_radius_in_another_unit_is_named_as_the_radius(radius_mm, said):
    """A run in mm of a 35 mm circle, with the radius given in µm (35000) or in m
    (0.035): the error said the run held m or µm and told the user to multiply or divide
    every *_mm column by 1000, which would spoil a good file. Where the run's circle is
    one a machine tool runs and the radius given is not, the radius is named."""
    t, cmd, tcp = circle()
    with pytest.raises(InputError, match=said) as got, warnings.catch_warnings():
        warnings.simplefilter("ignore")
        analyse_circle(run_of(t, cmd, tcp), radius_mm * 1e-3)
    assert "_mm column" not in str(got.value)
