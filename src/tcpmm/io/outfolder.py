"""The outputs' places: checked before a command's work, and the error of one that cannot
be written, naming it and what to do."""

from __future__ import annotations

import contextlib
import errno
import os
import tempfile
from pathlib import Path

from ..errors import InputError


def check_output_folder(path, output=None) -> Path:
    """Check that the folder ``path`` is or can be made an output folder, creating nothing.

    A command checks its outputs before any work and creates their folders only when it
    writes into them: one that fails on its input leaves no empty folder behind.

    Parameters
    ----------
    path : str or Path
        Folder [-].
    output : str or Path, optional
        The output file to go there, which an error names; default the folder [-].

    Returns
    -------
    Path
        The folder [-].
    """
    path = no_file_above(path)
    base = next((p for p in (path, *path.parents) if p.exists()), Path("."))
    if not os.access(base, os.W_OK | os.X_OK):
        what = ("nothing can be written there" if base == path else
                f"so the output folder {path} cannot be made there")
        raise InputError(f"cannot write into {base}, {what}; choose a folder you can "
                         "write to", file=output or path)
    # a read-only mount, a full disk or /proc, which the mode bits do not show
    probe_writable(base, output or path)
    return path


def no_file_above(path) -> Path:
    """``path`` as a Path, refused where it or one of its parents is a file [-]."""
    path = Path(path)
    for p in (path, *path.parents):
        if p.exists() and not p.is_dir():
            raise InputError(f"is a file, so the output folder {path} cannot be made; "
                             "choose another folder", file=p)
    return path


def make_folder(path: Path) -> Path:
    """Create the folder ``path`` and its parents [-]."""
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"cannot create the output folder: {exc.strerror}", file=path) from None
    return path


def output_folder(path) -> Path:
    """Create the folder ``path`` (and its parents) for outputs; refuse what cannot be one.

    Parameters
    ----------
    path : str or Path
        Folder [-].

    Returns
    -------
    Path
        The folder [-].
    """
    # the check probed the nearest folder that exists, on the same disk as the new ones
    return make_folder(check_output_folder(path))


def probe_writable(folder, output=None) -> None:
    """Refuse a folder no file can be made in, before the work whose outputs go there
    rather than after it (a read-only folder, a full disk).

    Parameters
    ----------
    folder : str or Path
        An existing folder [-].
    output : str or Path, optional
        The output to go there, which an error names; default the folder [-].
    """
    try:
        fd, tmp = tempfile.mkstemp(prefix=".tcpmm-probe.", dir=folder)
    except OSError as exc:
        raise cannot_write(exc, Path(output or folder), made_in=Path(folder)) from None
    os.close(fd)
    with contextlib.suppress(OSError):
        os.unlink(tmp)


def output_file(path) -> Path:
    """The file an output goes to: ``path``, or the target of a symbolic link there.

    Its folder is checked, not created (:func:`atomic_path` creates it when writing); a
    folder at ``path`` or a file among its parents is an error.

    Parameters
    ----------
    path : str or Path
        Output file [-].

    Returns
    -------
    Path
        The file to replace [-].
    """
    path = file_target(path)
    check_output_folder(path.parent, path)
    return path


def file_target(path) -> Path:
    """The file ``path`` names (a symbolic link's target), refused where it is no file
    name, a folder, or a file the user may not write [-]."""
    path = Path(path)
    if str(path) in ("", "."):
        raise InputError("the output needs a file name")
    if path.is_symlink():  # a link to a pipe (/dev/stdout) names no file: kept as it is
        real = Path(os.path.realpath(path))
        path = real if real.exists() or not path.exists() else path
    if path.is_dir():
        raise InputError("is a folder; give the output a file name", file=path)
    # the file is replaced by a rename, which only the folder's mode allows or forbids:
    # a file made read-only (a measured run kept safe) is refused as the shell refuses it
    if path.is_file() and not os.access(path, os.W_OK):
        raise InputError("cannot write the output: the file is read-only; nothing was "
                         f"written: make it writable (chmod u+w {path.name}) or choose "
                         "another output", file=path)
    return path


def new_file_mode() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


def cannot_write(exc: OSError, path: Path, made_in: Path | None = None) -> InputError:
    """The error of an output that cannot be written, with what to do; nothing of it is
    left behind and an earlier file of that name is unchanged. ``made_in`` is the folder
    in which a new file could not be made, where that was the failure."""
    if made_in is not None and exc.errno == errno.ENOENT and made_in.is_dir():
        # "No such file or directory" of a folder that is there: one of the kernel's
        # (/proc), which makes no new files
        return InputError(f"cannot write the output: the folder {made_in} cannot hold new "
                          "files; nothing was written: choose another folder", file=path)
    why = exc.strerror or str(exc)
    if exc.errno in (errno.ENOSPC, errno.EDQUOT):
        fix = "free space on that disk or choose another folder"
    elif exc.errno in (errno.EACCES, errno.EPERM, errno.EROFS):
        fix = "choose a folder you can write to"
    else:
        fix = "choose another output"
    return InputError(f"cannot write the output ({why}); nothing was written: {fix}",
                      file=path)
