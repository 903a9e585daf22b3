"""A plane given that leaves out an axis the path moves along: the signed error in it
leaves that axis' error out, and says so, on stderr and in ``--json``, for a run read whole
and one read in chunks alike; a plane that holds the motion says nothing."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

from tcpmm.analysis.contour import contour_error
from tcpmm.analysis.contour_stream import stream_contour
from tcpmm.analysis.plane import LEFT_OUT_FLOOR_M, OUT_OF_PLANE_SHARE, left_out_axes
from tcpmm.cli import main
from tcpmm.path.program import program_to_command
from tcpmm.sim.simulate import simulate

#: XZ arcs (G18), then a YZ arc (G19) to the other side of Z: X 20, Y 10, Z 10 mm of travel
PROGRAM = """G21 G90 G18 G64 P0.01
G0 X0 Y0 Z0
G1 X5 Z0 F3000
G2 X15 Z0 I5 K0
G1 X20
G19
G2 Y10 Z0 J5 K0
G4 P0.3
M30
"""
#: the same in XY alone
FLAT = PROGRAM.replace("G18", "G17").replace("G19", "G17").replace("K0", "J0").replace(
    "Y10 Z0 J5 J0", "X30 Y0 I5 J0")


def _quiet(fn, *args, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fn(*args, **kw)


@pytest.fixture(scope="module")
def runs(vmc, tmp_path_factory):
    """The non-plane run as CSV and as Parquet, and the flat one as CSV."""
    folder = tmp_path_factory.mktemp("left_out")
    run = _quiet(simulate, vmc, _quiet(program_to_command, PROGRAM))
    flat = _quiet(simulate, vmc, _quiet(program_to_command, FLAT))
    paths = {"csv": folder / "g18.csv", "parquet": folder / "g18.parquet",
             "flat": folder / "flat.csv"}
    run.write(paths["csv"])
    run.write(paths["parquet"])
    flat.write(paths["flat"])
    return paths


def _contour(capsys, path, *extra):
    assert main(["contour", str(path), *extra]) == 0
    cap = capsys.readouterr()
    return cap.out, " ".join(cap.err.split())


def test_a_plane_leaving_out_an_axis_that_moves_is_warned_of(runs, capsys):
    out, err = _contour(capsys, runs["csv"], "--plane", "XY")
    assert (f"warning: {runs['csv']}: the plane XY leaves out Z, which moves 10 mm" in err
            and "its contour error is left out of every figure" in err
            and "omit --plane" in err), err
    assert "warning" not in out
    data = json.loads(_contour(capsys, runs["csv"], "--plane", "XY", "--json")[0])
    assert data["left_out_travel_mm"].keys() == {"Z"}
    assert data["left_out_travel_mm"]["Z"] == pytest.approx(10.0, abs=1e-3)
    assert any("leaves out Z" in w for w in data["warnings"])
    # in the plane of the YZ arc, X moves 20 mm and is left out
    assert "the plane YZ leaves out X, which moves 20 mm" in _contour(
        capsys, runs["csv"], "--plane", "YZ")[1]


def test_the_3d_error_and_a_plane_that_holds_the_motion_say_nothing(runs, capsys):
    for path, extra in ((runs["csv"], ()), (runs["csv"], ("--plane", "3D")),
                        (runs["flat"], ("--plane", "XY")), (runs["flat"], ())):
        err = _contour(capsys, path, *extra)[1]
        assert "leaves out" not in err and "warning" not in err, (path, extra, err)
    data = json.loads(_contour(capsys, runs["flat"], "--plane", "XY", "--json")[0])
    assert data["left_out_travel_mm"] == {} and "warnings" not in data


def test_a_run_read_in_chunks_says_the_same(runs, capsys):
    whole = _contour(capsys, runs["csv"], "--plane", "XY")[1]
    chunked = _contour(capsys, runs["parquet"], "--plane", "XY", "--chunk-rows", "200")[1]
    said = [e.split(": ", 2)[2] for e in (whole, chunked)]  # past "warning: FILE: "
    assert said[0] == said[1] and "leaves out Z" in said[1]
    data = json.loads(_contour(capsys, runs["parquet"], "--plane", "XY", "--chunk-rows",
                               "200", "--json")[0])
    assert data["left_out_travel_mm"]["Z"] == pytest.approx(10.0, abs=1e-3)
    res = _quiet(stream_contour, runs["parquet"], ("X", "Y"), True, rows=200)
    assert res.left_out == _quiet(contour_error, _read(runs["parquet"]), plane="XY").left_out


def _read(path):
    from tcpmm.io.runfile import read_run

    return read_run(path)


def test_the_threshold_is_a_share_of_the_planes_smaller_travel_above_a_floor():
    ends = {"X": np.array([0.0, 0.06]), "Y": np.array([0.0, 0.04])}
    below, above = (OUT_OF_PLANE_SHARE * 0.04 * k for k in (0.9, 1.1))
    assert left_out_axes(("X", "Y"), {**ends, "Z": np.array([0.0, below])}) == {}
    assert left_out_axes(("X", "Y"), {**ends, "Z": np.array([0.0, above])}) == {
        "Z": pytest.approx(above)}
    # a plane of 2 um of travel: a Z within a count of a 1 um scale leaves nothing out
    tiny = {"X": np.array([0.0, 2e-6]), "Y": np.array([0.0, 2e-6])}
    assert left_out_axes(("X", "Y"), {**tiny, "Z": np.array([0.0, LEFT_OUT_FLOOR_M])}) == {}


def test_a_circle_in_a_plane_given_that_leaves_out_a_moving_axis_is_warned_of(tmp_path,
                                                                              capsys):
    """A circle of R 35 mm run in XY whose Z climbs 10 mm over the turn (a helix), taken
    with --plane XY: the circular test reads the radius in XY, and Z's error is in none
    of its figures. tcpmm circle said nothing; now it warns, on stderr and in --json,
    where the third axis moves more than a tenth of the plane's smaller travel (as
    contour does), and the same circle without Z's travel says nothing."""
    import pandas as pd

    from conftest import bench_path

    src = bench_path("d") / "circle_ccw_meas.csv"
    flat = pd.read_csv(src)
    helix = flat.copy()
    climb = np.linspace(0.0, 10.0, len(helix))
    for s in ("cmd", "motor", "scale", "tcp"):
        helix[f"z_{s}_mm"] = climb
    paths = {"helix": tmp_path / "helix.csv", "flat": tmp_path / "flat.csv"}
    helix.to_csv(paths["helix"], index=False)
    flat.to_csv(paths["flat"], index=False)
    for name, path in paths.items():
        assert main(["circle", str(path), "--radius", "35", "--plane", "XY"]) == 0
        err = " ".join(capsys.readouterr().err.split())
        said = "the plane XY leaves out Z, which moves 10 mm" in err
        assert said == (name == "helix"), (name, err)
    assert main(["circle", str(paths["helix"]), "--radius", "35", "--plane", "XY",
                 "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert any("leaves out Z" in w and "reads the radius in the plane given" in w
               for w in data["warnings"])


def test_the_tables_print_no_negative_zero(tmp_path, capsys):
    """A square in G18 measured in XZ: the scale's least signed error and a corner's
    coordinates round to zero from below, and read -0.00 and -0.000 (a small negative
    value that is not there)."""
    (tmp_path / "sq.nc").write_text("G21 G90 G18\nG0 X0 Z0\nG1 X20 F2000\nZ20\nX0\nZ0\n"
                                    "G4 P0.3\nM30\n")
    run = tmp_path / "run.csv"
    assert main(["simulate", "builtin:vmc", "--gcode", str(tmp_path / "sq.nc"),
                 "-o", str(run)]) == 0
    capsys.readouterr()
    assert main(["contour", str(run), "--plane", "XZ"]) == 0
    out = capsys.readouterr().out
    assert "corners, tcp" in out and "-0.00 " not in out and "-0.000," not in out


def test_a_travel_between_rapids_is_the_same_bits_read_whole_or_in_chunks(vmc, tmp_path):
    """The travel within the feed moves was taken in mm and scaled after, where a whole run
    is read in metres sample by sample: Z's 9.567247916106165 mm against
    9.567247916106163 in --json."""
    prog = ("G21 G90 G17\nG0 X0 Y0 Z1.5355\nG1 X5.0713 F3000\nG1 X10.1234 Y3.77 Z14.5046\n"
            "G0 Z20\nM30\n")
    path = tmp_path / "r.parquet"
    _quiet(simulate, vmc, _quiet(program_to_command, prog)).write(path)
    whole = _quiet(contour_error, _read(path), plane="XY").left_out
    for rows in (7, 200, 100_000):
        assert _quiet(stream_contour, path, ("X", "Y"), True, rows=rows).left_out == whole
    assert whole.keys() == {"Z"}
