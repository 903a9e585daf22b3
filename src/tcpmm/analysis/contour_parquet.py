"""The Parquet run file a streamed contour reads: opened, its rows counted, its command's
travel, and its columns a chunk at a time, checked as a whole run is."""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..io.runfile import (
    checked_parquet_names,
    column_unit,
    float_values,
    refuse_coarse_time,
    refuse_gaps,
    refuse_not_numbers,
    refuse_time_back,
)
from .contour_inputs import NO_COMMAND, SENSORS, no_sensors, warn_one_sided
from .rapids import MoveTravel

#: rows read at a time [-]
STREAM_ROWS = 200_000


def parquet_file(path, **options):
    """The Parquet file at ``path``, opened; what is no Parquet file (junk, empty, cut
    short) an :class:`InputError` as :func:`~tcpmm.io.runfile.read_run` gives it [-]."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    try:
        return pq.ParquetFile(path, **options)
    except (pa.ArrowException, OSError) as exc:
        raise InputError(f"cannot read as Parquet: {exc}", file=path) from None


def parquet_rows(path) -> int:
    """Rows of a Parquet file, from its footer [-]."""
    return parquet_file(path).metadata.num_rows


def travel_positions(path, feed_only: bool = False) -> dict:
    """Per axis of the run's command, two positions as far apart as it travels: a
    two-sample signal with the command's travel (:func:`~tcpmm.analysis.plane.motion_plane`);
    with ``feed_only`` its largest travel within one feed move, where it has samples out of
    G0 rapids and in them (:func:`.rapids.feed_commands`) [m]."""
    lo, hi, moves, seen = {}, {}, MoveTravel(), set()
    for cols in batches(path, None, lambda c: c.endswith("_cmd_mm")
                         or (feed_only and c == "rapid")):
        feed = cols.pop("rapid", None)
        # in metres sample by sample, as a whole run is read: its travels to the bit
        cols = {c.split("_")[0].upper(): v * 1e-3 for c, v in cols.items()}
        for a, v in cols.items():
            if v.size:
                lo[a] = min(lo.get(a, np.inf), float(np.min(v)))
                hi[a] = max(hi.get(a, -np.inf), float(np.max(v)))
        if feed is not None:
            moves.add(cols, feed == 0)
            seen.update(np.unique(feed == 0).tolist())
    if seen == {False, True}:
        return {a: np.array([0.0, t]) for a, t in moves.travel().items()}
    return {a: np.array([lo[a], hi[a]]) for a in lo}


def batches(path, rows, keep):
    """The columns ``keep`` accepts of a Parquet file, ``rows`` rows at a time, checked as
    :func:`~tcpmm.io.runfile.read_run` checks a whole run [-]."""
    # pre-buffered reads keep every row group's bytes read so far until the scan ends
    f = parquet_file(path, pre_buffer=False)
    checked_parquet_names(f.schema_arrow.names, path)
    _refuse_other_units(f.schema_arrow.names, path)
    names = [c for c in f.schema_arrow.names if keep(c)]
    for c in names:
        refuse_not_numbers(c, f.schema_arrow.field(c).type, path)
    row0, t_before = 0, -np.inf
    for b in _read_batches(f, rows or STREAM_ROWS, names, path):
        cols = {c: float_values(b.column(c)) for c in names}
        for c, v in cols.items():
            refuse_gaps(c, v, path, row0 + 1)
        t = cols.get("time_s")
        if t is not None and t.size:
            refuse_time_back(t, path, row0 + 1, t_before=t_before)
            refuse_coarse_time(f.schema_arrow.field("time_s").type, t, path)
            t_before = float(t[-1])
        row0 += b.num_rows
        yield cols


def _read_batches(f, rows: int, names: list, path):
    """The record batches of the open Parquet file ``f``; a row group that cannot be read
    (a file cut short after its footer was written) an :class:`InputError` [-]."""
    import pyarrow as pa

    try:
        yield from f.iter_batches(batch_size=rows, columns=names)
    except (pa.ArrowException, OSError) as exc:
        raise InputError(f"cannot read as Parquet: {exc}", file=path) from None


def has_columns(path, cmd_cols: list, axes) -> None:
    """Refuse a run without time, command or any sensor of the axes, as
    :func:`~tcpmm.analysis.contour.contour_error` refuses it [-]."""
    found = parquet_file(path).schema_arrow.names
    names = set(found)
    if "time_s" not in names:
        raise InputError(f"missing column 'time_s' (found: {', '.join(found)})", file=path)
    if not names.issuperset(cmd_cols):
        raise InputError(NO_COMMAND, file=path)
    if not any(names.issuperset(c.replace("_cmd_", f"_{s}_") for c in cmd_cols)
               for s in SENSORS):
        raise InputError(no_sensors(axes), file=path)
    warn_one_sided({s: [a for a, c in zip(axes, cmd_cols, strict=True)
                        if c.replace("_cmd_", f"_{s}_") in names] for s in SENSORS}, axes)


def _refuse_other_units(names, path) -> None:
    """Refuse a position column in a unit other than mm: read a chunk at a time, the run
    is taken by the run file's own names, and the column would be left out unsaid [-]."""
    for c in names:
        unit = column_unit(c)
        if unit not in (None, "mm", "A"):
            raise InputError(
                f"a Parquet run read a chunk at a time takes its positions in mm, and this "
                f"column is in {unit}: write it in mm ({c[:-len(unit)]}mm), or read the run "
                "whole (without --chunk-rows, up to 2 000 000 rows)", file=path, column=c)
