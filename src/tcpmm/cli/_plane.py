"""The ``--plane`` option the analysis commands share: a plane by name, or the one the run
moves in, said on stderr."""

from __future__ import annotations

import numpy as np
import typer

from ..errors import InputError
from ._app import console, in_file

COMMAND_HELP = ("CMD.csv: measure against this command, the program, instead of the run's "
                "own command signals: for a run of a command tcpmm compensate wrote.")
PLANE_HELP = ("Plane: XY, XZ, YZ (or ZX as G18 has it); CCW turns the first axis into the "
              "second. Default: the plane in which the command moves.")


def plane_option(option: str) -> tuple[str, str]:
    """The two axes of ``--plane``; a bad name is a usage error."""
    from ..analysis.plane import plane_axes

    try:
        return plane_axes(option)
    except Exception as exc:
        raise typer.BadParameter(str(exc), param_hint="--plane") from None


def run_plane_said(option: str | None, run, what, allow_3d: bool = False):
    """The plane of ``--plane``, else the one the run's command moves in, said on stderr.

    With ``allow_3d``, ``--plane 3D`` and a run that does not move in a plane give
    ``None`` (3-D) [-].
    """
    from ..analysis.plane import run_plane, run_positions

    if option is not None:
        if allow_3d and option.strip().upper() == "3D":
            return None
        axes = plane_option(option)
        # a run of one axis has no plane of its own, and its command's travel says where
        # it moves
        pos = run_positions(run)[1] or {a: r.cmd for a, r in run.axes.items()}
        _refuse_a_plane_off_the_motion(axes, pos, what, allow_3d)
        if not allow_3d:  # the commands with a 3-D error say it with their figures
            _warn_left_out(axes, pos, what)
        return axes
    with in_file(what):
        try:
            axes, why, flat = run_plane(run)
        except InputError as exc:
            if not allow_3d:
                raise
            axes, why, flat = None, exc.message, False
    if not flat and allow_3d:
        console.print(f"3D (unsigned), taken from {what}: {why}", highlight=False)
        return None
    console.print(f"plane {''.join(axes)}, taken from {what}: {why}", highlight=False)
    return axes


def _refuse_a_plane_off_the_motion(axes, pos: dict, what, allow_3d: bool) -> None:
    """Refuse ``--plane`` where it misses the motion ``pos`` of the run's command (else
    its first position sensor of two axes) [m]: the error in it would be that of a line,
    read as firm."""
    from ..analysis.plane import plane_misses

    why = plane_misses(axes, pos)
    if why:
        with in_file(what):
            raise InputError(f"{why}; give --plane for the plane it runs in"
                             + (", or --plane 3D" if allow_3d else ""))


def _warn_left_out(axes, pos: dict, what) -> None:
    """Warn where ``--plane`` leaves out an axis that moves substantially in ``pos``
    (:func:`tcpmm.analysis.plane.left_out_axes`) [m]: a circular test reads the radius in
    the plane given, and that axis' error is in none of its figures."""
    import warnings

    from ..analysis.plane import left_out_axes, left_out_note
    from ..errors import InputWarning

    note = left_out_note(axes, left_out_axes(axes, pos),
                         "a circular test reads the radius in the plane given; a helix or a "
                         "tilted circle needs its own plane, or the contour error in 3-D "
                         "(tcpmm contour)")
    if note is not None:
        warnings.warn(f"{what}: {note}", InputWarning, stacklevel=2)


#: the sensors a circular test measures, as ``--help`` names them: the command is what
#: they are measured against, not one of them
MEASURED = ("tcp", "scale", "motor")


def refuse_unmeasured(run, axes, path, advice: str = "") -> None:
    """Refuse a run none of whose sensors (:data:`MEASURED`) both plane axes have: its
    circular test would measure the command against itself and show every figure 0.00.

    Parameters
    ----------
    run : Run
        The run read from ``path`` [-].
    axes : tuple of str
        The plane [-].
    path : Path
        The run file, named in the error [-].
    advice : str
        What else the command takes, said last (", or --sensor cmd ...") [-].
    """
    have = {a: [s for s in MEASURED if r.sensor(s) is not None] for a, r in run.axes.items()}
    if any(all(s in have.get(a, ()) for a in axes) for s in MEASURED):
        return
    found = [f"{a.lower()}_{s}_mm" for a, r in run.axes.items() for s in ("cmd", *MEASURED)
             if r.sensor(s) is not None]
    which = ("no sensor columns" if not any(have.values())
             else f"no sensor columns that both {' and '.join(axes)} have")
    raise InputError(
        f"the run has {which} (<axis>_tcp_mm, <axis>_scale_mm, <axis>_motor_mm; found: "
        f"{', '.join(found) or 'none'}): a circular test measures a sensor's path against "
        "the nominal circle, and the command is what it is measured against, not a "
        "measurement; give a run with the positions of the TCP, the scales or the motors "
        f"(tcpmm simulate writes them){advice}", file=path)


def command_plane(option, cmd) -> tuple[str, str]:
    """The plane of ``--plane``, else of the program's arcs, else the one it moves in."""
    from ..analysis.plane import command_plane as plane_of

    if option is not None:
        shown = plane_option(option)
        travel = {a: float(np.ptp(p)) for a, p in cmd.positions.items()}
        inside = [a for a in shown if travel.get(a, 0.0) > 0.0]
        outside = [a for a in travel if a not in shown and travel[a] > 0.0]
        if len(inside) < 2 and outside:  # the plot would show a line or a point
            moving = ", ".join(f"{a} {travel[a] * 1e3:.4g} mm" for a in travel if travel[a])
            raise typer.BadParameter(
                f"the path does not move in the {''.join(shown)} plane, which would show "
                f"it as a line or a point (travel {moving}); give the plane it moves in",
                param_hint="--plane")
        return shown
    return plane_of(cmd)


def judged_circle(radius_mm, centre_m, option, cmd):
    """``(radius, centre, plane)`` of the circle a compensation is judged on: the one of
    ``--radius`` (and ``--centre``), else the circle the command runs where it is a
    circular test (:func:`tcpmm.analysis.circle_find.command_circle`), said on stderr;
    ``None`` where there is none [m, m, -]."""
    from ..analysis.circle_find import judged_circle as judged
    from ..compensate.cornerguard import mm_text

    plane = command_plane(option, cmd)
    found = judged(cmd, None if radius_mm is None else radius_mm * 1e-3, centre_m, plane)
    if found is None or radius_mm is not None:
        return found
    radius, centre, _ = found
    at = mm_text(c * 1e3 for c in centre)
    console.print(f"circle R {radius * 1e3:.4f} mm about ({at}) mm in the {''.join(plane)} "
                  "plane, taken from the command: its reversal spikes and G are judged "
                  "too (--radius and --centre give the nominal circle)", highlight=False)
    return radius, centre, plane


def with_given_command(run, command_file, window_s: float = 0.2):
    """``run`` measured against the command file ``--command`` where given, within
    ``window_s`` of its own command's time line [s]."""
    if command_file is None:
        return run
    from ..path import read_command_csv

    with in_file(command_file):
        return run.with_command(read_command_csv(command_file), window_s)
