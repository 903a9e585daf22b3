"""NI TDMS adapter (npTDMS): TDMS channels into SweepRecord / FrictionRecord."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

import numpy as np

from tcpmm.errors import InputError
from tcpmm.io.declared import factor_for
from tcpmm.io.signalmap import build_record, parse_signal_map, read_mapped
from tcpmm.io.text import existing_file


def _open(path: Path):
    from nptdms import TdmsFile

    existing_file(path, ".tdms file", "TDMS file")
    with open(path, "rb") as fh:
        lead_in = fh.read(4)
    if lead_in != b"TDSm":
        raise InputError("cannot read as TDMS: the file does not start with 'TDSm'", file=path)
    try:
        tdms = TdmsFile.read(path)
    except Exception as exc:  # npTDMS raises several kinds on a damaged file
        raise InputError(f"cannot read as TDMS: {exc}", file=path) from None
    if not any(g.channels() for g in tdms.groups()):
        raise InputError("the TDMS file holds no channels (empty or truncated?)", file=path)
    return tdms


def _catalogue(tdms) -> str:
    return "; ".join(
        f"{g.name}: {', '.join(c.name for c in g.channels()) or '-'}" for g in tdms.groups()
    )


def _names(tdms) -> list[str]:
    """Every channel as ``group/channel`` and as bare ``channel``, for suggestions."""
    full = [f"{g.name}/{c.name}" for g in tdms.groups() for c in g.channels()]
    return list(dict.fromkeys([*full, *(c.name for g in tdms.groups() for c in g.channels())]))


def _resolver(tdms, group: str | None, path: Path):
    groups = {g.name: g for g in tdms.groups()}
    if group is not None and group not in groups:
        raise InputError(
            f"group '{group}' not in the file; groups: {', '.join(groups) or 'none'}",
            file=path,
            column=group,
        )

    def find(name: str):
        if group is not None:
            chans = {c.name: c for c in groups[group].channels()}
            if name in chans:
                return chans[name]
        for g, grp in groups.items():  # group names may hold '/' themselves
            if name.startswith(f"{g}/"):
                chans = {ch.name: ch for ch in grp.channels()}
                if name[len(g) + 1 :] in chans:
                    return chans[name[len(g) + 1 :]]
        if group is None:
            hits = [c for g in groups.values() for c in g.channels() if c.name == name]
            if len(hits) > 1:
                raise InputError(
                    f"channel '{name}' exists in several groups; write 'group/{name}' or give "
                    "group=",
                    file=path,
                )
            if hits:
                return hits[0]
        return None

    return find


def _property(channel, prop: str, key: str, path: Path, default=None) -> float:
    """A numeric channel property, or an InputError naming the channel and property."""
    value = channel.properties.get(prop, default)
    try:
        return float(value)
    except (TypeError, ValueError):
        raise InputError(
            f"property {prop} of channel '{channel.name}' is {value!r}, not a number [s]; "
            "repair it or map a time channel as channel_map['time_s']",
            file=path,
            column=key,
        ) from None


def _x_unit(channel, key: str, path: Path) -> tuple[str, float]:
    """A waveform's x unit (``wf_xunit_string``: s, ms, us, in any case or in words;
    seconds where none is given) and the factor from it to seconds [-]."""
    unit = channel.properties.get("wf_xunit_string")
    if unit is None or not str(unit).strip():
        return "s", 1.0
    factor = factor_for("time_s", str(unit))
    if factor is None:
        raise InputError(
            f"property wf_xunit_string of channel '{channel.name}' is {str(unit)!r}, not a "
            "unit of time (s, ms, us); a waveform over another x (a spectrum in Hz) is no "
            "record. Map a time channel as channel_map['time_s']",
            file=path, column=key)
    return str(unit).strip(), factor


def _increments(smap, channels: dict, path: Path) -> tuple[dict, dict]:
    """Per signal with a ``wf_increment``: its sample interval and its start
    (``wf_start_offset``), both in the channel's x unit turned into seconds [s]."""
    incs, starts = {}, {}
    for key, src in smap.items():
        ch = channels.get(src.name)
        if ch is None or "wf_increment" not in ch.properties:
            continue
        unit, factor = _x_unit(ch, key, path)
        inc = _property(ch, "wf_increment", key, path)
        if not (np.isfinite(inc) and inc > 0):
            raise InputError(
                f"wf_increment of '{src.name}' is {inc!r} {unit}; it must be the positive "
                "sample interval. Map a time channel as channel_map['time_s']",
                file=path, column=key)
        incs[key] = inc * factor
        starts[key] = _property(ch, "wf_start_offset", key, path, 0.0) * factor
    return incs, starts


def _waveform_time(smap, channels: dict, cols: dict, path: Path) -> np.ndarray:
    """The time base of unmapped time: the channels' common ``wf_increment`` from their
    ``wf_start_offset``, in the x unit each declares (``wf_xunit_string``).

    Parameters
    ----------
    smap : dict of str to SignalSource
        Parsed map [-].
    channels : dict
        The TDMS channel of each file name read [-].
    cols : dict of str to ndarray
        The signals read, for their length [-].
    path : Path
        The file, for the messages [-].

    Returns
    -------
    ndarray
        Time of each sample [s].
    """
    incs, starts = _increments(smap, channels, path)
    if not incs:
        raise InputError(
            "no time base: no channel has a wf_increment property. Map a time channel "
            "as channel_map['time_s']",
            file=path,
        )
    values = np.array(list(incs.values()))
    if np.ptp(values) > 1e-9 * values.max():
        raise InputError(
            f"channels have different wf_increment {incs} (in s); resample to one rate",
            file=path,
        )
    first = next(iter(incs))
    t0 = starts[first]
    late = {k: v for k, v in starts.items() if abs(v - t0) > 0.5 * values[0]}
    if late:  # one time base for all would shift them against one another unsaid
        raise InputError(
            f"channels start at different times (wf_start_offset: {first} {t0:g} s, "
            + ", ".join(f"{k} {v:g} s" for k, v in late.items())
            + "); align them to one start, or map a time channel as channel_map['time_s']",
            file=path)
    n = next(iter(cols.values())).size
    return t0 + np.arange(n) * values[0]


def read_record_tdms(
    path: str | Path,
    kind: str,
    channel_map: Mapping | None = None,
    group: str | None = None,
    axis: str | None = None,
):
    """Read a TDMS file into a sweep or friction record.

    Parameters
    ----------
    path : str or Path
        TDMS file [-].
    kind : {"sweep", "friction"}
        Record kind [-].
    channel_map : mapping, optional
        tcpmm name to ``"group/channel"`` (or ``"channel"`` with ``group``), optionally
        ``(name, scale)``; None means the channels carry the tcpmm names [-].
    group : str, optional
        Group in which bare channel names are looked up [-].
    axis : str, optional
        Axis name stored in the record [-].

    Returns
    -------
    SweepRecord or FrictionRecord
        The record, SI.
    """
    path = Path(path)
    tdms = _open(path)
    smap = parse_signal_map(channel_map, kind, file=path)
    find = _resolver(tdms, group, path)
    channels = {}

    def fetch(name):
        ch = find(name)
        if ch is None:
            return None
        channels[name] = ch
        return ch[:]

    try:
        cols = read_mapped(smap, fetch, file=path, candidates=_names(tdms),
                           unit_of=lambda name: (
                               channels[name].properties.get("unit_string"), "unit_string",
                               True))
    except InputError as exc:
        raise InputError(
            f"{exc.message}. Channels in the file: {_catalogue(tdms)}",
            file=path,
            column=exc.column,
        ) from None
    if "time_s" not in cols:
        cols["time_s"] = _waveform_time(smap, channels, cols, path)
    return build_record(kind, cols, path, axis)


def read_sweep_tdms(
    path: str | Path,
    channel_map: Mapping | None = None,
    group: str | None = None,
    axis: str | None = None,
):
    """Read a servo-excitation record from an NI TDMS file.

    Time comes from ``channel_map['time_s']`` when mapped (a time-stamp channel counts
    seconds from its first sample), else from the channels' ``wf_increment`` (and
    ``wf_start_offset``) properties.

    Parameters
    ----------
    path : str or Path
        TDMS file [-].
    channel_map : mapping, optional
        tcpmm name (``excitation_A``, ``current_cmd_A``, ``motor_angle_rad``, ``scale_mm``,
        ``tcp_mm``, ``time_s``) to ``"group/channel"``, ``(name, scale)`` or
        ``{"name": ..., "scale": ...}``; the scale turns the stored value into the tcpmm
        unit [-].
    group : str, optional
        Group in which bare channel names are looked up [-].
    axis : str, optional
        Axis name stored in the record [-].

    Returns
    -------
    SweepRecord
        The record, SI.
    """
    return read_record_tdms(path, "sweep", channel_map, group, axis)


def read_friction_tdms(
    path: str | Path,
    channel_map: Mapping | None = None,
    group: str | None = None,
    axis: str | None = None,
):
    """Read constant-velocity runs from an NI TDMS file (see :func:`read_sweep_tdms`).

    Parameters
    ----------
    path : str or Path
        TDMS file [-].
    channel_map : mapping, optional
        tcpmm name (``current_cmd_A``, ``motor_angle_rad``, ``scale_mm``, ``time_s``) to
        channel, as in :func:`read_sweep_tdms` [-].
    group : str, optional
        Group in which bare channel names are looked up [-].
    axis : str, optional
        Axis name stored in the record [-].

    Returns
    -------
    FrictionRecord
        The record, SI.
    """
    return read_record_tdms(path, "friction", channel_map, group, axis)
