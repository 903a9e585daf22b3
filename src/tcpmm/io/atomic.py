"""Write files so that a reader never sees half an output: temp file, then rename."""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path


@contextlib.contextmanager
def atomic_path(path, suffix: str = ""):
    """Yield a temporary path beside ``path``; rename it onto ``path`` on success.

    Parameters
    ----------
    path : str or Path
        Final destination [-].
    suffix : str
        Suffix of the temporary file (some writers infer the format from it) [-].
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(
        prefix=f".{path.name}.", suffix=suffix or path.suffix, dir=path.parent
    )
    os.close(fd)
    try:
        yield Path(tmp)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def write_text_atomic(path, text: str) -> None:
    """Write text to ``path`` atomically."""
    with atomic_path(path) as tmp, open(tmp, "w", encoding="utf-8", newline="\n") as fh:
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
        printf format of the numbers [-].

    Returns
    -------
    Path
        The file written.
    """
    with atomic_path(path) as tmp, open(tmp, "w", encoding="utf-8", newline="") as fh:
        frame.to_csv(fh, index=False, float_format=float_format, lineterminator="\n")
    return Path(path)
