"""Commands that run a program on a model and analyse runs: demo, simulate, circle, compare,
path."""

from __future__ import annotations

from pathlib import Path

import typer

from ._app import (
    WARNED,
    Sensor,
    app,
    checked_output,
    checked_plot,
    checked_report_file,
    console,
    emit_json,
    esc,
    floats,
    in_file,
    interp_settings,
    load_command,
    out,
    positive,
    progress_bar,
    read_model,
    refuse_unstable,
)
from ._circles import (
    circle_diagnostics_asked,
    diagnostics_json,
    print_diagnostics,
    print_passes,
)
from ._controller import CONTROLLER_HELP, as_the_drives_take_it
from ._outputs import checked_csv_output, distinct_outputs, outputs_together
from ._plane import (
    COMMAND_HELP,
    PLANE_HELP,
    command_plane,
    refuse_unmeasured,
    run_plane_said,
    with_given_command,
)
from ._stream import (
    CHUNK_HELP,
    PATH_STREAM_ABOVE_LINES,
    count_lines,
    path_to_csv,
    simulate_to_parquet,
)


@app.command()
@outputs_together()
def demo(out_dir: Path = typer.Option(Path("out/demo"), "-o", "--out", help="Output folder."),
         report: Path = typer.Option(None, "--report", help="The HTML report REPORT.html "
                                     "(tcpmm report); default report.html in the output "
                                     "folder."),
         tolerance_um: float = typer.Option(None, "--tolerance-um", help="Largest circular "
                                            "deviation G the report's verdict accepts [µm]; "
                                            "default the machine's specification, 40 µm.")):
    """The paper's circular test (R35 mm, 5000 mm/min, CCW and CW) on the built-in machine."""
    from ..demo import DEMO_STEPS, run_demo
    from ..io.atomic import check_output_folder

    check_output_folder(out_dir)
    checked_report_file(report)
    tol = None if tolerance_um is None else positive(tolerance_um, "--tolerance-um") * 1e-6
    with progress_bar(len(DEMO_STEPS), "demo") as adv:
        res = run_demo(out_dir, progress=adv, console=out, report=report, tolerance_m=tol)
    out.print(f"Wrote {len(res['files'])} files to [bold]{Path(out_dir).resolve()}[/bold]")
    width = max(map(len, res["files"]), default=0)
    for k, v in res["files"].items():
        out.print(f"  {k:{width}s} {Path(v).resolve()}")
    out.print(f"report: [bold]{Path(res['files']['report']).resolve()}[/bold]")





@app.command()
def simulate(model: str = typer.Argument(..., help="MODEL.yaml or builtin:vmc"),
             command: Path = typer.Option(None, "--command", help="Command file CMD.csv."),
             gcode: Path = typer.Option(None, "--gcode", help="NC program PROG.nc."),
             output: Path = typer.Option(
                 ..., "-o", "--output",
                 help="Run file RUN.csv, or RUN.parquet (smaller and faster for long runs)."),
             record_period_s: float = typer.Option(None, help="Output period [s]."),
             allow_unstable: bool = typer.Option(
                 False, "--allow-unstable",
                 help="Simulate even where the sampled servo loop is unstable (the run "
                      "then diverges; for studying the instability itself)."),
             chunk_blocks: int = typer.Option(None, "--chunk-blocks", min=1,
                                              help=CHUNK_HELP),
             controller: Path = typer.Option(None, "--controller", help=CONTROLLER_HELP),
             as_json: bool = typer.Option(False, "--json")):
    """Drive the machine model with a position command; write the run file. An axis that
    runs away from its command or holds its current at the limit is said on stderr (and
    in --json, "faults"). An NC program run to Parquet streams: it is read, interpolated,
    simulated and written a chunk of blocks at a time, in bounded memory; on a terminal a
    bar counts the program's lines the run has reached (comment and blank lines too) and
    the time left."""
    from ..io.runfile import is_parquet
    from ..sim.simulate import simulate as _simulate

    checked_output(output, model, command, gcode)
    if record_period_s is not None:
        positive(record_period_s, "--record-period-s [s]")
    m = read_model(model)
    if record_period_s is not None:
        _record_period_fits(m, record_period_s)
    if not allow_unstable:
        refuse_unstable(m, model)
    streams = gcode is not None and command is None and is_parquet(output)
    if controller is not None and streams:
        raise typer.BadParameter("a run streamed to Parquet runs the command alone: give "
                                 "-o RUN.csv", param_hint="--controller")
    if chunk_blocks is not None and not streams:
        raise typer.BadParameter("only an NC program run to Parquet streams: give --gcode "
                                 "PROG.nc and -o RUN.parquet", param_hint="--chunk-blocks")
    if streams:
        with in_file(gcode):
            res = simulate_to_parquet(m, gcode, output, interp_settings(m),
                                      record_period_s=record_period_s,
                                      chunk_blocks=chunk_blocks)
        _said_run(output, res, as_json, gcode)
        return
    cmd, pulses = as_the_drives_take_it(load_command(command, gcode, m), controller, m)
    with progress_bar(len(m.axes), "simulate") as adv, in_file(command or gcode):
        run = _simulate(m, cmd, record_period_s=record_period_s, progress=adv,
                        current_feedforward_A=pulses)
    run.write(output)
    _said_run(output, run.to_dict(), as_json, gcode)


def _record_period_fits(machine, record_period_s: float) -> None:
    """``--record-period-s`` refused by the option's name where it is no whole number of
    an axis's velocity-loop periods (the message named the program or command file)."""
    from ..errors import InputError
    from ..sim.simulate import record_every

    for axis in machine.axes.values():
        try:
            record_every(record_period_s, record_period_s, axis.servo.T_v)
        except InputError as exc:
            raise typer.BadParameter(exc.message, param_hint="--record-period-s") from None


def _said_run(output: Path, summary: dict, as_json: bool, gcode: Path | None) -> None:
    """Say the run file written: its samples and axes (``Run.to_dict``'s summary); in
    JSON, of a program, also the zero-length moves skipped, as a number."""
    if as_json:
        if gcode is not None:
            from ..path.gcode import zero_length_skipped

            summary = {**summary, "zero_length_skipped": zero_length_skipped(WARNED)}
        emit_json({"output": str(output), **summary})
        return
    out.print(f"wrote {output} ({summary['samples']} samples, axes "
              f"{', '.join(summary['axes'])})")


@app.command()
@outputs_together()
def circle(run_file: Path = typer.Argument(
               ..., help="RUN.csv or RUN.parquet (simulated or measured)"),
           other: Path = typer.Argument(
               None, help="RUN_CW.csv: a second run; the diagnostics take the CCW circle "
                          "from the first run and the CW circle from the second."),
           radius: float = typer.Option(..., "--radius", help="Nominal radius [mm]."),
           centre: str = typer.Option("0,0", "--centre",
                                      help="Nominal centre in the plane's axes, A,B [mm]."),
           plane: str = typer.Option(None, "--plane", help=PLANE_HELP),
           direction: str = typer.Option(None, "--direction", help="ccw or cw."),
           sensor: Sensor = typer.Option(
               None, "--sensor", help="Sensor of the diagnostics (default tcp, else scale, "
                                      "motor)."),
           command: Path = typer.Option(None, "--command", help=COMMAND_HELP),
           as_json: bool = typer.Option(False, "--json"),
           plot: Path = typer.Option(None, "--plot", help="Save a plot (PNG/PDF/SVG)."),
           diag_plot: Path = typer.Option(None, "--diag-plot",
                                          help="Save the diagnostics plot (PNG/PDF/SVG).")):
    """Circular test: radial and contour error, circular deviation G, reversal spikes A-D;
    with a CCW and a CW circle (one run or two) also the diagnostics: backlash, lateral
    play, servo and scale mismatch, squareness, cyclic error, G(b), hysteresis."""
    from ..analysis.circular import CircleResult, analyse_circle
    from ..io.runfile import read_run

    _one_run_options(direction, command, other)
    c = floats(centre, "--centre", 2)
    positive(radius, "--radius [mm]")
    checked_plot(plot)
    checked_plot(diag_plot)
    distinct_outputs(("--plot", plot), ("--diag-plot", diag_plot))
    results, axes = [], None
    for f in (run_file, other) if other is not None else (run_file,):
        run = with_given_command(read_run(f), command)
        axes = axes or run_plane_said(plane, run, f)
        if sensor is None or sensor.value != "cmd":
            refuse_unmeasured(run, axes, f, ", or --sensor cmd for the command's own figures")
        with in_file(f):
            results.append(analyse_circle(run, radius * 1e-3, (c[0] * 1e-3, c[1] * 1e-3),
                                          plane=axes,
                                          direction=direction.lower() if direction else None))
    res = CircleResult(results[0].radius, results[0].centre,
                       [p for r in results for p in r.passes], axes)
    diag = circle_diagnostics_asked(res, other is not None, bool(sensor or diag_plot),
                                    sensor.value if sensor else None)
    if plot is not None:
        res.plot(path=plot)
    if diag_plot is not None:
        diag.plot(path=diag_plot)
    if as_json:
        data = res.to_dict()
        if diag is not None:
            key = "diagnostics" if len(diag.directions) == 2 else "diagnostics_one_direction"
            data[key] = diagnostics_json(diag, res)
        emit_json(data)
        return
    title = f"{run_file}" + (f" and {other}" if other is not None else "")
    title += f", {''.join(axes)} plane" if axes != ("X", "Y") else ""
    print_passes(res, title)
    if diag is not None:
        print_diagnostics(diag, res)


def _one_run_options(direction, command, other) -> None:
    """Refuse ``--direction`` and ``--command`` where two runs are given, and a direction
    that is none [-]."""
    if direction is not None and direction.lower() not in ("ccw", "cw"):
        raise typer.BadParameter("--direction must be ccw or cw")
    if direction is not None and other is not None:
        raise typer.BadParameter("give --direction or a second run, not both")
    if command is not None and other is not None:
        raise typer.BadParameter("--command is the command of one run: give one run")


@app.command()
@outputs_together()
def compare(measured: Path = typer.Argument(..., help="Measured RUN.csv or RUN.parquet"),
            predicted: Path = typer.Argument(..., help="Predicted RUN.csv or RUN.parquet"),
            radius: float = typer.Option(..., "--radius", help="Nominal radius [mm]."),
            centre: str = typer.Option("0,0", "--centre",
                                       help="Nominal centre in the plane's axes, A,B [mm]."),
            plane: str = typer.Option(None, "--plane", help=PLANE_HELP),
            as_json: bool = typer.Option(False, "--json"),
            plot: Path = typer.Option(None, "--plot", help="Save an overlay plot."),
            report: Path = typer.Option(None, "--report",
                                        help="Also write the HTML report REPORT.html."),
            model: str = typer.Option(
                None, "--model", help="The identified MODEL.yaml the prediction came from: "
                                      "each TCP difference is set against the predicted "
                                      "figure's 90 % interval and verdict.")):
    """Measured minus predicted: reversal spikes A-D and contour error (paper Table 2)."""
    from ..analysis.compare import compare_circles
    from ..io.runfile import read_run
    from ._circle_files import analysed_pair, compare_page
    from ._tables import judged_rows, print_table

    c = floats(centre, "--centre", 2)
    ctr = (c[0] * 1e-3, c[1] * 1e-3)
    positive(radius, "--radius [mm]")
    checked_plot(plot)
    checked_report_file(report, measured, predicted)
    distinct_outputs(("--plot", plot), ("--report", report))
    runs = [read_run(f) for f in (measured, predicted)]
    axes = run_plane_said(plane, runs[0], measured)
    for f, r in zip((measured, predicted), runs, strict=True):
        refuse_unmeasured(r, axes, f)
    # the prediction's transient is the measurement's to compare; the measured run's
    # warnings are the report's cautions, as in tcpmm report
    rm, rp, rate, said = analysed_pair(measured, predicted, (
        radius * 1e-3, ctr, plane, {Path(f).resolve(): axes for f in (measured, predicted)}),
        runs)
    cmp = compare_circles(rm, rp)
    judged = judged_rows_of(cmp, None if model is None else read_model(model), runs[1],
                            radius, ctr, axes, predicted)
    if plot is not None:
        cmp.plot(path=plot)
    if report is not None:
        compare_page(report, cmp, (measured, predicted), rate, said,
                     cmp.judged_long(judged) if judged else None)
    if as_json:
        emit_json({**cmp.to_dict(), **({"tcp_judged": judged} if judged else {})})
    else:
        print_table(cmp.to_pandas(), out, "measured - predicted (raw spikes e - b, as in the "
                    "paper's Table 2)")
        for line in cmp.notes():
            out.print(line)
        if judged:
            import pandas as pd

            print_table(pd.DataFrame(judged_rows(cmp.judged_long(judged))), out,
                        "tcp: measured - predicted against the predicted 90 % interval [µm]")


def judged_rows_of(cmp, m, predicted_run, radius_mm: float, centre_m, plane, where):
    """The TCP rows against the verdict of the model ``m`` on the predicted run's command
    (``None`` without a model); refused where the model did not predict that run [-]."""
    if m is None:
        return None
    from ..path.command import Command
    from ..uncertainty import CircleTest, prediction_verdict
    from ..uncertainty.verdict import not_its_prediction

    cmd = Command(predicted_run.time_s,
                  {n: a.cmd for n, a in predicted_run.axes.items() if a.cmd is not None})
    plane = tuple(plane) if plane else tuple(list(m.axes)[:2])
    test = CircleTest(f"R{radius_mm:g}", cmd, radius_mm * 1e-3, centre_m, plane)
    verdict = prediction_verdict(m, [test])
    not_its_prediction(verdict, cmp.predicted, f"{where} (predicted)")
    return cmp.judged(verdict)


@app.command()
@outputs_together()
def path(program: Path = typer.Argument(..., help="NC program PROG.nc"),
         output: Path = typer.Option(..., "-o", "--output", help="Command file CMD.csv."),
         model: str = typer.Option(None, "--model", help="Model file with interpolator settings."),
         plot: bool = typer.Option(False, "--plot", help="Also save CMD.png beside the CSV."),
         plane: str = typer.Option(None, "--plane", help="Plane of the plotted path: XY, XZ, "
                                   "YZ (or ZX); default the plane of the program's arcs "
                                   "(G17/G18/G19), else the one it moves in."),
         chunk_blocks: int = typer.Option(
             None, "--chunk-blocks", min=1,
             help="Interpolate this many blocks at a time (bounded memory; no feed summary, "
                  "no plot; on a terminal a bar counts the program's lines written). "
                  f"Default: whole, unless the program has more than "
                  f"{PATH_STREAM_ABOVE_LINES} lines.")):
    """Interpolate an NC program into the position command per axis; say how much of the
    path runs at the programmed feed and which limit holds it back where it does not."""
    from ..path import write_command_csv
    from ..path.limits import RunningPeak, feed_limits
    from ..path.program import program_to_interpolation
    from ._pathtext import print_corner_overload, print_feed

    checked_csv_output(output, program, model)
    m = None
    if model is not None:
        from ..io.modelfile import read_machine

        m = read_machine(model)
    long = chunk_blocks is None and program.is_file() and (
        count_lines(program) > PATH_STREAM_ABOVE_LINES)
    if chunk_blocks is not None or long:
        if plot:
            raise typer.BadParameter("a program interpolated in chunks is not plotted",
                                     param_hint="--plot")
        if long:
            console.print(f"note: {esc(str(program))} has more than "
                          f"{PATH_STREAM_ABOVE_LINES} lines: interpolated in chunks, in "
                          "bounded memory, without the summary of where the feed is held "
                          "back", highlight=False)
        res = path_to_csv(program, output, interp_settings(m), chunk_blocks)
        out.print(f"wrote {output} ({res['samples']} samples at {res['period_s'] * 1e3:g} "
                  f"ms, {res['duration_s']:.3f} s)")
        print_corner_overload(res["peak_acceleration"], interp_settings(m))
        return
    interp = program_to_interpolation(program, interp_settings(m))
    cmd = interp.command
    shown = command_plane(plane, cmd) if plot else None  # refused before anything is written
    write_command_csv(cmd, output)
    out.print(f"wrote {output} ({cmd.time_s.size} samples at {cmd.period_s * 1e3:g} ms, "
              f"{cmd.time_s[-1] - cmd.time_s[0]:.3f} s)")
    limits = feed_limits(interp)
    print_feed(limits)
    print_corner_overload(RunningPeak.of(cmd.positions, 2, cmd.period_s), interp_settings(m))
    if plot:
        from ..plot.path import plot_command

        p = output.with_suffix(".png")
        plot_command(cmd, p, plane=shown, limits=limits)
        out.print(f"wrote {p}")
