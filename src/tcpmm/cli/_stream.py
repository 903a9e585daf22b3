"""The streaming runs of the command line: a program a chunk of blocks at a time, the run
to Parquet a row group a chunk (short chunks gathered into one), and a progress bar of the
program's lines the results have reached (of the rows measured, for a run's contour
error)."""

from __future__ import annotations

import threading
from contextlib import contextmanager
from pathlib import Path

from ._app import console, on_screen

#: help of ``--chunk-blocks``
CHUNK_HELP = ("Most blocks of the NC program read, interpolated and simulated at a time "
              "(default 100000; fewer where the blocks are long, so that a chunk gives "
              "some 200000 samples); the results do not depend on it, the memory does.")


def count_lines(path: Path) -> int:
    """Lines of a text file (``\\n``, ``\\r\\n`` or ``\\r`` ending them), for the progress
    bar's total [-]."""
    n, last = 0, b""
    with open(path, "rb") as f:
        while block := f.read(1 << 24):
            n += block.count(b"\n") + block.count(b"\r") - block.count(b"\r\n")
            if last == b"\r" and block[:1] == b"\n":
                n -= 1  # a \r\n cut between two blocks
            last = block[-1:]
    return n + (last not in (b"", b"\n", b"\r"))


@contextmanager
def line_progress(program: Path, description: str):
    """A progress bar of the program's lines that the results (the command written, the
    axes simulated) have reached, with the time left, on a terminal.

    It counts lines, comment and blank lines among them, and says so: its total is the
    file's lines, counted by a scan of its bytes (:func:`count_lines`), and where it
    stands the source line of the last command sample out (``nc_line``, the line the
    messages name too). Blocks would need every line lexed once more, for the total
    before the run and for the blocks up to a sample's line during it.

    Yields
    ------
    Bar or None
        ``bar(line)`` and ``bar.end()`` on a terminal; ``None`` in a pipe or a log, where
        nothing is drawn and the work is not followed [-].
    """
    # a pipe is read once, by the interpolation: its length is not known before
    total = (lambda: count_lines(program)) if Path(program).is_file() else (lambda: None)
    with _drawn(total, description, "lines") as bar:
        yield bar


@contextmanager
def count_progress(total, description: str, unit: str):
    """A progress bar of ``total()`` things (counted only on a terminal) named ``unit``,
    with the time left, on a terminal; nothing in a pipe or a log. Yields
    ``update(done)``."""
    with _drawn(total, description, unit) as bar:
        yield bar if bar is not None else (lambda *_: None)


class Bar:
    """A progress bar's count: ``bar(done)`` sets it, never back and never past its total,
    from any thread (the axes report from theirs); ``bar.end()`` sets it to its total.

    Parameters
    ----------
    progress : rich.progress.Progress
        The bars drawn [-].
    task : int
        This bar's task in ``progress`` [-].
    total : int or None
        The count at the end, ``None`` where it is not known [-].
    """

    def __init__(self, progress, task, total):
        self.progress, self.task, self.total = progress, task, total
        self.done = 0
        self.lock = threading.Lock()

    def __call__(self, done) -> None:
        with self.lock:
            done = done if self.total is None else min(done, self.total)
            if done > self.done:
                self.done = done
                self.progress.update(self.task, completed=done)

    def end(self) -> None:
        """The bar at its total, where it is known [-]."""
        if self.total is not None:
            self(self.total)


@contextmanager
def _drawn(total, description: str, unit: str):
    """A :class:`Bar` of ``total()`` things named ``unit`` drawn on a terminal, ``None``
    in a pipe or a log (``total`` is not called there) [-]."""
    if not on_screen(console):
        yield None
        return
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        TextColumn,
        TimeRemainingColumn,
    )

    with Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
                  TextColumn(unit), TimeRemainingColumn(), console=console,
                  transient=True) as p:
        n = total()
        yield Bar(p, p.add_task(description, total=n), n)


def simulate_to_parquet(machine, program: Path, output: Path, settings, *,
                        record_period_s=None, chunk_blocks: int | None = None) -> dict:
    """Simulate an NC program on a model streaming, to a Parquet run file.

    Parameters
    ----------
    machine : Machine
        The model [SI].
    program : Path
        The NC program [-].
    output : Path
        The Parquet run file [-].
    settings : InterpolatorSettings
        Interpolator settings [-].
    record_period_s : float, optional
        Output period [s].
    chunk_blocks : int, optional
        Blocks a chunk, default :data:`tcpmm.path.stream.CHUNK_BLOCKS` [-].

    Returns
    -------
    dict
        ``samples``, ``duration_s``, ``axes``, ``meta`` (the interpolator's settings, the
        path's length, the program and the model, as a run's ``to_dict`` gives them) and
        ``faults`` of the run written (the faults also warned,
        :class:`tcpmm.errors.RunFaultWarning`) [-].
    """
    from ..analysis.runaway import warn_faults
    from ..analysis.runaway_stream import FaultWatch
    from ..io.runfile import run_parquet_writer
    from ..path.interpolate import settings_meta
    from ..path.stream import CHUNK_BLOCKS
    from ..result import scalar_meta
    from ..sim.simulate import refuse_one_record
    from ..sim.streamrun import stream_simulate

    chunk_blocks = chunk_blocks or CHUNK_BLOCKS
    samples, last_t, axes, done, plane = 0, 0.0, None, 0.0, None
    watch = FaultWatch(machine)
    with line_progress(program, "simulate") as bar, run_parquet_writer(output) as write:
        for run in stream_simulate(machine, program, settings, chunk_blocks=chunk_blocks,
                                   record_period_s=record_period_s, progress=bar):
            if run.time_s.size:
                write(run)
                watch.add(run)
                samples += run.time_s.size
                last_t = float(run.time_s[-1])
            axes = axes or run.to_dict()["axes"]
            done = run.meta["path_done_m"] if run.meta["path_done_m"] is not None else done
            plane = run.meta["plane_axes"]
        if samples < 2 and record_period_s is not None:  # before the file is put in place
            refuse_one_record(record_period_s)
        if bar is not None:
            bar.end()
    faults = watch.faults()
    warn_faults(faults)
    meta = {**settings_meta(settings), "path_length_m": done, "file": str(program),
            "plane_axes": plane, "machine": machine.name}
    return {"samples": samples, "duration_s": last_t, "axes": axes, "meta": scalar_meta(meta),
            "faults": [f.to_dict() for f in faults]}


#: a Parquet run of more rows than this is read in chunks by ``tcpmm contour`` [-]
STREAM_ABOVE_ROWS = 2_000_000


def streamed(run_file: Path, chunk_rows: int | None) -> bool:
    """Whether ``tcpmm contour`` reads the run in chunks: a Parquet run, with
    ``--chunk-rows`` or longer than :data:`STREAM_ABOVE_ROWS` [-]."""
    from ..io.runfile import is_parquet

    if not is_parquet(run_file) or not Path(run_file).is_file():
        return False
    from ..analysis.contour_parquet import parquet_rows

    return chunk_rows is not None or parquet_rows(run_file) > STREAM_ABOVE_ROWS


def contour_streamed(run_file: Path, plane: str | None, window_s: float | None,
                     chunk_rows: int | None, *, corner_deg: float = 30.0,
                     corner_span_m: float = 0.5e-3, settle_tol_m: float = 1e-6,
                     rapids: bool = False):
    """The contour error summary and the corners of a Parquet run read in chunks, in the
    plane of ``--plane`` or the one its command moves in (said on stderr, as for a whole
    run).

    Parameters
    ----------
    run_file : Path
        The Parquet run [-].
    plane : str or None
        ``--plane`` [-].
    window_s : float or None
        ``--window-s`` [s].
    chunk_rows : int or None
        Rows a chunk [-].
    corner_deg : float
        ``--corner-deg`` [deg].
    corner_span_m : float
        ``--corner-span-mm``, in metres [m].
    settle_tol_m : float
        ``--settle-um``, in metres [m].
    rapids : bool
        ``--rapids`` [-].
    """
    import numpy as np

    from ..analysis.contour_parquet import STREAM_ROWS, parquet_rows, travel_positions
    from ..analysis.contour_stream import stream_contour
    from ..result import AxisRun, Run
    from ._plane import run_plane_said

    travel = travel_positions(run_file, feed_only=not rapids)
    ends = Run(np.array([0.0, 1.0]), {a: AxisRun(cmd=v) for a, v in travel.items()})
    how = run_plane_said(plane, ends, run_file, allow_3d=True)
    axes, signed = (tuple(how), True) if how else (tuple(a for a in "XYZ" if a in travel),
                                                   False)
    with count_progress(lambda: parquet_rows(run_file), "contour", "rows") as update:
        counted = {}

        def each(sensor, errors):  # rows measured so far, counted on the first sensor
            first = counted.setdefault("sensor", sensor)
            if sensor == first:
                counted["rows"] = counted.get("rows", 0) + errors.size
                update(counted["rows"])

        return stream_contour(run_file, axes, signed, window_s, chunk_rows or STREAM_ROWS,
                              each, corner_deg=corner_deg, corner_span_m=corner_span_m,
                              settle_tol_m=settle_tol_m, rapids=rapids, travel=travel)


#: an NC program of more lines than this is interpolated in chunks by ``tcpmm path`` [-]
PATH_STREAM_ABOVE_LINES = 1_000_000


def path_to_csv(program: Path, output: Path, settings, chunk_blocks: int | None) -> dict:
    """Interpolate an NC program streaming into a command file (the text of the whole
    program's, :func:`tcpmm.path.write_command_csv`).

    Parameters
    ----------
    program : Path
        The NC program [-].
    output : Path
        The command file [-].
    settings : InterpolatorSettings
        Interpolator settings [-].
    chunk_blocks : int, optional
        Blocks a chunk, default :data:`tcpmm.path.stream.CHUNK_BLOCKS` [-].

    Returns
    -------
    dict
        ``samples``, ``period_s`` and ``duration_s`` of the command written [-], [s], [s];
        ``peak_acceleration``, the largest second difference per axis [m/s^2].
    """
    from ..path.commandfile import command_csv_writer
    from ..path.limits import RunningPeak
    from ..path.stream import CHUNK_BLOCKS, StreamInterpolator, stream_program

    ip = StreamInterpolator(settings)
    last = 0.0
    peaks = RunningPeak(2, settings.period_s)
    with line_progress(program, "path") as bar, \
            command_csv_writer(output, blocks=True) as w:
        for piece in stream_program(program, settings, chunk_blocks or CHUNK_BLOCKS,
                                    interpolator=ip):
            _write_piece(w, piece, bar)
            peaks.add(piece.positions)
            last = float(piece.time_s[-1])
        if bar is not None:
            bar.end()
        w.axes = tuple(a for a in ("X", "Y", "Z") if a in ip.used_axes)
    return {"samples": w.samples, "period_s": settings.period_s, "duration_s": last,
            "peak_acceleration": peaks.most}


def _write_piece(w, piece, bar) -> None:
    """Write a piece of the command; where ``bar`` follows it,
    :data:`~tcpmm.path.stream.PART_SAMPLES` rows at a time, each part's last line told
    (the rows' text is each row's alone: the file is the same) [-]."""
    if bar is None:
        w.write(piece.time_s, piece.positions, (piece.nc_line, piece.rapid))
        return
    from ..path.stream import PART_SAMPLES

    for a in range(0, piece.time_s.size, PART_SAMPLES):
        part = slice(a, a + PART_SAMPLES)
        w.write(piece.time_s[part], {k: v[part] for k, v in piece.positions.items()},
                (piece.nc_line[part], piece.rapid[part]))
        bar(int(piece.nc_line[part].max()))  # line 0, the interpolator's own, counts least
