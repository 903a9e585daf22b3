"""Turn pydantic validation failures into messages that name the field and the fix, and
check the numbers given to public functions alike."""

from __future__ import annotations

import difflib
import math
import numbers
import os
import re
from collections.abc import Iterable
from pathlib import Path

from pydantic import ValidationError

from .errors import InputError


def did_you_mean(name: str, candidates: Iterable[str]) -> str:
    """`` (did you mean 'x'?)`` for the closest of ``candidates`` to ``name``, or ``""``."""
    near = difflib.get_close_matches(name, list(candidates), n=1, cutoff=0.6)
    return f" (did you mean '{near[0]}'?)" if near else ""


def is_number_text(text: str) -> bool:
    """Whether ``text`` reads as a number (Python's ``float``) [-]."""
    try:
        float(text)
    except ValueError:
        return False
    return True


#: An axis name: one or two ASCII letters, as an axis is addressed in G-code (``X``) and as
#: its run-file columns begin (``x_cmd_mm``, read back case-insensitively) [-].
AXIS_NAME = re.compile(r"[A-Za-z]{1,2}")
AXIS_NAME_RULE = "one or two letters A to Z (e.g. X, Y, Z)"


def axis_names(names) -> dict[str, str]:
    """Check axis names against :data:`AXIS_NAME` and map each to its upper case.

    Parameters
    ----------
    names : iterable of str
        Axis names as given [-].

    Returns
    -------
    dict of str to str
        Upper-case name to the name as given [-].

    Raises
    ------
    ValueError
        For a name that breaks the rule, or two names equal but for case.
    """
    names = list(names)
    for name in names:
        if not isinstance(name, str) or not AXIS_NAME.fullmatch(name):
            raise ValueError(f"axis name {name!r} must be {AXIS_NAME_RULE}: it is the "
                             "axis's G-code letter and begins its run-file columns "
                             "(x_cmd_mm)")
    return upper_names(names)


def upper_names(names) -> dict[str, str]:
    """Map each name to its upper case; names equal but for case are an error.

    Parameters
    ----------
    names : iterable of str
        Axis names as given [-].

    Returns
    -------
    dict of str to str
        Upper-case name to the name as given [-].
    """
    given: dict[str, str] = {}
    for name in names:
        key = str(name).upper()
        if key in given:
            raise ValueError(f"axis {name!r} duplicates {given[key]!r} (axis names are "
                             "case-insensitive); rename or remove one")
        given[key] = name
    return given


def validation_message(err: ValidationError, prefix: str = "") -> str:
    """One line per problem: ``field.path: message (got value)``."""
    lines = []
    for e in err.errors():
        loc = ".".join(str(p) for p in e["loc"])
        loc = f"{prefix}.{loc}" if prefix and loc else (prefix or loc)
        got = e.get("input")
        got_s = "" if isinstance(got, dict) else f" (got {got!r})"
        lines.append(f"{loc}: {e['msg']}{got_s}")
    return "; ".join(lines)


def build(model_cls, data: dict, prefix: str = "", file=None):
    """Validate ``data`` into ``model_cls`` or raise :class:`InputError` naming the fields."""
    try:
        return model_cls.model_validate(data)
    except ValidationError as err:
        raise InputError(validation_message(err, prefix), file=file) from None


def plausible(value, field: str, ranges: dict):
    """``value`` if it lies in its field's plausible range, else a ``ValueError`` saying
    the range. A number far outside what a machine tool has (a stiffness of 1e300, a mass
    of 1e-300) is a typo or a wrong unit, and would overflow the plant's matrices.

    Parameters
    ----------
    value : float or None
        The validated number; ``None`` passes [SI].
    field : str
        The field's name [-].
    ranges : dict of str to (float, float, str)
        Per field the lowest and highest plausible value and the unit [SI].
    """
    if value is None or field not in ranges:
        return value
    low, high, unit = ranges[field]
    if not low <= value <= high:  # also NaN
        unit = "" if unit == "-" else f" {unit}"
        raise ValueError(f"outside the plausible range {low:g} to {high:g}{unit} of a "
                         "machine tool's feed axis; check the number and its unit")
    return value


def _is_real(value) -> bool:
    # bool is an int to Python, but True as a radius is a slip, not a number
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


def finite_number(name: str, value, unit: str) -> float:
    """``value`` as a float, or an :class:`InputError` naming ``name`` unless it is a
    finite number (text such as ``"0.035"`` is refused: a number read from a file or
    typed is to be converted where its unit is known).

    Parameters
    ----------
    name : str
        The argument's name [-].
    value : object
        The value given [unit].
    unit : str
        Its unit, said in the message (``"m"``, ``"-"``) [-].
    """
    if not _is_real(value) or not math.isfinite(value):
        kind = "" if _is_real(value) else f" (a {type(value).__name__})"
        raise InputError(f"{name} must be a finite number{_in(unit)}, got {value!r}{kind}")
    return float(value)


def positive_number(name: str, value, unit: str) -> float:
    """``value`` as a float, or an :class:`InputError` unless a finite number above 0
    (``unit`` as :func:`finite_number`) [unit]."""
    v = finite_number(name, value, unit)
    if v <= 0:
        raise InputError(f"{name} must be above 0{_in(unit)}, got {value!r}")
    return v


def nonnegative_number(name: str, value, unit: str) -> float:
    """``value`` as a float, or an :class:`InputError` unless a finite number of at least
    0 (``unit`` as :func:`finite_number`) [unit]."""
    v = finite_number(name, value, unit)
    if v < 0:
        raise InputError(f"{name} must be 0 or more{_in(unit)}, got {value!r}")
    return v


def count(name: str, value, low: int = 0) -> int:
    """``value`` as an int, or an :class:`InputError` unless a whole number of at least
    ``low`` (a seed, a number of draws) [-]."""
    whole = isinstance(value, numbers.Integral) and not isinstance(value, bool)
    if not whole or value < low:
        raise InputError(f"{name} must be a whole number of at least {low}, got {value!r}")
    return int(value)


def plane_point(name: str, value, unit: str = "m") -> tuple[float, float]:
    """``value`` as two floats, or an :class:`InputError` unless two finite coordinates
    (a circle's centre in its plane) [unit]."""
    return coordinates(name, value, 2, unit)


def coordinates(name: str, value, n: int, unit: str = "m") -> tuple[float, ...]:
    """``value`` as ``n`` floats, or an :class:`InputError` unless ``n`` finite
    coordinates (a point in a plane, or of X, Y and Z).

    Parameters
    ----------
    name : str
        The argument's name [-].
    value : object
        The value given [unit].
    n : int
        How many coordinates [-].
    unit : str
        Their unit, said in the message [-].
    """
    try:
        ok = len(value) == n and all(_is_real(c) and math.isfinite(c) for c in value)
    except TypeError:  # a bare number has no length
        ok = False
    if not ok:
        word, axes = {2: "two", 3: "three"}.get(n, str(n)), " (X, Y, Z)" if n == 3 else ""
        raise InputError(f"{name} must be {word} finite coordinates{axes} in {unit}, got "
                         f"{value!r}")
    return tuple(float(c) for c in value)


def file_path(name: str, value, what: str = "a file's path (str or pathlib.Path)") -> Path:
    """``value`` as a :class:`~pathlib.Path`, or an :class:`InputError` unless it is text
    or a path (``None``, a table or a model where a file is asked for).

    Parameters
    ----------
    name : str
        The argument's name [-].
    value : object
        The value given [-].
    what : str
        What the argument may be, said in the message [-].
    """
    if not isinstance(value, str | os.PathLike) or not str(value):
        raise InputError(f"{name} must be {what}, got {_shown(value)}")
    return Path(value)


def instance_of(name: str, value, kinds, what: str):
    """``value``, or an :class:`InputError` unless an instance of ``kinds`` (a run given
    where its analysis is asked for, a command where a list of tests is).

    Parameters
    ----------
    name : str
        The argument's name [-].
    value : object
        The value given [-].
    kinds : type or tuple of type
        What it must be an instance of [-].
    what : str
        What it must be, in words with the call that makes one, for the message [-].
    """
    if not isinstance(value, kinds):
        raise InputError(f"{name} must be {what}, got {_shown(value)}")
    return value


def _shown(value) -> str:
    # a table or an array is no help spelt out: its kind is
    if value is None or isinstance(value, str | int | float | tuple | list):
        return repr(value)
    return f"a {type(value).__name__}"


def _in(unit: str) -> str:
    return "" if unit == "-" else f" in {unit}"
