"""Header and row faults of CSV inputs are named at the line where they are."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from tcpmm.analysis.circular import analyse_circle
from tcpmm.errors import InputError, InputWarning
from tcpmm.io.csvutil import read_numeric_csv
from tcpmm.io.runfile import read_run_csv
from tcpmm.result import AxisRun, Run

HEADER = "time_s,x_cmd_mm,y_cmd_mm,x_tcp_mm"
ROWS = ["0,1,2,3", "0.001,1,2,3", "0.002,1,2,3"]


def read_both(path):
    """Errors of the run-file reader and of the bundle's numeric reader."""
    errors = []
    for read in (read_run_csv,
                 lambda p: read_numeric_csv(p, ["time_s", "x_cmd_mm", "y_cmd_mm", "x_tcp_mm"])):
        with pytest.raises(InputError) as info:
            read(path)
        errors.append(info.value)
    return errors


@pytest.mark.parametrize(
    "lines, line, text",
    [
        ([HEADER.replace("y_cmd_mm", "x_cmd_mm"), *ROWS], 1, "'x_cmd_mm' appears twice"),
        (ROWS, 1, "holds numbers, not column names"),
        ([HEADER, ROWS[0] + ",7", *ROWS[1:]], 2, "row has 5 fields but the header has 4"),
        ([HEADER, *ROWS[:2], ROWS[2] + ",7"], 4, "row has 5 fields but the header has 4"),
        ([HEADER], 2, "header but no data rows"),
    ],
    ids=["duplicate", "no-header", "extra-first-row", "extra-later-row", "header-only"],
)
def test_header_and_row_faults_are_named_where_they_are(tmp_path, lines, line, text):
    path = tmp_path / "run.csv"
    path.write_text("\n".join(lines) + "\n")
    for err in read_both(path):
        assert err.line == line
        assert text in str(err)
        assert ".1" not in str(err)  # never a column name the file does not have


def test_run_file_reads_bom_and_spaces_in_header(tmp_path):
    path = tmp_path / "run.csv"
    path.write_text("\ufeff" + HEADER.replace(",", ", ") + "\n" + "\n".join(ROWS) + "\n",
                    encoding="utf-8")
    run = read_run_csv(path)
    assert run.axes["X"].tcp == pytest.approx(3e-3)
    assert run.time_s[-1] == pytest.approx(0.002)


def test_half_present_sensor_is_reported():
    t = np.arange(2000) * 1e-3
    th = 2 * np.pi * t / t[-1]
    x, y = 0.035 * np.cos(th), 0.035 * np.sin(th)
    run = Run(t, {"X": AxisRun(cmd=x), "Y": AxisRun(cmd=y, tcp=y)})
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = analyse_circle(run, 0.035)
    assert res.passes and all("tcp" not in p.sensors for p in res.passes)
    texts = [str(w.message) for w in caught if issubclass(w.category, InputWarning)]
    assert any("tcp signal is present for Y but not for X" in s for s in texts)


@pytest.mark.parametrize("data, line, text", [
    ((HEADER + "\n" + ROWS[0] + "\n").encode("utf-16"), 1,
     r"not a UTF-8 text file \(it is UTF-16\)"),
    ((HEADER + "\n0,1,2,\xb53\n").encode("latin-1"), 2, r"not a UTF-8 text file \(byte 0xb5\)"),
])
def test_csv_inputs_that_are_not_utf8_are_named(tmp_path, data, line, text):
    from tcpmm.path.commandfile import read_command_csv

    path = tmp_path / "in.csv"
    path.write_bytes(data)
    for read in (read_run_csv, read_command_csv, lambda p: read_numeric_csv(p, ["time_s"])):
        with pytest.raises(InputError, match=text) as info:
            read(path)
        assert info.value.file == str(path) and info.value.line == line


def test_a_folder_is_called_a_folder(tmp_path):
    from tcpmm.path.commandfile import read_command_csv

    for read in (read_run_csv, read_command_csv, lambda p: read_numeric_csv(p, ["time_s"])):
        with pytest.raises(InputError, match="this is a directory"):
            read(tmp_path)


@pytest.mark.parametrize("cell", ["nan", "NaN", ""])
def test_a_nan_cell_is_not_called_only_empty(tmp_path, cell):
    p = tmp_path / "f.csv"
    p.write_text(f"time_s,x_mm\n0,0\n0.001,{cell}\n0.002,0\n")
    with pytest.raises(InputError) as e:
        read_numeric_csv(p, ["time_s", "x_mm"])
    assert e.value.line == 3 and e.value.column == "x_mm"
    assert "empty or NaN" in e.value.message


def test_a_word_among_many_numbers_is_refused_without_a_pandas_warning(tmp_path):
    """pandas types a long file in chunks and warns, naming a line inside the package,
    where a column's chunks differ (a word in the first, numbers after); the user gets
    the reader's error alone."""
    names = ["time_s"] + [f"{a}_{s}" for a in "abcdefghijklm"
                          for s in ("cmd_mm", "motor_mm", "scale_mm", "tcp_mm", "current_A")]
    rows = [",".join([f"{k * 1e-3:g}"] + ["1"] * (len(names) - 1)) for k in range(9000)]
    rows[1] = rows[1].replace(",1,", ",oops,", 1)
    path = tmp_path / "long.csv"
    path.write_text(",".join(names) + "\n" + "\n".join(rows) + "\n")
    for read in (read_run_csv, lambda p: read_numeric_csv(p, names)):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            with pytest.raises(InputError) as info:
                read(path)
        assert [str(w.message) for w in caught] == []
        assert (info.value.line, info.value.column) == (3, "a_cmd_mm")


def test_a_table_in_fixed_point_has_no_negative_zero(tmp_path):
    """The demo's circle table wrote the command's spikes, -1e-9 um, as -0.0000: a small
    negative value that is not there. A value that rounds to zero is written as zero;
    one that does not keeps its sign, and other formats are as they were."""
    import pandas as pd

    from tcpmm.io.atomic import write_table_atomic

    frame = pd.DataFrame({"name": ["a", "b", "c"], "v": [-1e-9, -6e-5, 0.25],
                          "n": [1, -2, 3]})
    write_table_atomic(frame, tmp_path / "t.csv", "%.4f")
    assert (tmp_path / "t.csv").read_text() == ("name,v,n\na,0.0000,1\nb,-0.0001,-2\n"
                                                "c,0.2500,3\n")
    write_table_atomic(frame, tmp_path / "g.csv", "%.6g")
    assert "-1e-09" in (tmp_path / "g.csv").read_text()
