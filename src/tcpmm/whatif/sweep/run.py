"""Running a sweep: the variants not yet in the results folder, in this process, on the
local cores or on a Dask cluster, each row written as it arrives.

Every variant is an independent task (:func:`tcpmm.whatif.sweep.task.evaluate_variant`). On a
cluster a task whose worker dies is run again on another (Dask counts the death against
the task, and ``retries`` more tries are allowed for an exception); a task that fails for
good is reported and left out, so that the next run of the same sweep tries it again.
"""

from __future__ import annotations

import time
import uuid
from dataclasses import dataclass, field
from itertools import islice
from pathlib import Path

from ..._heap import keep_freed_memory
from ..._threads import usable_cores
from ...errors import InputError
from ...io.atomic import output_folder
from .cluster import SchedulerLost, finished_within, local_client, scheduler_lost
from .intervals import INTERVALS_FILE, write_intervals
from .space import apply_parameters
from .store import (
    PARTS_DIR,
    PartWriter,
    done_variants,
    forget_summary,
    open_study,
    run_file_name,
    study_record,
    to_row,
    write_summary,
    writing,
)
from .task import evaluate_variant, program_command

#: Tries of a task that raised, beyond the first [-].
RETRIES = 2


@dataclass
class SweepResult:
    """What a sweep ran and where its rows are.

    Parameters
    ----------
    out_dir : Path
        Results folder [-].
    summary : Path
        The CSV summary, one row per variant of the design in its order [-].
    variants : int
        Variants of the design [-].
    computed : int
        Variants computed by this run [-].
    reused : int
        Variants whose rows were there already [-].
    failed : list of dict
        Variants whose task failed for good: ``variant`` and ``reason`` [-].
    wall_s : float
        Time of the run [s].
    intervals : Path or None
        A draws design's intervals per point of the grid
        (:mod:`tcpmm.whatif.sweep.intervals`); ``None`` for the other designs [-].
    """

    out_dir: Path
    summary: Path
    variants: int
    computed: int
    reused: int
    failed: list = field(default_factory=list)
    wall_s: float = 0.0
    intervals: Path | None = None

    def to_dict(self) -> dict:
        """JSON-ready summary [-]."""
        return {"out_dir": str(self.out_dir), "results": str(self.out_dir / PARTS_DIR),
                "summary": str(self.summary), "variants": self.variants,
                "computed": self.computed, "reused": self.reused, "failed": self.failed,
                "wall_s": self.wall_s,
                "intervals": None if self.intervals is None else str(self.intervals)}

    def to_pandas(self):
        """The summary table [file units]."""
        import pandas as pd

        return pd.read_csv(self.summary, keep_default_na=False, na_values=[""])

    def plot(self, ax=None, path=None, x: str | None = None, y: str = "spike_max_um"):
        """One metric against one parameter, a point per variant; the figure.

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Where to draw; a new figure when omitted [-].
        path : str or Path, optional
            Also save it there (PNG/PDF/SVG) [-].
        x : str, optional
            Parameter column, default the first [-].
        y : str
            Metric column [um].
        """
        from ...plot.sweep import plot_sweep  # tcpmm.plot is a floor above this one

        return plot_sweep(self.to_pandas(), ax=ax, x=x, y=y, path=path)


def check_design(machine, program, variants, specs=()) -> None:
    """Refuse a design any of whose parameters leaves the model or program invalid at its
    smallest or largest value, before any work is done; and a draws design of a model
    without uncertainty.

    Parameters
    ----------
    machine : Machine
        The model swept [SI].
    program : CircleProgram or GcodeProgram
        The program [-].
    variants : list of Variant
        The design [-].
    specs : sequence of ParamSpec, optional
        The parameters as given: a range ``LOW:HIGH`` is judged at its ends as typed, not
        at the points drawn inside it, which hang on ``n`` and the seed [unit of each].
    """
    if any(v.draw is not None for v in variants) and all(
            a.uncertainty is None for a in machine.axes.values()):
        raise InputError(f"machine '{machine.name}' carries no uncertainty to draw from: "
                         "the draws design needs a model written by `tcpmm identify`; or use "
                         "--design grid or lhs")

    ends = {s.name: (s.low, s.high) for s in specs if not s.values and s.low is not None}
    names = {n for v in variants for n, _ in v.values} | set(ends)
    for name in sorted(names):
        vals = ends.get(name) or [dict(v.values)[name] for v in variants
                                  if name in dict(v.values)]
        for value in sorted({min(vals), max(vals)}):
            one = {name: value}
            program_command(program, apply_parameters(machine, one), one)


def _serial(task, args, todo, sink) -> list[dict]:
    """Run the tasks in this process; returns the variants that failed, as
    :func:`_on_client` does."""
    keep_freed_memory()
    failed = []
    for v in todo:
        try:
            result = task(*args(v))
        except Exception as exc:  # reported per variant; the others go on
            failed.append({"variant": v.id, "reason": f"{type(exc).__name__}: {exc}"})
            result = None
        sink(v, result)
    return failed


#: Seconds of work a task on a cluster should hold: a task costs the scheduler a few
#: milliseconds, and a worker lost mid-task costs its task.
TASK_S = 1.0
#: Seconds the tasks running when a sweep is stopped (Ctrl-C) are given to finish, their
#: rows kept: a task holds about :data:`TASK_S` of work, longer on a loaded machine [s].
STOP_WAIT_S = 3.0
#: Seconds a variant is taken to need when the tasks are cut (fixed: the paper's circle
#: takes 15-18 ms on one core, a longer program more) [s].
VARIANT_S = 0.025


def _run_chunk(task, machine, program, chunk, *rest) -> list:
    """``task(machine, program, v, *rest)`` for each variant ``v`` of ``chunk``; one that
    fails gives its error instead of a result, and the others go on [-]."""
    keep_freed_memory()
    out = []
    for v in chunk:
        try:
            out.append(task(machine, program, v, *rest))
        except Exception as exc:  # reported per variant by the caller
            out.append(exc)
    return out


class _Shared:
    """The model and the program scattered to every worker of a cluster; scattered anew
    when the cluster has lost them with the last worker that held them.

    Parameters
    ----------
    client : distributed.Client
        The cluster's client [-].
    objects : tuple
        What every task takes [-].
    """

    def __init__(self, client, objects):
        self.client, self.objects, self.gen = client, list(objects), 0
        self.futures = self._scatter()

    def _scatter(self):
        return self.client.scatter(self.objects, broadcast=True, hash=False)

    def renewed(self, gen: int) -> bool:
        """Whether the data a task of generation ``gen`` took is lost and has been
        scattered anew since (now, if it is lost now) [-]."""
        if gen == self.gen and any(f.status != "finished" for f in self.futures):
            self.futures = self._scatter()
            self.gen += 1
        return gen < self.gen


def _on_client(client, task, args, todo, sink, window: int | None = None) -> list[dict]:
    """Run the tasks on a Dask client, in chunks of variants that hold :data:`TASK_S` of
    work each, ``window`` chunks at a time; returns the variants that failed.

    ``args(v)`` is ``(machine, program, v, *rest)``: the model and the program go to every
    worker once (scattered), not with each task. A worker lost mid-task costs its chunk,
    which the scheduler runs again (``RETRIES``). Scattered data a cluster loses with the
    last worker that held it cannot be run again by the scheduler: it is scattered anew and
    the chunks that needed it are submitted again, as many times.
    """
    from distributed import as_completed

    threads = sum(client.nthreads().values()) or 1
    if window is None:
        window = max(8, 4 * threads)
    size = max(1, min(int(TASK_S / VARIANT_S), -(-len(todo) // (2 * threads))))
    machine, program, _, *rest = args(todo[0])
    shared = _Shared(client, (machine, program))
    token = uuid.uuid4().hex[:8]
    pending, failed = {}, []

    def submit(chunk, n=0):
        fut = client.submit(_run_chunk, task, *shared.futures, chunk, *rest, retries=RETRIES,
                            key=f"tcpmm-variants-{chunk[0].id}-{token}-{n}")
        pending[fut.key] = (chunk, shared.gen, n, fut)
        return fut

    chunks = iter([todo[i:i + size] for i in range(0, len(todo), size)])
    flow = as_completed([submit(c) for c in islice(chunks, window)])
    try:
        for fut in flow:
            chunk, gen, n, _ = pending.pop(fut.key)
            try:
                results = fut.result()
            except Exception as exc:  # a worker lost for good, or a fault of the code
                if scheduler_lost(client, exc):
                    raise SchedulerLost(client) from None
                if shared.renewed(gen) and n < RETRIES:
                    flow.add(submit(chunk, n + 1))
                    continue
                results = [exc] * len(chunk)
            _take(chunk, results, sink, failed)
            fut.release()
            nxt = next(chunks, None)
            if nxt is not None:
                flow.add(submit(nxt))
    except KeyboardInterrupt:
        # the workers ignore the interrupt (local_cluster) and finish the chunks they run,
        # their run files written: the rows of those done soon are kept with them
        chunk_of = {p[3].key: p[0] for p in pending.values()}
        for fut in finished_within([p[3] for p in pending.values()], STOP_WAIT_S):
            _take(chunk_of[fut.key], fut.result(), sink, failed)
        raise
    return failed


def _take(chunk, results, sink, failed: list) -> None:
    """The results of a chunk's variants to ``sink``; those that raised to ``failed`` [-]."""
    for v, result in zip(chunk, results, strict=True):
        if isinstance(result, Exception):
            failed.append({"variant": v.id, "reason": f"{type(result).__name__}: {result}"})
            sink(v, None)
        else:
            sink(v, result)


def run_sweep(machine, program, variants, out_dir, *, sensor: str = "tcp", client=None,
              workers: int | None = None, keep_runs=None, floors=None, progress=None,
              batch: int = 1024, task=evaluate_variant) -> SweepResult:
    """Run the variants of a design not yet in ``out_dir`` and write the summary.

    Parameters
    ----------
    machine : Machine
        The model [-].
    program : CircleProgram or GcodeProgram
        The program [-].
    variants : list of Variant
        The design (:mod:`tcpmm.whatif.sweep.design`) [-].
    out_dir : str or Path
        Results folder; rows already there are kept and their variants not run again [-].
    sensor : str
        Sensor analysed [-].
    client : distributed.Client, optional
        Run on this Dask cluster; else on ``workers`` local processes [-].
    workers : int, optional
        Local processes, default every core; 1 runs in this process [-].
    keep_runs : str or Path, optional
        Folder for each variant's run file (``VARIANT_ID-STUDY.csv``, STUDY a hash of
        the model, program, sensor and draws); it must be reachable by every worker [-].
    floors : dict, optional
        Smallest standard deviations of a draw (:data:`tcpmm.whatif.spread.MODEL_ERROR`) [-].
    progress : callable, optional
        ``progress(done, total)`` after each variant [-].
    batch : int
        Rows per Parquet part [-].
    task : callable
        The function run per variant, :func:`evaluate_variant` or one with its
        signature [-].

    Returns
    -------
    SweepResult
        Counts and files [-].
    """
    t0 = time.perf_counter()
    if not variants:
        raise InputError("the design has no variants")
    check_design(machine, program, variants)
    record = study_record(machine, program, sensor, floors)
    out = open_study(out_dir, record)
    with writing(out):
        return _run_held(machine, program, variants, out, sensor, client, workers,
                         (keep_runs, record["key"]), floors, progress, batch, task, t0)


def _run_held(machine, program, variants, out, sensor, client, workers, keep_runs, floors,
              progress, batch, task, t0) -> SweepResult:
    """:func:`run_sweep` with the folder held; ``keep_runs`` the runs' folder (or None)
    and the study's key, which names their files [-]."""
    keep_runs, study = keep_runs
    runs = None if keep_runs is None else str(Path(keep_runs).resolve())
    if runs is not None:
        output_folder(runs)
    done = done_variants(out)
    if runs is not None:  # a row without its run is not done (its run was not written)
        done = {d for d in done if Path(runs, run_file_name(d, study)).is_file()}
    todo = list({v.id: v for v in variants if v.id not in done}.values())
    if todo:
        forget_summary(out, (INTERVALS_FILE,))
    writer = PartWriter(out, batch)
    count = [0]

    def sink(v, result):
        if result is not None:
            writer.add(to_row(v, result))
        count[0] += 1
        if progress is not None:
            progress(count[0], len(todo))

    def args(v):
        return machine, program, v, sensor, runs, floors, study

    failed = []
    workers = workers or usable_cores()
    try:
        if not todo:
            pass
        elif client is not None:
            failed = _on_client(client, task, args, todo, sink)
        elif workers == 1 or len(todo) == 1:
            failed = _serial(task, args, todo, sink)
        else:
            with local_client(workers) as c:
                failed = _on_client(c, task, args, todo, sink)
    finally:
        writer.flush()
    summary = write_summary(out, variants)
    drawn = any(v.draw is not None for v in variants)
    return SweepResult(out, summary, len(variants), writer.written,
                       len({v.id for v in variants}) - len(todo), failed,
                       time.perf_counter() - t0,
                       write_intervals(out, summary) if drawn else None)
