"""Reading text input files: UTF-8 (with or without a byte-order mark), or a named error."""

from __future__ import annotations

import codecs
from pathlib import Path

from ..errors import InputError


def existing_file(path, what: str, missing: str | None = None, hint: str | None = None) -> Path:
    """``path`` as a Path when it is a file; a folder or a missing file is an error.

    Parameters
    ----------
    path : str or Path
        The file [-].
    what : str
        What the file is, e.g. ``"command file"`` [-].
    missing : str, optional
        What a missing file is called, default ``what`` [-].
    hint : str, optional
        What to give instead, said where the file is missing [-].
    """
    path = Path(path)
    if path.is_dir():
        raise InputError(f"this is a directory; give the path of the {what}", file=path)
    if path.is_file() or path.is_fifo():  # a pipe: a shell's <(...), read once
        return path
    if path.exists():
        raise InputError(f"this is a device, not a file; give the path of the {what}",
                         file=path)
    raise InputError(f"{missing or what} not found" + (f"; {hint}" if hint else ""), file=path)


#: Files of other formats given as text: their first bytes, the format, its extension [-]
_BINARY = ((b"PAR1", "Parquet", ".parquet"), (b"MATLAB 5.0 MAT-file", "MATLAB", ".mat"),
           (b"MATLAB 7.3 MAT-file", "MATLAB", ".mat"), (b"TDSm", "TDMS", ".tdms"))


def read_text(path, what: str, hint: str | None = None) -> str:
    """The text of a UTF-8 file; a missing file, a folder or other bytes are errors.

    Parameters
    ----------
    path : str or Path
        The file [-].
    what : str
        What the file is, for messages, e.g. ``"command file"`` [-].
    hint : str, optional
        What to give instead, said where the file is missing [-].

    Returns
    -------
    str
        The text without a byte-order mark [-].
    """
    path = existing_file(path, what, hint=hint)
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise InputError(f"cannot read the {what}: {exc.strerror}", file=path) from None
    if data.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)):
        raise InputError(f"not a UTF-8 text file (it is UTF-16); save the {what} as "
                         "UTF-8 text", file=path, line=1)
    data = data.removeprefix(codecs.BOM_UTF8)
    for magic, kind, ext in _BINARY:
        if data.startswith(magic):
            rename = (f"; name it {path.stem}{ext} to read it as such"
                      if what == "run file" and ext == ".parquet" else
                      "; write it as a CSV or Parquet run file (time_s and <axis>_cmd_mm, "
                      "<axis>_tcp_mm ... in mm: docs/formats.md)" if what == "run file" else "")
            raise InputError(f"this is a {kind} file, not the UTF-8 text a {what} is{rename}",
                             file=path)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise InputError(f"not a UTF-8 text file (byte {data[exc.start]:#04x}); save the "
                         f"{what} as UTF-8 text", file=path,
                         line=data.count(b"\n", 0, exc.start) + 1) from None


def file_lines(text: str) -> list[str]:
    """The lines of a text file as an editor counts them: only ``\\n``, ``\\r\\n`` and
    ``\\r`` end a line. ``str.splitlines`` also ends one at a form feed, a vertical tab,
    ``\\x1c``-``\\x1e``, ``\\x85`` (an ellipsis of cp1252 read as latin-1), ``\\u2028``
    and ``\\u2029``, and then every message after one named the wrong line; a final line
    break ends the last line rather than starting an empty one.

    Parameters
    ----------
    text : str
        The file's text [-].

    Returns
    -------
    list of str
        The lines without their line breaks [-].
    """
    lines = text.replace("\r\n", "\n").replace("\r", "\n").split("\n")
    if lines and lines[-1] == "":
        lines.pop()
    return lines


def unquoted(name: str) -> str:
    """A header field without its blanks and the double quotes a spreadsheet or a logger
    puts around it (``"time_s"``), as a CSV reader takes it [-]."""
    name = name.strip()
    if len(name) >= 2 and name[0] == name[-1] == '"':
        name = name[1:-1].strip()
    return name


def separator_error(header: str, file) -> InputError | None:
    """The error for a CSV header whose columns are separated by semicolons or tabs, as a
    spreadsheet set to a decimal comma writes them; ``None`` for any other header. Every
    CSV reader asks this first: the header read as one column name would otherwise be
    refused as a wrong first column, naming no cause.

    Parameters
    ----------
    header : str
        The first line, without its line break [-].
    file : str or Path
        The file, for the message [-].
    """
    if "," in header or not (";" in header or "\t" in header):
        return None
    sep = "semicolons" if ";" in header else "tabs"
    return InputError(f"columns are separated by {sep}; use commas and a '.' decimal point",
                      file=file, line=1)


def fields_error(file, line: int, fields: int, header: int) -> InputError:
    """The error for a CSV row of more fields than the header has columns: most likely a
    decimal comma, which splits each number in two [-].

    Parameters
    ----------
    file : str or Path
        The file [-].
    line : int
        The row's line (the header is line 1) [-].
    fields, header : int
        Fields in the row, columns in the header [-].
    """
    return InputError(
        f"row has {fields} fields but the header has {header} (a decimal comma or a stray "
        "separator?); use ',' between fields and '.' as decimal point",
        file=file,
        line=line,
    )
