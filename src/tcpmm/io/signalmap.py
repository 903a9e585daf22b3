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
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from tcpmm._validate import did_you_mean
from tcpmm.errors import InputError
from tcpmm.io.declared import check_declared
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


def _scale_of(value, key: str, file) -> float:
    """Scale factor of a map entry as a float, or an InputError naming the entry."""
    if not isinstance(value, bool):
        try:
            return float(value)
        except (TypeError, ValueError):
            pass
    raise InputError(
        f"scale factor {value!r} of the map entry for {key} is not a number; give a real "
        "number such as 1e-3",
        file=file,
        column=key,
    )


def _check_keys(mapping, kind: str, file) -> None:
    """Refuse a map that is not a dict, names an unknown signal or lacks a required one.

    Parameters
    ----------
    mapping : object
        The map as given [-].
    kind : {"sweep", "friction"}
        Record kind [-].
    file : str or Path or None
        File named in messages [-].
    """
    required, optional = SIGNALS[kind]
    known = ("time_s", *required, *optional)
    if not isinstance(mapping, Mapping):
        raise InputError(
            f"the signal map must be a dict from tcpmm name to file name, got "
            f"{type(mapping).__name__} {mapping!r}",
            file=file,
        )
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


def _entry(key: str, value, file) -> SignalSource:
    """One map entry as a :class:`SignalSource`, its name and scale checked.

    Parameters
    ----------
    key : str
        The tcpmm signal name [-].
    value : str, (str, float) or mapping
        The file's name, with its scale factor when given [-].
    file : str or Path or None
        File named in messages [-].

    Returns
    -------
    SignalSource
        Where the signal comes from [-].
    """
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
        src = SignalSource(value["name"], _scale_of(value.get("scale", 1.0), key, file))
    elif isinstance(value, tuple | list) and len(value) == 2:
        src = SignalSource(value[0], _scale_of(value[1], key, file))
    else:
        raise InputError(
            f"map entry for {key} must be a name, (name, scale) or "
            f"{{'name': ..., 'scale': ...}}; got {value!r}",
            file=file,
            column=key,
        )
    if not (isinstance(src.name, str) and src.name.strip()):
        raise InputError(
            f"map entry for {key}: the name must be a non-empty string, got {src.name!r}",
            file=file,
            column=key,
        )
    if not (math.isfinite(src.scale) and src.scale != 0):
        raise InputError(
            f"scale factor {src.scale!r} must be finite and non-zero", file=file, column=key
        )
    return src


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
        One entry per signal to read, ``time_s`` included when mapped [-].
    """
    if kind not in SIGNALS:
        raise InputError(
            f"unknown record kind {kind!r}; use one of {', '.join(SIGNALS)}", file=file
        )
    required, optional = SIGNALS[kind]
    if mapping is None:
        out = {n: SignalSource(n) for n in required}
        out.update({n: SignalSource(n, optional=True) for n in ("time_s", *optional)})
        return out
    _check_keys(mapping, kind, file)
    return {key: _entry(key, value, file) for key, value in mapping.items()}


def _samples(data, name: str, key: str, file) -> np.ndarray:
    """Stored samples as floats; time stamps become seconds since the first sample."""
    a = np.asarray(data)
    if a.dtype.kind == "M" and a.size:  # absolute time stamps (TDMS time channels)
        a = a - a.flat[0]
    if a.dtype.kind in "mM":
        return a / np.timedelta64(1, "s")
    if a.dtype.kind == "c":
        if np.any(a.imag != 0):
            raise InputError(
                f"'{name}' holds complex values; store the real signal (real() or abs() "
                "before saving)",
                file=file,
                column=key,
            )
        a = a.real
    try:
        return a.astype(float)
    except (TypeError, ValueError):
        raise InputError(
            f"'{name}' holds {a.dtype} values, not numbers; map a numeric channel or variable",
            file=file,
            column=key,
        ) from None


def read_mapped(
    smap: dict[str, SignalSource],
    fetch: Callable[[str], np.ndarray | None],
    file=None,
    candidates: Sequence[str] = (),
    unit_of: Callable[[str], tuple] | None = None,
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
    candidates : sequence of str, optional
        Names in the file, from which a close match is suggested for a missing one [-].
    unit_of : callable, optional
        The unit a fetched name declares, where it says so, whether the file declares it
        (refused when the map's factor disagrees) or only a name suggests it (warned):
        ``(unit or None, where, strict)`` (:func:`tcpmm.io.declared.check_declared`) [-].

    Returns
    -------
    dict of str to ndarray
        Samples in tcpmm units, keyed by tcpmm name [-].
    """
    out = {}
    for key, src in smap.items():
        data = _fetched(key, src, fetch, file, candidates)
        if data is None:
            continue
        if unit_of is not None:
            unit, how, strict = unit_of(src.name)
            check_declared(key, src.name, src.scale, unit, how, file, strict)
        out[key] = data * src.scale
    lengths = {k: v.size for k, v in out.items()}
    if len(set(lengths.values())) > 1:
        raise InputError(
            f"signals differ in length: {lengths}; all must hold the same samples", file=file
        )
    return out


def _fetched(key: str, src: SignalSource, fetch, file, candidates) -> np.ndarray | None:
    """The samples of one mapped signal as a float vector in the file's unit; ``None``
    for an optional one the file lacks [-]."""
    try:
        data = fetch(src.name)
    except InputError as exc:
        if exc.column is not None:
            raise
        raise InputError(exc.message, file=exc.file, line=exc.line, column=key) from None
    if data is None:
        if src.optional:
            return None
        hint = did_you_mean(src.name, (c for c in candidates if c != src.name))
        raise InputError(
            f"'{src.name}' (mapped to {key}) not found{hint}", file=file, column=key
        )
    data = _samples(data, src.name, key, file)
    if data.ndim != 1:
        data = np.squeeze(data)
    if data.ndim != 1:
        raise InputError(
            f"'{src.name}' has shape {data.shape}; expected a vector (select a column "
            "with name(:,k) or a row with name(k,:))",
            file=file,
            column=key,
        )
    return data


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
