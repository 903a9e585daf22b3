"""Numbers of a model file that lie where a machine tool's do not, but would if they had
been written in millimetres or micrometres: the file is in SI units, and such a number
is most often one written in the unit of a drawing or a data sheet. A warning names the
key and the number it would be in metres; the model is still read (a rack or a coarse
sensor may be meant)."""

from __future__ import annotations

import warnings

from ..errors import InputWarning

#: Per checked key: where it is on an axis, the range a feed axis has [m], and what it is.
_TYPICAL = {
    "mechanics.lead": (("mechanics", "lead"), 5e-4, 0.2,
                       "a feed axis's lead per motor revolution"),
    "sensors.scale_resolution": (("sensors", "scale_resolution"), 1e-10, 1e-4,
                                 "a linear scale's resolution"),
    "sensors.tcp_resolution": (("sensors", "tcp_resolution"), 1e-10, 1e-4,
                               "a TCP sensor's resolution"),
}
#: Units a number may have been written in, with their factor to metres [-].
_UNITS = (("mm", 1e-3), ("um", 1e-6))


def _value(axis, where):
    """The number at ``where`` on ``axis``; ``None`` where the axis has none [SI]."""
    obj = axis
    for name in where:
        obj = getattr(obj, name, None)
        if obj is None:
            return None
    return float(obj)


def unit_suspects(machine) -> list[str]:
    """One sentence per number of ``machine`` outside a feed axis's range that a unit
    would bring into it [-]."""
    out = []
    for name, axis in machine.axes.items():
        for key, (where, low, high, what) in _TYPICAL.items():
            v = _value(axis, where)
            if v is None or v == 0.0 or low <= v <= high:
                continue
            fits = [(u, v * f) for u, f in _UNITS if low <= v * f <= high]
            if not fits:
                continue
            written = "; ".join(f"if in {u}, write {m:g}" for u, m in fits)
            out.append(f"axis {name} {key} is {v:g} m, beyond {what} ({low:g} to "
                       f"{high:g} m); the model file is in metres: {written}")
    return out


def warn_unit_suspects(machine, file) -> None:
    """Warn of each of :func:`unit_suspects`, naming ``file`` [-]."""
    for text in unit_suspects(machine):
        warnings.warn(f"{file}: {text}", InputWarning, stacklevel=3)
