"""What the contour error of a run is measured from: the axes of its plane, its
command polyline and its sensors' paths (:mod:`tcpmm.analysis.contour`)."""

from __future__ import annotations

import warnings

import numpy as np

from ..errors import InputError, InputWarning
from .plane import left_out_axes, plane_axes, run_plane
from .rapids import feed_commands

SENSORS = ("motor", "scale", "tcp")
#: What a run without its command signals is told (no command given) [-].
NO_COMMAND = "the run has no command signals (<axis>_cmd_mm); give the command"


def run_signals(run, command, axes):
    """Times, command polyline and actual paths per sensor of a run."""
    missing = [a for a in axes if a not in run.axes]
    if missing:
        raise InputError(f"the run has no axis {', '.join(missing)} (axes: "
                         f"{', '.join(run.axes)})")
    t = np.asarray(run.time_s, float)
    if command is not None:
        tc = np.asarray(command.time_s, float)
        cmd = np.column_stack([command.positions[a] for a in axes])
    else:
        if any(run.axes[a].cmd is None for a in axes):
            raise InputError(NO_COMMAND)
        tc, cmd = t, np.column_stack([run.axes[a].cmd for a in axes])
    warn_one_sided({s: [a for a in axes if run.axes[a].sensor(s) is not None]
                    for s in SENSORS}, axes)
    actual = {s: np.column_stack([run.axes[a].sensor(s) for a in axes]) for s in SENSORS
              if all(run.axes[a].sensor(s) is not None for a in axes)}
    if not actual:
        raise InputError(no_sensors(axes))
    return t, tc, cmd, actual


def warn_one_sided(having: dict, axes) -> None:
    """Warn of each sensor that only some of ``axes`` have (``having``: sensor -> the axes
    with its signal): it is left out of the contour error, and a user who recorded it
    (a run whose x_tcp_mm column is missing) is told why its row is not there [-]."""
    for s, have in having.items():
        if 0 < len(have) < len(axes):
            lack = [a for a in axes if a not in have]
            warnings.warn(InputWarning(
                f"the {s} signal is present for {', '.join(have)} but not for "
                f"{', '.join(lack)}; the {s} sensor is left out of the contour error"),
                stacklevel=3)


def no_sensors(axes) -> str:
    """What a run without the signals of any sensor of ``axes`` is told [-]."""
    return f"the run has no motor, scale or tcp signals of {', '.join(axes)}"


def contour_axes(run, plane, command=None, rapids=False):
    """``(axes, signed)`` for a plane given, ``"auto"`` or ``None`` (3-D); in 3-D the axes
    with a command, the given ``command``'s where it has fewer (a program that moves one
    axis commands no other). ``"auto"`` takes the plane of the feed moves unless
    ``rapids`` count (:func:`tcpmm.analysis.rapids.feed_commands`), as the command line
    does: a Z retracting in G0 makes no 3-D path [-]."""
    if plane is None or str(plane).upper() == "3D":
        names = [a for a in ("X", "Y", "Z") if a in run.axes and run.axes[a].cmd is not None
                 and (command is None or a in command.positions)]
        return tuple(names or run.axes), False
    if isinstance(plane, str) and plane.lower() == "auto":
        try:
            axes, _, flat = run_plane(feed_commands(run, rapids))
        except InputError:  # fewer than two axes move: a step along one axis
            flat = False
        return (axes, True) if flat else contour_axes(run, None, command)
    return plane_axes(plane), True


def plane_left_out(run, command, axes, rapids: bool) -> dict:
    """The axes outside the plane ``axes`` that the command measured against moves along
    substantially, with their travel (:func:`tcpmm.analysis.plane.left_out_axes`): over its feed
    samples where the rapids are left out (a Z retracting in G0 between XY passes is no
    part of the error) [m].

    Parameters
    ----------
    run : Run
        The run [SI].
    command : Command, optional
        The command it is measured against; default its own [SI].
    axes : tuple of str
        The plane [-].
    rapids : bool
        The rapids count [-].
    """
    if command is not None:
        return left_out_axes(axes, command.positions)
    feed = feed_commands(run, rapids)
    return left_out_axes(axes, {a: r.cmd for a, r in feed.axes.items() if r.cmd is not None})


def command_flags(run, command) -> np.ndarray:
    """Per command sample, its rapid flag: the run's (``run.rapid``, which the run must
    have) where the command is the run's own, else the given command's
    (:meth:`~tcpmm.path.command.Command.blocks`), or the run's at the command sample's
    time where it has none [-]."""
    if command is None:
        return run.rapid
    if command.blocks() is not None:
        return command.blocks()[1]
    k = np.clip(np.searchsorted(run.time_s, command.time_s, side="right") - 1, 0,
                run.time_s.size - 1)
    return run.rapid[k]
