"""Command file (docs/formats.md section 2): ``time_s, x_mm, y_mm[, z_mm]``, one row per
period, and of a program's command ``nc_line, rapid``: the line of the block each sample
is in and whether it is a G0 rapid (:mod:`tcpmm.path.blocktrack`)."""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..io.atomic import CSV_BLOCK_ROWS, atomic_path
from ..io.text import fields_error, file_lines, read_text, separator_error, unquoted
from .command import Command

_AXIS_COLUMNS = {"x_mm": "X", "y_mm": "Y", "z_mm": "Z"}
#: the columns of the block each sample is in, after the axes [-]
BLOCK_COLUMNS = ("nc_line", "rapid")
_LAYOUT = "time_s, x_mm, y_mm[, z_mm][, nc_line, rapid]"
#: allowed relative deviation of a time step from the mean step [-]
UNIFORM_REL_TOL = 1e-6


def _header(line: str, file) -> list[str]:
    if (wrong := separator_error(line, file)) is not None:
        raise wrong
    names = [unquoted(h) for h in line.split(",")]
    if names[0] != "time_s":
        raise InputError(
            f"the first column must be time_s, found {names[0]!r}; expected the header {_LAYOUT}",
            file=file,
            line=1,
            column=1,
        )
    seen = set()
    for k, name in enumerate(names[1:], start=2):
        if name not in _AXIS_COLUMNS and name not in BLOCK_COLUMNS:
            raise InputError(
                f"unknown column {name!r}; a command file has the columns {_LAYOUT}",
                file=file,
                line=1,
                column=k,
            )
        if name in seen:
            raise InputError(f"column {name!r} appears twice", file=file, line=1, column=k)
        seen.add(name)
    for need in ("x_mm", "y_mm"):
        if need not in seen:
            raise InputError(
                f"column {need!r} is missing; expected the header {_LAYOUT}", file=file, line=1
            )
    return names


def _locate_bad_value(rows, names, file):
    for r, row in enumerate(rows):
        fields = row.split(",")
        if len(fields) > len(names):
            raise fields_error(file, r + 2, len(fields), len(names))
        if len(fields) != len(names):
            raise InputError(
                f"{len(fields)} values for {len(names)} columns; every row needs "
                f"one value per column ({', '.join(names)})",
                file=file,
                line=r + 2,
            )
        for c, text in enumerate(fields):
            try:
                float(text)
            except ValueError:
                raise InputError(
                    f"{text.strip()!r} is not a number", file=file, line=r + 2, column=names[c]
                ) from None


def _numbers(rows, names, file) -> np.ndarray:
    """The samples of a command file as a table of finite numbers.

    Parameters
    ----------
    rows : list of str
        The lines after the header [-].
    names : list of str
        The columns of the header [-].
    file : Path
        The file, for the messages [-].

    Returns
    -------
    ndarray, shape (len(rows), len(names))
        The values as written: time [s] and positions [mm].
    """
    try:
        data = np.array([row.split(",") for row in rows], dtype=float)
    except ValueError:
        data = None
    if data is None or data.ndim != 2 or data.shape[1] != len(names):
        _locate_bad_value(rows, names, file)
        raise InputError("the rows cannot be read as numbers", file=file)
    bad = ~np.isfinite(data)
    if bad.any():
        r, c = np.argwhere(bad)[0]
        raise InputError(
            f"{rows[r].split(',')[c].strip()!r} is not a finite number",
            file=file,
            line=int(r) + 2,
            column=names[c],
        )
    return data


def _check_uniform_time(t, file) -> None:
    """Refuse a time column that does not increase by one constant step.

    Parameters
    ----------
    t : ndarray
        The time column [s].
    file : Path
        The file, for the messages [-].
    """
    dt = np.diff(t)
    if np.any(dt <= 0):
        r = int(np.argmax(dt <= 0)) + 1
        raise InputError(
            f"time must increase from row to row ({t[r - 1]} s, then {t[r]} s)",
            file=file,
            line=r + 2,
            column="time_s",
        )
    step = (t[-1] - t[0]) / (t.size - 1)
    off = np.abs(dt - step) > UNIFORM_REL_TOL * step + 1e-12
    if np.any(off):
        # point at the first step that differs from the first one, if any does
        first = np.abs(dt - dt[0]) > UNIFORM_REL_TOL * dt[0] + 1e-12
        r = int(np.argmax(first if np.any(first) else off)) + 1
        raise InputError(
            f"time must be uniformly sampled: the step is {dt[r - 1]:.9g} s here but "
            f"{dt[0]:.9g} s at the start; write one row per interpolation period",
            file=file,
            line=r + 2,
            column="time_s",
        )


#: Longest period of a command file's samples: a CNC's interpolator samples every 0.25 to
#: 20 ms; a time column in ms or us, read as seconds, gives 1 s and more (a circle of
#: 8 s became 2 h of machine time, simulated without a word) [s].
MAX_PERIOD_S = 0.1


def read_command_csv(path) -> Command:
    """Read a command file.

    Parameters
    ----------
    path : str or Path
        The CSV file [-].

    Returns
    -------
    Command
        Positions in metres on a uniform time base [-].

    Raises
    ------
    InputError
        If the file is missing, the header is not ``time_s, x_mm, y_mm[, z_mm]``, a value
        is not a finite number, or the time is not strictly increasing and uniform; the
        message names the file, line and column.
    """
    path = Path(path)
    text = read_text(path, "command file")
    lines = file_lines(text)
    while lines and not lines[-1].strip():
        lines.pop()
    if not lines:
        raise InputError(f"the command file is empty; expected the header {_LAYOUT}", file=path)
    names = _header(lines[0], path)
    rows = lines[1:]
    if len(rows) < 2:
        raise InputError(
            "a command file needs at least two rows of samples", file=path, line=len(lines) + 1
        )
    data = _numbers(rows, names, path)
    t = data[:, 0]
    _check_uniform_time(t, path)
    if t[1] - t[0] > MAX_PERIOD_S:
        raise InputError(f"the samples are {t[1] - t[0]:g} s apart, where an interpolator "
                         f"samples its command every few ms (at most {MAX_PERIOD_S:g} s): is "
                         "time_s in milliseconds or microseconds? Write seconds",
                         file=path, line=3, column="time_s")
    positions = {_AXIS_COLUMNS[n]: data[:, k] * 1e-3 for k, n in enumerate(names)
                 if n in _AXIS_COLUMNS}
    order = [a for a in ("X", "Y", "Z") if a in positions]
    blocks = {n: data[:, k].astype(np.int32 if n == "nc_line" else np.int8)
              for k, n in enumerate(names) if n in BLOCK_COLUMNS}
    return Command(
        time_s=t,
        positions={a: positions[a] for a in order},
        meta={"source": "command file", "file": str(path), **blocks},
    )


def write_command_csv(command: Command, path) -> None:
    """Write a command file atomically (temporary file, then rename).

    Parameters
    ----------
    command : Command
        Must have axes X and Y, optionally Z; a program's command
        (``meta["nc_line"]`` and ``meta["rapid"]``) writes its blocks too [-].
    path : str or Path
        The CSV file; its folder is created if needed [-].
    """
    axes = [a for a in ("X", "Y", "Z") if a in command.positions]
    extra = [a for a in command.positions if a not in ("X", "Y", "Z")]
    if extra or "X" not in axes or "Y" not in axes:
        raise InputError(
            f"a command file holds axes X, Y and optionally Z; this command has "
            f"{', '.join(command.positions)}"
        )
    blocks = list(command.blocks() or ())
    table = np.column_stack([command.time_s] + [command.positions[a] * 1e3 for a in axes]
                            + blocks)
    header = ",".join(["time_s"] + [f"{a.lower()}_mm" for a in axes]
                      + list(BLOCK_COLUMNS)[:len(blocks)])
    fmt = ["%.12f"] + ["%.9f"] * len(axes) + ["%d"] * len(blocks)
    with atomic_path(path) as tmp, open(tmp, "w", encoding="utf-8", newline="\n") as fh:
        np.savetxt(fh, table, fmt=fmt, delimiter=",", header=header, comments="")


@contextlib.contextmanager
def command_csv_writer(path, blocks: bool = False):
    """Write a command that comes in pieces as a command file, atomically: the pieces'
    X, Y and Z go to a temporary file beside ``path``, Z is dropped at the end where the
    command does not move it, and the file is renamed onto ``path``; removed where the
    work fails or is interrupted. The text is that of :func:`write_command_csv`.

    Parameters
    ----------
    path : str or Path
        The CSV file [-].
    blocks : bool
        Write the columns ``nc_line`` and ``rapid`` too [-].

    Yields
    ------
    writer : _PieceWriter
        ``writer.write(time_s, positions, blocks)`` appends a piece (``positions`` of X,
        Y, Z [m], times [s], and where written ``blocks``, the lines and rapid flags
        [-]); ``writer.axes`` is set to the axes kept before the block ends [-].
    """
    with atomic_path(path) as tmp:
        w = _PieceWriter(tmp, blocks)
        try:
            yield w
        finally:
            w.fh.close()
        if "Z" not in w.axes:
            _drop_z(tmp)


class _PieceWriter:
    """The rows of a command file, X, Y and Z, a piece at a time."""

    def __init__(self, tmp: Path, blocks: bool):
        self.fh = open(tmp, "w", encoding="utf-8", newline="\n")
        self.blocks = len(BLOCK_COLUMNS) if blocks else 0
        self.fh.write(",".join(["time_s", "x_mm", "y_mm", "z_mm",
                                *BLOCK_COLUMNS[:self.blocks]]) + "\n")
        self.axes = ("X", "Y", "Z")
        self.samples = 0
        # np.savetxt's text, formatted here: it makes a class of its own at every call,
        # garbage in a reference cycle that the start-up's lazy collector keeps for long
        # (3 KB a piece of one block)
        self.row = ",".join(["%.12f"] + ["%.9f"] * 3 + ["%d"] * self.blocks) + "\n"

    def write(self, time_s, positions, blocks=()) -> None:
        table = np.column_stack([time_s] + [positions[a] * 1e3 for a in ("X", "Y", "Z")]
                                + list(blocks)[:self.blocks])
        for k in range(0, table.shape[0], CSV_BLOCK_ROWS):  # a block's text at a time
            block = table[k:k + CSV_BLOCK_ROWS]
            self.fh.write((self.row * block.shape[0]) % tuple(block.ravel().tolist()))
        self.samples += table.shape[0]


def _without_z(line: str) -> str:
    """A row of X, Y, Z and perhaps more without its fourth field, Z [-]."""
    i = line.index(",", line.index(",", line.index(",") + 1) + 1)
    j = line.find(",", i + 1)
    return line[:i] + (line[j:] if j >= 0 else "\n")


def _drop_z(path: Path) -> None:
    """Remove the column z_mm (the fourth) of a CSV file, line by line (bounded
    memory)."""
    fd, short = tempfile.mkstemp(prefix=f".{path.name}.", dir=path.parent)
    try:
        with open(path, encoding="utf-8") as src, os.fdopen(fd, "w", encoding="utf-8",
                                                            newline="\n") as dst:
            dst.writelines(map(_without_z, src))
        os.replace(short, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(short)
        raise
