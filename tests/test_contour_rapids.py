"""A run made from an NC program records per sample the line of the block its command is
in and whether that is a G0 rapid."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from conftest import run_cli
from tcpmm.io.runfile import read_run
from tcpmm.path.commandfile import read_command_csv
from tcpmm.path.program import program_to_command
from tcpmm.path.settings import InterpolatorSettings
from tcpmm.path.stream import stream_program

#: feed passes along X joined by diagonal rapids, each rapid followed by a dwell in which
#: the servo settles from it (a dwell after a rapid counts as the rapid): the error of
#: the rapids (the axes' lags differ on a diagonal) is several times the passes'
PROGRAM = "\n".join(["G21 G90 G17", "G1 X10 F600", "G0 X40 Y25", "G4 P0.3", "G1 X50 F600",
                     "G0 X0 Y0", "G4 P0.3", "G1 X10 F600", "M30"]) + "\n"
#: the lines of PROGRAM in rapids: the G0s and the dwells after them
RAPID_LINES = {3, 4, 6, 7}


def quiet(fn, *args, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fn(*args, **kw)


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """The program's run as CSV (made whole) and as Parquet (streamed a block a chunk)."""
    d = tmp_path_factory.mktemp("rapids")
    (d / "p.nc").write_text(PROGRAM)
    model = d / "m.yaml"
    assert run_cli_plain("machine", "export", "vmc", "-o", model) == 0
    for name, extra in (("run.csv", []), ("run.parquet", ["--chunk-blocks", "1"])):
        assert run_cli_plain("simulate", model, "--gcode", d / "p.nc", "-o", d / name,
                             *extra) == 0
    return d / "run.csv", d / "run.parquet"


def run_cli_plain(*args) -> int:
    from tcpmm.cli import main

    return quiet(main, [str(a) for a in args])


def test_a_program_run_records_the_line_and_the_rapids_of_each_sample(runs):
    csv, parquet = (read_run(p) for p in runs)
    assert np.array_equal(csv.nc_line, parquet.nc_line)
    assert np.array_equal(csv.rapid, parquet.rapid)
    lines = csv.nc_line[np.r_[0, np.flatnonzero(np.diff(csv.nc_line)) + 1]].tolist()
    assert lines == [2, 3, 4, 5, 6, 7, 8]  # every block in order, the header none
    for line in lines:
        flags = set(csv.rapid[csv.nc_line == line].tolist())
        assert flags == {int(line in RAPID_LINES)}, line


def test_a_run_without_the_columns_is_read_as_before(runs, tmp_path):
    """A measured run has no nc_line and no rapid; nothing is made up for it."""
    run = read_run(runs[0])
    bare = type(run)(run.time_s, run.axes, run.meta)
    bare.write(path := tmp_path / "bare.csv")
    back = read_run(path)
    assert back.nc_line is None and back.rapid is None
    assert "rapid" not in path.read_text().splitlines()[0]


@pytest.mark.parametrize("kind", ["linear", "bell"])
def test_the_rapid_flag_covers_the_filtered_rapid(kind):
    """Through a post-interpolation filter the command moves on after the unfiltered
    rapid ends: the flag holds while any sample the filter takes is in the rapid, so that
    every sample not flagged lies on a feed pass (Y 0 or 20, exactly), and the pieces of
    a program streamed a block a chunk give the whole command's flags."""
    text = "G21 G90 G17\nG1 X10 F3000\nG0 X10 Y20\nG1 X0 F3000\nM30\n"
    settings = InterpolatorSettings(filter_kind=kind, filter_time_s=0.016)
    cmd = program_to_command(text, settings)
    y, rapid = cmd.positions["Y"], cmd.meta["rapid"]
    assert y.size == rapid.size == cmd.meta["nc_line"].size
    on_pass = np.minimum(np.abs(y), np.abs(y - 0.02)) < 1e-12
    assert np.all(on_pass[rapid == 0]) and not np.all(on_pass)
    pieces = list(stream_program(text, settings, 1))
    assert np.array_equal(np.concatenate([p.rapid for p in pieces]), rapid)
    assert np.array_equal(np.concatenate([p.nc_line for p in pieces]), cmd.meta["nc_line"])


def test_a_command_file_carries_the_blocks(runs, tmp_path, capsys):
    """``tcpmm path`` writes nc_line and rapid (whole and streamed, the same text)."""
    program = runs[0].parent / "p.nc"
    for name, extra in (("whole.csv", []), ("streamed.csv", ["--chunk-blocks", "1"])):
        code, _, _ = run_cli(capsys, "path", program, "-o", tmp_path / name, *extra)
        assert code == 0
    text = (tmp_path / "whole.csv").read_text()
    assert text == (tmp_path / "streamed.csv").read_text()
    assert text.splitlines()[0] == "time_s,x_mm,y_mm,nc_line,rapid"
    cmd = read_command_csv(tmp_path / "whole.csv")
    run = read_run(runs[0])
    assert np.array_equal(cmd.meta["rapid"], run.rapid[:cmd.time_s.size])
