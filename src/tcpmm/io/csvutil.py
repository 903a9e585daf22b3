"""Strict reading and atomic writing of the plain numeric CSV files of docs/formats.md.

Line numbers in messages are file lines: the header is line 1, the first data row line 2.
"""

from __future__ import annotations

import io
import re
import warnings
from collections.abc import Iterable
from pathlib import Path

import numpy as np
import pandas as pd

from tcpmm._validate import did_you_mean, is_number_text
from tcpmm.errors import InputError, InputWarning
from tcpmm.io.atomic import write_columns_atomic
from tcpmm.io.text import fields_error, read_text, separator_error, unquoted


def warn_input(message: str, file=None, line=None, column=None) -> None:
    """Emit an :class:`InputWarning` whose text names the file, line and column.

    Parameters
    ----------
    message : str
        What is suspicious and what to do [-].
    file : str or Path, optional
        File concerned [-].
    line : int, optional
        1-based line [-].
    column : int or str, optional
        Column number or name [-].
    """
    text = InputError(message, file=file, line=line, column=column).format()
    warnings.warn(InputWarning(text), stacklevel=3)


def unreadable(path: Path, what: str) -> InputError:
    """The error for a file that cannot be opened or is not UTF-8 text: the one
    :func:`tcpmm.io.text.read_text` gives, with the line of the first bad byte.

    Parameters
    ----------
    path : Path
        The file [-].
    what : str
        What the file is, for messages [-].
    """
    try:
        read_text(path, what)
    except InputError as exc:
        return exc
    return InputError(f"cannot read the {what} as UTF-8 text", file=path)


def pipe_text(path: Path, what: str = "CSV file") -> str | None:
    """The whole text of a pipe or other stream that can be read only once (``<(...)`` in
    a shell), so that header check and parser see the same text; ``None`` for a regular
    file, which is opened as often as needed.

    Parameters
    ----------
    path : Path
        The input [-].
    what : str
        What it is, for messages [-].
    """
    if not path.exists() or path.is_file() or path.is_dir():
        return None
    try:
        return path.read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError):
        raise unreadable(path, what) from None


def _header_names(first: str, path: Path) -> list[str]:
    """The column names of a header line, refused where the line is not a header.

    Parameters
    ----------
    first : str
        The first line, without its line break [-].
    path : Path
        CSV file, for the messages [-].

    Returns
    -------
    list of str
        Column names, stripped, none empty or twice [-].
    """
    if not first.strip():
        raise InputError(
            "the first line must be the header (column names separated by commas); "
            "the file is empty or starts with a blank line",
            file=path,
            line=1,
        )
    if (wrong := separator_error(first, path)) is not None:
        raise wrong
    names = [unquoted(c) for c in first.split(",")]
    if all(is_number_text(n) for n in names):
        raise InputError(
            "the first line holds numbers, not column names; add a header line with the "
            "column names (see docs/formats.md)",
            file=path,
            line=1,
        )
    for i, name in enumerate(names):
        if not name:
            index = "; a table's index written as a column? write it with index=False" \
                if i == 0 else ""
            raise InputError(f"empty column name in the header{index}", file=path, line=1,
                             column=i + 1)
        if name in names[:i]:
            raise InputError(
                f"column '{name}' appears twice in the header; keep one",
                file=path,
                line=1,
                column=name,
            )
    return names


def read_header(path: Path, what: str = "CSV file", text: str | None = None) -> list[str]:
    """Return the stripped column names of a CSV file's first line.

    The first data row is checked too: pandas would take surplus fields there as an
    index column and shift every column, so the fault would surface later at the wrong
    line and column.

    Parameters
    ----------
    path : Path
        CSV file [-].
    what : str
        What the file is, for messages [-].
    text : str, optional
        Its text, when it was read already (:func:`pipe_text`) [-].

    Returns
    -------
    list of str
        Column names [-].
    """
    try:  # the first two lines only: the rest is left to the parser
        with (io.StringIO(text) if text is not None
              else open(path, encoding="utf-8-sig", newline="")) as fh:
            first, row = fh.readline().strip("\r\n"), fh.readline().strip("\r\n")
    except (OSError, UnicodeDecodeError):
        raise unreadable(path, what) from None
    if first.lstrip().startswith("#"):  # a recorder's note above the header
        raise InputError("the first line is a comment; the header (the column names) must "
                         "be the first line: remove the comment lines", file=path, line=1)
    names = _header_names(first, path)
    if row.strip() and len(row.split(",")) > len(names):
        raise fields_error(path, 2, len(row.split(",")), len(names))
    return names


def parse_error(exc: Exception, path: Path) -> InputError:
    """The error for a pandas parser failure, at the row pandas names.

    Parameters
    ----------
    exc : Exception
        The pandas ``ParserError`` [-].
    path : Path
        CSV file [-].
    """
    m = re.search(r"Expected (\d+) fields in line (\d+), saw (\d+)", str(exc))
    if m:
        return fields_error(path, int(m.group(2)), int(m.group(3)), int(m.group(1)))
    return InputError(f"cannot parse CSV: {exc}", file=path)


def no_rows_error(path: Path) -> InputError:
    """The error for a CSV file that has a header but no data rows.

    Parameters
    ----------
    path : Path
        CSV file [-].
    """
    return InputError("the file has a header but no data rows", file=path, line=2)


def _check_required(names: list[str], required: list[str], optional: list[str],
                    path: Path) -> None:
    """Refuse a header that lacks a required column, naming the nearest one it has.

    Parameters
    ----------
    names : list of str
        The header's column names [-].
    required, optional : list of str
        Columns that must be and that may be present [-].
    path : Path
        CSV file, for the message [-].
    """
    missing = [c for c in required if c not in names]
    if missing:
        hints = "".join(did_you_mean(m, names) for m in missing[:1])
        raise InputError(
            f"missing column(s) {', '.join(missing)}{hints}; the file has "
            f"{', '.join(names)}; expected {', '.join(required)}"
            + (f" and optionally {', '.join(optional)}" if optional else "")
            + " (units are part of the name, see docs/formats.md)",
            file=path,
            line=1,
            column=missing[0],
        )


def read_frame(source, **options) -> pd.DataFrame:
    """``pandas.read_csv`` with the whole file typed at once, so that no pandas warning
    reaches the user.

    Read in chunks, a column whose chunks differ in type (a word among numbers) raises
    pandas' DtypeWarning with a path inside this package; the cell is then refused by
    the caller with its file, line and column. Silencing the warning instead would swap
    the process's warning filters, which is not safe where readers run in threads.

    Parameters
    ----------
    source : str, Path or file-like
        The CSV file or its text [-].
    **options
        Further ``pandas.read_csv`` options [-].

    Returns
    -------
    DataFrame
        The table as pandas reads it [-].
    """
    return pd.read_csv(source, low_memory=False, **options)


def _data_rows(path: Path, text: str | None) -> pd.DataFrame:
    """The rows of a CSV file under its header, trailing blank lines dropped.

    Parameters
    ----------
    path : Path
        CSV file [-].
    text : str or None
        Its text, when it was read already (:func:`pipe_text`) [-].

    Returns
    -------
    DataFrame
        Every column, names stripped, at least one row [-].
    """
    # all columns are read: usecols would silently drop surplus fields of a row
    try:
        frame = read_frame(
            io.StringIO(text) if text is not None else path,
            skip_blank_lines=False,
            skipinitialspace=True,
            encoding="utf-8-sig",
            na_filter=True,
        )
    except pd.errors.ParserError as exc:
        raise parse_error(exc, path) from None
    except UnicodeDecodeError:
        raise unreadable(path, "CSV file") from None
    frame.columns = [c.strip() for c in frame.columns]
    # A final blank line is harmless; blank lines inside the data are not.
    n = len(frame)
    while n > 0 and frame.iloc[n - 1].isna().all():
        n -= 1
    if n == 0:
        raise no_rows_error(path)
    return frame.iloc[:n]


def read_numeric_csv(
    path: str | Path,
    required: Iterable[str],
    optional: Iterable[str] = (),
    unused: dict | None = None,
) -> dict[str, np.ndarray]:
    """Read the named numeric columns of a CSV file, with checks that name file/line/column.

    Parameters
    ----------
    path : str or Path
        CSV file with a header line [-].
    required : iterable of str
        Columns that must be present [-].
    optional : iterable of str
        Columns read when present [-].
    unused : dict, optional
        Known columns left unread, each with why: said so, not called unknown [-].

    Returns
    -------
    dict of str to ndarray
        float64 array per column found, in file units [-].

    Raises
    ------
    InputError
        Missing file or column, a column neither required, optional nor ``unused``,
        malformed row, non-numeric, empty, NaN or infinite value.

    Warns
    -----
    InputWarning
        Columns of ``unused`` (they are not read).
    """
    path = Path(path)
    required = list(required)
    optional = list(optional)
    expected = required + optional
    text = pipe_text(path)
    names = read_header(path, text=text)
    _check_required(names, required, optional, path)
    extra = [c for c in names if c not in expected]
    for c in extra:
        why = (unused or {}).get(c)
        if not why:  # a typo would leave a column out and change the result
            raise InputError(f"unknown column{did_you_mean(c, expected)}; rename or remove "
                             f"it (the columns read: {', '.join(expected)})", file=path,
                             line=1, column=c)
        warn_input(f"column '{c}' is not read: {why}", file=path, line=1, column=c)
    use = [c for c in expected if c in names]
    frame = _data_rows(path, text)
    return {name: _finite_column(frame[name], name, path) for name in use}


def _finite_column(col, name: str, path: Path) -> np.ndarray:
    """A column as float64, with the first cell that is not a finite number named by
    file, line and column [-]."""
    if col.dtype == bool:
        raise InputError(
            "values are True/False; expected numbers", file=path, line=2, column=name
        )
    if not pd.api.types.is_numeric_dtype(col.dtype):
        num = pd.to_numeric(col, errors="coerce")
        bad = np.flatnonzero(num.isna().to_numpy() & col.notna().to_numpy())
        if bad.size:
            i = int(bad[0])
            raise InputError(
                f"value '{col.iloc[i]}' is not a number (use '.' as decimal point, "
                "no units or thousands separators in cells)",
                file=path,
                line=i + 2,
                column=name,
            )
        col = num
    values = col.to_numpy(dtype=float)
    finite = np.isfinite(values)
    if not finite.all():
        i = int(np.flatnonzero(~finite)[0])
        what = ("empty or NaN (a missing value, a blank line or a 'nan' in the cell)"
                if np.isnan(values[i]) else "infinite")
        raise InputError(
            f"value is {what}; every cell must hold a finite number. Remove or "
            "repair the row (do not interpolate silently over sensor drop-outs)",
            file=path,
            line=i + 2,
            column=name,
        )
    return values


#: Named numeric columns as CSV, atomically (``%.15g`` unless told otherwise).
atomic_write_columns = write_columns_atomic
