"""Turn pydantic validation failures into messages that name the field and the fix."""

from __future__ import annotations

import difflib
from collections.abc import Iterable

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
