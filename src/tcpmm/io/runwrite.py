"""Writing run files (docs/formats.md section 3), CSV or Parquet, from a run's columns.

The writers need only :meth:`tcpmm.result.Run.columns`, so :class:`~tcpmm.result.Run` can
write itself without importing the readers of :mod:`tcpmm.io.runfile`, which build runs.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .atomic import CSV_BLOCK_ROWS, atomic_path, write_columns_atomic

#: Extensions read and written as Parquet; every other one is CSV.
PARQUET_SUFFIXES = (".parquet", ".pq")
#: Fewest rows of a row group that :class:`RowGroups` gathers pieces into [-]. Arrow keeps
#: some 15 KB of metadata a row group until the file is closed and twice that while it
#: writes the footer: a row group of each piece of a few rows (``--chunk-blocks 1``) cost
#: 32 KB of memory a piece (320 MB of the 430 MB peak of a program of 10 000 blocks). Two
#: groups of this many rows are held at most (one gathered, one written), 9 MB of a run
#: of three axes.
LEAST_ROW_GROUP_ROWS = 1 << 15


def is_parquet(path) -> bool:
    """Whether a run file is Parquet (by its extension)."""
    return Path(path).suffix.lower() in PARQUET_SUFFIXES


def write_run(run, path) -> None:
    """Write a run file atomically: Parquet for ``.parquet``, else CSV."""
    if is_parquet(path):
        write_run_parquet(run, path)
    else:
        write_run_csv(run, path)


def write_run_csv(run, path) -> None:
    """Write a run file as CSV atomically (``%.10g``, as always)."""
    write_columns_atomic(path, run.columns(), "%.10g")


def write_run_parquet(run, path) -> None:
    """Write a run file as Parquet atomically (the CSV's names; float64 columns, the
    block columns ``nc_line`` and ``rapid`` int32 and int8), a row group of
    :data:`~tcpmm.io.atomic.CSV_BLOCK_ROWS` rows at a time (bounded memory)."""
    import pyarrow.parquet as pq

    cols = parquet_columns(run)
    schema = parquet_schema(cols)
    n = run.time_s.size
    with atomic_path(path) as tmp, pq.ParquetWriter(tmp, schema, use_dictionary=False) as w:
        for k in range(0, max(n, 1), CSV_BLOCK_ROWS):
            w.write_table(arrow_table({c: v[k:k + CSV_BLOCK_ROWS] for c, v in cols.items()},
                                      schema))


def parquet_columns(run) -> dict:
    """The run-file columns of ``run`` as Parquet stores them: float64, the integer
    columns (:data:`~tcpmm.result.BLOCK_COLUMNS`) as they are [-]."""
    return {k: v if v.dtype.kind == "i" else np.asarray(v, dtype=float)
            for k, v in run.columns().items()}


def parquet_schema(cols: dict):
    """The Arrow schema of :func:`parquet_columns`: each column's type from its array's
    (float64, int32 or int8), none of them nullable (a run has a value in every cell:
    Parquet then stores no definition levels, which took a seventh of the writing) [-]."""
    import pyarrow as pa

    return pa.schema([pa.field(k, pa.from_numpy_dtype(v.dtype), nullable=False)
                      for k, v in cols.items()])


def arrow_table(cols: dict, schema):
    """An Arrow table of numeric columns over their own memory. ``pyarrow.table`` and
    ``pyarrow.array`` of a numpy array import pandas to ask whether it is one of its
    objects (0.4 s, more than writing a short run); Arrow's buffers of the arrays do not.

    Parameters
    ----------
    cols : dict of ndarray
        Columns by name, in the order of ``schema``, equally long [-].
    schema : pyarrow.Schema
        Their names and types (float64, or an integer type) [-].
    """
    import pyarrow as pa

    arrays = []
    for v, f in zip(cols.values(), schema, strict=True):
        v = np.ascontiguousarray(v, dtype=f.type.to_pandas_dtype())
        arrays.append(pa.Array.from_buffers(f.type, v.size, [None, pa.py_buffer(v)]))
    return pa.Table.from_arrays(arrays, schema=schema)


class RowGroups:
    """The pieces of a run's columns as row groups of at least ``least`` rows: a piece as
    long goes on as it is (not copied), shorter ones are gathered into one group, copied
    into a fresh buffer each (a group given on is written while the next is gathered).
    Only a group given on before a long piece, and the last one, may be shorter; so the
    groups are as many as the rows make, however the run was cut.

    Parameters
    ----------
    least : int, optional
        Fewest rows of a group, default :data:`LEAST_ROW_GROUP_ROWS` [-].
    """

    def __init__(self, least: int | None = None):
        self.least = int(least or LEAST_ROW_GROUP_ROWS)
        self.held: dict | None = None  # columns of room for twice ``least`` rows
        self.n = 0

    def add(self, cols: dict) -> list:
        """The row groups complete with the piece ``cols`` (equally long columns by name,
        the same names each piece), in order [-]."""
        rows = len(next(iter(cols.values())))
        if rows >= self.least:
            return [*self.rest(), cols]
        if self.held is None:
            # a piece is shorter than ``least`` and added only while fewer are held
            self.held = {c: np.empty(2 * self.least, np.asarray(v).dtype)
                         for c, v in cols.items()}
        for c, v in cols.items():
            self.held[c][self.n:self.n + rows] = v
        self.n += rows
        return self.rest() if self.n >= self.least else []

    def rest(self) -> list:
        """The rows held, as one group (none where none are held) [-]."""
        if not self.n:
            return []
        group = {c: v[:self.n] for c, v in self.held.items()}
        self.held, self.n = None, 0
        return [group]
