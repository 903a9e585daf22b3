"""An NC program through the interpolator and the machine model a chunk of blocks at a
time: the run comes out in pieces, and neither the command nor the run is ever held
whole.

The pieces put end to end are the run of :func:`tcpmm.sim.simulate.simulate` on the
command of :func:`tcpmm.path.program_to_command`, signal for signal to the bit. Its
times are the record index times the record period, where the whole run takes the
period as the command's span over its samples less one: that quotient can differ from
the period in the last bit, and then a time differs by as much (a relative 2.2e-16).
"""

from __future__ import annotations

import dataclasses
import threading
from collections.abc import Iterator
from concurrent.futures import CancelledError, Future, ThreadPoolExecutor

import numpy as np

from .._threads import limit_blas_threads, usable_cores
from ..errors import InputError
from ..model import Machine
from ..path.blocktrack import HeldBlocks
from ..path.settings import AXES, InterpolatorSettings
from ..path.stream import CHUNK_BLOCKS, PART_SAMPLES, StreamInterpolator, stream_program
from ..result import AxisRun, Run
from .axisstream import AxisStream
from .commandcheck import CommandCheck
from .simulate import check_stability


def stream_simulate(machine: Machine, program, settings: InterpolatorSettings | None = None,
                    *, chunk_blocks: int = CHUNK_BLOCKS, record_period_s=None,
                    quantise_feedback: bool = True, threads: int | None = None,
                    interpolator: StreamInterpolator | None = None,
                    progress=None) -> Iterator[Run]:
    """Run the machine model on an NC program, piece by piece.

    Parameters
    ----------
    machine : Machine
        The machine model [SI].
    program : str or Path
        The NC program file, or its text [-].
    settings : InterpolatorSettings, optional
        Interpolator settings, default the model's [-].
    chunk_blocks : int
        Blocks read and interpolated at a time [-].
    record_period_s : float, optional
        Output period, default the interpolation period [s].
    quantise_feedback : bool
        Quantise the feedback sensors to their resolution [-].
    threads : int, optional
        Cores to use: one reads and interpolates, the others run the axes; default all;
        1 does all in turn [-].
    interpolator : StreamInterpolator, optional
        The interpolator to feed (to read its state afterwards) [-].
    progress : callable, optional
        ``progress(line)``, called as the axes run, with the program's line their command
        samples have reached, on average over the axes, never less than the call before;
        from the thread that ran the axis. With it an axis runs a piece
        :data:`~tcpmm.path.stream.PART_SAMPLES` at a time, which gives the same records
        (:mod:`tcpmm.sim.axisstream`) and calls it within a chunk [-].

    Yields
    ------
    Run
        The run's records in order; ``meta["lines_read"]`` the program's lines read so
        far, ``meta["path_done_m"]`` the distance along the path at the piece's end (``None``
        for a piece without samples) [SI].
    """
    limit_blas_threads()
    settings = _checked_settings(machine, settings)
    dt = settings.period_s
    rp = dt if record_period_s is None else record_period_s
    axes = {a: AxisStream(machine.axes[a], dt, rp, quantise_feedback) for a in machine.axes}
    ip = interpolator or StreamInterpolator(settings)
    pieces = stream_program(program, settings, chunk_blocks, interpolator=ip)
    reached = _Reached(list(axes), progress) if progress is not None else None
    yield from _run_pieces(pieces, axes, threads, rp, machine, ip, HeldBlocks(dt), reached)


def _checked_settings(machine: Machine, settings: InterpolatorSettings | None):
    """The interpolator settings, default the model's, after refusing a machine an NC
    program cannot drive or whose sampled loops are unstable [-]."""
    if settings is None:
        settings = InterpolatorSettings.model_validate(machine.interpolation or {})
    extra = [a for a in machine.axes if a not in AXES]
    if extra:
        raise InputError(f"an NC program drives X, Y and Z; the machine's axis "
                         f"{', '.join(extra)} has no command from it")
    check_stability(machine)
    return settings


def _run_pieces(pieces, axes: dict, threads: int | None, rp: float, machine: Machine,
                ip: StreamInterpolator, blocks: HeldBlocks, reached=None) -> Iterator[Run]:
    """The runs of the command pieces through the axes' streams, in order, with the
    blocks of their records' commands (``blocks``, fed the pieces'), the lines the axes
    reach told to ``reached`` (a :class:`_Reached`) where given [SI]."""
    names = list(axes)
    # the axes run in worker threads while the main thread reads and interpolates the next
    # chunk and hands on the last (the kernel releases the GIL): one core is left to that,
    # the others share the axes; an axis of the piece it needs that no worker has started
    # yet, the main thread runs itself rather than wait. A piece starts as soon as it is
    # interpolated, as if more were to come; after the last, the axes run the steps its
    # end leaves, and those records join the last piece's.
    cores = threads or usable_cores()
    workers = min(len(names), cores - 1) if cores > 1 else 0
    pool = ThreadPoolExecutor(max_workers=workers) if workers else None
    turns = _Turns(names, reached)

    def start(k, positions, final, span, lines=None):
        tasks = [(turns.run, axes[a], a, k, positions[a], final, span, lines) for a in names]
        return [pool.submit(*t) for t in tasks] if pool else [t[0](*t[1:]) for t in tasks], tasks

    r0, running, k, span = 0, None, 0, 0.0  # the piece under way, its number, its span
    check = CommandCheck(machine)  # as a command made whole is checked, a piece at a time
    try:
        for piece in pieces:
            check.add(piece.time_s, piece.positions)
            span = float(piece.time_s[-1])
            blocks.add(piece.nc_line, piece.rapid)
            res, tasks = start(k, piece.positions, False, span, piece.nc_line)
            if running is not None:
                run = _collect(*running, names, r0, rp, machine, ip, blocks)
                r0 += run.time_s.size
                yield run
            running, k = (res, tasks, piece), k + 1
        check.warn()
        if running is not None:
            end = start(k, dict.fromkeys(names, np.empty(0)), True, span)
            yield _collect(*running, names, r0, rp, machine, ip, blocks, end)
    finally:
        turns.close()
        if pool is not None:
            pool.shutdown(cancel_futures=True)


class _Turns:
    """Each axis's pieces pushed in order, whichever thread runs them: the push of piece
    ``k`` waits for that of piece ``k - 1``; a part at a time where ``reached`` follows
    them [-]."""

    def __init__(self, names, reached=None):
        self.next = dict.fromkeys(names, 0)
        self.cv = threading.Condition()
        self.closed = False
        self.reached = reached

    def run(self, stream: AxisStream, name: str, k: int, positions, final: bool,
            span: float, lines) -> AxisRun:
        """``stream.push(positions, final, span)`` as piece ``k`` of axis ``name``, whose
        samples are in the program's ``lines`` [SI]."""
        with self.cv:
            self.cv.wait_for(lambda: self.next[name] == k or self.closed)
            if self.next[name] != k:  # the run was given up while this piece waited
                raise CancelledError
        try:
            if self.reached is None or final:
                return stream.push(positions, final, span)
            return self.reached.push(stream, name, positions, lines)
        finally:
            with self.cv:
                self.next[name] = k + 1
                self.cv.notify_all()

    def close(self) -> None:
        """Give up: pieces still waiting for their turn end [-]."""
        with self.cv:
            self.closed = True
            self.cv.notify_all()


def _collect(res, tasks, piece, names, r0: int, rp: float, machine, ip, blocks,
             end=None) -> Run:
    """The run of one piece from its axes' records or futures, and those of ``end`` (the
    steps the end of the command leaves) joined to them, with the blocks of their
    commands; an axis no worker has started is run here, the last first (the workers take
    them from the first) [SI]."""
    runs = dict(zip(names, _results(res, tasks), strict=True))
    if end is not None:
        runs = {a: _joined(runs[a], r) for a, r in zip(names, _results(*end), strict=True)}
    n = next(iter(runs.values())).cmd.size
    time_s = (r0 + np.arange(n)) * rp
    return Run(time_s, runs,
               {"lines_read": piece.lines_read, "machine": machine.name,
                "plane_axes": ip.plane_axes,
                "path_done_m": float(piece.path_s_m[-1]) if piece.path_s_m.size else None},
               *blocks.at(time_s))


def _results(res, tasks) -> list:
    """The records of each axis's task, those no worker has started run here [SI]."""
    out = list(res)
    for i in reversed(range(len(out))):
        if isinstance(out[i], Future) and out[i].cancel():
            out[i] = tasks[i][0](*tasks[i][1:])
    return [r.result() if isinstance(r, Future) else r for r in out]


def _joined(*runs: AxisRun) -> AxisRun:
    """The signals of the runs one after the other [SI]."""
    return AxisRun(**{f.name: np.concatenate([getattr(r, f.name) for r in runs])
                      for f in dataclasses.fields(AxisRun)})


class _Reached:
    """The program's line the axes' command samples have reached, on average over the
    axes, told to ``progress`` as each axis runs its pieces a part at a time [-].

    The average, not the least, moves as soon as any axis does: where one core runs the
    axes of a piece one after the other, the least would stand still until the last.
    """

    def __init__(self, names: list, progress):
        self.line = dict.fromkeys(names, 0)
        self.progress = progress
        self.lock = threading.Lock()
        self.told = 0

    def push(self, stream: AxisStream, name: str, positions, lines) -> AxisRun:
        """``stream.push(positions)`` :data:`~tcpmm.path.stream.PART_SAMPLES` at a time,
        the line of each part's last sample told; the same records as one push, the
        stream's steps not depending on how its command is cut [SI]."""
        runs = []
        for a in range(0, max(positions.size, 1), PART_SAMPLES):
            runs.append(stream.push(positions[a:a + PART_SAMPLES]))
            part = lines[a:a + PART_SAMPLES]
            if part.size:  # a sample of the interpolator's own has line 0: the most counts
                self._tell(name, int(part.max()))
        return runs[0] if len(runs) == 1 else _joined(*runs)

    def _tell(self, name: str, line: int) -> None:
        # under the lock, so that the threads' calls come in order and never go back
        with self.lock:
            self.line[name] = max(self.line[name], line)
            mean = sum(self.line.values()) // len(self.line)
            if mean > self.told:
                self.told = mean
                self.progress(mean)
