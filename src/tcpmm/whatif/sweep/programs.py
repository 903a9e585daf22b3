"""A study over many NC programs and several machine models: every (model, program) pair
one task that streams its program (:func:`tcpmm.sim.streamrun.stream_simulate`, the run
to a Parquet file a chunk at a time, its contour error then read back a chunk at a time,
:func:`tcpmm.analysis.contour_stream.stream_contour`) and gives one summary row, here, on
local worker processes or on a Dask cluster.

A program that cannot be run (malformed G-code, a motion the machine cannot make) gives a
row with its error, the file and the line, and the study goes on. The table is written at
the end, atomically, as CSV, Parquet and JSON.
"""

from __future__ import annotations

import glob
import json
import tempfile
import threading
import time
import warnings
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

from ..._heap import keep_freed_memory
from ...analysis.contour_parquet import travel_positions
from ...analysis.contour_sampling import unresolved_corners
from ...analysis.contour_stream import stream_contour
from ...analysis.plane import run_plane
from ...analysis.runaway_stream import FaultWatch
from ...errors import InputError, InputWarning, RunFaultWarning
from ...io.atomic import atomic_path, output_folder, write_table_atomic, write_text_atomic
from ...io.runfile import run_parquet_writer
from ...path.gcode import zero_length_skipped
from ...path.settings import InterpolatorSettings
from ...path.stream import CHUNK_BLOCKS
from ...result import AxisRun, Run
from ...sim.streamrun import stream_simulate
from .cluster import SchedulerLost, local_client, refuse_unreadable_on_worker, scheduler_lost
from .run import RETRIES
from .store import writing

#: file endings taken as NC programs in a folder [-]
PROGRAM_SUFFIXES = (".nc", ".ngc", ".gcode", ".g", ".tap", ".mpf", ".spf", ".cnc", ".iso")
#: columns of a row, in order [-]
COLUMNS = ("model", "program", "status", "blocks", "zero_length_skipped", "duration_s",
           "samples", "plane", "contour_rms_um", "contour_max_um", "corners",
           "corner_rounding_max_um", "faults",
           "warnings", "task_s", "error", "error_file", "error_line")
#: file names of the table in the results folder [-]
TABLE = "programs"


def program_files(spec) -> list[Path]:
    """The NC programs of a folder (the files ending in :data:`PROGRAM_SUFFIXES`) or of a
    glob pattern (every file it matches), sorted by name.

    Parameters
    ----------
    spec : str or Path
        A folder, or a pattern such as ``cam/*.nc`` (``**`` goes into sub-folders) [-].
    """
    p = Path(spec)
    if p.is_dir():
        files = [f for f in p.iterdir() if f.is_file() and f.suffix.lower() in PROGRAM_SUFFIXES]
        fix = f"name them with one of {', '.join(PROGRAM_SUFFIXES)} or give a glob pattern"
    elif glob.has_magic(str(spec)):
        files = [Path(f) for f in glob.glob(str(spec), recursive=True) if Path(f).is_file()]
        fix = "check the pattern"
    elif p.is_file():
        files = [p]
    else:
        raise InputError("no such folder, file or pattern of NC programs", file=spec)
    if not files:
        raise InputError(f"no NC program found; {fix}", file=spec)
    return sorted(files)


_task = threading.local()
_hook_lock = threading.Lock()


def _show(message, category, filename, lineno, file=None, line=None):
    """Into the list of the task running in this thread, else as Python would [-]."""
    sink = getattr(_task, "warnings", None)
    if sink is None:
        return _show.passed_on(message, category, filename, lineno, file, line)
    sink.append((str(message), category))


@contextmanager
def _warnings_of_this_task():
    """The warnings of the task running in this thread, in a list: a Dask worker runs
    tasks in threads, and ``warnings.catch_warnings`` swaps the process's warning state,
    which one task's exit would restore under another's feet [-]."""
    with _hook_lock:
        if warnings.showwarning is not _show:
            _show.passed_on = warnings.showwarning
            warnings.showwarning = _show
        # each program's warnings are counted, not only the first of a kind
        warnings.filterwarnings("always", category=InputWarning)
    _task.warnings = said = []
    try:
        yield said
    finally:
        _task.warnings = None


def _zero_length(said) -> tuple[int, str, list]:
    """Zero-length moves skipped, from the interpreter's warnings (the first said, and
    "(and N more times)"); the other warnings, joined; the run's faults said as warnings
    (an unstable sampled loop), which go with the faults, not the warnings [-]."""
    faults = list(dict.fromkeys(t for t, c in said if issubclass(c, RunFaultWarning)))
    said = [t for t, c in said if not issubclass(c, RunFaultWarning)]
    counted = [zero_length_skipped([text]) for text in said]
    rest = "; ".join(t for t, n in zip(said, counted, strict=True) if not n)
    return sum(counted), rest, faults


def _simulate(machine, program: Path, run_file: Path, chunk_blocks: int) -> dict:
    """Stream ``program`` through ``machine`` into the Parquet ``run_file``; its blocks,
    samples, duration, faults and warnings [-], [s]."""
    settings = InterpolatorSettings.model_validate(machine.interpolation or {})
    watch, samples, last_t, lines = FaultWatch(machine), 0, 0.0, 0
    with _warnings_of_this_task() as said, run_parquet_writer(run_file) as write:
        # one core a task: the cluster's workers are the parallelism
        for run in stream_simulate(machine, program, settings, chunk_blocks=chunk_blocks,
                                   threads=1):
            if run.time_s.size:
                write(run)
                watch.add(run)
                samples += run.time_s.size
                last_t = float(run.time_s[-1])
            lines = run.meta["lines_read"]
    skipped, said, faults = _zero_length(said)
    faults = "; ".join(faults + [f.text() for f in watch.faults()])
    return {"blocks": lines, "zero_length_skipped": skipped, "samples": samples,
            "duration_s": last_t, "faults": faults, "warnings": said}


def run_contour(run_file: Path, window_s: float | None, sensor: str = "tcp") -> dict:
    """The contour error of a Parquet run read in chunks, in the plane its command's feed
    moves run in (unsigned in 3-D where they leave a plane), as ``tcpmm contour`` takes it.

    Parameters
    ----------
    run_file : Path
        The Parquet run [-].
    window_s : float or None
        Time around each sample in which its closest command point is sought; ``None``:
        as for :func:`~tcpmm.analysis.contour.contour_error` [s].
    sensor : str
        Sensor reported [-].

    Returns
    -------
    dict
        ``plane``, ``contour_rms_um``, ``contour_max_um`` (largest magnitude), ``corners``
        and ``corner_rounding_max_um`` (``None`` where none is found or measured) [-], [um].
    """
    import numpy as np

    # the feed moves' plane, the rapids left out of the error: a G0 lift is not 3-D
    travel = travel_positions(run_file, feed_only=True)
    ends = Run(np.array([0.0, 1.0]), {a: AxisRun(cmd=v) for a, v in travel.items()})
    try:
        axes, _, flat = run_plane(ends)
    except InputError:
        flat = False
    if not flat:
        axes = tuple(a for a in "XYZ" if a in travel)
    res = stream_contour(run_file, tuple(axes), flat, window_s, travel=travel)
    unresolved_corners(res)  # n/a where the command's samples cut the corners, as contour
    d = res.to_dict()
    if sensor not in d["sensors"]:
        raise InputError(f"the run measures no sensor {sensor!r}; give one of "
                         f"{', '.join(sorted(d['sensors']))}", file=run_file)
    s = d["sensors"][sensor]
    # no corners sought: none to say, not zero; the path's end (no turn) is not counted
    corners = [c for c in d.get("corners") or [] if c.get("sensor", sensor) == sensor
               and c.get("turn_deg") is not None and c["turn_deg"] == c["turn_deg"]]
    rounding = [c["rounding_um"] for c in corners if c.get("rounding_um") is not None]
    return {"plane": d["axes"] if flat else "3D", "contour_rms_um": s["rms_um"],
            "contour_max_um": s["max_abs_um"], "corners": len(corners) or None,
            "corner_rounding_max_um": max(rounding, default=None)}


def _failure(exc: Exception, program=None) -> dict:
    """The row's columns of a failed task: its cause, file (else ``program``) and line [-]."""
    if isinstance(exc, InputError):
        exc = exc.in_file(program)
        return {"error": exc.format(), "error_file": exc.file, "error_line": exc.line}
    # a row a line: Dask's errors run over several, with advice after the first
    first = (str(exc).strip().splitlines() or [""])[0]
    return {"error": f"{type(exc).__name__}: {first}", "error_file": None, "error_line": None}


def program_task(model: str, machine, program, chunk_blocks: int,
                 window_s: float | None = None, sensor: str = "tcp") -> dict:
    """One (model, program) pair: the program streamed through the model, the run's
    contour error streamed back; a failure becomes the row's error, never an exception.

    Parameters
    ----------
    model : str
        The model's name in the table [-].
    machine : Machine
        The model [SI].
    program : str or Path
        The NC program file, at a path the worker reads [-].
    chunk_blocks : int
        Blocks read, interpolated and simulated at a time [-].
    window_s : float, optional
        Contour error search window; default as for
        :func:`~tcpmm.analysis.contour.contour_error` [s].
    sensor : str
        Sensor whose contour error and corners the row gives: ``tcp``, ``scale`` or
        ``motor`` [-].

    Returns
    -------
    dict
        The row, columns :data:`COLUMNS` [-], [s], [um].
    """
    keep_freed_memory()
    t0 = time.perf_counter()
    row = dict.fromkeys(COLUMNS)
    row.update(model=model, program=str(program), status="ok")
    try:
        refuse_unreadable_on_worker(program)
        with tempfile.TemporaryDirectory(prefix="tcpmm-sweep-") as tmp:
            run_file = Path(tmp) / "run.parquet"
            row.update(_simulate(machine, Path(program), run_file, chunk_blocks))
            # a machine that ran away, held its current or has an unstable loop has no
            # contour error of the path: its figures are left out, as a sweep's variant's
            if row["faults"]:
                row["status"] = "fault"
            else:
                row.update(run_contour(run_file, window_s, sensor))
    except Exception as exc:  # the row says it; the other pairs go on
        row.update(status="failed", **_failure(exc, program))
    row["task_s"] = time.perf_counter() - t0
    return row


@dataclass
class ProgramSweep:
    """The rows of a study over programs and where they were written.

    Parameters
    ----------
    rows : list of dict
        One per (model, program), models in the order given, programs sorted [-].
    files : dict of str to Path
        ``csv``, ``parquet`` and ``json`` [-].
    wall_s : float
        Wall time of the study [s].
    """

    rows: list
    files: dict = field(default_factory=dict)
    wall_s: float = 0.0

    @property
    def failed(self) -> list:
        """The rows that failed [-]."""
        return [r for r in self.rows if r["status"] == "failed"]

    @property
    def faulty(self) -> list:
        """The rows whose machine ran away, saturated its current or is unstable: no figures [-]."""
        return [r for r in self.rows if r["status"] == "fault"]

    def to_dict(self) -> dict:
        """JSON-ready [-]."""
        return {"pairs": len(self.rows), "failed": len(self.failed), "wall_s": self.wall_s,
                "files": {k: str(v) for k, v in self.files.items()}, "rows": self.rows}


def _serial(pairs, args, progress) -> list:
    """The tasks in this process, in turn [-]."""
    rows = []
    for i, (name, machine, prog) in enumerate(pairs):
        rows.append(program_task(name, machine, prog, *args))
        progress(i + 1, len(pairs))
    return rows


def _on_client(client, pairs, args, progress) -> list:
    """The tasks on a Dask client, one a pair, each model sent to the workers once; a
    task lost with its worker for good becomes a failed row [-]."""
    import uuid

    from distributed import as_completed

    token = uuid.uuid4().hex[:8]
    models = {}
    for name, machine, _ in pairs:
        if name not in models:
            models[name] = client.scatter(machine, broadcast=True, hash=False)
    # the workers read the programs where the paths lead from their own folders: a path
    # as the user gave it, relative to this one, leads nowhere from a worker started elsewhere
    futures = {client.submit(program_task, name, models[name], str(Path(prog).resolve()),
                             *args, key=f"tcpmm-program-{i}-{token}", retries=RETRIES): i
               for i, (name, _, prog) in enumerate(pairs)}
    rows = [None] * len(pairs)
    for done, fut in enumerate(as_completed(futures), start=1):
        i = futures[fut]
        try:
            rows[i] = _as_given(fut.result(), pairs[i][2])
        except Exception as exc:  # the worker lost, or the scheduler
            if scheduler_lost(client, exc):
                raise SchedulerLost(client, resumed=False) from None
            name, _, prog = pairs[i]
            rows[i] = {**dict.fromkeys(COLUMNS), "model": name, "program": str(prog),
                       "status": "failed", **_failure(exc)}
        fut.release()
        progress(done, len(pairs))
    return rows


def _as_given(row: dict, program: Path) -> dict:
    """A worker's row, which names the program by the absolute path it was sent, naming it
    as the user gave it, as a row of this process does [-]."""
    sent, given = str(program.resolve()), str(program)
    row = {**row, "program": given}
    if row.get("error_file") == sent:
        row["error_file"] = given
    for k in ("error", "warnings", "faults"):
        if isinstance(row.get(k), str):
            row[k] = row[k].replace(sent, given)
    return row


def write_table(rows, out_dir) -> dict:
    """The rows as ``programs.csv``, ``programs.parquet`` and ``programs.json`` in
    ``out_dir``, each written atomically [-]."""
    import pandas as pd

    out = output_folder(out_dir)
    frame = pd.DataFrame(rows, columns=list(COLUMNS))
    for c in ("blocks", "zero_length_skipped", "samples", "corners", "error_line"):
        frame[c] = frame[c].astype("Int64")
    files = {"csv": out / f"{TABLE}.csv", "parquet": out / f"{TABLE}.parquet",
             "json": out / f"{TABLE}.json"}
    write_table_atomic(frame, files["csv"])
    with atomic_path(files["parquet"]) as tmp:
        frame.to_parquet(tmp, index=False)
    write_text_atomic(files["json"], json.dumps(rows, indent=1, default=str) + "\n")
    return files


def run_programs(models: dict, programs, out_dir, *, client=None, workers: int | None = None,
                 chunk_blocks: int | None = None, window_s: float | None = None,
                 sensor: str = "tcp", progress=None) -> ProgramSweep:
    """Every program through every model, each pair a streaming task; the table written.

    Parameters
    ----------
    models : dict of str to Machine
        The models by the name the table gives them [SI].
    programs : list of Path
        The NC programs, at paths the workers read too [-].
    out_dir : str or Path
        The results folder [-].
    client : distributed.Client, optional
        Run on this Dask cluster [-].
    workers : int, optional
        Without a client: local worker processes; default and 1 run in this process [-].
    chunk_blocks : int, optional
        Blocks a chunk, default :data:`tcpmm.path.stream.CHUNK_BLOCKS` [-].
    window_s : float, optional
        Contour error search window; default as for
        :func:`~tcpmm.analysis.contour.contour_error` [s].
    sensor : str
        Sensor whose contour error the rows give: ``tcp``, ``scale`` or ``motor`` [-].
    progress : callable, optional
        Called with the pairs done and their total [-].
    """
    t0 = time.perf_counter()
    pairs = [(name, m, Path(p)) for name, m in models.items() for p in programs]
    args = (chunk_blocks or CHUNK_BLOCKS, window_s, sensor)
    progress = progress or (lambda done, total: None)
    # a folder that cannot be written is refused before any work; one study at a time
    # writes into it, the table of a second would replace the first's
    with writing(output_folder(out_dir)):
        if client is not None:
            rows = _on_client(client, pairs, args, progress)
        elif workers is not None and workers > 1:
            rows = _on_local_cluster(workers, pairs, args, progress)
        else:
            rows = _serial(pairs, args, progress)
        files = write_table(rows, out_dir)
    return ProgramSweep(rows, files, time.perf_counter() - t0)


def _on_local_cluster(workers: int, pairs, args, progress) -> list:
    """The tasks on a Dask cluster of ``workers`` processes on this machine [-]."""
    with local_client(workers) as client:
        return _on_client(client, pairs, args, progress)
