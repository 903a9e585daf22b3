"""Command that pre-compensates a position command on an identified model: compensate."""

from __future__ import annotations

from contextlib import contextmanager
from pathlib import Path

import typer

from ._app import (
    app,
    checked_output,
    checked_report_file,
    emit_json,
    floats,
    in_file,
    interp_settings,
    load_command,
    positive,
    progress_bar,
    read_model,
)
from ._compensate_dense import write_dense
from ._compensate_text import (
    say_compensation,
    warn_current,
    warn_extra_reversals,
    warn_over_limits,
    warn_worse,
)
from ._outputs import checked_csv_output, distinct_outputs, outputs_together
from ._pathtext import warn_feed_held
from ._plane import judged_circle

_PLANE_HELP = ("Plane of the circle (--radius): XY, XZ, YZ (or ZX as G18 has it); default "
               "the plane of the program's arcs, else the one it moves in.")
_ACCEL_HELP = ("Axis acceleration the compensated command may use [m/s^2]; default the "
               "model's interpolation settings (1 without them).")
_JERK_HELP = ("Axis jerk the compensated command may use [m/s^3]; default the model's "
              "S-curve jerk, none for a trapezoid. Given with a trapezoid, an NC program "
              "with headroom is planned with an S-curve at it.")
_REPORT_HELP = ("REPORT.html: the TCP error before and after, the figures and the settings "
                "per axis.")
_CONTROLLER_HELP = ("PARAMS.yaml: also compute the controller-side compensation of the "
                    "circle (--radius), a friction pulse per reversal and a cross-talk "
                    "feed-forward per axis, and learn the command with them on the "
                    "controller: it is right only with them.")
_REFERENCE_HELP = ("REF.csv: also write the program as planned for the correction, "
                   "uncompensated: measure a run of the compensated command against it "
                   "(tcpmm contour RUN --command REF.csv), on its time line.")
_HEADROOM_HELP = ("Share of the axes' acceleration and jerk left to the correction: an NC "
                  "program (--gcode) is planned with the rest, so that the correction has "
                  "room in the feed ramps and corners; the path is the same, the ramps and "
                  "corners longer, and on a curve the feed no more than the rest of the "
                  "acceleration allows: the program takes longer. Default 0.25 for --gcode; "
                  "a command file is already timed.")


@app.command()
@outputs_together()
def compensate(model: str = typer.Argument(..., help="MODEL.yaml (identified) or builtin:vmc"),
               command: Path = typer.Option(None, "--command", help="Command file CMD.csv."),
               gcode: Path = typer.Option(None, "--gcode", help="NC program PROG.nc."),
               output: Path = typer.Option(..., "-o", "--output",
                                           help="Compensated command CMD_comp.csv."),
               gcode_out: Path = typer.Option(None, "--gcode-out",
                                              help="Also write it as a dense G1 program."),
               radius: float = typer.Option(None, "--radius",
                                            help="Circle radius [mm]: also judge spikes "
                                                 "and G on every draw; default the circle "
                                                 "the command runs, where it is one."),
               centre: str = typer.Option("0,0", "--centre", help="Centre of the circle "
                                          "(--radius) in its plane's axes, A,B [mm]."),
               plane: str = typer.Option(None, "--plane", help=_PLANE_HELP),
               draws: int = typer.Option(16, "--draws", min=0, help="Machines drawn from the "
                                         "model's uncertainty to test it on (0: none)."),
               iterations: int = typer.Option(30, "--iterations", min=1,
                                              help="Learning steps."),
               accel: float = typer.Option(None, "--accel-m-per-s2", help=_ACCEL_HELP),
               jerk: float = typer.Option(None, "--jerk-m-per-s3", help=_JERK_HELP),
               headroom: float = typer.Option(None, "--headroom", help=_HEADROOM_HELP),
               controller_out: Path = typer.Option(None, "--controller-out",
                                                   help=_CONTROLLER_HELP),
               report: Path = typer.Option(None, "--report", help=_REPORT_HELP),
               reference_out: Path = typer.Option(None, "--reference-out",
                                                  help=_REFERENCE_HELP),
               as_json: bool = typer.Option(False, "--json")):
    """Pre-compensate a command so that the model's predicted TCP follows the programmed
    path, within the axes' limits (an NC program is planned with headroom for the
    correction); write it (for tcpmm simulate --command) and report before and after."""
    from ..analysis.circle_find import circle_said
    from ..compensate import machine_bounds
    from ..compensate.held import without_held

    _check_outputs(output, (report, controller_out, reference_out, gcode_out), radius, model,
                   command, gcode)
    centre_m = tuple(c * 1e-3 for c in floats(centre, "--centre", 2))
    m = read_model(model)
    bounds = machine_bounds(m, accel, jerk)
    full, cmd, headroom = _planned(command, gcode, m, headroom, bounds)
    (full, cmd), held = without_held(m, full, cmd)
    circle = judged_circle(radius, centre_m, plane, cmd)
    with _controller_bar(m, cmd, circle, (iterations, draws), controller_out) as (tune, learn):
        tuned = None if controller_out is None else _tuned(m, cmd, circle, draws, tune)
        comp, headroom = _of_program(m, (full, cmd, headroom), command or gcode,
                                     (iterations, draws), bounds, circle, tuned, learn)
    compensated = comp.command  # built anew at each access: the correction fitted to the limits
    _write_commands(compensated, cmd if headroom else full, held, output, reference_out)
    comp.settings.update(circle=circle_said(circle, radius is None), held_axes_m=held)
    if gcode_out is not None:
        write_dense(compensated, comp, m, gcode_out, output.name)
    cc = None if controller_out is None else _write_parameters(comp, controller_out, output, m)
    planner = None if gcode is None else machine_bounds(m)  # the limits it was planned to
    if report is not None:
        _write_report(report, comp, m, model, command or gcode, circle, cc, planner)
    _warn(comp, compensated, cc, planner)
    if as_json:
        emit_json({**comp.to_dict(), **({"controller": cc.to_dict()} if cc else {})})
        return
    say_compensation(output, report, comp, controller_out, cc, reference_out, planner)


def _of_program(machine, plans, source, steps, bounds, circle, tuned, progress=None):
    """The compensation of the plan with headroom, or of the program as programmed where
    the draws keep none of it or a figure ends worse than the program's
    (:func:`tcpmm.compensate.headroom.on_the_program`: the draws judge it against its own
    plan), with the headroom kept in its settings, and that headroom.

    Parameters
    ----------
    machine : Machine
        The model [-].
    plans : tuple
        The program as programmed, as planned with the headroom, and the headroom [m, -].
    source : Path
        The program's file [-].
    steps : tuple of int
        ``--iterations`` and ``--draws`` [-].
    bounds : dict
        The axes' limits [SI].
    circle : tuple or None
        ``(radius, centre, plane)`` of the circle [m, m, -].
    tuned : ControllerCompensation or None
        Controller-side parameters the correction is learned with [-].
    progress : callable, optional
        Called with no argument after each step of the correction learned with ``tuned``
        (:func:`tcpmm.compensate.combined.combined_steps`) [-].
    """
    from ..compensate.headroom import corner_steps_s, on_the_program, scurve_plan

    full, cmd, headroom = plans
    iterations, draws = steps
    comp = _compensated(machine, cmd, source, iterations, bounds, draws, circle,
                        full if headroom else None, tuned, progress)
    if headroom and tuned is None and draws:
        comp, kept = on_the_program(machine, full, comp, bounds, lambda: _compensated(
            machine, full, source, iterations, bounds, draws, circle), circle)
        headroom = headroom if kept else 0.0
    comp.settings["headroom"] = headroom
    comp.settings["scurve_plan"] = scurve_plan(interp_settings(machine), bounds, headroom)
    if headroom:  # an NC program, planned anew
        comp.settings["corner_steps_s"] = corner_steps_s(
            source, interp_settings(machine), headroom, comp.settings["planned_duration_s"],
            bounds)
    return comp, headroom


def _write_commands(compensated, planned, held: dict, output, reference_out) -> None:
    """The compensated command, and the plan it compensates (with the headroom, else as
    programmed) where ``--reference-out`` asks, each with the axes held put back [-]."""
    from ..compensate.held import with_held
    from ..path import write_command_csv

    write_command_csv(with_held(compensated, held), output)
    if reference_out is not None:
        write_command_csv(with_held(planned, held), reference_out)


def _check_outputs(output: Path, extra, radius, model: str, command, gcode) -> None:
    """Refuse output paths that clash with the inputs (the model, ``command`` or ``gcode``)
    or each other before any work, and a controller-side compensation without the
    circle's ``radius`` [mm]; ``extra`` holds the report page, the controller parameters
    file, the reference command file and the dense program, each None where not asked."""
    report, controller_out, reference_out, gcode_out = extra
    if radius is not None:
        positive(radius, "--radius [mm]")
    checked_csv_output(output, model, command, gcode)
    if gcode_out is not None:
        checked_output(gcode_out, model, command, gcode)
    checked_report_file(report, model, command, gcode, output)
    if controller_out is not None:
        checked_output(controller_out, model, command, gcode, output)
        if radius is None:
            raise typer.BadParameter("--controller-out needs the circle's --radius [mm]")
    if reference_out is not None:
        checked_csv_output(reference_out, model, command, gcode, output)
    distinct_outputs(("-o", output), ("--gcode-out", gcode_out), ("--report", report),
                     ("--controller-out", controller_out), ("--reference-out", reference_out))


def _planned(command, gcode, machine, headroom, bounds):
    """The program at the axes' full limits, the one the correction is learned on and the
    headroom left to it (:mod:`tcpmm.compensate.headroom`).

    Parameters
    ----------
    command, gcode : Path or None
        The command file or the NC program [-].
    machine : Machine
        Whose interpolator settings plan the program [-].
    headroom, bounds : float or None, dict of str to AxisBounds
        ``--headroom``, a share of the limits the compensated command keeps [-], [SI].
    """
    from ..compensate.headroom import headroom_for, program_with_headroom
    from ..path.program import program_to_interpolation

    headroom = headroom_for(gcode is not None and command is None, headroom)
    if gcode is None or command is not None:
        cmd = load_command(command, gcode, machine)
        return cmd, cmd, 0.0
    settings = interp_settings(machine)
    with in_file(gcode):
        interp = program_to_interpolation(gcode, settings)  # once: the plan and its feeds
        full, planned = program_with_headroom(gcode, settings, headroom, bounds,
                                              interp.command)
        warn_feed_held(gcode, interp)
    return full, planned, headroom


def _compensated(machine, cmd, source, iterations: int, bounds, draws: int, circle,
                 programmed=None, tuned=None, progress=None):
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
    circle : tuple or None
        ``(radius, centre, plane)`` of the circle, where it is one [m, m, -].
    programmed : Command, optional
        The program at the axes' full limits, judged before, where ``cmd`` was planned
        with headroom [m].
    tuned : ControllerCompensation, optional
        Controller-side parameters tuned on the model: the correction is learned with
        them on the controller and scaled back together with them
        (:mod:`tcpmm.compensate.combined`) [-].
    progress : callable, optional
        Called with no argument after each step of that learning [-].

    Returns
    -------
    Compensation
        The compensated command with its robustness and scores [-].
    """
    from ..analysis.circle_find import circle_where
    from ..compensate import predicted_scores
    from ..compensate.candidates import compensate_within_draws
    from ..compensate.combined import combined_compensation

    where = circle_where(circle)
    with in_file(source):
        if tuned is not None:
            comp = combined_compensation(machine, cmd, tuned.axes, bounds=bounds,
                                         iterations=iterations, n_draws=draws,
                                         progress=progress, **where)
        else:  # learned two ways where draws judge it (compensate.candidates)
            comp = compensate_within_draws(machine, cmd, n_draws=draws, bounds=bounds,
                                           iterations=iterations, **where)
        comp.scores = predicted_scores(machine, comp, programmed=programmed, **where)
    full = cmd if programmed is None else programmed
    comp.settings.update(programmed_duration_s=float(full.time_s[-1]),
                         planned_duration_s=float(cmd.time_s[-1]))
    return comp


def _write_report(path: Path, comp, machine, model: str, source, circle, cc,
                  planner) -> None:
    """The compensation's report page: its section, then the model's; ``circle`` the
    ``(radius, centre, plane)`` of the circle or ``None`` [m, m, -]; ``planner`` the
    interpolator's own limits where an NC program was planned, else ``None`` [-]."""
    from ..report import model_section, write_report
    from ..report.compensation import compensation_section

    sections = [compensation_section(comp, str(source), machine, circle, cc, planner),
                model_section(machine, model)]
    write_report(path, sections, "Compensation", [("model", model), ("program", source)])


@contextmanager
def _controller_bar(machine, cmd, circle, steps, controller_out):
    """A bar on a terminal over the controller-side compensation of ``cmd`` on the circle
    ``(radius, centre, plane)`` [m, m, -], ``steps`` the ``--iterations`` and ``--draws``
    [-]: ``(tune, learn)``, each called with no argument after each step of the tuning of
    the parameters and of the command learned with them; ``None`` each where
    ``controller_out`` (``--controller-out``) is ``None`` [-]."""
    if controller_out is None:
        yield None, None
        return
    from ..compensate.adaptation import DRAWS
    from ..compensate.combined import combined_steps
    from ..compensate.controller import controller_steps

    iterations, draws = steps
    # the tuning and the learning with its parameters judged on the draws, each some hundred
    # runs of the model, take half a minute or more on a bench's circle with the default
    # draws: one bar over both, so that it is filled once, when the wait is over
    total = (controller_steps(machine, cmd, circle[2], min(draws, DRAWS))
             + combined_steps(cmd, iterations, draws))
    with progress_bar(total, "controller-side compensation") as advance:
        yield advance, lambda: advance("the command learned with the parameters")


def _tuned(machine, cmd, circle, draws: int, progress=None):
    """The controller-side compensation of the circle ``(radius, centre, plane)`` tuned on
    the model, unscaled; its pulses' adaptation characteristics checked on up to ``draws``
    draws of the model; ``progress`` called with no argument after each step of
    :func:`tcpmm.compensate.controller.controller_steps` [-]."""
    from ..compensate.adaptation import DRAWS
    from ..compensate.controller import controller_compensation

    radius_m, centre_m, plane = circle
    return controller_compensation(machine, cmd, radius_m, centre_m, plane,
                                   min(draws, DRAWS), progress=progress)


def _write_parameters(comp, path: Path, command_file: Path, machine):
    """The parameters the compensated command was learned with, as kept over the draws,
    written to ``path`` with a note that the command needs them and the model they were
    computed on [-]."""
    from ..compensate.controller import ControllerCompensation
    from ..io.atomic import write_text_atomic
    from ..io.modelfile import model_identity

    rob = comp.robustness or {}
    share = rob.get("parameter_share", 1.0)
    cc = ControllerCompensation(comp.controller, comp.scores, {"share": share})
    write_text_atomic(path, _parameter_note(command_file.name, share, rob.get("draws", 0))
                      + cc.parameter_text(model_identity(machine)))
    return cc


def _parameter_note(command_file: str, share: float, draws: int) -> str:
    """The head of the parameter file: what the compensated command needs on the
    controller, and whether draws of the model's uncertainty tested the parameters [-]."""
    if share == 0.0:  # the draws kept none: the command is for a controller without them
        return (f"# The {draws} draws of the model's uncertainty kept none of the tuned "
                f"parameters: all are 0.\n# The compensated command {command_file} was "
                "learned without them and is right only with them off (0) on the "
                "controller.\n")
    note = (f"# These parameters go with the compensated command {command_file}: it was "
            "learned with them\n# on the controller and is right only with them")
    if not draws:
        return note + (" (as tuned on the model; --draws 0: not tested on draws of "
                       "the model's\n# uncertainty).\n")
    return note + (f" (tested on {draws} draws of the model's uncertainty;\n# share of the "
                   f"tuned parameters kept: {share:g}).\n")


def _warn(comp, compensated, cc, planner) -> None:
    """The warnings of the compensation, before its figures and in ``--json`` alike: a
    figure the correction makes worse where no draws scaled it back, a current above the
    share of the drive's limit, a limit the command goes beyond (``planner``: the limits
    a program was planned to, None for a command file), and turns of the correction's own
    under the friction pulse of the parameters ``cc`` (None: none written) [-]."""
    warn_worse(comp)
    warn_current(comp)
    warn_over_limits(comp, planner)
    if cc is not None:
        warn_extra_reversals(compensated, comp.reference, cc)
