"""Mapping of tcpmm signal names onto the channels/variables of foreign files (TDMS, MAT).

A map is a dict from tcpmm names (``time_s``, ``excitation_A``, ``current_cmd_A``,
``motor_angle_rad``, ``scale_mm``, ``tcp_mm``) to the name in the file, optionally with a
scale factor that turns the stored value into the tcpmm unit::

    {"excitation_A": "DAQ/ai0",
     "motor_angle_rad": ("DAQ/encoder", 2 * np.pi / 10000),   # counts -> rad
     "scale_mm": {"name": "DAQ/scale_um", "scale": 1e-3}}     # um -> mm
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np

from tcpmm.errors import InputError
from tcpmm.io.records import FrictionRecord, SweepRecord
from tcpmm.units import MM

#: Per record kind: signals that must be mapped, signals that may be mapped.
SIGNALS: dict[str, tuple[tuple[str, ...], tuple[str, ...]]] = {
    "sweep": (("excitation_A", "current_cmd_A", "motor_angle_rad", "scale_mm"), ("tcp_mm",)),
    "friction": (("current_cmd_A", "motor_angle_rad", "scale_mm"), ()),
}


@dataclass(frozen=True)
class SignalSource:
    """Where one tcpmm signal comes from.

    Parameters
    ----------
    name : str
        Channel or variable name in the file [-].
    scale : float
        Factor from the stored value to the tcpmm unit [-].
    optional : bool
        Skip the signal when the file lacks it [-].
    """

    name: str
    scale: float = 1.0
    optional: bool = False


def parse_signal_map(mapping: Mapping | None, kind: str, file=None) -> dict[str, SignalSource]:
    """Validate a signal map; ``None`` means "the file uses the tcpmm names".

    Parameters
    ----------
    mapping : mapping or None
        tcpmm name to file name, ``(name, scale)`` or ``{"name": ..., "scale": ...}`` [-].
    kind : {"sweep", "friction"}
        Record kind [-].
    file : str or Path, optional
        File named in messages [-].

    Returns
    -------
    dict of str to SignalSource
        One entry per signal to read, ``time_s`` included when mapped.
    """
    required, optional = SIGNALS[kind]
    known = ("time_s", *required, *optional)
    if mapping is None:
        out = {n: SignalSource(n) for n in required}
        out.update({n: SignalSource(n, optional=True) for n in ("time_s", *optional)})
        return out
    unknown = [k for k in mapping if k not in known]
    if unknown:
        raise InputError(
            f"unknown tcpmm signal name(s) {unknown} in the map; known: {', '.join(known)}",
            file=file,
            column=unknown[0],
        )
    missing = [k for k in required if k not in mapping]
    if missing:
        raise InputError(
            f"the map lacks {', '.join(missing)}; a {kind} record needs "
            f"{', '.join(required)} (and optionally {', '.join(('time_s', *optional))})",
            file=file,
            column=missing[0],
        )
    out = {}
    for key, value in mapping.items():
        if isinstance(value, str):
            src = SignalSource(value)
        elif isinstance(value, Mapping):
            extra = set(value) - {"name", "scale"}
            if extra or "name" not in value:
                raise InputError(
                    f"map entry for {key} must be {{'name': ..., 'scale': ...}}, got {value!r}",
                    file=file,
                    column=key,
                )
            src = SignalSource(str(value["name"]), float(value.get("scale", 1.0)))
        elif isinstance(value, tuple | list) and len(value) == 2:
            src = SignalSource(str(value[0]), float(value[1]))
        else:
            raise InputError(
                f"map entry for {key} must be a name, (name, scale) or "
                f"{{'name': ..., 'scale': ...}}; got {value!r}",
                file=file,
                column=key,
            )
        if not (math.isfinite(src.scale) and src.scale != 0):
            raise InputError(
                f"scale factor {src.scale!r} must be finite and non-zero", file=file, column=key
            )
        out[key] = src
    return out


def read_mapped(
    smap: dict[str, SignalSource],
    fetch: Callable[[str], np.ndarray | None],
    file=None,
) -> dict[str, np.ndarray]:
    """Fetch and scale every mapped signal.

    Parameters
    ----------
    smap : dict of str to SignalSource
        Parsed map [-].
    fetch : callable
        Returns the stored samples of a file name, or None when absent [-].
    file : str or Path, optional
        File named in messages [-].

    Returns
    -------
    dict of str to ndarray
        Samples in tcpmm units, keyed by tcpmm name [-].
    """
    out = {}
    for key, src in smap.items():
        data = fetch(src.name)
        if data is None:
            if src.optional:
                continue
            raise InputError(f"'{src.name}' (mapped to {key}) not found", file=file, column=key)
        data = np.asarray(data, dtype=float)
        if data.ndim != 1:
            data = np.squeeze(data)
        if data.ndim != 1:
            raise InputError(
                f"'{src.name}' has shape {data.shape}; expected a vector (select a column "
                "with name(:,k))",
                file=file,
                column=key,
            )
        out[key] = data * src.scale
    lengths = {k: v.size for k, v in out.items()}
    if len(set(lengths.values())) > 1:
        raise InputError(
            f"signals differ in length: {lengths}; all must hold the same samples", file=file
        )
    return out


def build_record(kind: str, columns: dict[str, np.ndarray], source, axis,
                 line_of: Callable[[int], int] | None = None):
    """Make a checked SI record from tcpmm-unit columns (``scale_mm``, ``tcp_mm``).

    Parameters
    ----------
    kind : {"sweep", "friction"}
        Record kind [-].
    columns : dict of str to ndarray
        Signals in file units, ``time_s`` included [-].
    source : str or Path
        Originating file [-].
    axis : str or None
        Axis name [-].
    line_of : callable, optional
        Sample index to file line, for error messages [-].

    Returns
    -------
    SweepRecord or FrictionRecord
        The record.
    """
    if kind == "sweep":
        tcp = columns.get("tcp_mm")
        return SweepRecord.from_arrays(
            columns["time_s"],
            columns["excitation_A"],
            columns["current_cmd_A"],
            columns["motor_angle_rad"],
            columns["scale_mm"] * MM,
            None if tcp is None else tcp * MM,
            source=str(source),
            axis=axis,
            line_of=line_of,
        )
    return FrictionRecord.from_arrays(
        columns["time_s"],
        columns["current_cmd_A"],
        columns["motor_angle_rad"],
        columns["scale_mm"] * MM,
        source=str(source),
        axis=axis,
        line_of=line_of,
    )
