"""Measurement bundle (docs/formats.md section 1): read and write.

A bundle is a folder with ``machine.yaml`` and one folder per axis holding ``sweep.csv``
and optionally ``friction.csv``. Files are in mm; the records returned are SI.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

from tcpmm.errors import InputError
from tcpmm.io.atomic import output_folder
from tcpmm.io.bundle_schema import (
    AxisConfig,
    MachineConfig,
    as_machine_config,
    read_machine_yaml,
    write_machine_yaml,
)
from tcpmm.io.checks import check_excitation_band, check_sweep_plausibility
from tcpmm.io.csvutil import atomic_write_columns, read_numeric_csv, warn_input
from tcpmm.io.recordfaults import refuse_dead_tcp, refuse_wrapped_angle
from tcpmm.io.records import AxisRecords, FrictionRecord, SweepRecord
from tcpmm.io.signalmap import build_record
from tcpmm.units import MM

__all__ = [
    "FRICTION_COLUMNS",
    "SWEEP_COLUMNS",
    "SWEEP_OPTIONAL",
    "AxisConfig",
    "AxisRecords",
    "Bundle",
    "FrictionRecord",
    "MachineConfig",
    "SweepRecord",
    "check_excitation_band",
    "read_bundle",
    "read_friction_csv",
    "read_machine_yaml",
    "read_sweep_csv",
    "write_bundle",
    "write_friction_csv",
    "write_sweep_csv",
]

SWEEP_COLUMNS = ("time_s", "excitation_A", "current_cmd_A", "motor_angle_rad", "scale_mm")
SWEEP_OPTIONAL = ("tcp_mm",)
FRICTION_COLUMNS = ("time_s", "current_cmd_A", "motor_angle_rad", "scale_mm")
MACHINE_FILE = "machine.yaml"
SWEEP_FILE = "sweep.csv"
FRICTION_FILE = "friction.csv"


def _csv_line(i: int) -> int:
    return i + 2


@dataclass(frozen=True, eq=False)
class Bundle:
    """A measurement bundle in memory.

    Parameters
    ----------
    machine : MachineConfig
        Validated ``machine.yaml`` [-].
    axes : dict of str to AxisRecords
        Records per axis, in the order of machine.yaml [-].
    path : Path or None
        Folder it was read from [-].
    """

    machine: MachineConfig
    axes: dict[str, AxisRecords] = field(default_factory=dict)
    path: Path | None = None


def read_sweep_csv(path: str | Path, axis: str | None = None) -> SweepRecord:
    """Read a ``sweep.csv`` (docs/formats.md section 1) into an SI :class:`SweepRecord`.

    Parameters
    ----------
    path : str or Path
        CSV file [-].
    axis : str, optional
        Axis name stored in the record [-].

    Returns
    -------
    SweepRecord
        The record; ``tcp_m`` is None when the file has no ``tcp_mm`` column.
    """
    cols = read_numeric_csv(path, SWEEP_COLUMNS, SWEEP_OPTIONAL)
    return build_record("sweep", cols, path, axis, line_of=_csv_line)


def read_friction_csv(path: str | Path, axis: str | None = None) -> FrictionRecord:
    """Read a ``friction.csv`` into an SI :class:`FrictionRecord`.

    Parameters
    ----------
    path : str or Path
        CSV file [-].
    axis : str, optional
        Axis name stored in the record [-].

    Returns
    -------
    FrictionRecord
        The record.
    """
    cols = read_numeric_csv(path, FRICTION_COLUMNS)
    return build_record("friction", cols, path, axis, line_of=_csv_line)


#: Recorders' files a bundle does not read, by suffix: what they are and the reader that
#: turns one into a sweep record [-].
FOREIGN_RECORDS = {".tdms": ("a TDMS file", "tcpmm.io.tdms.read_sweep_tdms"),
                   ".mat": ("a MATLAB file", "tcpmm.io.matfile.read_sweep_mat")}


def foreign_route(suffix: str) -> str:
    """What a TDMS or MATLAB record is, and the way from it into a bundle, for a message
    [-]."""
    what, reader = FOREIGN_RECORDS[suffix.lower()]
    return (f"{what}, which a bundle does not hold: read it in Python with {reader} and a "
            "channel map, and write the bundle with tcpmm.io.bundle.write_bundle, which "
            "writes its CSV records (docs/measure.md, 'From TDMS or MATLAB files')")


def _bundle_dir(path: Path) -> Path:
    if path.is_file() and path.name == MACHINE_FILE:
        return path.parent
    if path.is_dir():
        return path
    if path.is_file() and path.suffix.lower() in FOREIGN_RECORDS:
        raise InputError(f"this is not a bundle folder but {foreign_route(path.suffix)}; "
                         "then give that folder", file=path)
    if path.exists():  # a record or other file given for its folder
        kind = "file" if path.is_file() else "device"
        raise InputError(f"this is a {kind}, not a folder; give the path of the bundle "
                         "folder, the one that holds machine.yaml", file=path)
    raise InputError(
        "bundle folder not found; give the folder that holds machine.yaml", file=path
    )


def read_bundle(path: str | Path, *, check: bool = True) -> Bundle:
    """Read and check a measurement bundle.

    Parameters
    ----------
    path : str or Path
        Bundle folder, or its ``machine.yaml`` [-].
    check : bool
        Also warn about records that contradict machine.yaml (current limit reached,
        scale not following the motor, TCP not following the scale) [-].

    Returns
    -------
    Bundle
        Machine description and records per axis (SI).

    Raises
    ------
    InputError
        Bad machine.yaml, missing axis folder or sweep.csv, bad CSV content.
    """
    root = _bundle_dir(Path(path))
    machine = read_machine_yaml(root / MACHINE_FILE)
    folders = sorted(p.name for p in root.iterdir() if p.is_dir() and not p.name.startswith("."))
    axes: dict[str, AxisRecords] = {}
    for name, cfg in machine.axes.items():
        folder = root / name
        if not folder.is_dir():
            near = [f for f in folders if f.lower() == name.lower()]
            hint = f" (folder '{near[0]}' differs only in case)" if near else ""
            raise InputError(
                f"machine.yaml lists axis '{name}' but the bundle has no folder '{name}'"
                f"{hint}; folders present: {', '.join(folders) or 'none'}. Add "
                f"{name}/{SWEEP_FILE} or remove the axis from machine.yaml",
                file=folder,
            )
        sweep_path = folder / SWEEP_FILE
        if not sweep_path.is_file():
            _refuse_no_sweep(folder, name)
        sweep = read_sweep_csv(sweep_path, axis=name)
        fpath = folder / FRICTION_FILE
        friction = read_friction_csv(fpath, axis=name) if fpath.is_file() else None
        if check:
            _check_axis(sweep, cfg, name)
            if friction is not None:
                refuse_wrapped_angle(friction, cfg, _csv_line)
        axes[name] = AxisRecords(name=name, sweep=sweep, friction=friction)
    for f in folders:
        if f not in machine.axes:
            warn_input(
                f"folder '{f}' is not an axis of machine.yaml and is ignored",
                file=root / f,
            )
    return Bundle(machine=machine, axes=axes, path=root)


def _refuse_no_sweep(folder: Path, name: str) -> None:
    """Refuse an axis folder without its sweep.csv, saying what it holds and, for a
    recorder's TDMS or MATLAB file, the way to make the CSV of it."""
    others = sorted(p.name for p in folder.iterdir())
    foreign = [o for o in others if Path(o).suffix.lower() in FOREIGN_RECORDS]
    route = f", {foreign_route(Path(foreign[0]).suffix)}" if foreign else ""
    raise InputError(f"{SWEEP_FILE} is required for every axis; {name}/ holds "
                     f"{', '.join(others) or 'nothing'}{route}", file=folder / SWEEP_FILE)


def _check_axis(sweep: SweepRecord, cfg: AxisConfig, name: str) -> None:
    if sweep.tcp_m is None and cfg.sensors.tcp_resolution_um is not None:
        warn_input(
            f"machine.yaml declares a TCP device for axis {name} but the file has no "
            "tcp_mm column; G_tcp will not be identified",
            file=sweep.source,
            line=1,
        )
    if sweep.tcp_m is not None and cfg.sensors.tcp_resolution_um is None:
        warn_input(
            f"the file has a tcp_mm column but machine.yaml gives axis {name} no TCP device "
            "(sensors: tcp_resolution_um): its samples are taken as exact, and what is "
            "read from them is given smaller uncertainties than the device allows; give "
            "its resolution",
            file=sweep.source,
            line=1,
        )
    refuse_wrapped_angle(sweep, cfg, _csv_line)
    refuse_dead_tcp(sweep, cfg)
    check_sweep_plausibility(sweep, cfg)


def write_sweep_csv(record: SweepRecord, path: str | Path) -> Path:
    """Write a :class:`SweepRecord` as ``sweep.csv`` (mm in the file), atomically.

    Parameters
    ----------
    record : SweepRecord
        Record in SI [-].
    path : str or Path
        Target file [-].

    Returns
    -------
    Path
        The file written.
    """
    cols = {
        "time_s": record.time_s,
        "excitation_A": record.excitation_A,
        "current_cmd_A": record.current_cmd_A,
        "motor_angle_rad": record.motor_angle_rad,
        "scale_mm": record.scale_m / MM,
    }
    if record.tcp_m is not None:
        cols["tcp_mm"] = record.tcp_m / MM
    return atomic_write_columns(path, cols)


def write_friction_csv(record: FrictionRecord, path: str | Path) -> Path:
    """Write a :class:`FrictionRecord` as ``friction.csv`` (mm in the file), atomically.

    Parameters
    ----------
    record : FrictionRecord
        Record in SI [-].
    path : str or Path
        Target file [-].

    Returns
    -------
    Path
        The file written.
    """
    cols = {
        "time_s": record.time_s,
        "current_cmd_A": record.current_cmd_A,
        "motor_angle_rad": record.motor_angle_rad,
        "scale_mm": record.scale_m / MM,
    }
    return atomic_write_columns(path, cols)


def _axis_records(name: str, value) -> AxisRecords:
    if isinstance(value, AxisRecords):
        return value
    if isinstance(value, SweepRecord):
        return AxisRecords(name=name, sweep=value)
    if isinstance(value, Mapping) and "sweep" in value:
        unknown = set(value) - {"sweep", "friction"}
        if unknown:
            raise InputError(f"axis {name}: unknown record(s) {sorted(unknown)}")
        return AxisRecords(name=name, sweep=value["sweep"], friction=value.get("friction"))
    raise InputError(
        f"axis {name}: expected AxisRecords, SweepRecord or {{'sweep': ..., 'friction': ...}},"
        f" got {type(value).__name__}"
    )


def write_bundle(bundle, path: str | Path) -> Path:
    """Write a measurement bundle folder; every file goes through temp-then-rename.

    Parameters
    ----------
    bundle : Bundle, mapping or tuple
        A :class:`Bundle`; or ``{"machine": ..., "axes": {...}}``; or
        ``(machine, axes)``. ``machine`` is a MachineConfig or a dict in the machine.yaml
        layout; each axis value is AxisRecords, SweepRecord, or
        ``{"sweep": SweepRecord, "friction": FrictionRecord}`` [-].
    path : str or Path
        Bundle folder, created if needed [-].

    Returns
    -------
    Path
        The bundle folder.

    Raises
    ------
    InputError
        Invalid machine description, or axes that do not match it.
    """
    root = Path(path)
    if isinstance(bundle, Bundle):
        machine, axes = bundle.machine, bundle.axes
    elif isinstance(bundle, Mapping):
        machine, axes = bundle["machine"], bundle["axes"]
    else:
        machine, axes = bundle
    machine = as_machine_config(machine, file=root / MACHINE_FILE)
    records = {name: _axis_records(name, v) for name, v in axes.items()}
    if set(records) != set(machine.axes):
        raise InputError(
            f"records for axes {sorted(records)} but machine.yaml lists "
            f"{sorted(machine.axes)}; give one record set per axis",
            file=root,
        )
    output_folder(root)
    for name, rec in records.items():
        write_sweep_csv(rec.sweep, root / name / SWEEP_FILE)
        if rec.friction is not None:
            write_friction_csv(rec.friction, root / name / FRICTION_FILE)
    write_machine_yaml(machine, root / MACHINE_FILE)
    return root
