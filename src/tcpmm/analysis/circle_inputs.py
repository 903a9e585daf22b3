"""The arguments of a circular test, checked before any figure is computed: the run (a
run, its file or its table), the nominal circle, the plane and the sensors. A wrong one
is an :class:`~tcpmm.errors.InputError` that names it, never an error from inside the
analysis (:func:`tcpmm.analysis.circular.analyse_circle`, and the spread and verdict
that analyse their own runs)."""

from __future__ import annotations

from .._validate import did_you_mean, plane_point, positive_number
from ..errors import InputError
from ..io.runfile import as_run

#: The sensors of a circular test, command first [-].
SENSORS = ("cmd", "motor", "scale", "tcp")


def sensor_names(sensors, name: str = "sensors") -> tuple[str, ...]:
    """``sensors`` as a tuple of names of :data:`SENSORS`, in lower case; one name alone
    (``"tcp"``) is that sensor, not its letters.

    Parameters
    ----------
    sensors : str or sequence of str
        The sensors asked for [-].
    name : str
        The argument's name, for the message [-].
    """
    given = (sensors,) if isinstance(sensors, str) else sensors
    try:
        names = tuple(s.lower() if isinstance(s, str) else s for s in given)
    except TypeError:  # not a sequence: one wrong name
        names = (sensors,)
    wrong = [s for s in names if s not in SENSORS]
    if wrong or not names:
        what = (f"{wrong[0]!r} is no sensor{did_you_mean(str(wrong[0]).lower(), SENSORS)}"
                if wrong else "no sensor named")
        raise InputError(f"{name}={sensors!r}: {what}; give "
                         f"{'one' if isinstance(sensors, str) else 'some'} of "
                         f"{', '.join(SENSORS)}")
    return names


def sensor_name(sensor, name: str = "sensor") -> str:
    """``sensor``, one name of :data:`SENSORS`, in lower case; else an :class:`InputError`
    naming ``name`` and the sensors [-]."""
    if not isinstance(sensor, str):
        raise InputError(f"{name}={sensor!r}: give one sensor's name, of {', '.join(SENSORS)}")
    return sensor_names(sensor, name)[0]


def circle_arguments(run, radius_m, centre_m, plane, sensors) -> tuple:
    """The arguments of :func:`~tcpmm.analysis.circular.analyse_circle` checked: the run
    (:func:`~tcpmm.io.runfile.as_run`), the radius [m], the centre [m], the plane's two
    axes of the run, upper case, and the sensors [-].

    Returns
    -------
    tuple
        ``(run, radius_m, centre_m, axes, sensors)`` [-], [m], [m], [-], [-].
    """
    run = as_run(run)
    radius = positive_number("radius_m", radius_m, "m")
    centre = plane_point("centre_m", centre_m)
    named = (plane,) if not isinstance(plane, str | tuple | list) else plane
    axes = tuple(str(a).upper() for a in named)
    if len(axes) != 2 or axes[0] == axes[1]:
        raise InputError(f"plane={plane!r} must be two different axes of the run, e.g. "
                         "('X', 'Y') or 'ZX'")
    for a in axes:
        if a not in run.axes:
            raise InputError(f"the run has no axis {a} (axes: {', '.join(run.axes)})")
    return run, radius, centre, axes, sensor_names(sensors)
