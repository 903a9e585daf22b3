"""Numbers of a model file that lie where a machine tool's do not, but would if they had
been written in another unit (millimetres, micrometres, N/mm, grams, milliseconds): the
file is in SI units, and such a number is most often one written in the unit of a
drawing or a data sheet. A warning names the key and the number it would be in SI units;
the model is still read (a rack or a coarse sensor may be meant). The stiffness and mass
of an identified axis (one with an uncertainty) are not judged here: identification gave
them, and its gates judge them."""

from __future__ import annotations

import warnings

from ..errors import InputWarning

#: Keys an identified axis has from its sweep, not from the user (the lead, the torque
#: constant and the sensors' resolutions come from the bundle's configuration) [-].
_IDENTIFIED = ("mechanics.K_t", "mechanics.M_t")
#: Units a length may have been written in, with their factor to metres [-].
_LENGTHS = (("mm", 1e-3), ("um", 1e-6))
#: ... and a time, to seconds [-].
_TIMES = (("ms", 1e-3), ("us", 1e-6))
#: Per checked key: where it is on an axis, the range a feed axis has [SI], what it is, its
#: SI unit, and the units it may have been written in with their factor to it.
_TYPICAL = {
    "mechanics.lead": (("mechanics", "lead"), 5e-4, 0.2,
                       "a feed axis's lead per motor revolution", "m", _LENGTHS),
    "sensors.scale_resolution": (("sensors", "scale_resolution"), 1e-10, 1e-4,
                                 "a linear scale's resolution", "m", _LENGTHS),
    "sensors.tcp_resolution": (("sensors", "tcp_resolution"), 1e-10, 1e-4,
                               "a TCP sensor's resolution", "m", _LENGTHS),
    "mechanics.K_t": (("mechanics", "K_t"), 5e6, 5e9,
                      "a ball screw and nut's axial stiffness", "N/m",
                      (("N/mm", 1e3), ("N/um", 1e6))),
    "mechanics.M_t": (("mechanics", "M_t"), 0.5, 1e5, "a feed axis's moving mass", "kg",
                      (("g", 1e-3),)),
    "mechanics.K_tc": (("mechanics", "K_tc"), 0.02, 300.0, "a feed motor's torque constant",
                       "N m/A", (("N mm/A", 1e-3),)),
    "servo.T_p": (("servo", "T_p"), 5e-5, 0.02, "a drive's position-loop period", "s",
                  _TIMES),
    "servo.T_v": (("servo", "T_v"), 1e-5, 5e-3, "a drive's velocity-loop period", "s",
                  _TIMES),
}


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
        for key, (where, low, high, what, si, units) in _TYPICAL.items():
            v = _value(axis, where)
            if v is None or v == 0.0 or low <= v <= high:
                continue
            if key in _IDENTIFIED and getattr(axis, "uncertainty", None) is not None:
                continue  # identified, not typed: identification judged it, not a unit
            fits = [(u, v * f) for u, f in units if low <= v * f <= high]
            if not fits:
                continue
            written = "; ".join(f"if in {u}, write {m:g}" for u, m in fits)
            out.append(f"axis {name} {key} is {v:g} {si}, beyond {what} ({low:g} to "
                       f"{high:g} {si}); the model file is in SI units: {written}")
    return out


def warn_unit_suspects(machine, file) -> None:
    """Warn of each of :func:`unit_suspects`, naming ``file`` [-]."""
    for text in unit_suspects(machine):
        warnings.warn(f"{file}: {text}", InputWarning, stacklevel=3)
