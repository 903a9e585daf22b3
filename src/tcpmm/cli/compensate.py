"""Command that pre-compensates a position command on an identified model: compensate."""

from __future__ import annotations

from pathlib import Path

import typer

from ._app import (
    app,
    checked_output,
    checked_report_file,
    emit_json,
    in_file,
    interp_settings,
    load_command,
    out,
    read_model,
)


def _row(label: str, fig: dict) -> str:
    path = fig["path"]
    text = f"  {label:7s} contour error to the command {path['contour_error_um']:8.2f} µm (rms " \
           f"{path['contour_rms_um']:.2f})"
    if "circle" in fig:
        c = fig["circle"]
        text += f", largest raw spike (e - b) {c['largest_spike_um']:.2f} µm, G " \
                f"{c['circular_deviation_um']:.2f} µm"
    return text


_HEADROOM_HELP = ("Share of the axes' acceleration and jerk left to the correction: an NC "
                  "program (--gcode) is planned with the rest, so that the correction has "
                  "room in the feed ramps and corners; the path and feed are the same, the "
                  "program takes longer. Default 0.25 for --gcode; a command file is "
                  "already timed.")


@app.command()
def compensate(model: str = typer.Argument(..., help="MODEL.yaml (identified) or builtin:vmc"),
               command: Path = typer.Option(None, "--command", help="Command file CMD.csv."),
               gcode: Path = typer.Option(None, "--gcode", help="NC program PROG.nc."),
               output: Path = typer.Option(..., "-o", "--output",
                                           help="Compensated command CMD_comp.csv."),
               gcode_out: Path = typer.Option(None, "--gcode-out",
                                              help="Also write it as a dense G1 program."),
               radius: float = typer.Option(None, "--radius",
                                            help="Circle radius [mm]: also judge spikes "
                                                 "and G, and keep them from getting "
                                                 "worse on any draw."),
               draws: int = typer.Option(8, "--draws", help="Machines drawn from the "
                                         "model's uncertainty to test it on (0: none)."),
               iterations: int = typer.Option(30, "--iterations", help="Learning steps."),
               accel: float = typer.Option(None, "--accel-m-per-s2",
                                           help="Axis acceleration the compensated command "
                                                "may use [m/s^2]; default the model's "
                                                "interpolation settings (1 without them)."),
               jerk: float = typer.Option(None, "--jerk-m-per-s3",
                                          help="Axis jerk the compensated command may use "
                                               "[m/s^3]; default the model's S-curve jerk, "
                                               "none for a trapezoid."),
               headroom: float = typer.Option(None, "--headroom", help=_HEADROOM_HELP),
               controller_out: Path = typer.Option(
                   None, "--controller-out",
                   help="PARAMS.yaml: also compute the controller-side compensation of the "
                        "circle (--radius), a friction pulse per reversal and a cross-talk "
                        "feed-forward per axis, and learn the command with them on the "
                        "controller: it is right only with them."),
               report: Path = typer.Option(None, "--report",
                                           help="REPORT.html: the TCP error before and "
                                                "after, the figures and the settings per "
                                                "axis."),
               as_json: bool = typer.Option(False, "--json")):
    """Pre-compensate a command so that the model's predicted TCP follows the programmed
    path, within the axes' limits (an NC program is planned with headroom for the
    correction); write it (for tcpmm simulate --command) and report before and after."""
    from ..compensate import machine_bounds
    from ..compensate.gcodeout import write_dense_program
    from ..path import write_command_csv

    _check_outputs(output, report, controller_out, radius, model, command, gcode)
    m = read_model(model)
    bounds = machine_bounds(m, accel, jerk)
    full, cmd, headroom = _planned(command, gcode, m, headroom)
    radius_m = None if radius is None else radius * 1e-3
    tuned = None if controller_out is None else _tuned(m, cmd, radius_m)
    comp = _compensated(m, cmd, command or gcode, iterations, bounds, draws, radius_m, full,
                        tuned)
    comp.settings["headroom"] = headroom
    write_command_csv(comp.command, output)
    if gcode_out is not None:
        write_dense_program(comp.command, gcode_out)
    cc = None if controller_out is None else _write_parameters(comp, controller_out, output)
    if report is not None:
        _write_report(report, comp, m, model, command or gcode, radius_m, cc)
    if as_json:
        emit_json({**comp.to_dict(), **({"controller": cc.to_dict()} if cc else {})})
        return
    _say(output, report, comp, controller_out, cc)


def _check_outputs(output: Path, report, controller_out, radius, model: str, command,
                   gcode) -> None:
    """Refuse output paths that clash with the inputs or each other before any work, and
    a controller-side compensation without the circle's radius.

    Parameters
    ----------
    output : Path
        The compensated command file [-].
    report, controller_out : Path or None
        The report page and the controller parameters file, where asked [-].
    radius : float or None
        The circle's radius [mm].
    model : str
        The model file or builtin name [-].
    command, gcode : Path or None
        The program's command file or NC program [-].
    """
    checked_output(output, model, command, gcode)
    checked_report_file(report, model, command, gcode, output)
    if controller_out is not None:
        checked_output(controller_out, model, command, gcode, output)
        if radius is None:
            raise typer.BadParameter("--controller-out needs the circle's --radius [mm]")


def _planned(command, gcode, machine, headroom):
    """The program at the axes' full limits, the one the correction is learned on and the
    headroom left to it (:mod:`tcpmm.compensate.headroom`).

    Parameters
    ----------
    command, gcode : Path or None
        The command file or the NC program [-].
    machine : Machine
        Whose interpolator settings plan the program [-].
    headroom : float or None
        ``--headroom`` [-].
    """
    from ..compensate.headroom import headroom_for, program_with_headroom

    headroom = headroom_for(gcode is not None and command is None, headroom)
    if gcode is None or command is not None:
        cmd = load_command(command, gcode, machine)
        return cmd, cmd, 0.0
    with in_file(gcode):
        full, planned = program_with_headroom(gcode, interp_settings(machine), headroom)
    return full, planned, headroom


def _compensated(machine, cmd, source, iterations: int, bounds, draws: int, radius_m,
                 programmed=None, tuned=None):
    """The compensation of a command, tested on drawn machines and scored.

    Parameters
    ----------
    machine : Machine
        The model [-].
    cmd : Command
        The programmed command [m].
    source : Path
        The program's file, named by input errors [-].
    iterations : int
        Learning steps [-].
    bounds : dict
        The axes' limits the command keeps (``machine_bounds``) [SI].
    draws : int
        Machines drawn from the model's uncertainty, 0 for none [-].
    radius_m : float or None
        The circle's radius, where it is one [m].
    programmed : Command, optional
        The program at the axes' full limits, judged before, where ``cmd`` was planned
        with headroom [m].
    tuned : ControllerCompensation, optional
        Controller-side parameters tuned on the model: the correction is learned with
        them on the controller and scaled back together with them
        (:mod:`tcpmm.compensate.combined`) [-].

    Returns
    -------
    Compensation
        The compensated command with its robustness and scores [-].
    """
    from ..compensate import compensate, predicted_scores, robust_factors
    from ..compensate.combined import combined_compensation

    with in_file(source):
        if tuned is not None:
            comp = combined_compensation(machine, cmd, tuned.axes, bounds=bounds,
                                         iterations=iterations, n_draws=draws,
                                         radius_m=radius_m)
        else:
            comp = compensate(machine, cmd, iterations=iterations, bounds=bounds)
        if draws > 0 and tuned is None:
            robust_factors(machine, comp, n_draws=draws, radius_m=radius_m)
        comp.scores = predicted_scores(machine, comp, radius_m, programmed=programmed)
    full = cmd if programmed is None else programmed
    comp.settings.update(programmed_duration_s=float(full.time_s[-1]),
                         planned_duration_s=float(cmd.time_s[-1]))
    return comp


def _say(output: Path, report, comp, controller_out, cc) -> None:
    """Print what was written and the TCP error before and after, on the console.

    Parameters
    ----------
    output : Path
        The compensated command file [-].
    report, controller_out : Path or None
        The report page and the controller parameters file, where written [-].
    comp : Compensation
        The compensation [-].
    cc : ControllerCompensation or None
        The controller-side compensation, where computed [-].
    """
    result = comp.command
    out.print(f"wrote {output} ({result.time_s.size} samples, TCP delayed by "
              f"{comp.delay_s * 1e3:.1f} ms)" + (f" and the report {report}" if report else ""))
    out.print(_row("before", comp.scores["before"]))
    if "planned" in comp.scores:
        out.print(_row("planned", comp.scores["planned"]) + " (the program planned with the "
                  "headroom below, uncorrected)")
    out.print(_row("after", comp.scores["after"]))
    if not comp.applied:
        out.print("  no share of the correction is applied: the figures after are those of "
                  "the command as planned", highlight=False)
    st = comp.settings
    if st.get("headroom"):
        out.print(f"  planned with {1 - st['headroom']:.0%} of the axes' acceleration and "
                  f"jerk, the rest left to the correction: {st['planned_duration_s']:.2f} s "
                  f"instead of {st['programmed_duration_s']:.2f} s")
    if comp.robustness:
        for line in _verdict_lines(comp.robustness):
            out.print(line)
    if cc is not None:
        out.print(f"wrote {controller_out} (controller-side compensation: friction pulses "
                  f"and cross-talk feed-forward; {output} was learned with them and is "
                  "right only with them on the controller; the figures above are with "
                  "both)")
        if cc.robustness:
            out.print(f"  share of the tuned parameters kept: {cc.robustness['share']:g}")


#: How each verdict over the draws reads [-].
_VERDICT_TEXT = {"firm": "firm: every draw at least {r:.1f}x smaller",
                 "improves": "improves: every draw smaller by more than the model's "
                             "error, the least by {r:.1f}x",
                 "uncertain": "uncertain: some draw not smaller by more than the model's "
                              "error; the share applied keeps it from growing"}


def _verdict_lines(robustness: dict) -> list[str]:
    """The shares applied and what the draws of the model say of them, on the console.

    Parameters
    ----------
    robustness : dict
        ``Compensation.robustness`` (:func:`tcpmm.compensate.robust_factors`) [-].
    """
    from ..compensate.robust import FIRM_RATIO

    f = ", ".join(f"{a} {v:g}" for a, v in robustness["factors"].items())
    return [f"  share of the correction applied: {f}; over {robustness['draws']} draws of "
            f"the model it improves {robustness['trusted_share']:.0%} of the samples, "
            f"at least {FIRM_RATIO:g}x (firm) {robustness['firm_share']:.0%}",
            *_figure_verdicts(robustness.get("circle", {}))]


def _figure_verdicts(figures: dict) -> list[str]:
    """A line per circle figure with the draws' verdict on it.

    Parameters
    ----------
    figures : dict
        ``{"spike": ..., "circular_deviation": ...}``, each of
        :func:`tcpmm.compensate.robust.over_draws` [-].
    """
    names = {"spike": "largest raw reversal spike (e - b)", "circular_deviation": "G"}
    return [f"  {name}: " + _VERDICT_TEXT[figures[key]["verdict"]].format(
        r=figures[key]["least_ratio"]) for key, name in names.items() if key in figures]


def _write_report(path: Path, comp, machine, model: str, source, radius_m, cc) -> None:
    """The compensation's report page: its section, then the model's."""
    from ..report import model_section, write_report
    from ..report.compensation import compensation_section

    sections = [compensation_section(comp, str(source), machine, radius_m, cc),
                model_section(machine, model)]
    write_report(path, sections, "Compensation", [("model", model), ("program", source)])


def _tuned(machine, cmd, radius_m: float):
    """The controller-side compensation of the circle tuned on the model, unscaled [-]."""
    from ..compensate.controller import controller_compensation

    plane = tuple(a for a in ("X", "Y", "Z") if a in cmd.axes)[:2]
    return controller_compensation(machine, cmd, radius_m, plane=plane)


def _write_parameters(comp, path: Path, command_file: Path):
    """The parameters the compensated command was learned with, as kept over the draws,
    written to ``path`` with a note that the command needs them [-]."""
    from ..compensate.controller import ControllerCompensation
    from ..io.atomic import write_text_atomic

    share = comp.robustness.get("parameter_share", 1.0) if comp.robustness else 1.0
    cc = ControllerCompensation(comp.controller, comp.scores, {"share": share})
    note = (f"# These parameters go with the compensated command {command_file.name}: it was "
            "learned with them\n# on the controller and is right only with them "
            f"(share of the tuned parameters kept: {share:g}).\n")
    if share == 0.0:  # the draws kept none: the command is for a controller without them
        note += "# No share is kept: all are 0, the command needs the controller without them.\n"
    write_text_atomic(path, note + cc.parameter_text())
    return cc
