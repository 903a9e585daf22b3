"""Run files: CSV and Parquet hold the same run; every run reader takes both."""

import itertools
import json

import numpy as np
import pytest

from tcpmm.cli import main
from tcpmm.errors import InputError
from tcpmm.io.runfile import read_run, write_run
from tcpmm.path import write_command_csv
from tcpmm.path.command import Command
from tcpmm.result import AxisRun, Run


def _run(n=500):
    t = np.arange(n) * 1e-3
    rng = np.random.default_rng(3)
    axes = {a: AxisRun(cmd=0.035 * np.sin(t + k), motor=rng.normal(size=n) * 1e-3,
                       scale=rng.normal(size=n) * 1e-3, tcp=rng.normal(size=n) * 1e-3,
                       current=rng.normal(size=n))
            for k, a in enumerate("XY")}
    return Run(time_s=t, axes=axes)


def test_csv_and_parquet_give_the_same_run(tmp_path):
    run = _run()
    write_run(run, tmp_path / "r.csv")
    write_run(run, tmp_path / "r.parquet")
    a, b = read_run(tmp_path / "r.csv"), read_run(tmp_path / "r.parquet")
    assert list(a.axes) == list(b.axes) == ["X", "Y"]
    # Parquet keeps the doubles (mm, then back to m); CSV keeps 10 significant digits
    for name, ax in run.axes.items():
        for f in ("cmd", "motor", "scale", "tcp", "current"):
            v = getattr(ax, f)
            np.testing.assert_allclose(getattr(b.axes[name], f), v, rtol=1e-15, atol=1e-18)
            np.testing.assert_allclose(getattr(a.axes[name], f), v, rtol=6e-10, atol=0)
    np.testing.assert_array_equal(b.time_s, run.time_s)


def test_csv_writer_writes_what_pandas_wrote(tmp_path):
    run = _run(50)
    run.axes["X"].tcp[7] = np.nan  # an empty cell, as pandas writes it
    run.write_csv(tmp_path / "r.csv")
    expected = run.to_pandas().to_csv(index=False, float_format="%.10g", lineterminator="\n")
    assert (tmp_path / "r.csv").read_text() == expected


def test_parquet_run_checked_like_csv(tmp_path):
    run = _run(20)
    run.time_s[5] = run.time_s[4]
    write_run(run, tmp_path / "r.parquet")
    with pytest.raises(InputError, match=r"time must increase strictly \(row 6\)"):
        read_run(tmp_path / "r.parquet")
    (tmp_path / "bad.parquet").write_text("not parquet")
    with pytest.raises(InputError, match="cannot read as Parquet"):
        read_run(tmp_path / "bad.parquet")


@pytest.mark.parametrize("reader", ["circle", "contour"])
def test_a_parquet_column_twice_or_a_pandas_index_is_a_named_error(tmp_path, capsys, reader):
    """Arrow keeps two columns of one name: the run reader stopped on its KeyError as an
    internal error (exit 1). A pandas index saved as a column is named with its fix."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    write_run(_run(50), tmp_path / "r.parquet")
    table = pq.read_table(tmp_path / "r.parquet")
    twice = table.append_column("x_tcp_mm", table.column("x_tcp_mm"))
    pq.write_table(twice, tmp_path / "twice.parquet")
    index = table.append_column("__index_level_0__", pa.array(np.arange(50) * 2))
    pq.write_table(index, tmp_path / "index.parquet")
    for name, said in (("twice", "column 'x_tcp_mm': the file has 2 columns of this name"),
                       ("index", "to_parquet(..., index=False)")):
        args = [reader, str(tmp_path / f"{name}.parquet")] + (
            ["--radius", "35"] if reader == "circle" else [])
        assert main(args) == 2
        err = capsys.readouterr().err
        assert said in err and "internal error" not in err, err


def test_a_comment_line_or_a_parquet_named_csv_is_told_for_what_it_is(tmp_path):
    """A recorder's '# ...' line above the header read as a header of one column, and
    every row 'has 11 fields' (a decimal comma?); a Parquet file named .csv was 'not a
    UTF-8 text file (byte 0xc0)'."""
    write_run(_run(20), tmp_path / "r.csv")
    (tmp_path / "c.csv").write_text("# recorded 2026-12-07\n" + (tmp_path / "r.csv").read_text())
    with pytest.raises(InputError, match=r"c\.csv, line 1: the first line is a comment"):
        read_run(tmp_path / "c.csv")
    write_run(_run(20), tmp_path / "p.parquet")
    (tmp_path / "p.csv").write_bytes((tmp_path / "p.parquet").read_bytes())
    with pytest.raises(InputError, match=r"this is a Parquet file, not the UTF-8 text a run "
                                         r"file is; name it p\.parquet"):
        read_run(tmp_path / "p.csv")


def test_parquet_of_any_layout_and_number_type_reads_as_written(tmp_path):
    """Row groups of several sizes, chunks that start inside a buffer (a sliced table),
    float32 and integer columns; a missing value is named with its row."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    rng = np.random.default_rng(8)
    t, x = np.arange(1000) * 1e-3, rng.normal(size=1000)
    whole = pa.table({"time_s": t, "x_cmd_mm": x, "x_tcp_mm": x.astype(np.float32),
                      "x_scale_mm": np.round(x * 1e3).astype(np.int64)})
    pq.write_table(whole.slice(3, 900), tmp_path / "r.parquet", row_group_size=128)
    assert pq.ParquetFile(tmp_path / "r.parquet").metadata.num_row_groups == 8
    ax = read_run(tmp_path / "r.parquet").axes["X"]
    np.testing.assert_array_equal(ax.cmd, x[3:903] * 1e-3)
    np.testing.assert_array_equal(ax.tcp, x[3:903].astype(np.float32).astype(float) * 1e-3)
    np.testing.assert_array_equal(ax.scale, np.round(x[3:903] * 1e3) * 1e-3)
    assert ax.cmd.flags.writeable
    pq.write_table(whole.set_column(1, "x_cmd_mm", pa.array([*x[:7], None, *x[8:]])),
                   tmp_path / "n.parquet")
    with pytest.raises(InputError, match=r"missing or not a number \(row 8\)"):
        read_run(tmp_path / "n.parquet")


def test_a_column_of_any_kind_reads_as_floats_with_nulls_as_nan():
    """A record batch's column (streamed runs) and a table's (whole runs): float64 with and
    without nulls, sliced, in several chunks, float32 and integers."""
    import pyarrow as pa

    from tcpmm.io.runfile import float_values

    v = np.arange(10.0)
    cases = [pa.array(v), pa.array(v).slice(3, 5), pa.array([*v[:4], None, *v[5:]]),
             pa.chunked_array([pa.array(v[:4]), pa.array(v[4:]).slice(1)]),
             pa.chunked_array([pa.array([0.0, None]), pa.array(v[2:])]),
             pa.chunked_array([], pa.float64()), pa.array(v, pa.float32()),
             pa.chunked_array([pa.array(np.arange(10))])]
    want = [v, v[3:8], np.r_[v[:4], np.nan, v[5:]], np.r_[v[:4], v[5:]],
            np.r_[0.0, np.nan, v[2:]], np.empty(0), v, v]
    for col, w in zip(cases, want, strict=True):
        got = float_values(col)
        assert got.dtype == np.float64
        np.testing.assert_array_equal(got, w)


def test_simulate_to_parquet_then_circle(tmp_path, capsys):
    t = np.arange(0.0, 3.0, 1e-3)
    w = 2 * np.pi / 2.6
    cmd = Command(t, {"X": 0.035 * np.cos(w * t) - 0.035, "Y": 0.035 * np.sin(w * t)})
    write_command_csv(cmd, tmp_path / "cmd.csv")
    for out in ("run.parquet", "run.csv"):
        assert main(["simulate", "builtin:vmc", "--command", str(tmp_path / "cmd.csv"),
                     "-o", str(tmp_path / out)]) == 0
    capsys.readouterr()
    res = {}
    for f in ("run.parquet", "run.csv"):
        assert main(["circle", str(tmp_path / f), "--radius", "35", "--centre", "-35,0",
                     "--json"]) == 0
        res[f] = json.loads(capsys.readouterr().out)
    assert res["run.parquet"]["passes"]
    for pa, pc in zip(res["run.parquet"]["passes"], res["run.csv"]["passes"], strict=True):
        for ra, rc in zip(pa["sensors"], pc["sensors"], strict=True):
            assert ra["sensor"] == rc["sensor"]
            assert abs(ra["contour_error_um"] - rc["contour_error_um"]) < 1e-3


@pytest.mark.parametrize(("cell", "message"), [
    ("1.2.3", "value '1.2.3' is not a number (use '.' as decimal point, no units or "
              "thousands separators in cells)"),
    ("", "value is empty; every cell must hold a finite number: repair or remove the row"),
    ("nan", "value 'nan' is not a finite number; every cell must hold a finite number: "
            "repair or remove the row"),
], ids=["text", "empty", "nan"])
def test_a_bad_cell_of_a_csv_run_is_quoted_with_the_fix(tmp_path, cell, message):
    """"value is missing or not a number" said neither which nor what to do, where the
    bundle and command-file readers quote the cell; the line and column stay."""
    path = tmp_path / "run.csv"
    write_run(_run(), path)
    lines = path.read_text().splitlines()
    names = lines[0].split(",")
    fields = lines[99].split(",")
    fields[names.index("x_scale_mm")] = cell
    lines[99] = ",".join(fields)
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(InputError) as info:
        read_run(path)
    assert (info.value.line, info.value.column) == (100, "x_scale_mm")
    assert info.value.message == message


def _piece(run, a, b):
    return Run(run.time_s[a:b], {n: AxisRun(cmd=x.cmd[a:b], motor=x.motor[a:b],
                                            scale=x.scale[a:b], tcp=x.tcp[a:b],
                                            current=x.current[a:b])
                                 for n, x in run.axes.items()})


def test_short_pieces_go_into_row_groups_of_the_least_rows(tmp_path, monkeypatch):
    """A row group a piece: Arrow keeps some 15 KB a row group until the file closes and
    twice that at the close, so a run streamed in pieces of a few rows took 32 KB of
    memory a piece. Short pieces are gathered into groups of the least rows or more; a
    piece as long goes on as it is, after the rows gathered before it."""
    import pyarrow.parquet as pq

    from tcpmm.io import runwrite
    from tcpmm.io.runfile import run_parquet_writer

    monkeypatch.setattr(runwrite, "LEAST_ROW_GROUP_ROWS", 100, raising=False)
    run = _run(1000)
    cuts = [0, 1, 3, 6, 40, 90, 160, 161, 400, 437, 600, 601, 990, 1000]
    with run_parquet_writer(tmp_path / "r.parquet") as write:
        for a, b in itertools.pairwise(cuts):
            write(_piece(run, a, b))
    meta = pq.ParquetFile(tmp_path / "r.parquet").metadata
    assert [meta.row_group(k).num_rows for k in range(meta.num_row_groups)] == [
        160, 1, 239, 37, 163, 1, 389, 10]
    write_run(run, tmp_path / "w.parquet")
    back, want = read_run(tmp_path / "r.parquet"), read_run(tmp_path / "w.parquet")
    assert np.array_equal(back.time_s, want.time_s)
    for a in "XY":
        for s in ("cmd", "motor", "scale", "tcp", "current"):
            assert np.array_equal(getattr(back.axes[a], s), getattr(want.axes[a], s))


def test_a_float32_time_too_coarse_for_its_period_is_refused(tmp_path):
    """Bench C's circle stored as float32 with a clock time of 1234.5 s: its time rounds to
    122 us, which read 1 kHz as 1024 Hz, the feed 0.1 % low and a false caution, with no
    word. Refused by both readers (the whole run and the contour's batches), naming the
    rounding and the fix; a float32 time from 0 rounds finely enough and reads."""
    import pandas as pd

    from conftest import bench_path
    from tcpmm.analysis.contour_parquet import batches

    a = pd.read_csv(bench_path("c") / "circle_ccw_meas.csv")
    a.astype("float32").to_parquet(tmp_path / "zero.parquet")
    a.assign(time_s=a.time_s + 1234.5).astype("float32").to_parquet(tmp_path / "clock.parquet")
    read_run(tmp_path / "zero.parquet")
    said = r"time stored as a float32 rounds to 122 µs at 123\d\.\d s, 12\.5%.* store time_s as"
    with pytest.raises(InputError, match=said):
        read_run(tmp_path / "clock.parquet")
    with pytest.raises(InputError, match=said):
        list(batches(tmp_path / "clock.parquet", 1000, lambda c: True))


def test_refusals_of_a_recorder_s_own_export_say_what_to_write(tmp_path):
    """A MATLAB file, a Parquet time of timestamps and a CSV with its index written as a
    column were refused with no fix: each now says what to write."""
    import pandas as pd
    import scipy.io

    scipy.io.savemat(tmp_path / "r.mat", {"time_s": np.arange(5.0)})
    t = pd.Series(pd.date_range("2026-01-01", periods=5, freq="ms"))
    pd.DataFrame({"time_s": t, "x_cmd_mm": np.arange(5.0)}).to_parquet(tmp_path / "t.parquet")
    pd.DataFrame({"time_s": np.arange(5.0), "x_cmd_mm": np.arange(5.0)}).to_csv(
        tmp_path / "i.csv")
    for name, said in (("r.mat", r"MATLAB file, .*; write it as a CSV or Parquet run file"),
                       ("t.parquet", r"timestamp.*; write time_s as seconds"),
                       ("i.csv", r"empty column name .*; a table's index written as a")):
        with pytest.raises(InputError, match=said):
            read_run(tmp_path / name)



@pytest.mark.parametrize("unit, factor", [("um", 1e3), ("nm", 1e6), ("m", 1e-3)])
def test_positions_in_the_unit_their_column_names_read_as_in_mm(tmp_path, unit, factor):
    """A TCP device or a ballbar's export that logs in um names it in the header
    (``x_tcp_um``): every command refused it as an unknown column. Each position column
    may name um, nm or m; the run read is the mm file's (to the CSV's 10 digits). A
    second column of one sensor, in another unit, is refused rather than one dropped."""
    import pandas as pd

    write_run(_run(), tmp_path / "mm.csv")
    df = pd.read_csv(tmp_path / "mm.csv")
    names = {c: c[:-2] + unit for c in df.columns if c.endswith("_mm") and "_cmd_" not in c}
    df = df.assign(**{u: df[c] * factor for c, u in names.items()}).drop(columns=list(names))
    df.to_csv(tmp_path / "u.csv", index=False)
    got, want = read_run(tmp_path / "u.csv"), read_run(tmp_path / "mm.csv")
    for a in "XY":
        for s in ("cmd", "motor", "scale", "tcp", "current"):
            np.testing.assert_allclose(getattr(got.axes[a], s), getattr(want.axes[a], s),
                                       rtol=1e-9, atol=1e-15)
    df.assign(x_tcp_mm=df[f"x_tcp_{unit}"] / factor).to_csv(tmp_path / "two.csv", index=False)
    with pytest.raises(InputError, match="a second column of x's tcp"):
        read_run(tmp_path / "two.csv")


def test_a_parquet_run_read_in_chunks_refuses_positions_in_another_unit(tmp_path):
    """Read a chunk at a time, the contour takes the run file's own column names: a TCP
    in um would be left out unsaid. It is refused, naming the column and the fix."""
    import pandas as pd

    from tcpmm.analysis.contour_stream import stream_contour

    write_run(_run(), tmp_path / "mm.parquet")
    df = pd.read_parquet(tmp_path / "mm.parquet")
    df.assign(x_tcp_um=df.x_tcp_mm * 1e3).drop(columns="x_tcp_mm").to_parquet(
        tmp_path / "um.parquet", index=False)
    with pytest.raises(InputError, match=r"in um: write it in mm \(x_tcp_mm\)"):
        stream_contour(tmp_path / "um.parquet", ("X", "Y"), True, rows=100)


def test_a_parquet_run_file_stores_no_definition_levels(tmp_path):
    """Every cell of a run holds a value, so its columns are written required, not
    nullable: Parquet then stores no definition level a cell (a seventh of the writing of
    a 1 M-block run). Whole and in pieces, every column reads back the same bits and
    dtype as written."""
    import pyarrow.parquet as pq

    from tcpmm.io.runfile import run_parquet_writer

    run = _run(1000)
    write_run(run, tmp_path / "w.parquet")
    with run_parquet_writer(tmp_path / "r.parquet") as write:
        for a, b in itertools.pairwise([0, 400, 1000]):
            write(_piece(run, a, b))
    for name in ("w.parquet", "r.parquet"):
        f = pq.ParquetFile(tmp_path / name)
        schema = f.metadata.schema
        assert [schema.column(k).max_definition_level for k in range(len(schema))] == [
            0] * len(schema)
        table = f.read()
        for c, v in run.columns().items():
            got = table.column(c).to_numpy()
            assert got.dtype == (v.dtype if v.dtype.kind == "i" else np.float64)
            assert got.tobytes() == np.asarray(v, got.dtype).tobytes(), c
