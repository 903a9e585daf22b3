"""The steps of the public API that are more than one existing function: reading a model
from wherever it is given, identifying a bundle from its folder, simulating a program
file, comparing two runs. Everything is imported when called, so that ``import tcpmm``
stays cheap."""

from __future__ import annotations

from pathlib import Path

#: What a command argument may be, said where it is none of them [-].
COMMAND_IS = ("a Command, an NC program's path or a command CSV's path (a table: write "
              "it with to_csv(path, index=False))")


def load_model(source):
    """A machine model from a model file, ``builtin:vmc``, or a Machine.

    Parameters
    ----------
    source : str or Path or Machine
        Model file (docs/formats.md), ``builtin:NAME``, or a machine, returned as it
        is [-].

    Returns
    -------
    Machine
        The model, SI inside [-].
    """
    return _model(source, "source")


def _model(source, name: str):
    """``source`` as a Machine (:func:`load_model`), an :class:`InputError` naming the
    argument ``name`` where it is neither a machine nor a path [-]."""
    from ._validate import file_path
    from .model import Machine

    if isinstance(source, Machine):
        return source
    from .io.modelfile import read_machine

    file_path(name, source, "a Machine, a model file's path or 'builtin:vmc'")
    return read_machine(source)


def save_model(machine, path) -> Path:
    """Write a model file atomically.

    Parameters
    ----------
    machine : Machine
        The model [-].
    path : str or Path
        Model file (YAML) [-].

    Returns
    -------
    Path
        The file written [-].
    """
    from ._validate import file_path
    from .errors import InputError
    from .io.modelfile import write_machine
    from .model import Machine

    if not isinstance(machine, Machine):
        raise InputError(f"machine must be a Machine (builtin_machine(), load_model(...), "
                         f"identify(...).machine), got {type(machine).__name__} "
                         f"{machine!r:.40}; the path comes second")
    path = file_path("path", path)
    write_machine(machine, path)
    return path


def as_command(command, machine=None):
    """A position command from a Command, an NC program file or a command CSV.

    Parameters
    ----------
    command : Command or str or Path
        The command itself, an NC program (``.nc``, ``.ngc``, ...; interpolated with the
        machine's interpolator settings) or a command file (``time_s, x_mm, ...``) [-].
    machine : Machine, optional
        Whose interpolator settings interpolate a program [-].

    Returns
    -------
    Command
        Interpolated position command [m].
    """
    from ._validate import file_path
    from .path import Command, InterpolatorSettings, program_to_command, read_command_csv
    from .path.program import PROGRAM_SUFFIXES

    if isinstance(command, Command):
        return command
    path = file_path("command", command, COMMAND_IS)
    if path.suffix.lower() not in PROGRAM_SUFFIXES:
        return read_command_csv(path)
    interp = getattr(machine, "interpolation", None)
    settings = (InterpolatorSettings.model_validate(interp) if interp is not None
                else InterpolatorSettings())
    return program_to_command(path, settings)


def simulate(machine, command, record_period_s=None, progress=None):
    """Run a machine model on a position command: every sensor of every axis.

    Parameters
    ----------
    machine : Machine or str or Path
        The model, a model file or ``builtin:vmc`` [-].
    command : Command or str or Path
        The command, an NC program file or a command CSV (:func:`as_command`) [-].
    record_period_s : float, optional
        Output period, default the interpolation period [s].
    progress : callable, optional
        Called with ``(axis_name, done, total)`` after each axis [-].

    Returns
    -------
    Run
        Command, motor encoder, linear scale, TCP and current per axis [SI].
    """
    from ._validate import positive_number
    from .sim.simulate import simulate as _simulate

    m = _model(machine, "machine")
    if record_period_s is not None:
        record_period_s = positive_number("record_period_s", record_period_s, "s")
    return _simulate(m, as_command(command, m), record_period_s=record_period_s,
                     progress=progress)


def identify(bundle, band_hz=None, guideway_share=None, presliding_m=None,
             accept_suspect=False, progress=None, jobs=1):
    """Identify every axis of a measurement bundle into a model.

    Parameters
    ----------
    bundle : str or Path or Bundle
        Bundle folder (docs/formats.md), or a bundle read by :func:`read_bundle` [-].
    band_hz : tuple of float, optional
        ``(f0, f1)`` band of the frequency responses; default the excitation's [Hz].
    guideway_share : float, optional
        Share of the friction put on the guideway; default from the friction runs [-].
    presliding_m : float, optional
        Pre-sliding displacement of the friction contacts, ``0`` for static friction;
        default fitted to the reversals of the friction runs, as ``tcpmm identify`` does
        (:data:`tcpmm.ident.friction.presliding.PRESLIDING` where they do not fix it) [m].
    accept_suspect : bool
        Return a model the gates find physically suspect, marked, instead of raising [-].
    progress : callable, optional
        Called with the axis name after each axis [-].
    jobs : int, optional
        Axes identified at once, each in a forked process of its own; ``0``: one per
        core. The numbers are the same [-].

    Returns
    -------
    Identification
        ``.machine`` (the model), per-axis fits, ``.to_dict()`` (the report) and
        ``.write_report(folder)`` (plots and tables) [-].
    """
    from .ident.chain import identify_bundle
    from .io.bundle import Bundle, read_bundle

    b = bundle if isinstance(bundle, Bundle) else read_bundle(bundle)
    f0, f1 = band_hz if band_hz is not None else (None, None)
    return identify_bundle(b, f0, f1, progress=progress, guideway_share=guideway_share,
                           presliding=presliding_m, accept_suspect=accept_suspect, jobs=jobs)


def compare(measured, predicted, radius_m=None, centre_m=(0.0, 0.0)):
    """Measured minus predicted circular test (the paper's Table 2).

    Parameters
    ----------
    measured, predicted : Run or CircleResult or str or Path
        Runs, run files, or their analyses (:func:`analyse_circle`) [-].
    radius_m : float, optional
        Nominal radius; default that of an analysis given [m].
    centre_m : tuple of float
        Nominal centre, with ``radius_m`` [m].

    Returns
    -------
    Comparison
        Spike and contour-error differences per direction and sensor, the sign flips,
        ``.plot()`` of the two circles [-].
    """
    from .analysis.circular import CircleResult, analyse_circle
    from .analysis.compare import compare_circles, cut_alike
    from .errors import InputError
    from .io.runfile import as_run

    given = [r for r in (measured, predicted) if isinstance(r, CircleResult)]
    if radius_m is None and given:
        radius_m, centre_m = given[0].radius, given[0].centre

    def analysed(r, settling):
        if isinstance(r, CircleResult):
            return r
        if radius_m is None:
            raise InputError("compare needs radius_m [m] to analyse a run")
        return analyse_circle(r, radius_m, centre_m, settling=settling)

    runs = [r if isinstance(r, CircleResult) else as_run(r, name)
            for r, name in ((measured, "measured"), (predicted, "predicted"))]
    if not any(isinstance(r, CircleResult) for r in runs):
        runs[1] = cut_alike(*runs)
    # a prediction's transient is the measurement's, to compare: said of the measurement
    return compare_circles(analysed(runs[0], True), analysed(runs[1], False))


def compensate(machine, command, draws: int = 16, radius_m=None, seed: int = 0,
               accel_m_per_s2=None, jerk_m_per_s3=None, headroom=None,
               centre_m=(0.0, 0.0), plane=None):
    """Pre-compensate a command on an identified model, scaled back over draws of the model
    from its uncertainty, with the predicted figures before and after.

    Parameters
    ----------
    machine : Machine or str or Path
        The identified model, a model file or ``builtin:vmc`` [-].
    command : Command or str or Path
        The programmed command, an NC program file or a command CSV [-].
    draws : int
        Machines drawn from the model's uncertainty to test the compensation on, 0 or
        more; 0 for none [-].
    radius_m : float, optional
        Radius of a circular test, to judge its spikes and G too and keep them from
        getting worse on any draw; default the circle the command runs, where it is a
        circular test (:func:`tcpmm.analysis.circle_find.command_circle`), which
        ``settings["circle"]`` of the result names [m].
    seed : int
        Seed of the draws [-].
    accel_m_per_s2 : float, optional
        Axis acceleration the compensated command may use; default the model's
        interpolation settings [m/s^2].
    jerk_m_per_s3 : float, optional
        Axis jerk the compensated command may use; default the model's S-curve jerk, none
        for a trapezoid [m/s^3].
    headroom : float, optional
        Share of the axes' acceleration and jerk left to the correction when ``command``
        is an NC program, planned with the rest (:mod:`tcpmm.compensate.headroom`);
        default :data:`~tcpmm.compensate.headroom.DEFAULT_HEADROOM` [-].
    centre_m : tuple of float
        Centre of the circle of ``radius_m`` in the plane's axes [m].
    plane : tuple of str, optional
        The circle's plane, e.g. ``("Z", "X")``; default the command's (its program's
        G17, G18, G19, else the plane it moves in) [-].

    Returns
    -------
    Compensation
        ``.command`` is the compensated command (:mod:`tcpmm.compensate`); axes the
        program holds still that the model lacks (a G18 program's Y on a machine of X and
        Z) are left out of it, and ``settings["held_axes_m"]`` says where they stand [-].
    """
    from ._validate import count
    from .analysis.circle_find import circle_said, judged_circle
    from .compensate import machine_bounds
    from .compensate.held import without_held

    draws, seed, m = count("draws", draws), count("seed", seed), _model(machine, "machine")
    bounds = machine_bounds(m, accel_m_per_s2, jerk_m_per_s3)
    full, cmd, headroom = _with_headroom(command, m, headroom, bounds)
    (full, cmd), held = without_held(m, full, cmd)
    circle = judged_circle(cmd, radius_m, centre_m, plane)
    comp = _learned_and_judged(m, (full, cmd, headroom), bounds, draws, seed, circle)
    comp.settings.update(circle=circle_said(circle, radius_m is None), held_axes_m=held)
    return comp


def _learned_and_judged(m, plans, bounds, draws: int, seed: int, circle):
    """The compensation of the plan with headroom, or of the program as programmed where
    the draws judge that one better (:func:`tcpmm.compensate.headroom.on_the_program`),
    scored, on ``circle`` ``(radius, centre, plane)`` too where there is one [-]."""
    from .analysis.circle_find import circle_where
    from .compensate import predicted_scores
    from .compensate.candidates import compensate_within_draws
    from .compensate.headroom import on_the_program

    full, cmd, headroom = plans
    where = circle_where(circle)

    def learned(on):
        comp = compensate_within_draws(m, on, n_draws=draws, bounds=bounds, seed=seed,
                                       **where)
        comp.scores = predicted_scores(m, comp, **where,
                                       programmed=full if headroom and on is not full else None)
        return comp

    comp = learned(cmd)
    if headroom and draws > 0:  # the draws judged it against its own plan
        comp, kept = on_the_program(m, full, comp, bounds, lambda: learned(full), circle)
        headroom, cmd = (headroom, cmd) if kept else (0.0, full)
    comp.settings.update(headroom=headroom, programmed_duration_s=float(full.time_s[-1]),
                         planned_duration_s=float(cmd.time_s[-1]))
    return comp


def _with_headroom(command, machine, headroom, bounds):
    """The command at the axes' full limits, the one the correction is learned on (its
    headroom a share of ``bounds``), and the headroom: only an NC program is planned
    anew [-]."""
    from ._validate import file_path
    from .compensate.headroom import headroom_for, program_with_headroom
    from .path import Command, InterpolatorSettings
    from .path.program import PROGRAM_SUFFIXES

    is_program = (not isinstance(command, Command)
                  and file_path("command", command, COMMAND_IS).suffix.lower()
                  in PROGRAM_SUFFIXES)
    headroom = headroom_for(is_program, headroom)
    if not is_program:
        cmd = as_command(command, machine)
        return cmd, cmd, 0.0
    settings = InterpolatorSettings.model_validate(machine.interpolation or {})
    full, planned = program_with_headroom(Path(command), settings, headroom, bounds)
    return full, planned, headroom
