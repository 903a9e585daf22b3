"""Write files so that a reader never sees half an output: temp file, then rename.

The file written keeps the permissions of the one it replaces (a new one gets those the
umask allows), and an output that is a symbolic link is written through to its target.
"""

from __future__ import annotations

import contextlib
import os
import re
import shutil
import stat
import tempfile
from pathlib import Path

from ..errors import InputError
from ._together import at_once, hold, together  # noqa: F401  (the API)
from ._together import held_back as _held_back
from .bytenames import HANDLER
from .outfolder import (  # noqa: F401  (the API)
    cannot_write,
    check_output_folder,
    file_target,
    make_folder,
    new_file_mode,
    no_file_above,
    output_file,
    output_folder,
    probe_writable,
)


@contextlib.contextmanager
def atomic_path(path, suffix: str = ""):
    """Yield a temporary path beside ``path``; rename it onto ``path`` on success, or,
    within :func:`together`, when every output of the command is written.

    Parameters
    ----------
    path : str or Path
        Final destination [-].
    suffix : str
        Suffix of the temporary file (some writers infer the format from it) [-].
    """
    # the temporary file made below is the test that the folder takes a file
    path = file_target(path)
    made = [p for p in (path.parent, *path.parent.parents) if not p.exists()]
    make_folder(no_file_above(path.parent))
    try:
        yield from _written(path, suffix, made)
    except BaseException:
        # a stream that fails part-way (a bad block of a program written as it is read)
        # leaves no empty folder of its output behind
        _remove_folders(made)
        raise


def _remove_folders(made) -> None:
    """Remove the folders ``made`` for an output, deepest first, where they are empty."""
    for folder in made:
        with contextlib.suppress(OSError):
            folder.rmdir()


def _temporary_name(suffix: str) -> dict:
    """``mkstemp``'s prefix and suffix of a temporary output: short, so that an output
    whose own name is as long as the file system allows can still be written [-]."""
    return {"prefix": ".tcpmm-", "suffix": suffix if len(suffix) <= 16 else ".tmp"}


def _written(path: Path, suffix: str, made=()):
    """:func:`atomic_path`'s temporary file in an existing folder, renamed on success."""
    # a device or a pipe (/dev/null, /dev/stdout, a FIFO) is written into, not replaced
    special = path.exists() and not path.is_file()
    mode = stat.S_IMODE(path.stat().st_mode) if path.exists() else new_file_mode()
    try:
        fd, tmp = tempfile.mkstemp(**_temporary_name(suffix or path.suffix),
                                   dir=None if special else path.parent)
    except OSError as exc:
        raise cannot_write(exc, path, made_in=None if special else path.parent) from None
    os.close(fd)
    try:
        yield Path(tmp)
        if not special:
            os.chmod(tmp, mode)
        # a device or a pipe is written into at once: writing is the step that fails there
        # (/dev/full), and held back it would fail after the command had said "wrote" it
        if _held_back(path) and not special:
            hold(path, lambda: _said(_put, path, tmp, path, special),
                 lambda: (_unlink(tmp), _remove_folders(made)))
        else:
            _put(tmp, path, special)
    except BaseException as exc:
        _unlink(tmp)
        if isinstance(exc, OSError):
            raise cannot_write(exc, path) from None
        raise


def _put(tmp: str, path: Path, special: bool) -> None:
    """The written temporary file ``tmp`` in its place ``path``."""
    if special:
        with open(tmp, "rb") as src, open(path, "wb") as dst:
            shutil.copyfileobj(src, dst)
        os.unlink(tmp)
    else:
        os.replace(tmp, path)


def _said(put, path: Path, *args) -> None:
    """``put(*args)``, its OSError as the error of the output ``path`` [-]."""
    try:
        put(*args)
    except OSError as exc:
        raise cannot_write(exc, path) from None


def _unlink(tmp) -> None:
    with contextlib.suppress(OSError):
        os.unlink(tmp)


@contextlib.contextmanager
def staged_folder(path):
    """Yield a temporary folder beside the output folder ``path``; on success move its
    files and subfolders into ``path``, on any failure (a full disk, a signal, an error
    of the work) remove it and the folders made for it, so that a report is there whole
    or not at all; an error names ``path``, not the temporary folder.

    Parameters
    ----------
    path : str or Path
        Output folder, created [-].
    """
    out = check_output_folder(path)
    made = [p for p in (out, *out.parents) if not p.exists()]
    make_folder(out.parent)
    try:
        tmp = Path(tempfile.mkdtemp(prefix=".tcpmm-", dir=out.parent))
    except OSError as exc:
        _remove_folders(made)
        raise cannot_write(exc, out, made_in=out.parent) from None
    remove = lambda: (shutil.rmtree(tmp, ignore_errors=True), _remove_folders(made))  # noqa: E731
    try:
        with at_once(tmp):
            yield tmp
        if _held_back(out):
            hold(out, lambda: _said(_moved, out, tmp, out), remove)
        else:
            _moved(tmp, out)
    except BaseException as exc:
        remove()
        named = _naming(exc, tmp, out)
        if named is exc:
            raise
        raise named from None


def _moved(tmp: Path, out: Path) -> None:
    """The staged folder ``tmp``'s content moved into ``out``, made where it is not."""
    out.mkdir(exist_ok=True)
    _move_into(tmp, out)
    shutil.rmtree(tmp, ignore_errors=True)


def _naming(exc: BaseException, tmp: Path, out: Path) -> BaseException:
    """The error of a staged folder's output as the user's folder ``out`` has it: a file
    of the temporary folder ``tmp`` named as ``out`` [-]."""
    if isinstance(exc, OSError):
        return cannot_write(exc, out)
    if isinstance(exc, InputError) and exc.file is not None:
        if Path(exc.file).is_relative_to(tmp):
            return InputError(exc.message, file=out, line=exc.line, column=exc.column)
    return exc


def _move_into(src: Path, dst: Path) -> None:
    """Every file of the folder ``src`` moved to its place in ``dst``: a subfolder that
    ``dst`` holds already (the identification's of an earlier demo, say) is merged file by
    file, as the files of ``dst`` are replaced, and not refused for not being empty."""
    for f in sorted(src.iterdir()):
        target = dst / f.name
        if f.is_dir() and not f.is_symlink() and target.is_dir() and not target.is_symlink():
            _move_into(f, target)
        else:
            os.replace(f, target)


def write_text_atomic(path, text: str) -> None:
    """Write text to ``path`` atomically."""
    with atomic_path(path) as tmp, open(tmp, "w", encoding="utf-8", errors=HANDLER,
                                             newline="\n") as fh:
        fh.write(text)


def write_table_atomic(frame, path, float_format: str | None = None) -> Path:
    """Write a pandas table as CSV to ``path`` atomically, without its index.

    Parameters
    ----------
    frame : pandas.DataFrame
        The table, in file units [-].
    path : str or Path
        Target file [-].
    float_format : str, optional
        printf format of the numbers; a fixed-point one (``%.4f``) writes a value that
        rounds to zero as zero, not ``-0.0000`` [-].

    Returns
    -------
    Path
        The file written.
    """
    m = re.fullmatch(r"%\.(\d+)f", float_format or "")
    if m:
        tiny = 0.5 * 10.0 ** -int(m.group(1))
        frame = frame.apply(lambda c: c.mask(c.abs() < tiny, 0.0)
                            if c.dtype.kind == "f" else c)
    with atomic_path(path) as tmp, open(tmp, "w", encoding="utf-8", errors=HANDLER,
                                             newline="") as fh:
        frame.to_csv(fh, index=False, float_format=float_format, lineterminator="\n")
    return Path(path)


#: Rows formatted at a time by :func:`write_columns_atomic` (bounds its memory) [-].
CSV_BLOCK_ROWS = 8192


def write_columns_atomic(path, columns, float_format: str = "%.15g") -> Path:
    """Write named numeric columns as CSV, atomically, without pandas.

    The text is the same as pandas ``to_csv(index=False, float_format=...)`` writes
    (missing values as empty cells); rows are formatted a block at a time, so that a long
    run does not hold its whole text in memory.

    Parameters
    ----------
    path : str or Path
        Target file [-].
    columns : mapping of str to array_like
        Column name to values, all of one length, in file units [-].
    float_format : str
        printf format of the numbers [-].

    Returns
    -------
    Path
        The file written.
    """
    import numpy as np

    names = list(columns)
    data = np.column_stack([np.asarray(columns[c], dtype=float) for c in names])
    row = ",".join([float_format] * data.shape[1]) + "\n"
    with atomic_path(path) as tmp, open(tmp, "w", encoding="utf-8", errors=HANDLER,
                                             newline="") as fh:
        fh.write(",".join(names) + "\n")
        for k in range(0, data.shape[0], CSV_BLOCK_ROWS):
            block = data[k:k + CSV_BLOCK_ROWS]
            if np.isnan(block).any():
                fh.writelines(",".join("" if v != v else float_format % v for v in r) + "\n"
                              for r in block.tolist())
            else:
                fh.write((row * block.shape[0]) % tuple(block.ravel().tolist()))
    return Path(path)
