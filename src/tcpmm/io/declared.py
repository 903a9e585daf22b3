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
#: declare to it [-].
TO_TCPMM = {
    "mm": {"m": 1e3, "mm": 1.0, "um": 1e-3, "µm": 1e-3, "μm": 1e-3, "nm": 1e-6,
           "in": 25.4, "inch": 25.4},
    "s": {"s": 1.0, "sec": 1.0, "ms": 1e-3, "us": 1e-6, "µs": 1e-6, "μs": 1e-6, "min": 60.0},
    "A": {"a": 1.0, "ma": 1e-3, "ka": 1e3},
    "rad": {"rad": 1.0, "mrad": 1e-3, "deg": math.pi / 180, "°": math.pi / 180,
            "rev": 2 * math.pi, "turn": 2 * math.pi},
}
#: A name that ends in one of these says its unit (``t_ms``, ``icmd_mA``, ``pos_um``) [-].
_NAME_UNIT = re.compile(r"[_\s\[(]([a-zA-Zµμ]+)[\])]?$")


def factor_for(key: str, unit: str | None) -> float | None:
    """The factor from ``unit`` to the unit of tcpmm signal ``key`` (``scale_mm``: mm);
    ``None`` for a unit not of that kind or not known [-]."""
    if not unit:
        return None
    table = TO_TCPMM.get(key.rsplit("_", 1)[-1])
    if table is None:
        return None
    u = unit.strip()
    return table.get(u, table.get(u.lower()))


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
        # a unit of no kind tcpmm converts (counts, V, Amps): read as it stands, said
        warnings.warn(f"{file}: '{name}' is in {unit.strip()} ({how}), a unit tcpmm does not "
                      f"convert to {key.rsplit('_', 1)[-1]}: it is read unconverted; if it is "
                      f"not in {key.rsplit('_', 1)[-1]}, map it as (\"{name}\", factor)",
                      InputWarning, stacklevel=3)
        return
    if f is None or math.isclose(scale, f, rel_tol=1e-9):
        return
    given = "no factor" if scale == 1.0 else f"the factor {scale:g}"
    msg = (f"'{name}' is in {unit} ({how}) but is mapped to {key} with {given}; to read "
           f"it as {key.rsplit('_', 1)[-1]} map it as (\"{name}\", {f:g})")
    if strict:
        raise InputError(msg, file=file, column=key)
    warnings.warn(f"{file}: {msg}", InputWarning, stacklevel=3)
