"""Run files (docs/formats.md section 3): simulated or measured runs as CSV or Parquet.

Both formats hold the same table: ``time_s``, then per axis the section 3 columns in mm
and A. CSV is the default; Parquet (``.parquet``) stores the doubles as they are and is
the better choice for long runs. :func:`read_run` reads either, by the file's extension.
"""

from __future__ import annotations

import contextlib
import io
import os
import re
from pathlib import Path

import numpy as np

from .._validate import file_path
from ..errors import InputError
from ..result import BLOCK_COLUMNS, RUN_COLUMNS, AxisRun, Run
from .atomic import atomic_path
from .runwrite import (  # noqa: F401  (the writers are part of this module's interface)
    PARQUET_SUFFIXES,
    RowGroups,
    arrow_table,
    is_parquet,
    parquet_columns,
    parquet_schema,
    write_run,
    write_run_csv,
    write_run_parquet,
)

_COL = re.compile(r"^([a-z]{1,2})_(cmd|motor|scale|tcp|current)_(mm|um|µm|nm|m|A)$")
#: The units a position column may name, to metres (a TCP device that logs in um) [-].
LENGTH_UNITS = {"mm": 1e-3, "um": 1e-6, "µm": 1e-6, "nm": 1e-9, "m": 1.0}


def column_unit(name: str) -> str | None:
    """The unit a run-file column's name ends with (``x_tcp_um``: um); None for a name
    that is no axis column [-]."""
    m = _COL.match(name)
    return m.group(3) if m else None


@contextlib.contextmanager
def run_parquet_writer(path):
    """Write a run that comes in pieces as a Parquet run file, a row group a piece, short
    pieces gathered into row groups of :data:`~tcpmm.io.runwrite.LEAST_ROW_GROUP_ROWS`
    (:class:`~tcpmm.io.runwrite.RowGroups`): the file is written under a temporary name
    beside ``path`` and renamed onto it when the ``with`` block ends, removed when it
    fails or is interrupted.

    Parameters
    ----------
    path : str or Path
        The run file [-].

    Yields
    ------
    callable
        ``write(run)``: appends the pieces's rows (:class:`~tcpmm.result.Run`, the
        columns of the first piece) [-].
    """
    from concurrent.futures import ThreadPoolExecutor, wait

    import pyarrow.parquet as pq

    # a piece is encoded and written in a thread (Arrow lets go of the GIL) while the
    # next is computed; one at a time, so memory holds one piece more
    with atomic_path(path) as tmp, ThreadPoolExecutor(1) as pool:
        opened: list = []
        pending: list = []
        groups = RowGroups()

        def put(cols: dict) -> None:
            table = arrow_table(cols, opened[0].schema)
            if pending:
                pending.pop().result()
            pending.append(pool.submit(opened[0].write_table, table))

        def write(run: Run) -> None:
            cols = parquet_columns(run)
            if not opened:
                schema = parquet_schema(cols)
                opened.append(pq.ParquetWriter(tmp, schema, use_dictionary=False))
            for group in groups.add(cols):
                put(group)

        try:
            yield write
            for group in groups.rest():
                put(group)
            if pending:
                pending.pop().result()
        finally:
            wait(pending)  # a failure elsewhere: the file is closed once written
            if opened:
                opened[0].close()


def read_run(path) -> Run:
    """Read a run file, CSV or Parquet (by extension); absent sensors are absent columns.

    Parameters
    ----------
    path : str or Path
        The run file [-].
    """
    path = file_path("path", path)
    return read_run_parquet(path) if is_parquet(path) else read_run_csv(path)


def as_run(run, name: str = "run") -> Run:
    """``run`` as a :class:`~tcpmm.result.Run`: a run as it is, a run file read, a table in
    the run-file layout checked as a file is; anything else an :class:`InputError`.

    Parameters
    ----------
    run : Run or str or Path or pandas.DataFrame
        The run, its file or its table (positions in mm) [-].
    name : str
        The argument's name, for the message [-].
    """
    if isinstance(run, Run):
        return run
    if isinstance(run, str | os.PathLike):
        return read_run(run)
    if type(run).__name__ == "DataFrame":  # pandas' own, without importing pandas here
        return run_from_table(run)
    raise InputError(f"{name} must be a Run, a run file's path or its table in the run-file "
                     f"layout (time_s, <axis>_cmd_mm, ... in mm), got {run!r:.60}")


def read_run_parquet(path) -> Run:
    """Read a Parquet run file (see :func:`read_run`).

    Parameters
    ----------
    path : str or Path
        The Parquet file [-].
    """
    import pyarrow as pa
    import pyarrow.parquet as pq

    path = Path(path)
    if not path.is_file():
        raise InputError("no such run file", file=path)
    try:
        # one file read as such: pq.read_table's dataset layer imports pandas (0.5 s)
        with pq.ParquetFile(path) as f:
            table = f.read()
    except (pa.ArrowException, OSError) as exc:
        raise InputError(f"cannot read as Parquet: {exc}", file=path) from None
    checked_parquet_names(table.column_names, path)
    cols = {}
    for name in table.column_names:
        col = table.column(name)
        refuse_not_numbers(name, col.type, path)
        v = float_values(col)
        if name == "time_s":
            refuse_coarse_time(col.type, v, path)
        cols[name] = v if v.flags.writeable else v.copy()  # the run's own, as from a CSV
    return _run_from_columns(cols, path, first_row=1, what="row")


def checked_parquet_names(names, path) -> None:
    """Refuse a Parquet run file whose columns repeat a name (Arrow keeps both; a CSV's
    reader refuses them too) or hold a pandas index, with what to do [-]."""
    for name in dict.fromkeys(names):
        if names.count(name) > 1:
            raise InputError(f"the file has {names.count(name)} columns of this name; keep "
                             "one", file=path, column=name)
        if name.startswith("__index_level_"):
            raise InputError("a pandas index written as a column: write the file with "
                             "DataFrame.to_parquet(..., index=False)", file=path, column=name)


def refuse_not_numbers(name: str, kind, path) -> None:
    """Refuse Parquet column ``name`` of Arrow type ``kind`` unless it holds numbers [-]."""
    import pyarrow as pa

    if not (pa.types.is_floating(kind) or pa.types.is_integer(kind)):
        when = ("; write time_s as seconds from the run's start, float64 (in pandas, "
                "(t - t.iloc[0]).dt.total_seconds())" if pa.types.is_temporal(kind) else "")
        raise InputError(f"column holds {kind}, not numbers{when}", file=path, column=name)


#: Finest share of the sample period a stored time may round to: a float32 time of
#: 1234.5 s rounds to 122 us, and 1 kHz read as 1024 Hz, its feed 0.1 % low [-]
TIME_ROUNDING_SHARE = 1e-3


def refuse_coarse_time(kind, t, path) -> None:
    """Refuse a Parquet ``time_s`` of Arrow type ``kind`` stored in fewer bits than a
    float64 (a float32, say) where its rounding at the latest time ``t`` holds exceeds
    :data:`TIME_ROUNDING_SHARE` of the median sample period, with what to do [-]."""
    import pyarrow as pa

    if t.size < 2 or not pa.types.is_floating(kind) or kind.bit_width >= 64:
        return
    period = float(np.median(np.diff(t)))
    step = float(np.spacing(np.abs(t).max().astype(kind.to_pandas_dtype())))
    if period > 0 and step > TIME_ROUNDING_SHARE * period:
        raise InputError(
            f"time stored as a float{kind.bit_width} rounds to {step * 1e6:.3g} µs at "
            f"{np.abs(t).max():.6g} s, {step / period:.1%} of the sample period "
            f"({period * 1e6:.4g} µs): the sample rate, the feed and every time read from it "
            "would be off; store time_s as float64 (or less its first value)", file=path,
            column="time_s")


def refuse_gaps(name: str, v, path, first_row: int = 1, what: str = "row",
                cells=None) -> None:
    """Refuse a value of column ``name`` that is missing or not finite, naming its row or
    line: ``first_row`` is the file's number of ``v[0]``, ``what`` ``row`` or ``line``;
    ``cells``, where given, are the column's cells as the CSV parser left them (text where
    it was no number, NaN where the cell was empty), which the message quotes [-]."""
    bad = np.flatnonzero(~np.isfinite(v))
    if bad.size:
        i = int(bad[0])
        text, place = _place(i, first_row, what)
        kind = "time" if name == "time_s" else "value"
        fault, fix = _fault(float(v[i]), None if cells is None else cells[i])
        raise InputError(f"{kind}{fault}{text}{fix}", file=path, column=name, **place)


def _fault(value: float, cell) -> tuple[str, str]:
    """What a value that is not a finite number is, and what to do: its cell quoted where
    there is one (``cell`` not None), else that it is missing or not a number [-]."""
    repair = "; every cell must hold a finite number: repair or remove the row"
    if cell is None:
        return " is missing or not a number", repair
    if isinstance(cell, str) and cell.strip():
        try:
            parsed = float(cell)
        except ValueError:
            parsed = 0.0
        if np.isfinite(parsed):  # also Python's "1_000", which the parser refused
            return (f" {cell.strip()!r} is not a number", " (use '.' as decimal point, no "
                    "units or thousands separators in cells)")
        return f" {cell.strip()!r} is not a finite number", repair
    return (" is empty" if np.isnan(value) else " is infinite"), repair


def refuse_time_back(t, path, first_row: int = 1, what: str = "row",
                     t_before: float = -np.inf) -> None:
    """Refuse a time not after the one before it (``t_before`` before ``t[0]``), naming its
    row or line as :func:`refuse_gaps` does [s]."""
    back = np.flatnonzero(np.diff(t, prepend=t_before) <= 0)
    if back.size:
        text, place = _place(int(back[0]), first_row, what)
        raise InputError(f"time must increase strictly{text}", file=path, column="time_s",
                         **place)


def _place(i: int, first_row: int, what: str) -> tuple[str, dict]:
    """Where the ``i``-th value is: as text after a message, and as the error's line [-]."""
    if what == "line":
        return "", {"line": i + first_row}
    return f" (row {i + first_row})", {}


def float_values(col) -> np.ndarray:
    """A Parquet column (an Arrow array or chunked array of numbers) as float64: its
    buffers' values where it holds float64 or integers (a run's ``nc_line``, ``rapid``)
    without nulls, which spares the import of pandas that pyarrow's own conversion makes
    (0.5 s and more), else converted [-]."""
    import pyarrow as pa

    chunks = col.chunks if isinstance(col, pa.ChunkedArray) else [col]
    if col.null_count == 0 and (col.type == pa.float64() or pa.types.is_integer(col.type)):
        kind = np.dtype(col.type.to_pandas_dtype())
        parts = [np.frombuffer(c.buffers()[1], kind, len(c), c.offset * kind.itemsize)
                 for c in chunks]
        v = parts[0] if len(parts) == 1 else np.concatenate(parts or [np.empty(0, kind)])
        return v if kind == np.float64 else v.astype(float)
    return col.to_numpy(zero_copy_only=False).astype(float)  # nulls as NaN


def read_run_csv(path) -> Run:
    """Read a CSV run file (see :func:`read_run`).

    Parameters
    ----------
    path : str or Path
        The CSV file [-].
    """
    import pandas as pd

    # the CSV readers load pandas, which a command that only writes a run never needs
    from .csvutil import (
        no_rows_error,
        parse_error,
        pipe_text,
        read_frame,
        read_header,
        unreadable,
    )

    path = Path(path)
    text = pipe_text(path, "run file")
    cols = read_header(path, "run file", text)
    try:
        # only an empty cell is NaN: a 'nan' or 'NA' stays text that the message quotes
        df = read_frame(io.StringIO(text) if text is not None else path,
                        encoding="utf-8-sig", keep_default_na=False, na_values=[""])
    except pd.errors.ParserError as exc:
        raise parse_error(exc, path) from None
    except UnicodeDecodeError:
        raise unreadable(path, "run file") from None
    except Exception as exc:  # pandas raises many kinds
        raise InputError(f"cannot read as CSV: {exc}", file=path) from None
    df.columns = cols
    if len(df) == 0:
        raise no_rows_error(path)
    cells = {str(c): df[c].to_numpy() for c in df.columns}
    return _run_from_columns(_numbers(df), path, first_row=2, what="line", cells=cells)


def run_from_table(df, path=None) -> Run:
    """A run from its table in the run-file layout (``time_s``, ``<axis>_cmd_mm``, ...),
    checked as a CSV run file is.

    Parameters
    ----------
    df : pandas.DataFrame
        The table, positions in mm, currents in A [-].
    path : str or Path, optional
        Where it came from, for messages [-].
    """
    return _run_from_columns(_numbers(df), path, first_row=2, what="line")


def _numbers(df) -> dict:
    """The columns of a table as float64, NaN where a cell is no number [-]."""
    import pandas as pd

    return {str(c): pd.to_numeric(df[c], errors="coerce").to_numpy(dtype=float)
            for c in df.columns}


def _run_from_columns(cols: dict, path: Path, first_row: int, what: str,
                      cells: dict | None = None) -> Run:
    """The run of a table of run-file columns, checked: names, finite numbers, time.

    ``first_row`` is the number of the first data row in the file's own counting (CSV
    lines count the header), ``what`` its name in messages (``line`` or ``row``);
    ``cells`` the CSV parser's columns, for the messages of :func:`refuse_gaps`.
    """
    cells = cells or {}
    names = list(cols)
    if "time_s" not in names:
        raise InputError(f"missing column 'time_s' (found: {', '.join(names)})", file=path,
                         line=1 if what == "line" else None)
    axes: dict[str, dict] = {}
    blocks = {}
    for c in names:
        if c == "time_s":
            continue
        if c in BLOCK_COLUMNS:
            refuse_gaps(c, cols[c], path, first_row, what, cells.get(c))
            blocks[c] = cols[c].astype(BLOCK_COLUMNS[c])
            continue
        m = _COL.match(c)
        if not m or (m.group(2) == "current") != (m.group(3) == "A"):
            raise InputError(
                f"unknown column {c!r}; run-file columns are time_s and <axis>_cmd_mm, "
                "<axis>_motor_mm, <axis>_scale_mm, <axis>_tcp_mm (or in um, nm, m: "
                "x_tcp_um), <axis>_current_A, nc_line, rapid",
                file=path, line=1 if what == "line" else None, column=c,
            )
        v = cols[c]
        refuse_gaps(c, v, path, first_row, what, cells.get(c))
        field = RUN_COLUMNS[f"{m.group(2)}_{'A' if m.group(3) == 'A' else 'mm'}"]
        axis = axes.setdefault(m.group(1).upper(), {})
        if field in axis:
            raise InputError(f"a second column of {m.group(1)}'s {m.group(2)} (in another "
                             "unit); keep one", file=path, column=c)
        axis[field] = v * LENGTH_UNITS.get(m.group(3), 1.0)
    t = cols["time_s"]
    if t.size == 0:
        raise InputError("the run has no rows", file=path)
    refuse_gaps("time_s", t, path, first_row, what, cells.get("time_s"))
    if t.size < 2:
        raise InputError("the run has one row; a run needs two or more (a record period "
                         "longer than the run keeps only its first sample)", file=path)
    refuse_time_back(t, path, first_row, what)
    if not axes:
        raise InputError("no axis columns (e.g. x_tcp_mm)", file=path,
                         line=1 if what == "line" else None)
    runs = {k: AxisRun(cmd=v.get("cmd"), motor=v.get("motor"), scale=v.get("scale"),
                       tcp=v.get("tcp"), current=v.get("current"))
            for k, v in axes.items()}
    return Run(time_s=t, axes=runs, meta={"source": None if path is None else str(path)},
               **blocks)
