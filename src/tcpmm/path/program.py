"""From an NC program (file or text) to the position command."""

from __future__ import annotations

import os
from pathlib import Path

from .._validate import coordinates
from ..errors import InputError
from .command import Command
from .gcode_stream import parse_gcode
from .interpolate import Interpolation, interpolate_detailed
from .segments import Arc
from .settings import InterpolatorSettings

#: file name endings taken as NC programs when a string is given [-]
PROGRAM_SUFFIXES = (".nc", ".ngc", ".gcode", ".tap", ".cnc", ".txt", ".mpf", ".h")


def read_program(path) -> str:
    """Text of an NC program file.

    Parameters
    ----------
    path : str or Path
        The file [-].

    Returns
    -------
    str
        The program text [-].
    """
    path = Path(path)
    try:
        with open(path, "rb") as f:
            # the start judged before the rest is read: a device without end (--gcode
            # /dev/zero) would be read until the memory ran out
            head = f.read(4096)
            _check_text(path, head)
            data = head + f.read()
    except OSError as exc:
        raise _unreadable(path, exc) from None
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError:
        return data.decode("latin-1")  # controllers often write latin-1 comments


def check_program_file(path: Path) -> Path:
    """``path`` when it can be read as an NC program (as :func:`read_program` checks its
    start), else an :class:`~tcpmm.errors.InputError` [-]."""
    try:
        with open(path, "rb") as f:
            head = f.read(4096)
    except OSError as exc:
        raise _unreadable(path, exc) from None
    _check_text(path, head)
    return path


def _unreadable(path: Path, exc: OSError) -> InputError:
    if isinstance(exc, FileNotFoundError):
        return InputError("NC program not found; check the path", file=path)
    if isinstance(exc, IsADirectoryError):
        return InputError("is a folder, not an NC program; give the program's file",
                          file=path)
    return InputError(f"cannot read the NC program: {exc.strerror}", file=path)


def _check_text(path: Path, head: bytes) -> None:
    """Refuse a file whose first bytes ``head`` are UTF-16 or binary, or a table (a command
    file given as a program read "letter T has no number after it") [-]."""
    if head[:2] in (b"\xff\xfe", b"\xfe\xff") or b"\x00" in head:
        raise InputError(
            "the file is not plain text (UTF-16 or binary); save the program as ASCII or "
            "UTF-8 text",
            file=path,
        )
    first = head.split(b"\n", 1)[0].decode("latin-1").lower()
    if "," in first and "time_s" in first:  # G-code has no commas
        raise InputError("is a table (its first line names the columns of a command or run "
                         "file), not an NC program; a command file goes to --command",
                         file=path, line=1)


def is_path(x) -> bool:
    if isinstance(x, os.PathLike):
        return True
    if not isinstance(x, str) or "\n" in x or "\r" in x:
        return False
    return Path(x).suffix.lower() in PROGRAM_SUFFIXES or os.path.isfile(x)


def program_to_command(
    path_or_text, settings: InterpolatorSettings | None = None, start_position_m=(0.0, 0.0, 0.0)
) -> Command:
    """Interpret and interpolate an NC program.

    Parameters
    ----------
    path_or_text : str or Path
        A program file (a ``Path``, or a one-line string naming an existing file or
        ending in ``.nc``, ``.ngc``, ...) or the program text itself [-].
    settings : InterpolatorSettings, optional
        Interpolator settings; defaults when omitted [-].
    start_position_m : sequence of float
        Position of X, Y, Z before the program starts [m].

    Returns
    -------
    Command
        The position command; ``meta["file"]`` names the program file if any,
        ``meta["plane_axes"]`` is the plane of its first arc (G17 XY, G18 ZX, G19 YZ),
        ``None`` without arcs [-].
    """
    return program_to_interpolation(path_or_text, settings, start_position_m).command


def program_to_interpolation(
    path_or_text, settings: InterpolatorSettings | None = None, start_position_m=(0.0, 0.0, 0.0)
) -> Interpolation:
    """Interpret and interpolate an NC program, keeping the look-ahead's results.

    Parameters and the command's ``meta`` as for :func:`program_to_command` [-].

    Returns
    -------
    Interpolation
        The command and the look-ahead results (:func:`tcpmm.path.limits.feed_limits`
        says what holds the feed back) [-].
    """
    file = None
    if is_path(path_or_text):
        file = Path(path_or_text)
        text = read_program(file)
    elif isinstance(path_or_text, str):
        text = path_or_text
    else:
        raise InputError(
            f"expected an NC program file or its text, got {type(path_or_text).__name__}"
        )
    start_position_m = coordinates("start_position_m", start_position_m, 3)
    segments = parse_gcode(text, file, start_position_m=start_position_m)
    if not segments:
        raise InputError(
            "the program has no motion and no dwell; nothing to interpolate", file=file
        )
    try:
        result = interpolate_detailed(segments, settings)
    except InputError as exc:  # the interpolator knows the line, not the file
        raise exc.in_file(file) from None
    command = result.command
    command.meta["file"] = None if file is None else str(file)
    planes = [s.plane_axes for s in segments if isinstance(s, Arc)]
    command.meta["plane_axes"] = planes[0] if planes else None
    return result
