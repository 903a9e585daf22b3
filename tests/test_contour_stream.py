"""Corners of a run read in chunks: every figure of every corner is the whole run's to the
bit, with the chunk boundaries falling anywhere, inside corners, rests and blends."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

from tcpmm.analysis.contour import contour_error
from tcpmm.analysis.contour_corners import CornerStream
from tcpmm.analysis.contour_stream import stream_contour
from tcpmm.analysis.corners import find_corners
from tcpmm.cli import main
from tcpmm.io.runfile import read_run
from tcpmm.path.program import program_to_command
from tcpmm.sim.simulate import simulate

#: a G64 zig-zag, sharp and blended corners of 60 to 170 degrees, an exact-stop square
#: (the command rests on each corner), a dwell, reversals along an axis and a diagonal, and
#: an arc out and back (its passes tie within their chords' sag), an arc that turns back
#: onto a line (a cusp): corners with and without rests
PROGRAM = "\n".join([
    "G21 G90 G64 P0.01", "G1 X0 Y0 F2000",
    *[f"G1 X{(i % 2) * 2:.3f} Y{i * 0.4:.3f}" for i in range(1, 9)],
    "G64 P0", "G1 X0.5 Y4", "G1 X1 Y3.8", "G1 X1.2 Y4.5",
    "G61", "G1 X3 Y4.5", "G1 X3 Y6", "G1 X1 Y6", "G4 P0.05", "G1 X1 Y4.5",
    "G64", "G1 X1 Y7", "G1 X1 Y6", "G1 X2.5 Y7.5", "G1 X1.5 Y6.5", "G1 X1.5 Y8",
    "G3 X3.5 Y8 I1 J0", "G2 X1.5 Y8 I-1 J0", "G1 X1.5 Y9", "G3 X3.5 Y9 R1",
    "G1 X3.8 Y7.5", "M30"]) + "\n"


def quiet(fn, *args, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fn(*args, **kw)


@pytest.fixture(scope="module")
def run_file(vmc, tmp_path_factory):
    path = tmp_path_factory.mktemp("corners") / "run.parquet"
    quiet(simulate, vmc, quiet(program_to_command, PROGRAM)).write(path)
    return path


def same(a, b) -> bool:
    """Equal to the bit, NaN equal to NaN."""
    return a == b or (a != a and b != b)


def assert_same_corners(got, want):
    assert len(got) == len(want)
    for g, w in zip(got, want, strict=True):
        assert set(g) == set(w)
        for k, v in w.items():
            if isinstance(v, dict):
                assert all(same(g[k][f], x) for f, x in v.items()), (w["number"], k, g[k], v)
            else:
                assert same(g[k], v), (w["number"], k)


def test_the_program_has_corners_of_every_kind(run_file):
    res = contour_error(read_run(run_file), plane=("X", "Y"))
    turns = [c["turn_rad"] for c in res.corners]
    assert len(turns) >= 14 and np.isnan(turns[-1])
    assert all(np.degrees(v) > 30 for v in turns[:-1])
    over = [c["tcp"]["overshoot_m"] for c in res.corners]
    settle = [c["tcp"]["settle_s"] for c in res.corners]
    assert max(over) > 0 and any(v == v for v in settle) and any(v != v for v in settle)


@pytest.mark.parametrize("cores", [1, 2])  # 2: the corners take the chunks in a thread
@pytest.mark.parametrize("rows", [5, 37, 97, 1000, 10**6])
def test_corners_in_chunks_are_the_whole_runs(run_file, rows, cores, monkeypatch):
    from tcpmm.analysis import contour_stream

    monkeypatch.setattr(contour_stream, "usable_cores", lambda: cores)
    ref = contour_error(read_run(run_file), plane=("X", "Y"))
    res = stream_contour(run_file, ("X", "Y"), True, rows=rows)
    assert_same_corners(res.corners, ref.corners)
    assert res.to_dict()["corners"] == ref.to_dict()["corners"]
    # the program ends without a dwell: the run stops before the machine is at rest
    assert res.unreached == ref.unreached and set(ref.unreached) == set(ref.errors)


@pytest.mark.parametrize("rows", [5, 37, 97])
def test_each_samples_error_in_chunks_is_the_whole_runs(run_file, rows):
    """The error and its sign sample by sample, where the passes out and back along the
    arc tie within their chords' sag that each chunk takes from the path before it."""
    ref = contour_error(read_run(run_file), plane=("X", "Y"))
    got = {}
    stream_contour(run_file, ("X", "Y"), True, rows=rows,
                   each=lambda s, e: got.setdefault(s, []).append(e))
    for s, e in ref.errors.items():
        assert np.array_equal(np.concatenate(got[s]), e), s


def test_a_fault_of_the_corners_thread_reaches_the_caller(run_file, monkeypatch):
    import threading

    from tcpmm.analysis import contour_stream
    from tcpmm.analysis.contour_corners import CornerStream

    def fails(self, *args):
        raise RuntimeError("corners failed")

    monkeypatch.setattr(contour_stream, "usable_cores", lambda: 2)
    monkeypatch.setattr(CornerStream, "add_samples", fails)
    before = threading.active_count()
    with pytest.raises(RuntimeError, match="corners failed"):
        stream_contour(run_file, ("X", "Y"), True, rows=37)
    assert threading.active_count() == before


def test_corners_of_other_settings_and_in_3d(run_file):
    run = read_run(run_file)
    for kw in ({"corner_deg": 60.0, "settle_tol_m": 0.2e-6},
               {"corner_deg": 20.0, "corner_span_m": 0.2e-3, "settle_tol_m": 5e-6}):
        ref = contour_error(run, plane=None, **kw)
        res = stream_contour(run_file, ("X", "Y", "Z"), False, rows=41, **kw)
        assert_same_corners(res.corners, ref.corners)


def test_corners_fed_a_row_at_a_time_are_found_once(run_file):
    """A command given in pieces of any size (here one and three rows) finds the corners
    of :func:`find_corners` on the whole; the samples come later, once the command is in
    a window past them (where the path comes back on itself a sample's closest point may
    lie on the way back), as the stream gives them."""
    ref = contour_error(read_run(run_file), plane=("X", "Y"))
    want = find_corners(ref.command)
    assert [i for i, _ in want] == [c["index"] for c in ref.corners]
    feet = _feet(ref)
    for piece in (1, 3):
        cs = CornerStream()
        for k in range(0, ref.command.shape[0], piece):
            cs.add_command(ref.command_time_s[k:k + piece], ref.command[k:k + piece])
            lag = slice(max(k - 250, 0), max(k - 250 + piece, 0)) if k >= 250 else slice(0, 0)
            if lag.stop > lag.start:
                _samples(cs, ref, feet, lag)
        _samples(cs, ref, feet, slice(max(ref.command.shape[0] - 250, 0), None))
        assert_same_corners(cs.finish(), ref.corners)


def _feet(ref):
    """Each sample's closest point on the whole command, per signal [-]."""
    from tcpmm.analysis.contour import distance_to_polyline

    return {s: distance_to_polyline(q, ref.command, ref.time_s, ref.command_time_s, 0.2,
                                    True)[1] for s, q in ref.actual.items()}


def _samples(cs, ref, feet, k):
    cs.add_samples(ref.time_s[k], {s: q[k] for s, q in ref.actual.items()},
                   {s: e[k] for s, e in ref.errors.items()}, {s: f[k] for s, f in feet.items()})


def test_the_cli_streams_the_corner_table(run_file, capsys):
    out = []
    for extra in ([], ["--chunk-rows", "53"]):
        code = main(["contour", str(run_file), "--plane", "XY", "--json", "--corner-deg",
                     "45", "--settle-um", "2", *extra])
        cap = capsys.readouterr()
        assert code == 0, cap.err
        out.append(json.loads(cap.out))
    assert out[1]["corners"] == out[0]["corners"] and len(out[0]["corners"]) > 30
    code = main(["contour", str(run_file), "--plane", "XY", "--chunk-rows", "53"])
    assert code == 0 and "corners, tcp" in capsys.readouterr().out


def test_the_cli_writes_the_corners_without_the_whole_table(run_file, capsys, monkeypatch):
    """``--json`` writes the corners as they are made, not a list of every corner of every
    sensor turned into one text (a 10 M-block zig-zag took 5 GB so): the same JSON as the
    whole result's, whole and in chunks."""
    from tcpmm.analysis.contour import ContourResult
    from tcpmm.analysis.contour_stream import StreamedContour

    whole = ContourResult.to_dict
    results = []

    def no_rows(self, corners=True):
        assert not corners, "every corner's row made at once"
        results.append(self)
        return whole(self, corners)

    for cls in (ContourResult, StreamedContour):
        monkeypatch.setattr(cls, "to_dict", no_rows)
    for extra in ([], ["--chunk-rows", "53"]):
        code = main(["contour", str(run_file), "--plane", "XY", "--json", *extra])
        cap = capsys.readouterr()
        assert code == 0, cap.err
        got = json.loads(cap.out)
        assert len(got["corners"]) > 30 and got == json.loads(json.dumps(
            whole(results[-1]), allow_nan=True).replace("NaN", "null"))


def test_a_streamed_contour_shows_the_rows_measured_on_a_terminal(run_file, monkeypatch,
                                                                   capsys):
    """On a terminal a bar counts the rows measured up to the run's; in a pipe there is
    none (the other tests run in one)."""
    import io

    from rich.console import Console

    from tcpmm.analysis.contour_parquet import parquet_rows
    from tcpmm.cli import _stream

    screen = io.StringIO()
    monkeypatch.setattr(_stream, "console", Console(file=screen, force_terminal=True,
                                                     width=120))
    assert main(["contour", str(run_file), "--plane", "XY", "--chunk-rows", "500"]) == 0
    total = parquet_rows(run_file)
    shown = screen.getvalue()
    assert f"{total}/{total}" in shown and "rows" in shown
    assert f"/{total}" in shown.split(f"{total}/{total}")[0]  # counted up to it
    assert "rows" not in capsys.readouterr().err


@pytest.mark.parametrize(("column", "row", "value", "message"), [
    ("x_tcp_mm", 120, None, "value is missing or not a number (row 120)"),
    ("y_scale_mm", 7, float("inf"), "value is missing or not a number (row 7)"),
    ("time_s", 200, float("nan"), "time is missing or not a number (row 200)"),
    ("time_s", 150, 0.0, "time must increase strictly (row 150)")])
def test_a_run_read_in_chunks_is_checked_as_a_whole_one(run_file, tmp_path, capsys, column,
                                                      row, value, message):
    """A gap, a number that is not finite or a time that goes back, in any chunk: the
    error of the whole run's reader, with its row, and no figure."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    table = pq.read_table(run_file)
    values = table.column(column).to_pylist()
    values[row - 1] = value
    bad = tmp_path / "bad.parquet"
    pq.write_table(table.set_column(table.column_names.index(column), column,
                                    pa.array(values, pa.float64())), bad, row_group_size=64)
    for extra in ([], ["--chunk-rows", "53"]):
        code = main(["contour", str(bad), "--plane", "XY", *extra])
        cap = capsys.readouterr()
        assert code == 2 and not cap.out
        assert message in cap.err and column in cap.err


@pytest.mark.parametrize("defect", ["no time", "no command", "no sensor", "text"])
def test_a_run_without_what_it_needs_is_refused_in_chunks_as_whole(run_file, tmp_path, capsys,
                                                                 defect):
    """The same error, with no traceback and no figure, whether the run is read whole or in
    chunks."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    table = pq.read_table(run_file)
    if defect == "text":
        table = table.set_column(1, table.column_names[1], pa.array(["1.0"] * table.num_rows))
    else:
        drop = {"no time": ("time_s",), "no command": ("x_cmd_mm",),
                "no sensor": tuple(c for c in table.column_names
                                   if c.split("_")[1:2] in (["motor"], ["scale"], ["tcp"]))
                }[defect]
        table = table.drop(list(drop))
    pq.write_table(table, bad := tmp_path / "bad.parquet")
    errs = []
    for extra in ([], ["--chunk-rows", "53"]):
        code = main(["contour", str(bad), "--plane", "XY", *extra])
        cap = capsys.readouterr()
        assert code == 2 and not cap.out and "Traceback" not in cap.err
        errs.append(cap.err)
    assert errs[0] == errs[1] and errs[0].startswith("error: ")


def test_a_tape_reads_back_across_its_file_and_memory():
    from tcpmm.analysis.tape import Tape

    tape, rows = Tape(spill_rows=11), np.column_stack([np.arange(47.0) * 0.5,
                                                        np.arange(47.0) ** 2])
    for k in range(0, 47, 6):  # blocks of 6 rows, to the file past 11
        tape.add(rows[k:k + 6])
    assert tape.in_file == 36 and tape.in_mem == 11
    for a, b in ((0, 47), (3, 41), (40, 44), (43, 47), (12, 13)):
        assert np.array_equal(tape.rows(a, b), rows[a:b])
        assert np.array_equal(tape.column(a, b, 1, block=4), rows[a:b, 1])
    for x in (-1.0, 0.0, 2.75, 3.0, 20.5, 23.0, 99.0):
        for side in ("left", "right"):
            assert tape.count(x, side) == np.searchsorted(rows[:, 0], x, side=side)
    tape.close()


def test_long_settling_stretches_go_to_disk_and_give_the_same(run_file, monkeypatch):
    from tcpmm.analysis import contour_corners, tape

    ref = contour_error(read_run(run_file), plane=("X", "Y"))
    monkeypatch.setattr(tape, "SPILL_ROWS", 50)
    monkeypatch.setattr(contour_corners, "_BACK_ROWS", 7)
    assert_same_corners(stream_contour(run_file, ("X", "Y"), True, rows=61).corners,
                        ref.corners)


def test_corners_of_a_run_without_sensors_are_found_without_figures():
    """Samples with no sensor's points still go through the corners: they are found, and
    carry no figures."""
    t = np.arange(0.0, 2.0, 1e-3)
    p = np.column_stack([np.minimum(t, 1.0) * 0.01, np.maximum(t - 1.0, 0.0) * 0.01])
    cs = CornerStream()
    cs.add_command(t, p)
    cs.add_samples(t, {}, {}, {})
    got = cs.finish()
    assert [c["number"] for c in got] == [1, 2]
    assert got[0]["index"] == 1000 and np.isnan(got[1]["turn_rad"])
    assert not any(k in c for c in got for k in ("tcp", "scale", "motor"))


def test_a_corner_on_a_tape_lets_go_of_its_batches(tmp_path, monkeypatch):
    """A path's one corner and a long leg after it (a spiral's lead-in, then the spiral):
    once the corner's stretch is on a tape, the batches its samples came in are let go.
    They were kept to the end of the run, some 75 bytes a sample: 1.8 GB on a spiral of
    10 M blocks."""
    from tcpmm.analysis import contour_corners, corner_store, tape
    from tcpmm.result import AxisRun, Run

    leg = 6000
    x = np.r_[np.linspace(0.0, 0.05, 1001), np.full(leg + 300, 0.05)]
    y = np.r_[np.zeros(1001), np.linspace(0.0, leg * 5e-5, leg), np.full(300, leg * 5e-5)]
    t = np.arange(x.size) * 1e-3
    lag = np.r_[x[:1], x[:-1]]
    run = Run(t, {"X": AxisRun(cmd=x, motor=lag, scale=lag, tcp=lag),
                  "Y": AxisRun(cmd=y, motor=y, scale=y, tcp=y)})
    path = tmp_path / "leg.parquet"
    run.write(path)
    held, add = [], corner_store.CornerStore.add

    def counting(self, *args):
        add(self, *args)
        held.append(len(self.batches))

    monkeypatch.setattr(corner_store.CornerStore, "add", counting)
    monkeypatch.setattr(tape, "SPILL_ROWS", 50)
    monkeypatch.setattr(contour_corners, "_BACK_ROWS", 7)
    got = stream_contour(path, ("X", "Y"), True, rows=61)
    assert len(held) > 100 and max(held) < 20 and held[-1] <= 1, held
    assert_same_corners(got.corners, contour_error(run, plane=("X", "Y")).corners)


def test_a_run_recorded_coarsely_is_said_to_cut_its_bends(tmp_path, capsys):
    """A square at F4000 recorded every 50 ms: its command samples cut the corners by
    0.3 mm, and the contour error measured against them read 13 um where the run recorded
    every 1 ms reads 55 um, with no word. The command's chord sag is now in --json, whole
    and in chunks alike, and said on stderr where it may move the contour error."""
    nc = tmp_path / "square.nc"
    nc.write_text("G21 G90 G64 P0.01\nG1 X0 Y0 F4000\nG1 X30\nG1 Y30\nG1 X0\nG1 Y0\nM30\n")
    sags = {}
    for period in ("0.001", "0.05"):
        run = tmp_path / f"run_{period}.parquet"
        assert main(["simulate", "builtin:vmc", "--gcode", str(nc), "-o", str(run),
                     "--record-period-s", period]) == 0
        capsys.readouterr()
        got = []
        for extra in ([], ["--chunk-rows", "37"]):
            assert main(["contour", str(run), "--json", *extra]) == 0
            cap = capsys.readouterr()
            got.append((json.loads(cap.out)["command_sag_um"], "cut the path's bends" in cap.err))
        assert got[0] == got[1]
        sags[period] = got[0]
    assert sags["0.001"][0] < 0.5 and not sags["0.001"][1]
    assert sags["0.05"][0] > 100 and sags["0.05"][1]


#: G0 rapids round a square, then a slow feed arc: recorded every 5 ms, the rapids' errors
#: peak between samples, the arc's do not
RAPID_SQUARE = ("G21 G90 G17\nG0 X20 Y0\nG0 X20 Y20\nG0 X0 Y20\nG0 X0 Y0\nG4 P0.3\n"
                "G1 X10 F300\nG3 X10 Y0 I5 J0\nG4 P0.5\nM30\n")
SQUARE_5MS = "G21 G90 G17 G64 P0.01\nG0 X0 Y0\nG1 X50 F3000\nY50\nX0\nY0\nG4 P0.5\nM30\n"


@pytest.mark.parametrize("program", [SQUARE_5MS, RAPID_SQUARE])
def test_a_peak_read_on_too_few_samples_is_said_in_chunks_too(tmp_path, capsys, program):
    """A square at F3000 recorded every 5 ms: read whole, its largest error is said to be
    read on samples whose neighbours lie well below it ('record the run more finely'); read
    in chunks, nothing was said. It is, the same, wherever the chunks cut the run (three
    rows cut it beside every peak). Where the rapids are left out, the peak said is the
    summary's largest error, whose neighbours may be in a rapid."""
    nc, run = tmp_path / "p.nc", tmp_path / "run.parquet"
    nc.write_text(program)
    assert main(["simulate", "builtin:vmc", "--gcode", str(nc), "-o", str(run),
                 "--record-period-s", "0.005"]) == 0
    capsys.readouterr()
    said = []
    for extra in ([], ["--chunk-rows", "3"], ["--chunk-rows", "4"], ["--chunk-rows", "1000"]):
        assert main(["contour", str(run), *extra]) == 0
        err = " ".join(capsys.readouterr().err.split())
        said.append([t for t in err.split("warning: ") if "more finely" in t])
    assert said[0] and all(s == said[0] for s in said), said


def test_corners_a_coarse_record_cuts_are_not_measured_in_chunks_either(tmp_path, capsys):
    """A square recorded every 50 ms: its samples cut the corners by 0.3 mm, and read whole
    the corners' overshoot and rounding are n/a, as the warning says. Read in chunks the
    same warning came with figures beside it (a rounding of 55 um at the first corner):
    the n/a were set in dicts the corners' columns made afresh for the reading."""
    nc, run = tmp_path / "square.nc", tmp_path / "run.parquet"
    nc.write_text("G21 G90 G64 P0.01\nG1 X0 Y0 F4000\nG1 X30\nG1 Y30\nG1 X0\nG1 Y0\n"
                  "G4 P0.5\nM30\n")
    assert main(["simulate", "builtin:vmc", "--gcode", str(nc), "-o", str(run),
                 "--record-period-s", "0.05"]) == 0
    capsys.readouterr()
    for extra in ([], ["--chunk-rows", "37"]):
        assert main(["contour", str(run), "--json", *extra]) == 0
        cap = capsys.readouterr()
        assert "overshoot and rounding are not given" in " ".join(cap.err.split())
        rows = [r for r in json.loads(cap.out)["corners"] if r["turn_deg"] is not None]
        assert len(rows) >= 9, extra  # three sensors, three corners at least
        assert all(r["rounding_um"] is None and r["overshoot_um"] is None for r in rows), extra


def test_a_run_of_one_row_is_refused_for_what_it_is(tmp_path, capsys):
    """A record period longer than the run keeps one sample; it was refused as a time that
    does not increase, on a file whose one row has nothing before it."""
    run = tmp_path / "one.csv"
    run.write_text("time_s,x_cmd_mm,x_tcp_mm\n0,0,0\n")
    assert main(["contour", str(run)]) != 0
    err = capsys.readouterr().err
    assert "the run has one row" in err and "increase" not in err


def test_a_sensor_of_one_axis_only_is_warned_of_whole_and_in_chunks(run_file, tmp_path):
    """A run without x_tcp_mm but with y_tcp_mm: `tcpmm contour` left the tcp out in
    silence, where `tcpmm circle` says so; the user lost the sensor without a word."""
    import pandas as pd

    from tcpmm.errors import InputWarning

    path = tmp_path / "no_x_tcp.parquet"
    pd.read_parquet(run_file).drop(columns=["x_tcp_mm"]).to_parquet(path)
    said = "the tcp signal is present for Y but not for X; the tcp sensor is left out"
    with pytest.warns(InputWarning, match=said):
        res = contour_error(read_run(path), plane=("X", "Y"))
    assert "tcp" not in res.errors
    with pytest.warns(InputWarning, match=said):
        quiet_but(InputWarning, stream_contour, path, ("X", "Y"), True, rows=500)


def quiet_but(kind, fn, *args, **kw):
    """``fn(*args, **kw)`` with every warning but those of ``kind`` kept quiet."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        warnings.simplefilter("always", kind)
        return fn(*args, **kw)
