"""Command-line interface: ``tcpmm --help``.

Units at this edge: mm, mm/min, Hz, um, as the option names say.
"""

from __future__ import annotations

import json
import math
import sys
import warnings
from contextlib import contextmanager
from enum import StrEnum
from pathlib import Path

import typer
from rich.console import Console

from .errors import InputError, InputWarning, TcpmmError


class Sensor(StrEnum):
    """Sensors a circular test is analysed for."""

    tcp = "tcp"
    scale = "scale"
    motor = "motor"
    cmd = "cmd"


# help texts carry units in brackets ([mm]); they are text, not rich markup
app = typer.Typer(add_completion=False, pretty_exceptions_enable=False, rich_markup_mode=None,
                  help="Virtual machine tool: mechatronic model of the tool center point.")
machine_app = typer.Typer(help="Built-in machines and model files.", rich_markup_mode=None)
app.add_typer(machine_app, name="machine")
console = Console(stderr=True)
out = Console()


def _print_version(value: bool) -> None:
    if value:
        from . import __version__

        out.print(f"tcpmm {__version__}")
        raise typer.Exit()


@app.callback()
def _root(version: bool = typer.Option(False, "--version", callback=_print_version,
                                       is_eager=True, help="Print the version and exit.")):
    """Virtual machine tool: mechatronic model of the tool center point."""


@contextmanager
def _progress(total: int, description: str):
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

    with Progress(TextColumn("{task.description}"), BarColumn(), TimeElapsedColumn(),
                  console=console, transient=True) as p:
        task = p.add_task(description, total=total)

        def advance(name=None, *_):
            p.update(task, advance=1, description=f"{description}: {name}" if name else None)

        yield advance


def _floats(text: str | None, what: str, n: int | None = None) -> list[float] | None:
    if text is None:
        return None
    try:
        vals = [float(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise typer.BadParameter(f"{what} must be numbers separated by commas, e.g. 1,2") from None
    if n is not None and len(vals) != n:
        raise typer.BadParameter(f"{what} needs {n} numbers separated by commas")
    if not vals:
        raise typer.BadParameter(f"{what} needs numbers separated by commas")
    return _finite(vals, what)


def _finite(vals, what):
    if any(not math.isfinite(v) for v in vals):
        raise typer.BadParameter(f"{what} must be finite numbers")
    return vals


def _positive(value: float, what: str) -> float:
    if not (math.isfinite(value) and value > 0):
        raise typer.BadParameter(f"{what} must be a positive number, got {value:g}")
    return value


def _band(text: str | None, what: str) -> tuple[float, float] | tuple[None, None]:
    if text is None:
        return None, None
    f0, f1 = _floats(text, what, 2)
    if not 0 <= f0 < f1:
        raise typer.BadParameter(f"{what} F0,F1 needs 0 <= F0 < F1 [Hz], got {text}")
    return f0, f1


def _output(output: Path, *inputs) -> Path:
    """Refuse an output that would replace one of the inputs; prepare its folder."""
    from .io.atomic import output_file

    target = output_file(output)
    for i in inputs:
        if i is not None and Path(i).exists() and Path(i).resolve() == target.resolve():
            raise typer.BadParameter(f"{output} is also an input; write the output elsewhere")
    return output


def _plot(plot: Path | None) -> Path | None:
    """Check a --plot file name before any work is done."""
    if plot is None:
        return None
    from .plot import plot_file

    _output(plot)
    return plot_file(plot)


@contextmanager
def _in_file(path):
    """Name ``path`` in an input error that names no file (the analysis of its content)."""
    try:
        yield
    except InputError as exc:
        if exc.file is not None:
            raise
        raise InputError(exc.message, file=path, line=exc.line, column=exc.column) from None


def _emit_json(data) -> None:
    out.print_json(json.dumps(data))


def _warn_suspect(machine, what: str) -> None:
    """Say loudly, on stderr, that a model carries the suspect marks of identification."""
    if not machine.suspect:
        return
    console.print(f"[bold red]WARNING: {_esc(what)} is marked physically suspect[/bold red] "
                  "(written by tcpmm identify --accept-suspect); its predictions may be "
                  "meaningless:")
    for s in machine.suspect:
        console.print(f"[red]  - {_esc(s)}[/red]")


def _read_model(model: str):
    """Read a model file, warning when it carries suspect marks."""
    from .io.modelfile import read_machine

    m = read_machine(model)
    _warn_suspect(m, f"model {model}")
    return m


@app.command()
def demo(out_dir: Path = typer.Option(Path("out/demo"), "-o", "--out", help="Output folder.")):
    """The paper's circular test (R35 mm, 5000 mm/min, CCW and CW) on the built-in machine."""
    from .demo import DEMO_STEPS, run_demo

    with _progress(len(DEMO_STEPS), "demo") as adv:
        res = run_demo(out_dir, progress=adv, console=out)
    out.print(f"Wrote {len(res['files'])} files to [bold]{Path(out_dir).resolve()}[/bold]")
    for k, v in res["files"].items():
        out.print(f"  {k:12s} {v}")


@machine_app.command("export")
def machine_export(name: str = typer.Argument(..., help="Built-in machine name (vmc)."),
                   output: Path = typer.Option(..., "-o", "--output", help="MODEL.yaml")):
    """Write a built-in machine as a model file."""
    from .builtin import builtin_machine
    from .io.modelfile import write_machine

    write_machine(builtin_machine(name), _output(output))
    out.print(f"wrote {output}")


@machine_app.command("show")
def machine_show(model: str = typer.Argument(..., help="MODEL.yaml or builtin:vmc"),
                 as_json: bool = typer.Option(False, "--json")):
    """Modes of each axis (natural frequencies and damping) and closed-loop stability."""
    import numpy as np

    from .mechanics.statespace import plant
    from .servo.closedloop import is_stable
    from .servo.sampled import sampled_spectral_radius

    m = _read_model(model)
    data = {}
    for ax, a in m.axes.items():
        ev = np.linalg.eigvals(plant(a.mechanics).A)
        ev = ev[ev.imag > 0]
        order = np.argsort(np.abs(ev))
        data[ax] = {"modes_hz": [float(abs(e) / (2 * np.pi)) for e in ev[order]],
                    "damping": [float(-e.real / abs(e)) for e in ev[order]],
                    "closed_loop_stable": is_stable(a.mechanics, a.servo),
                    "sampled_loop_spectral_radius": sampled_spectral_radius(a.mechanics, a.servo)}
    if as_json:
        _emit_json(data)
        return
    for ax, d in data.items():
        modes = ", ".join(f"{f:.1f} Hz (zeta {z:.3f})" for f, z in
                          zip(d["modes_hz"], d["damping"], strict=True))
        state = "stable" if d["closed_loop_stable"] else "UNSTABLE"
        rho = d["sampled_loop_spectral_radius"]
        sampled = "stable" if rho < 1.0 else "UNSTABLE"
        out.print(f"{ax}: {modes}; closed loop {state}; sampled loop {sampled} "
                  f"(spectral radius {rho:.4f})")


def _load_command(command: Path | None, gcode: Path | None, machine):
    from .path import program_to_command, read_command_csv

    if (command is None) == (gcode is None):
        raise typer.BadParameter("give exactly one of --command CMD.csv or --gcode PROG.nc")
    if command is not None:
        return read_command_csv(command)
    with _in_file(gcode):
        return program_to_command(gcode, _interp_settings(machine))


def _interp_settings(machine):
    from .path import InterpolatorSettings

    if machine is not None and machine.interpolation is not None:
        return InterpolatorSettings.model_validate(machine.interpolation)
    return InterpolatorSettings()


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
    from .simulate import simulate as _simulate

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
    from .analysis.circular import analyse_circle
    from .demo import print_circle_table
    from .io.runfile import read_run_csv

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
    from .analysis.circular import analyse_circle
    from .analysis.compare import compare_circles
    from .demo import print_circle_table
    from .io.runfile import read_run_csv

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
        from .plot.circle import plot_circle

        plot_circle(rm, plot, sensors=["tcp"], overlay=rp)
    if as_json:
        _emit_json(cmp.to_dict())
    else:
        print_circle_table(cmp.to_pandas(), out, "measured - predicted [um]")
        for line in cmp.notes():
            out.print(line)


def _refuse_unstable(machine, model: str) -> None:
    """An error naming each axis whose sampled loop is unstable: its run would diverge."""
    from .servo.sampled import sampled_spectral_radius

    bad = {n: sampled_spectral_radius(a.mechanics, a.servo) for n, a in machine.axes.items()}
    bad = {n: r for n, r in bad.items() if r >= 1.0}
    if bad:
        axes = ", ".join(f"{n} (spectral radius {r:.4f})" for n, r in bad.items())
        raise InputError(f"the sampled servo loop of axis {axes} is unstable, so a run would "
                         "diverge rather than predict anything; check the gains and periods "
                         "(tcpmm machine show), or pass --allow-unstable to simulate it anyway",
                         file=model)


@app.command()
def spread(model: str = typer.Argument(..., help="MODEL.yaml written by tcpmm identify"),
           command: Path = typer.Option(None, "--command", help="Command file CMD.csv."),
           gcode: Path = typer.Option(None, "--gcode", help="NC program PROG.nc."),
           radius: float = typer.Option(..., "--radius", help="Nominal radius [mm]."),
           centre: str = typer.Option("0,0", "--centre", help="Nominal centre X,Y [mm]."),
           draws: int = typer.Option(16, "--draws", min=1, help="Machines drawn [-]."),
           seed: int = typer.Option(0, "--seed", min=0, help="Seed of the draws [-]."),
           sensor: Sensor = typer.Option("tcp", "--sensor", help="Sensor analysed."),
           fit_only: bool = typer.Option(
               False, "--fit-only",
               help="Draw from the fits' own standard deviations alone, without the "
                    "floors of tcpmm.spread.MODEL_ERROR."),
           tolerance: float = typer.Option(
               None, "--tolerance-um",
               help="Spike difference to hold at nine in ten draws [um]; default: the "
                    "largest of the paper's Table 2, 4.1 um (tcpmm.spread.TOLERANCE)."),
           as_json: bool = typer.Option(False, "--json"),
           plot: Path = typer.Option(None, "--plot", help="Save a plot (PNG/PDF/SVG).")):
    """Reversal spikes of a circle with their spread over the identified uncertainty."""
    from .demo import print_circle_table
    from .spread import MODEL_ERROR, TOLERANCE, circle_spread

    if tolerance is not None:
        _positive(tolerance, "--tolerance-um [um]")
    _positive(radius, "--radius [mm]")
    _plot(plot)
    tol_m = TOLERANCE if tolerance is None else tolerance * 1e-6
    m = _read_model(model)
    cmd = _load_command(command, gcode, m)
    c = _floats(centre, "--centre", 2)
    with _progress(draws + 1, "spread") as adv:
        res = circle_spread(m, cmd, radius * 1e-3, (c[0] * 1e-3, c[1] * 1e-3), n=draws,
                            seed=seed, sensor=sensor.value,
                            floors=None if fit_only else MODEL_ERROR,
                            tolerance_m=tol_m, progress=adv)
    if plot is not None:
        res.plot(plot)
    if as_json:
        _emit_json(res.to_dict())
        return
    table = res.to_pandas()
    print_circle_table(table, out, f"{sensor.value} spikes over {draws} drawn machines [um]")
    for r in res.unsettled():
        out.print(f"{r['direction'].upper()} {r['point']}: the sign is not settled "
                  f"({100 * r['same_sign']:.0f} % of the draws give it): rise "
                  f"{r['rise_um']:+.2f} um, fall {r['fall_um']:+.2f} um; a measured spike "
                  "can differ from this one by their sum")
    for r in res.loose():
        out.print(f"{r['direction'].upper()} {r['point']}: the size is not firm "
                  f"({100 * r['within']:.0f} % of the draws lie within {tol_m * 1e6:g} um of "
                  f"{r['spike_um']:.2f} um; range {r['low_um']:.2f} to {r['high_um']:.2f} um)")


@app.command()
def bode(model: str = typer.Argument(..., help="MODEL.yaml or builtin:vmc"),
         axis: str = typer.Option(..., "--axis", help="Axis name, e.g. X."),
         tf: str = typer.Option(..., "--tf", help="G_M, G_T, G_tcp, G_v, G_p, cmd_to_tcp, "
                                 "cmd_to_motor or cmd_to_current."),
         freq_hz: str = typer.Option(None, "--freq-hz", help="F1,F2,... [Hz]"),
         as_json: bool = typer.Option(False, "--json"),
         plot: Path = typer.Option(None, "--plot", help="Save a Bode plot.")):
    """Frequency response of a transfer function of the model."""
    import numpy as np

    from .mechanics.transfer import REDUCED, reduced_freqresp
    from .servo.closedloop import CLOSED_LOOP_TFS, closed_loop_freqresp

    _plot(plot)
    m = _read_model(model)
    a = m.axis(axis)
    f = np.array(_floats(freq_hz, "--freq-hz")) if freq_hz else np.logspace(0, 3.2, 200)
    if np.any(f <= 0):
        raise typer.BadParameter("--freq-hz values must be positive")
    if tf in REDUCED:
        H = reduced_freqresp(a.mechanics, tf, f, a.servo.current_bandwidth_hz)
    elif tf in CLOSED_LOOP_TFS:
        H = closed_loop_freqresp(a.mechanics, a.servo, tf, f)
    else:
        raise typer.BadParameter(f"--tf must be one of {', '.join([*REDUCED, *CLOSED_LOOP_TFS])}")
    if plot is not None:
        from .plot.bode import plot_bode

        plot_bode({tf: [(f"{axis.upper()} model", f, H, {"color": "tab:red"})]}, plot)
    rows = [{"freq_hz": float(fi), "re": float(h.real), "im": float(h.imag)}
            for fi, h in zip(f, H, strict=True)]
    if as_json:
        _emit_json(rows)
    else:
        for r in rows:
            h = complex(r["re"], r["im"])
            out.print(f"{r['freq_hz']:12.4g} Hz  |H| {abs(h):.6g}  phase "
                      f"{np.degrees(np.angle(h)):8.2f} deg")


@app.command()
def path(program: Path = typer.Argument(..., help="NC program PROG.nc"),
         output: Path = typer.Option(..., "-o", "--output", help="Command file CMD.csv."),
         model: str = typer.Option(None, "--model", help="Model file with interpolator settings."),
         plot: bool = typer.Option(False, "--plot", help="Also save CMD.png beside the CSV.")):
    """Interpolate an NC program into the position command per axis."""
    from .path import program_to_command, write_command_csv

    _output(output, program, model)
    if plot and output.suffix.lower() == ".png":
        raise typer.BadParameter(f"{output} would be overwritten by the plot of --plot; "
                                 "give the command file the extension .csv")
    m = None
    if model is not None:
        from .io.modelfile import read_machine

        m = read_machine(model)
    cmd = program_to_command(program, _interp_settings(m))
    write_command_csv(cmd, output)
    out.print(f"wrote {output} ({cmd.time_s.size} samples at {cmd.period_s * 1e3:g} ms, "
              f"{cmd.time_s[-1] - cmd.time_s[0]:.3f} s)")
    if plot:
        from .plot.path import plot_command

        p = plot_command(cmd, output.with_suffix(".png"))
        out.print(f"wrote {p}")


@app.command()
def excite(kind: str = typer.Argument(..., help="linear, log, multisine or prbs"),
           band: str = typer.Option(..., "--band", help="F0,F1 [Hz]"),
           amplitude_A: float = typer.Option(..., "--amplitude-A", help="Amplitude [A]."),
           duration_s: float = typer.Option(..., "--duration-s", help="Duration [s]."),
           fs_hz: float = typer.Option(..., "--fs-hz", help="Sample rate [Hz]."),
           output: Path = typer.Option(..., "-o", "--output", help="FILE.csv"),
           taper_s: float = typer.Option(None, "--taper-s", help="Fade in/out [s] (sweeps)."),
           seed: int = typer.Option(None, "--seed", min=0,
                                    help="Random phases seed (multisine).")):
    """Design an excitation signal for the current command (time_s, excitation_A)."""
    from .ident.excitation import design_excitation

    f0, f1 = _band(band, "--band")
    _output(output)
    options = {"f0_hz": "--band", "f1_hz": "--band", "amplitude_A": "--amplitude-A",
               "duration_s": "--duration-s", "fs_hz": "--fs-hz", "taper_s": "--taper-s",
               "kind": "KIND", "seed": "--seed"}
    try:
        exc = design_excitation(kind, f0, f1, amplitude_A, duration_s, fs_hz,
                                taper_s=taper_s, seed=seed)
    except InputError as err:
        if err.file is None and err.column in options:
            raise typer.BadParameter(err.message, param_hint=options[err.column]) from None
        raise
    exc.write_csv(output)
    out.print(f"wrote {output}: {exc.kind}, band {exc.band_hz[0]:g}-{exc.band_hz[1]:g} Hz, "
              f"{exc.time_s.size} samples ({exc.time_s.size / exc.fs_hz:g} s), "
              f"peak {exc.peak_A:.3g} A, rms {exc.rms_A:.3g} A, crest {exc.crest_factor:.2f}")


@app.command()
def identify(bundle: Path = typer.Argument(..., help="Measurement bundle folder."),
             output: Path = typer.Option(..., "-o", "--output", help="MODEL.yaml"),
             report: Path = typer.Option(None, "--report", help="Folder for plots and tables."),
             band: str = typer.Option(None, "--band", help="F0,F1 of the FRFs [Hz]."),
             guideway_share: float = typer.Option(
                 None, "--guideway-share", min=0.0, max=1.0,
                 help="Share of the friction from friction.csv put on the guideway [-]; "
                      "default: from the encoder-minus-scale deflection of the runs."),
             presliding_um: float = typer.Option(
                 None, "--presliding-um", min=0.0,
                 help="Pre-sliding displacement of the friction contacts [um] (LuGre); "
                      "0: static friction that sticks rigidly; default: "
                      "tcpmm.ident.presliding.PRESLIDING."),
             accept_suspect: bool = typer.Option(
                 False, "--accept-suspect",
                 help="Write the model even when the gates find it physically suspect "
                      "(static friction beyond the drive, a negative fit, an unstable "
                      "sampled loop, a time column in the wrong unit), marked as suspect "
                      "in the file."),
             as_json: bool = typer.Option(False, "--json")):
    """Identify every axis of a measurement bundle into a model file.

    A model that the gates (tcpmm.ident.gates) find physically suspect is an error and is
    not written, unless --accept-suspect.
    """
    from .ident.pipeline import identify_bundle
    from .ident.presliding import PRESLIDING
    from .io.atomic import output_folder
    from .io.bundle import read_bundle
    from .io.modelfile import write_machine

    _output(output)
    if report is not None:
        output_folder(report)
    f0, f1 = _band(band, "--band")
    b = read_bundle(bundle)
    presliding = PRESLIDING if presliding_um is None else presliding_um * 1e-6
    with _progress(len(b.axes), "identify") as adv:
        idn = identify_bundle(b, f0, f1, progress=adv, guideway_share=guideway_share,
                              presliding=presliding, accept_suspect=accept_suspect)
    if report is not None:
        idn.write_report(report)
    write_machine(idn.machine, output)
    _warn_suspect(idn.machine, f"the model written to {output}")
    if as_json:
        _emit_json(idn.to_dict())
        return
    from .demo import print_circle_table

    print_circle_table(idn.quality_table().drop(columns=["modes_hz"]), out, "fit quality")
    if presliding > 0 and any(a.friction is not None for a in idn.axes.values()):
        out.print(f"friction: pre-sliding of {presliding * 1e6:g} um assumed on every contact "
                  "(the friction runs do not determine it; --presliding-um sets it)")
    out.print(f"wrote {output}" + (f" and the report in {report}" if report else ""))



def main(argv=None) -> int:
    """Entry point of the ``tcpmm`` console script."""
    shown = warnings.showwarning

    def show(message, category, filename, lineno, file=None, line=None):
        """Print input warnings as the user's problem, not as a place in the package."""
        if issubclass(category, InputWarning):
            console.print(f"[yellow]warning:[/yellow] {_esc(str(message))}")
        else:
            shown(message, category, filename, lineno, file, line)

    warnings.showwarning = show
    handlers = _exit_on_signals()
    try:
        app(args=argv, standalone_mode=True)
    except TcpmmError as exc:
        console.print(f"[red]error:[/red] {_esc(str(exc))}")
        return 2
    except OSError as exc:  # the system refused a file or a folder the command used
        where = f" ({exc.filename})" if exc.filename else ""
        console.print(f"[red]error:[/red] {_esc((exc.strerror or str(exc)) + where)}")
        return 2
    except SystemExit as exc:
        return int(exc.code or 0) if not isinstance(exc.code, str) else 1
    finally:
        warnings.showwarning = shown
        _restore_signals(handlers)
    return 0


def _exit_on_signals() -> dict:
    """Turn SIGTERM and SIGHUP into an orderly exit (128 + signal number), so that outputs
    being written are removed rather than left half-written; returns the handlers before.
    Only the main thread can set handlers; elsewhere nothing changes."""
    import signal
    import threading

    if threading.current_thread() is not threading.main_thread():
        return {}

    def leave(signum, frame):
        raise SystemExit(128 + signum)

    before = {}
    for name in ("SIGTERM", "SIGHUP"):
        sig = getattr(signal, name, None)
        if sig is not None:
            before[sig] = signal.signal(sig, leave)
    return before


def _restore_signals(before: dict) -> None:
    import signal

    for sig, handler in before.items():
        signal.signal(sig, handler)


def _esc(text: str) -> str:
    from rich.markup import escape

    return escape(text)


if __name__ == "__main__":
    sys.exit(main())
