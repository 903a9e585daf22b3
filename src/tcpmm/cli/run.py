"""Commands that run a program on a model and analyse runs: demo, simulate, circle, compare,
path."""

from __future__ import annotations

from pathlib import Path

import typer

from ._app import (
    _emit_json,
    _floats,
    _in_file,
    _interp_settings,
    _load_command,
    _output,
    _plot,
    _positive,
    _progress,
    _read_model,
    _refuse_unstable,
    app,
    out,
)


@app.command()
def demo(out_dir: Path = typer.Option(Path("out/demo"), "-o", "--out", help="Output folder.")):
    """The paper's circular test (R35 mm, 5000 mm/min, CCW and CW) on the built-in machine."""
    from ..demo import DEMO_STEPS, run_demo

    with _progress(len(DEMO_STEPS), "demo") as adv:
        res = run_demo(out_dir, progress=adv, console=out)
    out.print(f"Wrote {len(res['files'])} files to [bold]{Path(out_dir).resolve()}[/bold]")
    for k, v in res["files"].items():
        out.print(f"  {k:12s} {v}")





@app.command()
def simulate(model: str = typer.Argument(..., help="MODEL.yaml or builtin:vmc"),
             command: Path = typer.Option(None, "--command", help="Command file CMD.csv."),
             gcode: Path = typer.Option(None, "--gcode", help="NC program PROG.nc."),
             output: Path = typer.Option(..., "-o", "--output", help="Run file RUN.csv."),
             record_period_s: float = typer.Option(None, help="Output period [s]."),
             allow_unstable: bool = typer.Option(
                 False, "--allow-unstable",
                 help="Simulate even where the sampled servo loop is unstable (the run "
                      "then diverges; for studying the instability itself).")):
    """Drive the machine model with a position command; write the run file."""
    from ..simulate import simulate as _simulate

    _output(output, model, command, gcode)
    if record_period_s is not None:
        _positive(record_period_s, "--record-period-s [s]")
    m = _read_model(model)
    if not allow_unstable:
        _refuse_unstable(m, model)
    cmd = _load_command(command, gcode, m)
    with _progress(len(m.axes), "simulate") as adv, _in_file(command or gcode):
        run = _simulate(m, cmd, record_period_s=record_period_s, progress=adv)
    run.write_csv(output)
    out.print(f"wrote {output} ({run.time_s.size} samples, axes {', '.join(run.axes)})")


@app.command()
def circle(run_file: Path = typer.Argument(..., help="RUN.csv (simulated or measured)"),
           radius: float = typer.Option(..., "--radius", help="Nominal radius [mm]."),
           centre: str = typer.Option("0,0", "--centre", help="Nominal centre X,Y [mm]."),
           direction: str = typer.Option(None, "--direction", help="ccw or cw."),
           as_json: bool = typer.Option(False, "--json"),
           plot: Path = typer.Option(None, "--plot", help="Save a plot (PNG/PDF/SVG).")):
    """Circular test: radial and contour error, circular deviation G, reversal spikes A-D."""
    from ..analysis.circular import analyse_circle
    from ..demo import print_circle_table
    from ..io.runfile import read_run_csv

    if direction is not None and direction.lower() not in ("ccw", "cw"):
        raise typer.BadParameter("--direction must be ccw or cw")
    c = _floats(centre, "--centre", 2)
    _positive(radius, "--radius [mm]")
    _plot(plot)
    run = read_run_csv(run_file)
    with _in_file(run_file):
        res = analyse_circle(run, radius * 1e-3, (c[0] * 1e-3, c[1] * 1e-3),
                             direction=direction.lower() if direction else None)
    if plot is not None:
        res.plot(plot)
    if as_json:
        _emit_json(res.to_dict())
    else:
        print_circle_table(res.to_pandas(), out, f"{run_file} [um]")


@app.command()
def compare(measured: Path = typer.Argument(..., help="Measured RUN.csv"),
            predicted: Path = typer.Argument(..., help="Predicted RUN.csv"),
            radius: float = typer.Option(..., "--radius", help="Nominal radius [mm]."),
            centre: str = typer.Option("0,0", "--centre", help="Nominal centre X,Y [mm]."),
            as_json: bool = typer.Option(False, "--json"),
            plot: Path = typer.Option(None, "--plot", help="Save an overlay plot.")):
    """Measured minus predicted: reversal spikes A-D and contour error (paper Table 2)."""
    from ..analysis.circular import analyse_circle
    from ..analysis.compare import compare_circles
    from ..demo import print_circle_table
    from ..io.runfile import read_run_csv

    c = _floats(centre, "--centre", 2)
    ctr = (c[0] * 1e-3, c[1] * 1e-3)
    _positive(radius, "--radius [mm]")
    _plot(plot)
    runs = [read_run_csv(f) for f in (measured, predicted)]
    with _in_file(measured):
        rm = analyse_circle(runs[0], radius * 1e-3, ctr)
    with _in_file(predicted):
        rp = analyse_circle(runs[1], radius * 1e-3, ctr)
    cmp = compare_circles(rm, rp)
    if plot is not None:
        from ..plot.circle import plot_circle

        plot_circle(rm, plot, sensors=["tcp"], overlay=rp)
    if as_json:
        _emit_json(cmp.to_dict())
    else:
        print_circle_table(cmp.to_pandas(), out, "measured - predicted [um]")
        for line in cmp.notes():
            out.print(line)

@app.command()
def path(program: Path = typer.Argument(..., help="NC program PROG.nc"),
         output: Path = typer.Option(..., "-o", "--output", help="Command file CMD.csv."),
         model: str = typer.Option(None, "--model", help="Model file with interpolator settings."),
         plot: bool = typer.Option(False, "--plot", help="Also save CMD.png beside the CSV.")):
    """Interpolate an NC program into the position command per axis."""
    from ..path import program_to_command, write_command_csv

    _output(output, program, model)
    if plot and output.suffix.lower() == ".png":
        raise typer.BadParameter(f"{output} would be overwritten by the plot of --plot; "
                                 "give the command file the extension .csv")
    m = None
    if model is not None:
        from ..io.modelfile import read_machine

        m = read_machine(model)
    cmd = program_to_command(program, _interp_settings(m))
    write_command_csv(cmd, output)
    out.print(f"wrote {output} ({cmd.time_s.size} samples at {cmd.period_s * 1e3:g} ms, "
              f"{cmd.time_s[-1] - cmd.time_s[0]:.3f} s)")
    if plot:
        from ..plot.path import plot_command

        p = plot_command(cmd, output.with_suffix(".png"))
        out.print(f"wrote {p}")
