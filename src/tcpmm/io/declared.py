"""Units a foreign file declares for a signal (a TDMS channel's ``unit_string``, a MATLAB
variable's name ending in ``_ms`` or ``_um``) held against the factor the signal map gives.

A channel in metres mapped to ``scale_mm`` with no factor reads a thousandfold small,
and identification later refuses only the gross cases; a record used for anything else
came back wrong without a word. The factor from the declared unit to the tcpmm unit is
known, so a map without it is refused (a unit the file declares) or warned about (a unit
a name suggests), with the entry to write.
"""

from __future__ import annotations

import math
import re
import warnings

from ..errors import InputError, InputWarning

#: Per tcpmm unit (the suffix of the signal name): factor from each unit a file may
#: declare to it, by its short name in lower case [-].
TO_TCPMM = {
    "mm": {"m": 1e3, "mm": 1.0, "um": 1e-3, "nm": 1e-6, "in": 25.4},
    "s": {"s": 1.0, "ms": 1e-3, "us": 1e-6, "min": 60.0},
    "A": {"a": 1.0, "ma": 1e-3, "ka": 1e3},
    "rad": {"rad": 1.0, "mrad": 1e-3, "deg": math.pi / 180, "rev": 2 * math.pi},
}
#: The other spellings of those units, lower case: NI DAQmx writes a channel's unit as a
#: word ("Degrees", "Amps", "Meters", "Seconds"), other loggers in the singular or the
#: British spelling; each maps to its short name in :data:`TO_TCPMM` [-].
SPELLINGS = {
    **dict.fromkeys(("meter", "meters", "metre", "metres"), "m"),
    **dict.fromkeys(("millimeter", "millimeters", "millimetre", "millimetres"), "mm"),
    **dict.fromkeys(("µm", "μm", "micrometer", "micrometers", "micrometre", "micrometres",
                     "micron", "microns"), "um"),
    **dict.fromkeys(("nanometer", "nanometers", "nanometre", "nanometres"), "nm"),
    **dict.fromkeys(("inch", "inches"), "in"),
    **dict.fromkeys(("sec", "secs", "second", "seconds"), "s"),
    **dict.fromkeys(("msec", "millisecond", "milliseconds"), "ms"),
    **dict.fromkeys(("µs", "μs", "usec", "microsecond", "microseconds"), "us"),
    **dict.fromkeys(("minute", "minutes"), "min"),
    **dict.fromkeys(("amp", "amps", "ampere", "amperes"), "a"),
    **dict.fromkeys(("milliamp", "milliamps", "milliampere", "milliamperes"), "ma"),
    **dict.fromkeys(("kiloamp", "kiloamps", "kiloampere", "kiloamperes"), "ka"),
    **dict.fromkeys(("radian", "radians"), "rad"),
    **dict.fromkeys(("milliradian", "milliradians"), "mrad"),
    **dict.fromkeys(("°", "degree", "degrees"), "deg"),
    **dict.fromkeys(("revs", "revolution", "revolutions", "turn", "turns"), "rev"),
}
#: A name that ends in one of these says its unit (``t_ms``, ``icmd_mA``, ``pos_um``) [-].
_NAME_UNIT = re.compile(r"[_\s\[(]([a-zA-Zµμ]+)[\])]?$")


def factor_for(key: str, unit: str | None) -> float | None:
    """The factor from ``unit`` (any case, short or in words: ``deg``, ``Degrees``) to the
    unit of tcpmm signal ``key`` (``scale_mm``: mm); ``None`` for a unit not of that kind
    or not known [-]."""
    if not unit:
        return None
    table = TO_TCPMM.get(key.rsplit("_", 1)[-1])
    if table is None:
        return None
    u = unit.strip().lower()
    return table.get(SPELLINGS.get(u, u))


def name_unit(name: str) -> str | None:
    """The unit a variable's name ends in (``data.t_ms``: ``ms``), or ``None`` [-]."""
    m = _NAME_UNIT.search(name.rsplit(".", 1)[-1].rsplit("/", 1)[-1])
    return m.group(1) if m else None


def check_declared(key: str, name: str, scale: float, unit: str | None, how: str,
                   file, strict: bool) -> None:
    """Refuse (``strict``, a unit the file declares) or warn about (a unit the name
    suggests) a signal mapped with factor 1 whose declared unit is not the tcpmm one, or
    with a factor that is not the declared unit's.

    Parameters
    ----------
    key : str
        The tcpmm signal name (``scale_mm``) [-].
    name : str
        The channel or variable in the file [-].
    scale : float
        The factor the map gives [-].
    unit : str or None
        The declared unit [-].
    how : str
        Where the unit is declared, for the message (``unit_string``, ``its name``) [-].
    file : str or Path
        The file [-].
    strict : bool
        Refuse rather than warn [-].
    """
    f = factor_for(key, unit)
    if f is None and strict and unit and unit.strip() and scale == 1.0:
        # counts, volts, or a unit of another kind (A for an angle): no factor is known,
        # so the samples are taken as they stand, and said
        warnings.warn(f"{file}: '{name}' is in {unit.strip()} ({how}), a unit tcpmm does not "
                      f"convert to {key.rsplit('_', 1)[-1]}: it is read unconverted; if it is "
                      f"not in {key.rsplit('_', 1)[-1]}, map it as (\"{name}\", factor)",
                      InputWarning, stacklevel=3)
        return
    # six digits, as a factor is copied from a calculator (0.0174533 for deg), are its value
    if f is None or math.isclose(scale, f, rel_tol=1e-6):
        return
    given = "no factor" if scale == 1.0 else f"the factor {scale:g}"
    msg = (f"'{name}' is in {unit} ({how}) but is mapped to {key} with {given}; to read "
           f"it as {key.rsplit('_', 1)[-1]} map it as (\"{name}\", {f:.12g})")
    if strict:
        raise InputError(msg, file=file, column=key)
    warnings.warn(f"{file}: {msg}", InputWarning, stacklevel=3)
