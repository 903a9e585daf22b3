"""Command of what-if studies: sweep."""

from __future__ import annotations

from contextlib import contextmanager
from pathlib import Path

import typer

from .._threads import usable_cores
from ..errors import InputError
from ._app import (
    Sensor,
    app,
    console,
    emit_json,
    esc,
    floats,
    on_screen,
    out,
    positive,
    read_model,
    warn_unstable,
)
from ._outputs import STOP_SAID
from ._stream import CHUNK_HELP

_PARAM_HELP = ("NAME=START:STOP:STEP (grid, STOP included), NAME=LOW:HIGH (lhs range) or "
               "NAME=V1,V2,... (values; one value fixes it). Repeat for each parameter. "
               "Names: AXIS.mechanics.F, AXIS.servo.F (position_gain = K_pp), "
               "AXIS.sensors.F, AXIS.friction.backlash|level|guideway.F|screw.F, "
               "program.radius_mm, program.feed_mm_per_min (circle), program.feed_override, "
               "interpolation.F (NC program); values in the model file's units (SI). "
               "--list-params lists them all.")
_PROGRAMS_HELP = ("NC programs: a folder (its .nc, .ngc, .gcode, .tap, .mpf ... files) or a "
                  "glob pattern such as 'cam/**/*.nc'; every model runs every program, each "
                  "pair one streaming task. The workers read the programs at these paths.")

#: what a sweep of variants takes and a study over programs does not [-]
_VARIANTS_ONLY = ("--param", "--gcode", "--circle", "--centre", "--design", "--n", "--seed",
                  "--fit-only", "--keep-runs", "--list-params")
#: defaults of the options a study over programs refuses, which take None to tell them
#: given [-]
_DEFAULTS = {"design": "grid", "n": 16, "seed": 0, "centre": "0,0"}


@contextmanager
def _bar(description: str):
    """``progress(done, total)`` drawing a bar on stderr on a terminal; nothing in a pipe
    or a log, where the bar's end left a blank line, before an error too."""
    if not on_screen(console):
        yield lambda done, total: None
        return
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )

    with Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
                  TimeElapsedColumn(), TimeRemainingColumn(), console=console,
                  transient=True) as p:
        task = p.add_task(description, total=None)

        def progress(done, total):
            p.update(task, completed=done, total=total)

        yield progress


def _program(gcode: Path | None, circle: str | None, centre: str):
    from ..path import read_program
    from ..whatif.sweep import CircleProgram, GcodeProgram

    if gcode is not None and circle is not None:
        raise typer.BadParameter("give one of --gcode PROG.nc or --circle R,F")
    if gcode is not None:
        if centre is not None:  # a program's contour error has no centre
            raise typer.BadParameter("--centre is the circle's (--circle R,F); an NC "
                                     "program is measured along its own path: leave it out")
        return GcodeProgram(read_program(gcode), str(gcode))
    r, f = floats(circle or "35,5000", "--circle R,F [mm, mm/min]", 2)
    positive(r, "--circle radius [mm]")
    positive(f, "--circle feed [mm/min]")
    c = floats(centre or _DEFAULTS["centre"], "--centre", 2)
    return CircleProgram(r * 1e-3, f / 6e4, (c[0] * 1e-3, c[1] * 1e-3))


#: Longest wait for a scheduler's answer: an address that takes the connection but does
#: not answer as a Dask scheduler (its dashboard's port, 8787) kept the client waiting
#: past its own timeout for good [s]
ANSWER_S = 20.0


def _client(scheduler: str):
    import logging
    import threading

    from distributed import Client

    # the sweep says what becomes of the scheduler in one line; distributed's own logs
    # (its client's and tornado's, whose levels are their own) would add tracebacks
    for name in [n for n in logging.root.manager.loggerDict
                 if n.startswith(("distributed", "tornado"))] + ["distributed", "tornado"]:
        logging.getLogger(name).setLevel(logging.CRITICAL)
    got = {}

    def connect():
        try:
            got["client"] = Client(scheduler, timeout="10s")
        except Exception as exc:  # also what a client given up on raises as the command ends
            got["error"] = exc

    waiting = threading.Thread(target=connect, daemon=True)
    waiting.start()
    waiting.join(ANSWER_S)
    if "client" in got:
        return got["client"]
    why = (f" ({got['error']})" if "error" in got else
           f": it took the connection but no Dask scheduler answered in {ANSWER_S:g} s (the "
           "dashboard's port, 8787, for the scheduler's, 8786?)")
    raise InputError(f"cannot reach the Dask scheduler at {scheduler}{why}; start one "
                     "(`dask scheduler`, then `dask worker tcp://HOST:8786`) or check the "
                     "address")


def _close(client) -> None:
    """Close the client, within a second: one whose scheduler stopped would otherwise
    wait for it to come back."""
    import contextlib

    with contextlib.suppress(Exception):
        client.close(timeout=1)


def _report(res) -> None:
    out.print(f"{res.variants} variants: {res.computed} computed, {res.reused} already there, "
              f"{len(res.failed)} failed ({res.wall_s:.1f} s)")
    out.print(f"  results  {res.out_dir / 'results'} (Parquet parts)")
    out.print(f"  summary  {res.summary}")
    if res.intervals is not None:
        out.print(f"  intervals {res.intervals} (per point of the grid: each figure's median "
                  "and 90 % interval over the draws, and of its change from the first point, "
                  "draw by draw)")
    for f in res.failed:
        out.print(f"  failed   {f['variant']}: {f['reason']}")
    _warn_faults(res)
    if res.failed:
        out.print("Run the same command again to retry the failed variants.")


#: Variants whose faults are said one by one; the rest are counted [-].
SAID_FAULTS = 10


def _warn_faults(res) -> None:
    """A warning line per variant that ran away, saturated its current or has an
    unstable loop (the first :data:`SAID_FAULTS`), as ``tcpmm simulate`` says them."""
    from ..whatif.sweep.task import out_of_control

    bad = [("; ".join(t for t in (r.get("fault"), r.get("warning")) if isinstance(t, str) and t),
            r["variant"]) for r in res.to_pandas().to_dict("records") if out_of_control(r)]
    for text, v in bad[:SAID_FAULTS]:
        console.print(f"[yellow]warning:[/yellow] variant {esc(str(v))}: {esc(text)}")
    if len(bad) > SAID_FAULTS:
        console.print(f"[yellow]warning:[/yellow] {len(bad) - SAID_FAULTS} more variants ran "
                      "away, saturated their current or are unstable: see the columns fault "
                      f"and warning of {esc(str(res.summary))}")


@app.command()
def sweep(models: list[str] = typer.Argument(
              ..., help="MODEL.yaml or builtin:vmc; with --programs, one or more models."),
          param: list[str] = typer.Option(None, "--param", "-p", help=_PARAM_HELP),
          design: str = typer.Option(None, "--design", help="grid (default), lhs or draws."),
          n: int = typer.Option(None, "--n", help="Variants of lhs; draws a point (16) [-]."),
          seed: int = typer.Option(None, "--seed", min=0, help="Seed of lhs, draws (0) [-]."),
          gcode: Path = typer.Option(None, "--gcode", help="NC program PROG.nc."),
          circle: str = typer.Option(
              None, "--circle",
              help="Circular test R,F: radius [mm], feed [mm/min], CCW then CW; the "
                   "default without --gcode is the paper's 35,5000."),
          centre: str = typer.Option(None, "--centre", help="Circle centre X,Y (0,0) [mm]."),
          programs: str = typer.Option(None, "--programs", help=_PROGRAMS_HELP),
          chunk_blocks: int = typer.Option(None, "--chunk-blocks", min=1, help=CHUNK_HELP),
          output: Path = typer.Option(None, "-o", "--out", help="Results folder OUT_DIR."),
          scheduler: str = typer.Option(
              None, "--scheduler", help="Run on this Dask cluster, e.g. tcp://host:8786."),
          workers: int = typer.Option(
              None, "--workers", min=1,
              help="Local worker processes; default every core, 1 runs in this process."),
          keep_runs: Path = typer.Option(
              None, "--keep-runs", help="Write each variant's run file to this folder."),
          sensor: Sensor = typer.Option(
              "tcp", "--sensor", help="Sensor analysed; with --programs tcp, scale or motor."),
          fit_only: bool = typer.Option(
              False, "--fit-only", help="draws: the fits' own standard deviations alone."),
          list_params: bool = typer.Option(
              False, "--list-params", help="List the parameter names and exit."),
          as_json: bool = typer.Option(False, "--json")):
    """What-if study: the model and program over variants of named parameters.

    Each variant is simulated and analysed (circle: TCP spikes A-D, contour error and
    circular deviation G per direction; NC program: contour error) as an independent task,
    on every local core, or on a Dask cluster with --scheduler. Rows go to
    OUT_DIR/results as they arrive; OUT_DIR/summary.csv holds the design's rows at the end.
    Rerunning the same command runs only the variants whose rows are missing.

    With --programs, every (model, program) pair is one task streaming its program, and
    OUT_DIR/programs.csv (.parquet, .json) holds a row a pair; a program that fails gives
    a row with its error.

    Example: tcpmm sweep builtin:vmc -p X.servo.position_gain=20:60:5
    -p Y.servo.position_gain=20:60:5 --circle 35,5000 -o out/kpp
    """
    if output is None and not list_params:
        raise typer.BadParameter("give the results folder with -o OUT_DIR")
    if scheduler is not None and workers is not None:
        raise typer.BadParameter("--workers sets up a local cluster; with --scheduler the "
                                 "cluster's own workers run the sweep")
    if programs is not None:
        _refuse_with_programs((param, gcode, circle, centre, design, n, seed, fit_only,
                               keep_runs, list_params), sensor.value)
        return _sweep_programs(models, programs, output, scheduler, workers, chunk_blocks,
                               sensor.value, as_json)
    if len(models) != 1:
        raise typer.BadParameter(f"a sweep of variants takes one model, got {len(models)}; "
                                 "several models go with --programs DIR")
    how = dict(design=design, n=n, seed=seed, sensor=sensor.value, fit_only=fit_only)
    _sweep_variants(models[0], param, (gcode, circle, centre), output, scheduler, workers,
                    keep_runs, how, list_params, as_json)


def _refuse_with_programs(values, sensor: str) -> None:
    """Refuse the options of a sweep of variants given with ``--programs``, whose models
    run as they are over their programs: given, each would do nothing, in silence."""
    given = [flag for flag, v in zip(_VARIANTS_ONLY, values, strict=True)
             if v is not None and v is not False and v != []]
    if given:
        raise typer.BadParameter(
            f"--programs runs each model as it is over its programs: {', '.join(given)} "
            f"would do nothing with it; leave {'it' if len(given) == 1 else 'them'} out "
            f"({', '.join(_VARIANTS_ONLY)} go with a sweep of variants of one model)")
    if sensor == "cmd":
        raise typer.BadParameter("--sensor cmd with --programs: the command is the path the "
                                 "contour error is measured from; give tcp, scale or motor")


def _sweep_variants(model, param, prog, output, scheduler, workers, keep_runs, how: dict,
                    list_params: bool, as_json: bool) -> None:
    """``tcpmm sweep`` over variants of named parameters of one model."""
    how = {k: _DEFAULTS.get(k) if v is None else v for k, v in how.items()}
    from ..whatif.spread import MODEL_ERROR
    from ..whatif.sweep import DESIGNS, canonical_name, make_design, parameter_names, run_sweep

    m = read_model(model)
    kind = "gcode" if prog[0] is not None else "circle"
    if list_params:
        for name in parameter_names(m, kind):
            out.print(name, highlight=False)
        return
    warn_unstable(m, f"model {model}")
    if how["design"] not in DESIGNS:
        raise typer.BadParameter(f"--design must be one of {', '.join(DESIGNS)}")
    from ..whatif.sweep import parse_param
    from ..whatif.sweep.run import STOP_WAIT_S, check_design
    from ..whatif.sweep.space import idle_parameters
    from ..whatif.sweep.task import capped_feeds

    program = _program(*prog)
    specs = [parse_param(p, lambda name: canonical_name(m, name, kind)) for p in param or []]
    variants = make_design(how["design"], specs, how["n"], how["seed"])
    # a design refused is refused before any note on the figures it would have given
    check_design(m, program, variants, specs)
    for note in capped_feeds(program, m, variants) + idle_parameters(m, [s.name for s in specs]):
        console.print(f"warning: {esc(note)}", highlight=False)
    for note in _uncertainty_notes(m, how):
        console.print(f"note: {esc(note)}", highlight=False)
    floors = None if how["fit_only"] or how["design"] != "draws" else MODEL_ERROR
    try:
        res = _on_cluster(scheduler, "sweep", lambda client, progress: run_sweep(
            m, program, variants, output, sensor=how["sensor"], client=client,
            workers=workers, keep_runs=keep_runs, floors=floors, progress=progress))
    except (KeyboardInterrupt, SystemExit):
        console.print(f"stopped: the variants computed so far are kept in {esc(str(output))} "
                      f"(those under way on workers if done within {STOP_WAIT_S:g} s); the "
                      "same command goes on from there")
        STOP_SAID.append(True)
        raise
    _finish(res, as_json, _report)


def _uncertainty_notes(m, how: dict) -> list[str]:
    """What a design shows of the model's uncertainty: a grid or lhs of an identified model
    none of it; a draws design with few draws a point little of its 90 % interval [-]."""
    from ..whatif.sweep.intervals import FEW_DRAWS

    if how["design"] == "draws":
        if how["n"] >= FEW_DRAWS:
            return []
        return [f"{how['n']} draws a point: a 90 % interval over so few is little more than "
                f"their range; {FEW_DRAWS} or more (--n) make it one"]
    if all(a.uncertainty is None for a in m.axes.values()):
        return []
    return ["the figures are those of the model as identified, without its uncertainty: "
            f"--design draws --n {FEW_DRAWS} runs every point on machines drawn from it and "
            "writes each figure's 90 % interval (intervals.csv)"]


def _on_cluster(scheduler, description: str, run):
    """``run(client, progress)`` with the client of ``--scheduler`` (``None`` without),
    closed after, and a progress bar."""
    client = _client(scheduler) if scheduler is not None else None
    try:
        _warn_kernels(client)
        with _bar(description) as progress:
            return run(client, progress)
    except (TimeoutError, ValueError) as exc:
        if client is None or "No valid workers" not in str(exc):
            raise
        raise InputError(f"no worker is connected to the Dask scheduler at {scheduler}, or "
                         "every one has stopped: start workers (`dask worker "
                         f"{scheduler}`) and run the same command again (a sweep of "
                         "variants resumes, keeping what was computed)") from None
    finally:
        if client is not None:
            _close(client)


def _warn_kernels(client) -> None:
    """A warning where a worker of ``--scheduler`` runs other BLAS kernels or numpy loops
    than this process: ``dask worker`` loads numpy before tcpmm names them."""
    from ..whatif.sweep.cluster import differing_kernels

    said = differing_kernels(client, ANSWER_S) if client is not None else None
    if said:
        console.print(f"[yellow]warning:[/yellow] {esc(said)}")


def _finish(res, as_json: bool, report) -> None:
    """The result as JSON or as ``report`` says it; exit status 1 when any task failed."""
    if as_json:
        emit_json(res.to_dict())
        # the faults on stderr, as without --json (docs/sweep.md)
        (_warn_faults if report is _report else _warn_faulty_pairs)(res)
    else:
        report(res)
    if res.failed:
        raise typer.Exit(1)


def _sweep_programs(models, programs: str, output, scheduler, workers, chunk_blocks,
                    sensor: str, as_json: bool) -> None:
    """``tcpmm sweep --programs``: every model over every NC program."""
    from ..whatif.sweep.programs import program_files, run_programs

    files = program_files(programs)
    machines = {}
    for name in models:
        if name in machines:
            raise typer.BadParameter(f"model {name} given twice")
        machines[name] = read_model(name)
        warn_unstable(machines[name], f"model {name}")
    if workers is None and scheduler is None:
        workers = usable_cores()  # as a sweep of variants: every core it may use
    res = _on_cluster(scheduler, "programs", lambda client, progress: run_programs(
        machines, files, output, client=client, workers=workers, chunk_blocks=chunk_blocks,
        sensor=sensor, progress=progress))
    _finish(res, as_json, _report_programs)


def _report_programs(res) -> None:
    faulty = f" ({len(res.faulty)} with a fault: no figures)" if res.faulty else ""
    out.print(f"{len(res.rows)} (model, program) pairs: {len(res.rows) - len(res.failed)} "
              f"ran{faulty}, {len(res.failed)} failed ({res.wall_s:.1f} s)")
    for kind, path in res.files.items():
        out.print(f"  {kind:<8} {path}", highlight=False)
    for r in res.failed:
        out.print(f"  failed   {r['model']}: {r['error']}", highlight=False)
    _warn_faulty_pairs(res)


def _warn_faulty_pairs(res) -> None:
    """A warning line per pair whose machine ran away, saturated its current or has an
    unstable loop (the first :data:`SAID_FAULTS`): its row has no figures."""
    for r in res.faulty[:SAID_FAULTS]:
        console.print(f"[yellow]warning:[/yellow] {esc(r['model'])} on {esc(r['program'])}: "
                      f"{esc(r['faults'])}; no figures")
    if len(res.faulty) > SAID_FAULTS:
        console.print(f"[yellow]warning:[/yellow] {len(res.faulty) - SAID_FAULTS} more pairs "
                      "ran away, saturated their current or are unstable: see the column "
                      "faults of programs.csv")
