"""Run files (docs/formats.md section 3): simulated or measured runs as CSV."""

from __future__ import annotations

import io
import re
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..result import RUN_COLUMNS, AxisRun, Run
from .atomic import write_table_atomic

_COL = re.compile(r"^([a-z]{1,2})_(cmd_mm|motor_mm|scale_mm|tcp_mm|current_A)$")


def write_run_csv(run: Run, path) -> None:
    """Write a run file atomically (``time_s``, then per axis the section 3 columns)."""
    write_table_atomic(run.to_pandas(), path, "%.10g")


def read_run_csv(path) -> Run:
    """Read a run file; absent sensors are absent columns.

    Parameters
    ----------
    path : str or Path
        The CSV file [-].
    """
    import pandas as pd

    from .csvutil import no_rows_error, parse_error, pipe_text, read_header, unreadable

    path = Path(path)
    text = pipe_text(path, "run file")
    cols = read_header(path, "run file", text)
    try:
        df = pd.read_csv(io.StringIO(text) if text is not None else path,
                         encoding="utf-8-sig")
    except pd.errors.ParserError as exc:
        raise parse_error(exc, path) from None
    except UnicodeDecodeError:
        raise unreadable(path, "run file") from None
    except Exception as exc:  # pandas raises many kinds
        raise InputError(f"cannot read as CSV: {exc}", file=path) from None
    df.columns = cols
    if len(df) == 0:
        raise no_rows_error(path)
    if "time_s" not in cols:
        raise InputError(f"missing column 'time_s' (found: {', '.join(cols)})", file=path, line=1)
    axes: dict[str, dict] = {}
    for c in cols:
        if c == "time_s":
            continue
        m = _COL.match(c)
        if not m:
            raise InputError(
                f"unknown column {c!r}; run-file columns are time_s and <axis>_cmd_mm, "
                "<axis>_motor_mm, <axis>_scale_mm, <axis>_tcp_mm, <axis>_current_A",
                file=path,
                line=1,
                column=c,
            )
        v = pd.to_numeric(df[c], errors="coerce").to_numpy(dtype=float)
        bad = np.flatnonzero(~np.isfinite(v))
        if bad.size:
            raise InputError(
                "value is missing or not a number", file=path, line=int(bad[0]) + 2, column=c
            )
        scale = 1.0 if m.group(2) == "current_A" else 1e-3
        axes.setdefault(m.group(1).upper(), {})[RUN_COLUMNS[m.group(2)]] = v * scale
    t = pd.to_numeric(df["time_s"], errors="coerce").to_numpy(dtype=float)
    bad = np.flatnonzero(~np.isfinite(t))
    if bad.size:
        raise InputError(
            "time is missing or not a number", file=path, line=int(bad[0]) + 2, column="time_s"
        )
    if t.size < 2 or np.any(np.diff(t) <= 0):
        k = int(np.flatnonzero(np.diff(t) <= 0)[0]) + 3 if t.size >= 2 else 2
        raise InputError("time must increase strictly", file=path, line=k, column="time_s")
    if not axes:
        raise InputError("no axis columns (e.g. x_tcp_mm)", file=path, line=1)
    runs = {
        k: AxisRun(
            cmd=v.get("cmd"),
            motor=v.get("motor"),
            scale=v.get("scale"),
            tcp=v.get("tcp"),
            current=v.get("current"),
        )
        for k, v in axes.items()
    }
    return Run(time_s=t, axes=runs, meta={"source": str(path)})
