"""Command file (time_s, x_mm, y_mm[, z_mm]): round trip and bad files."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tcpmm.errors import InputError
from tcpmm.path import Command, circle_command, read_command_csv, write_command_csv


def test_round_trip_of_a_circle(tmp_path):
    cmd = circle_command(0.035, 5 / 60, smoothing_time_s=0.01)
    path = tmp_path / "out" / "cmd.csv"
    write_command_csv(cmd, path)
    assert path.read_text().splitlines()[0] == "time_s,x_mm,y_mm"
    back = read_command_csv(path)
    assert back.axes == ["X", "Y"]
    assert np.abs(back.time_s - cmd.time_s).max() < 1e-12
    for a in "XY":
        assert np.abs(back.positions[a] - cmd.positions[a]).max() < 1e-12
    assert back.period_s == pytest.approx(cmd.period_s, rel=1e-12)
    assert list(tmp_path.joinpath("out").iterdir()) == [path]  # no temporary file left


@settings(max_examples=25, deadline=None)
@given(
    n=st.integers(2, 50),
    period=st.floats(1e-4, 1e-2),
    t0=st.floats(-10.0, 100.0),
    z=st.booleans(),
    data=st.data(),
)
def test_round_trip_keeps_values_to_a_picometre(tmp_path_factory, n, period, t0, z, data):
    axes = ["X", "Y", "Z"] if z else ["X", "Y"]
    pos = {
        a: np.array(data.draw(st.lists(st.floats(-2.0, 2.0), min_size=n, max_size=n))) for a in axes
    }
    cmd = Command(time_s=t0 + period * np.arange(n), positions=pos)
    path = tmp_path_factory.mktemp("rt") / "c.csv"
    write_command_csv(cmd, path)
    back = read_command_csv(path)
    assert back.axes == axes
    assert np.abs(back.time_s - cmd.time_s).max() <= 1e-12 + 1e-15 * abs(t0)
    for a in axes:
        assert np.abs(back.positions[a] - pos[a]).max() <= 1e-12


def test_write_replaces_an_existing_file_and_refuses_other_axes(tmp_path):
    path = tmp_path / "c.csv"
    path.write_text("old")
    t = np.arange(3) * 1e-3
    write_command_csv(Command(t, {"X": t, "Y": t, "Z": t}), path)
    assert path.read_text().startswith("time_s,x_mm,y_mm,z_mm\n")
    with pytest.raises(InputError, match="axes X, Y"):
        write_command_csv(Command(t, {"X": t}), path)
    with pytest.raises(InputError, match="axes X, Y"):
        write_command_csv(Command(t, {"X": t, "Y": t, "A": t}), path)


BAD = [
    # (file text, line, column, part of the message)
    ("", None, None, "empty"),
    ("x_mm,y_mm,time_s\n0,0,0\n1,1,1\n", 1, 1, "first column must be time_s"),
    ("time_s,x_mm,q_mm\n0,0,0\n1,1,1\n", 1, 3, "unknown column 'q_mm'"),
    ("time_s,x_mm,x_mm\n0,0,0\n1,1,1\n", 1, 3, "appears twice"),
    ("time_s,x_mm\n0,0\n1,1\n", 1, None, "'y_mm' is missing"),
    ("time_s,x_mm,y_mm\n0,0,0\n", 3, None, "at least two rows"),
    ("time_s,x_mm,y_mm\n0,0,0\n0.001,nan,0\n", 3, "x_mm", "not a finite number"),
    ("time_s,x_mm,y_mm\n0,0,0\n0.001,0,inf\n", 3, "y_mm", "not a finite number"),
    ("time_s,x_mm,y_mm\n0,0,0\n0.001,abc,0\n", 3, "x_mm", "'abc' is not a number"),
    ("time_s,x_mm,y_mm\n0,0,0\n0.001,0\n", 3, None, "2 values for 3 columns"),
    ("time_s,x_mm,y_mm\n0,0,0\n\n0.002,0,0\n", 3, None, "1 values for 3 columns"),
    ("time_s,x_mm,y_mm\n0,0,0\n0.001,0,0\n0.001,0,0\n", 4, "time_s", "must increase"),
    ("time_s,x_mm,y_mm\n0,0,0\n0.001,0,0\n0.0025,0,0\n0.0035,0,0\n", 4, "time_s", "uniformly"),
]


@pytest.mark.parametrize(("text", "line", "column", "msg"), BAD)
def test_bad_files_name_file_line_and_column(tmp_path, text, line, column, msg):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(InputError) as info:
        read_command_csv(path)
    err = info.value
    assert err.file == str(path)
    assert (err.line, err.column) == (line, column)
    assert msg in err.message


def test_missing_file(tmp_path):
    with pytest.raises(InputError, match="not found"):
        read_command_csv(tmp_path / "nope.csv")


def test_line_numbers_count_only_line_breaks(tmp_path):
    """A form feed split a row in two for str.splitlines: the rows were misread."""
    p = tmp_path / "c.csv"
    p.write_text("time_s,x_mm,y_mm\n0.0,0,0\x0c\n0.001,0,0\n0.002,x,0\n")
    with pytest.raises(InputError) as e:
        read_command_csv(p)
    assert e.value.line == 4


@pytest.mark.parametrize("scale", [1e3, 1e6])
def test_a_time_column_in_ms_or_us_is_refused(tmp_path, scale):
    """time_s written in ms went through: a 8 s circle became 2 h of machine time at a
    1 s step, simulated without a word; in us it ran on for minutes and a SIGTERM did not
    stop it. A period beyond 0.1 s is refused, naming the column and the unit."""
    cmd = circle_command(0.035, 5000 / 60e3)
    path = tmp_path / "c.csv"
    write_command_csv(Command(cmd.time_s * scale, cmd.positions), path)
    with pytest.raises(InputError, match="milliseconds or microseconds") as e:
        read_command_csv(path)
    assert e.value.column == "time_s" and e.value.line == 3
    write_command_csv(cmd, path)
    assert read_command_csv(path).period_s == pytest.approx(cmd.period_s)


def test_a_header_in_double_quotes_reads_as_without(tmp_path):
    """A spreadsheet or logger writes "time_s","x_mm": every CSV reader refused it ('missing
    column time_s (did you mean '"time_s"'?)'), while it took quoted numbers in the rows.
    The header's quotes are taken off, as a CSV reader does."""
    from tcpmm.io.runfile import read_run
    from tcpmm.machines.builtin import builtin_machine
    from tcpmm.sim.simulate import simulate

    cmd = circle_command(0.01, 3000 / 60e3)
    path = tmp_path / "c.csv"
    write_command_csv(cmd, path)
    lines = path.read_text().splitlines()
    quoted = ",".join(f'"{n}"' for n in lines[0].split(","))
    path.write_text("\n".join([quoted, *lines[1:]]) + "\n")
    back = read_command_csv(path)
    assert np.abs(back.positions["X"] - cmd.positions["X"]).max() <= 1e-12
    run_file = tmp_path / "run.csv"
    simulate(builtin_machine(), back).write_csv(run_file)
    want = read_run(run_file)
    lines = run_file.read_text().splitlines()
    run_file.write_text("\n".join([",".join(f'"{n}"' for n in lines[0].split(",")),
                                   *lines[1:]]) + "\n")
    got = read_run(run_file)
    assert np.array_equal(got.axes["X"].tcp, want.axes["X"].tcp)


SEPARATORS = "columns are separated by {}; use commas and a '.' decimal point"


@pytest.mark.parametrize(("text", "sep"), [
    ("time_s;x_mm;y_mm\n0,000;1,0;2,0\n0,001;1,0;2,0\n", "semicolons"),
    ("time_s\tx_mm\ty_mm\n0.000\t1.0\t2.0\n0.001\t1.0\t2.0\n", "tabs"),
])
def test_a_spreadsheet_separator_is_named(tmp_path, text, sep):
    """A command file of a spreadsheet set to a decimal comma was refused as "the first
    column must be time_s, found 'time_s;x_mm;y_mm'", which names no cause; the run file
    and the other CSV readers said what is wrong."""
    path = tmp_path / "cmd.csv"
    path.write_text(text)
    with pytest.raises(InputError) as e:
        read_command_csv(path)
    assert (e.value.message, e.value.line) == (SEPARATORS.format(sep), 1)


def test_a_decimal_comma_is_named(tmp_path):
    path = tmp_path / "cmd.csv"
    path.write_text("time_s,x_mm,y_mm\n0.000,1.0,2.0\n0,001,1,0,2,0\n0.002,1.0,2.0\n")
    with pytest.raises(InputError, match=r"6 fields but the header has 3 \(a decimal comma") as e:
        read_command_csv(path)
    assert e.value.line == 3


def test_every_csv_reader_names_the_separator(tmp_path):
    """The command, FRF, run and bundle readers share one diagnosis of the separator."""
    from tcpmm.io.bundle import read_sweep_csv
    from tcpmm.io.frffile import read_frf_csv
    from tcpmm.io.runfile import read_run_csv

    path = tmp_path / "any.csv"
    path.write_text("time_s;x_mm;y_mm\n0,0;1,0;2,0\n0,1;1,0;2,0\n")
    for read in (read_command_csv, read_frf_csv, read_run_csv, read_sweep_csv):
        with pytest.raises(InputError) as e:
            read(path)
        assert (e.value.message, e.value.line) == (SEPARATORS.format("semicolons"), 1), read
