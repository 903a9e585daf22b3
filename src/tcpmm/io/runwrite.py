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
    (float64, int32 or int8) [-]."""
    import pyarrow as pa

    return pa.schema([(k, pa.from_numpy_dtype(v.dtype)) for k, v in cols.items()])


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
