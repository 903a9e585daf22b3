"""The circle a command holds, found from the command alone: circular tests in any plane,
about any centre, fed in or not, filtered; and programs that are no circular test."""

from __future__ import annotations

import json

import numpy as np
import pytest

from tcpmm.analysis.circle_find import command_circle
from tcpmm.cli import main
from tcpmm.path import Command, circle_command, write_command_csv


@pytest.mark.parametrize("radius_mm, centre_mm, direction, start_deg, plane, feed_in", [
    (35.0, (0.0, 0.0), "ccw", 0.0, ("X", "Y"), True),
    (30.0, (12.0, -3.0), "cw", 0.0, ("X", "Y"), True),
    (10.0, (-250.0, 400.0), "ccw", 45.0, ("Z", "X"), False),
    (120.0, (5.5, 7.25), "cw", 200.0, ("Y", "Z"), True),
])
def test_a_circular_test_is_found_about_its_centre(radius_mm, centre_mm, direction,
                                                   start_deg, plane, feed_in):
    """Exact commands, with a feed-in semicircle and a feed-out or starting on the circle
    at rest: the circle to two of its 0.1 um steps."""
    cmd = circle_command(radius_mm * 1e-3, 4000 / 60e3, tuple(c * 1e-3 for c in centre_mm),
                         direction, np.radians(start_deg), plane_axes=plane, feed_in=feed_in)
    radius, centre = command_circle(cmd.positions, plane)
    assert radius == pytest.approx(radius_mm * 1e-3, abs=2e-7)
    assert centre == pytest.approx(tuple(c * 1e-3 for c in centre_mm), abs=2e-7)


def test_a_filtered_circle_is_found_inside_its_nominal_radius():
    """A 40 ms moving average after interpolation, as a controller's ACC/DEC filter, pulls
    a R 35 mm circle at F10000 in by tens of micrometres: the circle run is found, its
    centre where the program put it."""
    cmd = circle_command(0.035, 10000 / 60e3, smoothing_time_s=0.04)
    radius, centre = command_circle(cmd.positions, ("X", "Y"))
    assert 0.035 - 100e-6 < radius < 0.035 - 10e-6
    assert centre == pytest.approx((0.0, 0.0), abs=1e-6)


def _polyline(points_mm, period_s=1e-3, speed_m_per_s=0.05) -> Command:
    """A command along straight lines through ``points_mm`` at constant speed [m]."""
    p = np.asarray(points_mm, float) * 1e-3
    s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(p, axis=0).T))])
    t = np.arange(0.0, s[-1] / speed_m_per_s, period_s)
    at = t * speed_m_per_s
    return Command(t, {"X": np.interp(at, s, p[:, 0]), "Y": np.interp(at, s, p[:, 1])})


def _arc_points(centre, radius, start_deg, span_deg, n=720):
    a = np.radians(start_deg + np.linspace(0.0, span_deg, n))
    return np.column_stack([centre[0] + radius * np.cos(a), centre[1] + radius * np.sin(a)])


@pytest.mark.parametrize("name, points", [
    ("square", [(0, 0), (40, 0), (40, 40), (0, 40), (0, 0)]),
    ("line", [(0, 0), (100, 20)]),
    ("half circle", _arc_points((0, 0), 35, 0, 180)),
    ("spiral", np.column_stack([(5 + 5 * np.linspace(0, 3, 3000)) * np.cos(
        np.linspace(0, 6 * np.pi, 3000)), (5 + 5 * np.linspace(0, 3, 3000)) * np.sin(
        np.linspace(0, 6 * np.pi, 3000))])),
    ("small circle in a long program", np.vstack([[(0, 0), (300, 0), (300, 300)],
                                                  _arc_points((300, 305), 5, -90, 360)])),
])
def test_what_is_no_circular_test_has_no_circle(name, points):
    assert command_circle(_polyline(points).positions, ("X", "Y")) is None, name


def test_a_command_that_stands_still_has_no_circle():
    t = np.arange(100) * 1e-3
    assert command_circle({"X": np.zeros(100), "Y": np.ones(100)}, ("X", "Y")) is None
    assert command_circle(Command(t, {"X": t * 0.0, "Y": t * 0.0}).positions,
                          ("X", "Y")) is None


def test_compensate_judges_the_spikes_of_a_circle_given_without_its_radius(tmp_path, capsys):
    """``tcpmm compensate MODEL --command CMD.csv``, as the circle's command is given with
    no ``--radius``: the circle is taken from the command and said, and its spikes and G
    are judged and reported as with ``--radius``. A square's command is judged as a path."""
    cmd = tmp_path / "circle.csv"
    write_command_csv(circle_command(0.02, 5000 / 60e3), cmd)
    args = ["compensate", "builtin:vmc", "--command", str(cmd), "-o", str(tmp_path / "c.csv"),
            "--draws", "2", "--iterations", "3"]
    assert main([*args, "--json"]) == 0
    got = capsys.readouterr()
    assert "circle R 20.0000 mm about (0.000, 0.000) mm in the XY plane" in got.err
    scores = json.loads(got.out)["scores"]
    assert {"largest_spike_um", "circular_deviation_um"} <= set(scores["after"]["circle"])
    square = tmp_path / "square.csv"
    write_command_csv(_polyline([(0, 0), (20, 0), (20, 20), (0, 20), (0, 0)]), square)
    assert main([*args[:3], str(square), *args[4:], "--json"]) == 0
    got = capsys.readouterr()
    assert "circle R" not in got.err and "circle" not in json.loads(got.out)["scores"]["after"]


def test_the_centre_of_a_filtered_command_is_the_one_it_runs_about():
    """Bench H's circle at F10000, pulled in by its controller's filter, was fitted about
    (0.003, 0.003) mm, 4.2 µm from the centre it runs about, and compensate's figures held
    that offset (with a warning to give --centre 0,0 that no one had given). Its centre
    is read as the circle analysis reads a command's: about (0, 0)."""
    from conftest import bench_path
    from tcpmm.path import read_command_csv

    cmd = read_command_csv(bench_path("h") / "circle_ccw_fast_cmd.csv")
    radius, centre = command_circle(cmd.positions, ("X", "Y"))
    assert centre == pytest.approx((0.0, 0.0), abs=1e-7)
    assert radius == pytest.approx(34.9499e-3, abs=2e-7)


def test_compensate_takes_a_filtered_circle_about_its_own_centre(tmp_path, capsys,
                                                                 monkeypatch):
    """No --centre given, compensate warned that the command ran 4.2 µm from "the centre
    given" and asked for --centre 0.0000,0.0000, and its figures held that offset. It
    finds that centre itself, warns of nothing, and its figures are those about the
    centre given."""
    from conftest import bench_path

    monkeypatch.chdir(tmp_path)
    src = str(bench_path("h") / "circle_ccw_fast_cmd.csv")
    args = ["compensate", "builtin:vmc", "--command", src, "-o", "c.csv", "--draws", "0",
            "--iterations", "1", "--json"]
    assert main(args) == 0
    got = capsys.readouterr()
    found = json.loads(got.out)
    assert "centre given" not in got.err and not any("centre given" in w
                                                     for w in found.get("warnings", []))
    circle = found["settings"]["circle"]
    assert circle["from"] == "command"
    assert circle["centre_m"] == pytest.approx([0.0, 0.0], abs=1e-7)
    assert main([*args, "--radius", str(circle["radius_m"] * 1e3), "--centre", "0,0"]) == 0
    given = json.loads(capsys.readouterr().out)
    assert found["scores"] == given["scores"]
