"""Streaming end to end: a program in chunks gives the command, the run and the contour
error of the whole program, to the bit (the run's times to one part in 1e15, the RMS
to 1e-12), in memory bounded by the chunk, not by the program."""

from __future__ import annotations

import json
import math
import warnings

import numpy as np
import pytest

from conftest import run_cli
from tcpmm.analysis.contour import contour_error
from tcpmm.analysis.contour_stream import stream_contour
from tcpmm.cli import main
from tcpmm.errors import InputError, InputWarning, RunFaultWarning
from tcpmm.io.runfile import read_run
from tcpmm.path import InterpolatorSettings
from tcpmm.path.program import program_to_command
from tcpmm.path.stream import StreamInterpolator, stream_program
from tcpmm.sim.axisstream import AxisStream
from tcpmm.sim.simulate import simulate
from tcpmm.sim.streamrun import stream_simulate


def spiral(n: int, feed: float = 3000.0, mode: str = "") -> str:
    lines = [f"G21 G90 {mode}", f"G1 X5 Y0 F{feed:g}"]
    for i in range(1, n + 1):
        r, phi = 5 + 0.0002 * i, i * 0.02
        lines.append(f"G1 X{r * math.cos(phi):.4f} Y{r * math.sin(phi):.4f}")
    return "\n".join([*lines, "M30"]) + "\n"


def zigzag(n: int) -> str:
    lines = ["G21 G90 G64 P0.01", "G1 X0 Y0.5 F2000"]
    lines += [f"G1 X{(i % 2) * 3:.3f} Y{i * 0.5 + 0.5:.3f}" for i in range(1, n + 1)]
    return "\n".join(lines) + "\n"


def arcs(n: int) -> str:
    lines = ["G21 G90 G17", "G1 X10 Y0 F1500"]
    for i in range(n):
        lines.append("G3 X-10 Y0 I-10 J0" if i % 2 == 0 else "G3 X10 Y0 I10 J0")
        if i % 3 == 2:
            lines += ["G4 P0.05", "G1 X10 Y0 Z0.1" if i % 2 == 0 else "G1 X10 Y0 Z0"]
    return "\n".join(lines) + "\n"


def repeated(n: int) -> str:
    """Short blocks, each point given twice (a zero-length move, warned and skipped), and
    a reversal at the end of a long straight run: a deceleration over many blocks."""
    lines = ["G21 G90", "G1 X0 Y0 F6000"]
    for i in range(1, n + 1):
        lines += [f"G1 X{i * 0.2:.3f} Y0"] * 2
    lines += ["G1 X0 Y0"]
    return "\n".join(lines) + "\n"


PROGRAMS = {"spiral": spiral(150), "zigzag": zigzag(30), "arcs": arcs(5),
            "repeated": repeated(60)}
SETTINGS = {"default": InterpolatorSettings(),
            "bell": InterpolatorSettings(filter_kind="bell", filter_time_s=0.016),
            "scurve_blend": InterpolatorSettings(profile="scurve", filter_kind="linear",
                                                 filter_time_s=0.01, blend_tolerance_m=2e-5)}


def quiet(fn, *args, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fn(*args, **kw)


def pieces(text, settings, chunk, ip=None):
    return quiet(lambda: list(stream_program(text, settings, chunk_blocks=chunk,
                                             interpolator=ip)))


@pytest.mark.parametrize("name", list(PROGRAMS))
@pytest.mark.parametrize("how", list(SETTINGS))
@pytest.mark.parametrize("chunk", [1, 4, 37])
def test_chunked_command_is_the_whole_programs(name, how, chunk):
    text, settings = PROGRAMS[name], SETTINGS[how]
    ref = quiet(program_to_command, text, settings)
    got = pieces(text, settings, chunk)
    assert len(got) > 1 or how == "scurve_blend"  # an S-curve brakes over all the blocks
    assert np.array_equal(np.concatenate([p.time_s for p in got]), ref.time_s)
    for axis, x in ref.positions.items():
        assert np.array_equal(np.concatenate([p.positions[axis] for p in got]), x), axis
    assert np.array_equal(np.concatenate([p.path_s_m for p in got]), ref.meta["path_s_m"])


@pytest.mark.parametrize("chunk", [1, 2, 3, 5])
def test_a_chunk_boundary_inside_a_deceleration(chunk):
    """The straight run of 0.2 mm blocks at 6 m/min brakes over many blocks before the
    reversal: the cuts fall inside the braking, whose blocks are held back."""
    text = repeated(60)
    ip = StreamInterpolator()
    got = pieces(text, None, chunk, ip)
    ref = quiet(program_to_command, text)
    assert np.array_equal(np.concatenate([p.positions["X"] for p in got]), ref.positions["X"])
    assert ip.most_held > 5  # the braking distance, in blocks, waited for the next chunk


def test_long_blocks_are_read_fewer_at_a_time(monkeypatch):
    """A program of long blocks: the chunks are sized by the samples a block gives, so
    that no chunk's command passes the samples a command may have at once; read the size
    given, a chunk of them did. The command is the whole program's."""
    import importlib

    from tcpmm.path import stream

    interpolate = importlib.import_module("tcpmm.path.interpolate")  # not the function
    text = arcs(40)  # semicircles of 10 mm radius at F1500, some 1.3 s each
    ref = quiet(program_to_command, text)
    monkeypatch.setattr(interpolate, "MAX_SAMPLES", 25_000)
    with pytest.raises(InputError, match="more than the limit"):
        pieces(text, None, 60)  # 60 blocks at once: some 60 000 samples
    monkeypatch.setattr(stream, "FIRST_CHUNK", 2)
    monkeypatch.setattr(stream, "LEAST_CHUNK", 1)
    monkeypatch.setattr(stream, "CHUNK_SAMPLES", 2_000)
    got = pieces(text, None, 60)
    assert max(p.time_s.size for p in got) <= 25_000
    assert np.array_equal(np.concatenate([p.time_s for p in got]), ref.time_s)
    for axis, x in ref.positions.items():
        assert np.array_equal(np.concatenate([p.positions[axis] for p in got]), x), axis


def short_then_long(short: int, long: int) -> str:
    """``short`` G1 blocks of 0.01 mm at F3000, then ``long`` semicircles of 2 mm radius
    at F1000, some 380 samples each."""
    lines = ["G21 G90 G17", "G0 X0 Y0", "G1 F3000"]
    lines += [f"X{0.01 * i:.2f}" for i in range(1, short + 1)]
    x = 0.01 * short
    lines += [f"G3 X{x + 4 * (i % 2 == 0):.2f} Y0 R2 F1000" for i in range(long)]
    return "\n".join([*lines, "M30"]) + "\n"


def test_blocks_that_turn_long_within_a_chunk_are_planned_in_parts(monkeypatch):
    """Short blocks, then long ones: the chunk after the short ones, sized from the samples
    they gave, held all the semicircles, more samples than a chunk may have, and the valid
    program was refused ('more than the limit ... of a chunk of blocks streamed'). The
    pieces stay about a chunk's samples; the command is the whole program's, to the bit."""
    import importlib

    from tcpmm.path import stream

    interpolate = importlib.import_module("tcpmm.path.interpolate")  # not the function
    text = short_then_long(200, 60)
    ref = quiet(program_to_command, text)
    small = pieces(text, None, 7)
    monkeypatch.setattr(interpolate, "MAX_SAMPLES", 10_000)
    monkeypatch.setattr(stream, "FIRST_CHUNK", 200)
    monkeypatch.setattr(stream, "LEAST_CHUNK", 1)
    monkeypatch.setattr(stream, "CHUNK_SAMPLES", 2_000)
    got = pieces(text, None, 100_000)
    assert ref.time_s.size > 20_000  # the semicircles twice the limit, ten chunks
    assert max(p.time_s.size for p in got) <= 2 * stream.CHUNK_SAMPLES
    assert np.array_equal(np.concatenate([p.time_s for p in got]), ref.time_s)
    for axis, x in ref.positions.items():
        assert np.array_equal(np.concatenate([p.positions[axis] for p in got]), x), axis
    for name in ("path_s_m", "nc_line", "rapid"):
        assert np.array_equal(np.concatenate([getattr(p, name) for p in got]),
                              np.concatenate([getattr(p, name) for p in small])), name


def test_chunk_sizes_follow_the_samples_a_block_gives():
    from tcpmm.path.stream import CHUNK_SAMPLES, FIRST_CHUNK, LEAST_CHUNK, ChunkSize

    size = ChunkSize(100_000)
    assert size() == FIRST_CHUNK
    lines, samples = FIRST_CHUNK, 2 * FIRST_CHUNK
    size.seen(lines, samples)  # 2 samples a block: twice as many blocks, no more at once
    assert size() == 2 * FIRST_CHUNK
    while size() < 100_000:  # up to as many as allowed
        lines, samples = lines + size(), samples + 2 * size()
        size.seen(lines, samples)
    assert size() == 100_000
    # the blocks turn long: sized by the last chunk's, not by the short ones before
    lines, samples = lines + 1_000, samples + 1_000 * CHUNK_SAMPLES // 2_000
    size.seen(lines, samples)
    assert size() == 2_000
    size.seen(lines + 1_000, samples)  # nothing given out yet: kept
    assert size() == 2_000
    size.seen(lines + 2_000, samples + 2_000 * CHUNK_SAMPLES)  # a block lasting long
    assert size() == LEAST_CHUNK
    assert ChunkSize(3)() == 3  # fewer asked for: never more


def test_the_held_tail_does_not_grow_with_the_program():
    held = []
    for n in (200, 800):
        ip = StreamInterpolator()
        pieces(spiral(n), None, 20, ip)
        held.append(ip.most_held)
    assert held[1] <= held[0] + 2 and held[1] < 60


def run_pieces(machine, text, chunk):
    """The records of each axis, run on the command piece by piece [SI]."""
    got = pieces(text, None, chunk)
    axes = {a: AxisStream(machine.axes[a], 1e-3) for a in machine.axes}
    out = {a: [] for a in axes}
    for k, p in enumerate(got):
        for a, s in axes.items():
            out[a].append(s.push(p.positions[a], k == len(got) - 1, float(p.time_s[-1])))
    return out, axes


@pytest.mark.parametrize("name", ["spiral", "zigzag", "arcs"])
@pytest.mark.parametrize("chunk", [3, 29])
def test_kernel_state_is_carried_to_the_bit(vmc, name, chunk):
    text = PROGRAMS[name]
    ref = quiet(simulate, vmc, quiet(program_to_command, text))
    out, _ = run_pieces(vmc, text, chunk)
    for a in vmc.axes:
        for sig in ("cmd", "motor", "scale", "tcp", "current", "motor_speed", "current_peak"):
            got = np.concatenate([getattr(r, sig) for r in out[a]])
            assert np.array_equal(got, getattr(ref.axes[a], sig)), (a, sig)


def test_the_samples_an_axis_holds_stay_bounded(vmc):
    most = []
    for n in (150, 600):
        _, axes = run_pieces(vmc, spiral(n), 10)
        most.append(max(s.most_held for s in axes.values()))
    assert most[1] <= most[0] + 5


def test_stream_simulate_is_simulate(vmc):
    text = PROGRAMS["arcs"]
    ref = quiet(simulate, vmc, quiet(program_to_command, text))
    runs = quiet(lambda: list(stream_simulate(vmc, text, chunk_blocks=2)))
    t = np.concatenate([r.time_s for r in runs])
    assert np.allclose(t, ref.time_s, rtol=1e-15, atol=0.0)
    for a in vmc.axes:
        assert np.array_equal(np.concatenate([r.axes[a].tcp for r in runs]), ref.axes[a].tcp)


def _slow_workers(monkeypatch, log):
    """AxisStream.push logging whether the main thread runs it, and slow in worker
    threads, so that the main thread finds axes no worker has started [-]."""
    import threading
    import time

    push = AxisStream.push

    def logged(self, *args, **kw):
        main_thread = threading.current_thread() is threading.main_thread()
        if not main_thread:
            time.sleep(0.01)
        log.append(main_thread)
        return push(self, *args, **kw)

    monkeypatch.setattr(AxisStream, "push", logged)


def test_axes_the_main_thread_takes_over_run_in_order(vmc, monkeypatch):
    text = PROGRAMS["arcs"]
    ref = quiet(simulate, vmc, quiet(program_to_command, text))
    log = []
    _slow_workers(monkeypatch, log)
    runs = quiet(lambda: list(stream_simulate(vmc, text, chunk_blocks=2, threads=2)))
    assert set(log) == {True, False}  # both threads ran pieces of axes
    for a in vmc.axes:
        assert np.array_equal(np.concatenate([r.axes[a].tcp for r in runs]), ref.axes[a].tcp)
        assert np.array_equal(np.concatenate([r.axes[a].current for r in runs]),
                              ref.axes[a].current)


def test_a_piece_runs_before_the_next_is_interpolated(vmc, monkeypatch):
    """The axes take a piece as soon as it is interpolated (the end of the command is
    told them after the last): the workers start a chunk earlier, and the run is the
    same."""
    from tcpmm.sim import streamrun

    log = []
    pieces, push = streamrun.stream_program, AxisStream.push

    def logged_pieces(*args, **kw):
        for piece in pieces(*args, **kw):
            log.append("piece")
            yield piece

    def logged_push(self, *args, **kw):
        log.append("push")
        return push(self, *args, **kw)

    monkeypatch.setattr(streamrun, "stream_program", logged_pieces)
    monkeypatch.setattr(AxisStream, "push", logged_push)
    text = PROGRAMS["zigzag"]
    runs = quiet(lambda: list(stream_simulate(vmc, text, chunk_blocks=3, threads=1)))
    assert log[:2] == ["piece", "push"]
    ref = quiet(simulate, vmc, quiet(program_to_command, text))
    for a in vmc.axes:
        assert np.array_equal(np.concatenate([r.axes[a].scale for r in runs]),
                              ref.axes[a].scale)


def test_a_stream_given_up_early_ends_its_workers(vmc, monkeypatch):
    import threading

    log = []
    _slow_workers(monkeypatch, log)
    before = threading.active_count()
    gen = stream_simulate(vmc, PROGRAMS["spiral"], chunk_blocks=5, threads=2)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        next(gen)
        gen.close()
    assert threading.active_count() == before


def test_contour_in_chunks_is_the_whole_runs(vmc, tmp_path):
    text = PROGRAMS["zigzag"]
    run = quiet(simulate, vmc, quiet(program_to_command, text))
    run.write(tmp_path / "run.parquet")
    ref = contour_error(read_run(tmp_path / "run.parquet"), plane=("X", "Y"))
    errors = {}
    res = stream_contour(tmp_path / "run.parquet", ("X", "Y"), True, rows=97,
                         each=lambda s, e: errors.setdefault(s, []).append(e))
    for s, e in ref.errors.items():
        assert np.array_equal(np.concatenate(errors[s]), e), s
        got, want = res.summary()[s], ref.summary()[s]
        assert all(got[k] == want[k] for k in ("max_abs_m", "max_m", "min_m"))
        assert got["rms_m"] == pytest.approx(want["rms_m"], rel=1e-12)
    assert res.most_rows < 97 + 2 * 400  # a chunk and the windows around it (0.2 s)


def test_cli_writes_row_groups_that_contour_reads(vmc, tmp_path, capsys, monkeypatch):
    import pyarrow.parquet as pq

    from tcpmm.io import runwrite

    # groups of a thousand rows, so that this short run has several
    monkeypatch.setattr(runwrite, "LEAST_ROW_GROUP_ROWS", 1000)
    prog = tmp_path / "zig.nc"
    prog.write_text(PROGRAMS["zigzag"])
    out = tmp_path / "run.parquet"
    code, _, err = run_cli(capsys, "simulate", "builtin:vmc", "--gcode", prog, "-o", out,
                       "--chunk-blocks", 5)
    assert code == 0, err
    meta = pq.ParquetFile(out).metadata
    rows = [meta.row_group(k).num_rows for k in range(meta.num_row_groups)]
    assert len(rows) > 2 and min(rows[:-1]) >= 1000
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]  # no temp file
    quiet(simulate, vmc, quiet(program_to_command, prog)).write(tmp_path / "whole.parquet")
    run, ref = read_run(out), read_run(tmp_path / "whole.parquet")  # both through mm
    for a in "XYZ":
        assert np.array_equal(run.axes[a].tcp, ref.axes[a].tcp)
        assert np.array_equal(run.axes[a].current, ref.axes[a].current)
    code, whole, _ = run_cli(capsys, "contour", out, "--plane", "XY", "--json")
    code2, chunked, _ = run_cli(capsys, "contour", out, "--plane", "XY", "--json",
                            "--chunk-rows", 300)
    assert code == code2 == 0
    a, b = json.loads(whole)["sensors"], json.loads(chunked)["sensors"]
    for s in a:
        assert a[s]["max_abs_um"] == b[s]["max_abs_um"]
        assert a[s]["rms_um"] == pytest.approx(b[s]["rms_um"], rel=1e-12)


@pytest.mark.parametrize("chunk", [1, 7])
def test_a_run_streamed_a_block_at_a_time_is_not_a_row_group_a_block(tmp_path, capsys,
                                                                       chunk):
    """Each piece was a row group, and Arrow keeps some 15 KB a row group until the file
    closes (twice that at the close): at one block a chunk the peak memory grew by 32 KB a
    block. A run shorter than a row group is one, the whole run's rows."""
    import pyarrow.parquet as pq

    prog = tmp_path / "p.nc"
    prog.write_text(PROGRAMS["spiral"])
    for out, more in (("whole.parquet", ()), ("run.parquet", ("--chunk-blocks", chunk))):
        code, _, err = run_cli(capsys, "simulate", "builtin:vmc", "--gcode", prog, "-o",
                               tmp_path / out, *more)
        assert code == 0, err
    streamed = pq.ParquetFile(tmp_path / "run.parquet")
    assert streamed.metadata.num_row_groups == 1
    assert streamed.read().equals(pq.read_table(tmp_path / "whole.parquet"))


def test_a_command_written_a_piece_at_a_time_leaves_no_garbage_cycles(tmp_path):
    """``np.savetxt`` made a class of its own at every piece: garbage in a reference
    cycle, which the command line's lazy first collection kept (3 KB a piece of one
    block). The text is the same. The file is written twice and the second counted: what
    a first use leaves once (a module's lazy import, a cache filled) is no garbage a
    piece, and whether a test before had left it moved the count."""
    import gc

    from tcpmm.path.commandfile import command_csv_writer

    t = np.arange(5) * 1e-3
    pos = {a: t * (k + 1) for k, a in enumerate("XYZ")}
    blocks = (np.arange(5, dtype=np.int32) + 3, np.array([0, 1, 1, 0, 0], np.int8))
    for _ in range(2):
        gc.collect()
        with command_csv_writer(tmp_path / "c.csv", blocks=True) as w:
            for k in range(0, 5, 2):
                w.write(t[k:k + 2], {a: v[k:k + 2] for a, v in pos.items()},
                        tuple(b[k:k + 2] for b in blocks))
    assert gc.collect() == 0
    assert (tmp_path / "c.csv").read_text().splitlines()[:3] == [
        "time_s,x_mm,y_mm,z_mm,nc_line,rapid",
        "0.000000000000,0.000000000,0.000000000,0.000000000,3,0",
        "0.001000000000,1.000000000,2.000000000,3.000000000,4,1"]


@pytest.mark.parametrize("name", ["zigzag", "arcs"])
def test_a_streamed_runs_summary_says_what_the_whole_runs_does(tmp_path, capsys, name):
    """``simulate --json`` of a run streamed to Parquet gave no ``meta`` (the interpolator's
    settings, the path's length, the program, the model), where the same run to CSV did."""
    prog = tmp_path / "p.nc"
    prog.write_text(PROGRAMS[name])
    said = {}
    for out, more in (("run.csv", ()), ("run.parquet", ("--chunk-blocks", 4))):
        code, text, err = run_cli(capsys, "simulate", "builtin:vmc", "--gcode", prog, "-o",
                              tmp_path / out, "--json", *more)
        assert code == 0, err
        said[out] = json.loads(text)
    whole, streamed = said["run.csv"], said["run.parquet"]
    assert streamed["meta"] == whole["meta"]
    assert streamed["meta"]["path_length_m"] > 0
    assert {k: v for k, v in streamed.items() if k != "output"} == {
        k: v for k, v in whole.items() if k != "output"}


def test_a_bad_line_far_in_is_named_and_leaves_no_file(tmp_path, capsys):
    lines = ["G21 G90", "G1 X0 Y0 F3000"]
    lines += [f"G1 X{i * 0.01:.3f} Y{(i % 7) * 0.01:.3f}" for i in range(1, 3000)]
    lines[2500] = "G1 X1 Y2 Q"
    prog = tmp_path / "bad.nc"
    prog.write_text("\n".join(lines) + "\n")
    with pytest.raises(InputError) as exc:
        pieces(prog, None, 64)
    assert exc.value.line == 2501 and exc.value.column is not None
    assert str(prog) in str(exc.value)
    out = tmp_path / "run.parquet"
    code, _, err = run_cli(capsys, "simulate", "builtin:vmc", "--gcode", prog, "-o", out,
                       "--chunk-blocks", 100)
    assert code == 2 and "line 2501" in err and "Traceback" not in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.nc"]


@pytest.mark.parametrize("name", ["spiral", "arcs"])  # Z kept where it moves, else not
def test_cli_path_in_chunks_writes_the_same_file(tmp_path, capsys, name):
    prog = tmp_path / "p.nc"
    prog.write_text(PROGRAMS[name])
    assert run_cli(capsys, "path", prog, "-o", tmp_path / "a.csv")[0] == 0
    assert run_cli(capsys, "path", prog, "-o", tmp_path / "b.csv", "--chunk-blocks", 3)[0] == 0
    whole, chunked = (tmp_path / "a.csv").read_bytes(), (tmp_path / "b.csv").read_bytes()
    assert chunked == whole and (b"z_mm" in whole) == (name == "arcs")


def test_chunks_are_asked_only_where_they_stream(tmp_path, capsys):
    prog = tmp_path / "p.nc"
    prog.write_text(PROGRAMS["zigzag"])
    code, _, err = run_cli(capsys, "simulate", "builtin:vmc", "--gcode", prog, "-o",
                       tmp_path / "run.csv", "--chunk-blocks", 5)
    assert code == 2 and "-o RUN.parquet" in err


def test_an_interrupted_stream_leaves_no_file(vmc, tmp_path, monkeypatch):
    """The row groups go to a temporary file that an interrupt removes."""
    from tcpmm.cli import _stream
    from tcpmm.sim import streamrun

    real = streamrun.stream_simulate

    def interrupted(*args, **kw):
        for k, run in enumerate(real(*args, **kw)):
            if k == 2:
                raise KeyboardInterrupt
            yield run

    monkeypatch.setattr(streamrun, "stream_simulate", interrupted)
    prog = tmp_path / "p.nc"
    prog.write_text(PROGRAMS["zigzag"])
    with pytest.raises(KeyboardInterrupt):
        quiet(_stream.simulate_to_parquet, vmc, prog, tmp_path / "run.parquet",
              InterpolatorSettings(), chunk_blocks=3)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["p.nc"]


@pytest.mark.parametrize("case", ["runaway", "saturating"])
def test_faults_of_a_streamed_run_are_the_whole_runs(vmc, case):
    from tcpmm.analysis.runaway import run_faults
    from tcpmm.analysis.runaway_stream import FaultWatch

    if case == "runaway":  # a load on Z its drive cannot hold
        z = vmc.axes["Z"]
        m = vmc.with_axis("Z", z.replace(mechanics=z.mechanics.model_copy(
            update={"load_force": -20000.0})))
    else:  # a current limit the corners reach
        x = vmc.axes["X"]
        m = vmc.with_axis("X", x.replace(servo=x.servo.model_copy(
            update={"current_limit": 0.5})))
    text = PROGRAMS["zigzag"]
    whole = run_faults(m, quiet(simulate, m, quiet(program_to_command, text)))
    watch = FaultWatch(m)
    for run in quiet(lambda: list(stream_simulate(m, text, chunk_blocks=3))):
        watch.add(run)
    got = watch.faults()
    assert whole and [f.axis for f in got] == [f.axis for f in whole]
    for a, b in zip(got, whole, strict=True):
        assert a.deviation_m == b.deviation_m and a.runaway_from_s == b.runaway_from_s
        assert a.saturated_s == pytest.approx(b.saturated_s, rel=1e-12)
        assert a.saturated_from_s == b.saturated_from_s
        assert a.tolerance_m == pytest.approx(b.tolerance_m, rel=1e-12)


def test_a_program_too_long_to_make_whole_points_to_streaming(tmp_path, capsys, monkeypatch):
    """A 300 000-block zig-zag to RUN.csv was refused with "check its feed rate and
    coordinates": the feed was right, the fix is to stream it to Parquet."""
    import importlib

    interpolate = importlib.import_module("tcpmm.path.interpolate")  # not the function
    monkeypatch.setattr(interpolate, "MAX_SAMPLES", 2_000)
    prog = tmp_path / "zz.nc"
    prog.write_text(PROGRAMS["zigzag"])
    code, _, err = run_cli(capsys, "simulate", "builtin:vmc", "--gcode", prog, "-o",
                       tmp_path / "run.csv")
    assert code == 2 and "-o RUN.parquet" in " ".join(err.split())
    code, _, err = run_cli(capsys, "simulate", "builtin:vmc", "--gcode", prog, "-o",
                       tmp_path / "run.parquet", "--chunk-blocks", 5)
    assert code == 0, err


@pytest.mark.parametrize("args", [["path", "{fifo}", "-o", "{out}.csv", "--chunk-blocks", "2"],
                                  ["simulate", "builtin:vmc", "--gcode", "{fifo}", "-o",
                                   "{out}.parquet"]])
def test_a_program_from_a_pipe_streams(tmp_path, capsys, args):
    """A program piped in (`--gcode /dev/stdin`, `<(zcat prog.nc.gz)`) was read three times
    when streamed, for its start, its encoding and its lines, and the third found the pipe
    empty: 'the program has no motion'. It streams as the file does."""
    import os
    import threading

    text = "G21 G90 G17\nG1 X10 F3000\nG1 Y10\nG1 X0\nM30\n"
    fifo = tmp_path / "prog.nc"
    os.mkfifo(fifo)

    done = threading.Event()

    def feed():
        with open(fifo, "w") as f:
            f.write(text)
        while not done.is_set():  # a reader opening the pipe again finds it empty, not hung
            with open(fifo, "w"):
                pass

    threading.Thread(target=feed, daemon=True).start()  # a daemon: its last open blocks
    out = tmp_path / "out"
    code = main([a.format(fifo=fifo, out=out) for a in args])
    done.set()
    assert code == 0, capsys.readouterr().err
    (tmp_path / "file.nc").write_text(text)
    code = main([a.format(fifo=tmp_path / "file.nc", out=tmp_path / "whole") for a in args])
    assert code == 0
    suffix = ".csv" if args[0] == "path" else ".parquet"
    assert (tmp_path / f"out{suffix}").read_bytes() == (tmp_path / f"whole{suffix}").read_bytes()


def test_a_block_too_long_for_a_stream_is_not_told_to_stream(tmp_path, capsys):
    """G1 X900 F5 lasts three hours, more samples than a chunk holds: the streamed run
    refused it with 'for a program this long, stream it: tcpmm simulate ... -o
    RUN.parquet', the command just run. It says what to check; so does the command made
    whole, which told the program of one such block to stream, and streamed it was refused."""
    prog = tmp_path / "long.nc"
    prog.write_text("G21 G90\nG1 X900 F5\nM30\n")
    assert main(["simulate", "builtin:vmc", "--gcode", str(prog), "-o",
                 str(tmp_path / "run.parquet")]) == 2
    err = " ".join(capsys.readouterr().err.split())
    assert "line 2" in err and "check its feed rate" in err and "stream it" not in err
    assert main(["path", str(prog), "-o", str(tmp_path / "cmd.csv")]) == 2
    err = " ".join(capsys.readouterr().err.split())
    assert "line 2" in err and "check its feed rate" in err and "stream it" not in err


def test_a_program_path_streams_for_its_length_says_so(tmp_path, capsys, monkeypatch):
    """Beyond a million lines `tcpmm path` interpolates in chunks and drops the summary of
    where the feed is held back, without a word why. It says so."""
    import importlib

    run_cli = importlib.import_module("tcpmm.cli.run")  # tcpmm.cli.run: also a function
    monkeypatch.setattr(run_cli, "PATH_STREAM_ABOVE_LINES", 3)
    prog = tmp_path / "p.nc"
    prog.write_text("G21 G90\nG1 X10 F3000\nG1 Y10\nG1 X0\nM30\n")
    assert main(["path", str(prog), "-o", str(tmp_path / "c.csv")]) == 0
    got = capsys.readouterr()
    assert "has more than 3 lines: interpolated in chunks" in " ".join(got.err.split())
    assert "at the programmed feed" not in got.out


@pytest.mark.parametrize("suffix", [".parquet", ".csv"])
def test_json_carries_the_warnings_said_on_stderr(tmp_path, capsys, suffix):
    """--json is the machine interface: a program reading it learned nothing of a move
    skipped, said on stderr only. The warnings go with the JSON, under "warnings"."""
    prog = tmp_path / "rep.nc"
    prog.write_text("G21 G90\nG1 X10 F3000\nG1 X10\nG1 Y10\nM30\n")
    out = tmp_path / f"run{suffix}"
    assert main(["simulate", "builtin:vmc", "--gcode", str(prog), "-o", str(out),
                 "--json"]) == 0
    said = json.loads(capsys.readouterr().out)["warnings"]
    assert len(said) == 1 and "line 3" in said[0] and "zero-length move" in said[0]
    prog.write_text("G21 G90\nG1 X10 F3000\nG1 Y10\nM30\n")
    assert main(["simulate", "builtin:vmc", "--gcode", str(prog), "-o", str(out),
                 "--json"]) == 0
    assert "warnings" not in json.loads(capsys.readouterr().out)


@pytest.mark.parametrize(("suffix", "more"), [(".csv", ()), (".parquet", ()),
                                            (".parquet", ("--chunk-blocks", "2"))])
def test_every_repeated_point_is_counted_g0_as_g1(tmp_path, capsys, suffix, more):
    """Two G0 to where the tool stood were skipped without a word: the summary counted one
    repeated point of three. ``--json`` gives the count as a number too."""
    prog = tmp_path / "rep.nc"
    prog.write_text("G21 G90 G17\nG1 X1 Y0 F3000\nX2\nG0 X2\nG0 X2\nG1 X3\nX3\nM30\n")
    code, text, err = run_cli(capsys, "simulate", "builtin:vmc", "--gcode", prog, "-o",
                              tmp_path / f"run{suffix}", "--json", *more)
    assert code == 0, err
    said = json.loads(text)
    assert said["zero_length_skipped"] == 3
    assert [w for w in said["warnings"] if "zero-length" in w] == [
        f"{prog}, line 4, column 4: zero-length move ignored (and 2 more times): a G0 or G1 "
        "to where the tool already is, skipped"]
    # another file name: the same text from the same place is shown once in one process
    again = tmp_path / "again.nc"
    again.write_text(prog.read_text())
    code, _, err = run_cli(capsys, "path", again, "-o", tmp_path / "cmd.csv", *more)
    assert code == 0 and "zero-length move ignored (and 2 more times)" in " ".join(err.split())


def test_a_disk_that_fills_while_a_piece_is_written_leaves_no_file(tmp_path, capsys,
                                                                   monkeypatch):
    """A piece is written while the next is computed: a disk that fills on the second
    piece ends the command with the reason in one line, the same as when each piece was
    written in turn, and neither the run file nor its temporary one is left."""
    import errno

    import pyarrow.parquet as pq

    real, calls = pq.ParquetWriter.write_table, []

    def full(self, table, *args, **kw):
        calls.append(table.num_rows)
        if len(calls) == 2:
            raise OSError(errno.ENOSPC, "No space left on device")
        return real(self, table, *args, **kw)

    monkeypatch.setattr(pq.ParquetWriter, "write_table", full)
    from tcpmm.io import runwrite

    monkeypatch.setattr(runwrite, "LEAST_ROW_GROUP_ROWS", 1000)  # row groups of this run
    prog = tmp_path / "p.nc"
    prog.write_text(PROGRAMS["zigzag"])
    code, out, err = run_cli(capsys, "simulate", "builtin:vmc", "--gcode", prog, "-o",
                             tmp_path / "run.parquet", "--chunk-blocks", 3)
    assert code == 2 and len(calls) == 2, (code, calls, err)
    assert "No space left on device" in err and "Traceback" not in out + err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["p.nc"]


def test_an_axis_the_machine_lacks_is_refused_when_streamed_too(vmc):
    """A program that moves Z on a model of X and Y: simulate refused the command made
    whole ('drives axis Z that the machine does not have'), but the stream dropped Z and
    ran the rest, a run of a path the program does not have, without a word."""
    xy = vmc.model_copy(update={"axes": {a: vmc.axes[a] for a in "XY"}})
    text = "G21 G90\nG1 X1 F3000\nG1 Y1\nG1 Z0.5\nG1 X0\nM30\n"
    with pytest.raises(InputError, match="drives axis Z that the machine does not have"):
        quiet(simulate, xy, quiet(program_to_command, text))
    with pytest.raises(InputError, match="drives axis Z that the machine does not have"):
        quiet(lambda: list(stream_simulate(xy, text, chunk_blocks=2)))
    # an axis it holds still is no matter, streamed as made whole
    runs = quiet(lambda: list(stream_simulate(xy, text.replace("G1 Z0.5\n", ""),
                                              chunk_blocks=2)))
    assert sum(r.time_s.size for r in runs) > 0


def test_a_command_beyond_any_travel_is_warned_when_streamed_too(vmc):
    """A rapid to X120000. (120 m, a program in micrometres read as millimetres): simulate
    warned 'beyond the travel of any machine tool' of the command made whole; the stream
    said nothing. The same warnings, with the same figures, whatever the chunks. A rapid
    traverse of 20 m/s and a path acceleration of 50 m/s^2 keep the command short."""
    fast = {**vmc.interpolation, "path_accel_m_per_s2": 50.0,
            "rapid_m_per_s": {"X": 20.0, "Y": 20.0, "Z": 20.0}}
    m = vmc.model_copy(update={"interpolation": fast})
    text = "G21 G90\nG1 X1 F3000\nG0 X120000.\nG0 X120001.\nM30\n"

    def said(fn):
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter("always")
            fn()
        # the axis runs away from such a command: a fault, said by the stream's caller
        return [str(x.message) for x in w if issubclass(x.category, InputWarning)
                and not issubclass(x.category, RunFaultWarning)]

    settings = InterpolatorSettings.model_validate(fast)
    whole = said(lambda: simulate(m, quiet(program_to_command, text, settings)))
    assert any("beyond the travel of any machine tool" in t for t in whole)
    for chunk in (1, 100):
        assert said(lambda c=chunk: list(stream_simulate(m, text, chunk_blocks=c))) == whole
