"""Circular tests in any plane: the plane by name, from the motion, and XZ and YZ circles
from the NC program to the analysis on the command line."""

import json

import numpy as np
import pytest

from tcpmm.analysis.circular import analyse_circle
from tcpmm.analysis.diagnostics import circle_diagnostics
from tcpmm.analysis.plane import motion_plane, plane_axes
from tcpmm.cli import main
from tcpmm.errors import InputError, InputWarning

# a circle of R10 at F2000 in G18 (ZX) and G19 (YZ): feed-in, CCW, feed-out; the same CW
XZ = """G21 G18 G90
G0 X0 Z0
G3 X10 Z0 I5 K0 F2000
G3 X10 Z0 I-10 K0
G3 X0 Z0 I-5 K0
G2 X10 Z0 I5 K0
G2 X10 Z0 I-10 K0
G2 X0 Z0 I-5 K0
M30
"""
YZ = XZ.replace("G18", "G19").replace("X", "Y").replace("I", "J")
XY = XZ.replace("G18", "G17").replace("Z", "Y").replace("K", "J")


def run(capsys, *args):
    code = main([str(a) for a in args])
    cap = capsys.readouterr()
    return code, cap.out, " ".join(cap.err.split())


def test_plane_names():
    assert plane_axes("xz") == ("X", "Z")
    assert plane_axes(("Z", "X")) == ("Z", "X")
    for bad in ("XX", "XA", "XYZ", ""):
        with pytest.raises(InputError, match="two different axes"):
            plane_axes(bad)


def test_motion_plane_is_the_gcode_plane_of_the_two_axes_moving_most():
    t = np.linspace(0, 1, 50)
    pos = {"X": np.cos(t), "Y": np.full(50, 3.0), "Z": 2 * np.sin(t)}
    axes, why, flat = motion_plane(pos)
    assert axes == ("Z", "X") and "Z and X" in why and flat and "not plane" not in why
    pos["Y"] = 0.2 * t
    assert "Y moves too" in motion_plane(pos)[1] and not motion_plane(pos)[2]
    # where the positions come from goes with their travel, not after the advice
    why = motion_plane(pos, " in the cmd signals")[1]
    assert ") in the cmd signals; Y moves too" in why and why.endswith("give --plane to choose")
    with pytest.raises(InputError, match="fewer than two"):
        motion_plane({"X": t, "Y": np.zeros(50)})


@pytest.mark.parametrize(("travel", "plane"), [("XY", "XY"), ("YX", "XY"), ("XZ", "ZX"),
                                               ("ZX", "ZX"), ("YZ", "YZ"), ("ZY", "YZ")])
def test_the_plane_note_names_the_axes_in_the_planes_order(travel, plane):
    """Whichever of the two axes moves more, the note names them as the plane does."""
    t = np.linspace(0, 1, 50)
    pos = {"X": np.zeros(50), "Y": np.zeros(50), "Z": np.zeros(50)}
    pos[travel[0]], pos[travel[1]] = 3.0 * t, 2.0 * t
    axes, why, _ = motion_plane(pos)
    assert axes == tuple(plane) and f"are {plane[0]} and {plane[1]} (" in why


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """Run files of the three circles on the built-in machine, through the CLI."""
    d = tmp_path_factory.mktemp("plane")
    out = {}
    for name, text in (("xz", XZ), ("yz", YZ), ("xy", XY)):
        (d / f"{name}.nc").write_text(text)
        assert main(["path", str(d / f"{name}.nc"), "-o", str(d / f"{name}_cmd.csv")]) == 0
        assert main(["simulate", "builtin:vmc", "--command", str(d / f"{name}_cmd.csv"),
                     "-o", str(d / f"{name}_run.csv")]) == 0
        out[name] = d / f"{name}_run.csv"
    return out


@pytest.mark.parametrize("name, plane, dirs", [("xz", "ZX", ["ccw", "cw"]),
                                               ("yz", "YZ", ["ccw", "cw"]),
                                               ("xy", "XY", ["ccw", "cw"])])
def test_circle_in_its_plane_from_the_cli(capsys, runs, name, plane, dirs):
    code, out, err = run(capsys, "circle", runs[name], "--radius", 10, "--json")
    assert code == 0, err
    res = json.loads(out)
    assert f"plane {plane}, taken from" in err
    assert res["plane"] == plane
    assert [p["direction"] for p in res["passes"]] == dirs  # G3 reads CCW in its G plane
    rows = {(p["direction"], r["sensor"]): r for p in res["passes"] for r in p["sensors"]}
    assert set(rows) == {(d, s) for d in dirs for s in ("cmd", "motor", "scale", "tcp")}
    # the command is on the circle; the machine follows it within tens of um
    assert rows["ccw", "cmd"]["contour_error_um"] < 0.01
    assert 0.5 < rows["ccw", "tcp"]["contour_error_um"] < 100
    terms = {t["term"] for t in res["diagnostics"]["terms"]}
    assert {f"backlash_{plane[0]}", f"backlash_{plane[1]}"} <= terms


def test_plane_seen_from_the_other_side_swaps_the_directions(capsys, runs):
    code, out, err = run(capsys, "circle", runs["xz"], "--radius", 10, "--plane", "XZ",
                         "--json")
    assert code == 0 and "taken from" not in err
    res = json.loads(out)
    assert res["plane"] == "XZ" and [p["direction"] for p in res["passes"]] == ["cw", "ccw"]


def test_wrong_plane_is_a_clear_error(capsys, runs):
    code, _, err = run(capsys, "circle", runs["xz"], "--radius", 10, "--plane", "XY")
    # the plane misses the motion: refused with the plane it runs in, before any circle
    # is sought in it
    err = " ".join(err.split())
    assert code == 2 and "the plane XY leaves out Z" in err and "runs in the ZX plane" in err
    code, _, err = run(capsys, "circle", runs["xz"], "--radius", 10, "--plane", "XQ")
    assert code == 2 and "two different axes" in err


def test_compare_in_the_plane_of_the_run(capsys, runs):
    code, out, err = run(capsys, "compare", runs["yz"], runs["yz"], "--radius", 10, "--json")
    assert code == 0, err
    rows = json.loads(out)["rows"]
    assert {r["sensor"] for r in rows} == {"motor", "scale", "tcp"}
    assert all(abs(r["contour_error_um"]) < 1e-9 for r in rows)


def test_plots_name_the_plane_axes(runs):
    from tcpmm.io.runfile import read_run_csv

    with pytest.warns(InputWarning, match="quadrant point B"):  # the circles start at B
        res = analyse_circle(read_run_csv(runs["xz"]), 0.01, plane=("Z", "X"))
    fig = res.plot()
    assert [(a.get_xlabel(), a.get_ylabel()) for a in fig.axes] == [("Z [mm]", "X [mm]")] * 2
    diag = circle_diagnostics(res)
    assert diag.axes == ("Z", "X") and "servo_mismatch" in diag.terms
    import matplotlib.pyplot as plt

    plt.close(fig)


def test_path_plot_of_a_g18_program_is_in_its_plane(tmp_path, capsys):
    (tmp_path / "p.nc").write_text(XZ)
    code, _, err = run(capsys, "path", tmp_path / "p.nc", "-o", tmp_path / "c.csv", "--plot")
    assert code == 0, err and (tmp_path / "c.png").is_file()
    from tcpmm.path import program_to_command
    from tcpmm.plot.path import plot_command

    cmd = program_to_command(tmp_path / "p.nc")
    assert cmd.meta["plane_axes"] == ("Z", "X")
    fig = plot_command(cmd, plane=("Z", "X"))
    assert (fig.axes[0].get_xlabel(), fig.axes[0].get_ylabel()) == ("Z [mm]", "X [mm]")
    x, z = fig.axes[0].lines[0].get_data()
    assert np.ptp(x) == pytest.approx(20, abs=0.1) and np.ptp(z) == pytest.approx(20, abs=0.1)
    import matplotlib.pyplot as plt

    plt.close(fig)
