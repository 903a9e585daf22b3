"""A place for numba's compiled-function cache wherever the package is installed.

The compiled kernels are cached (``cache=True``) beside their sources, or else in the
user's cache folder. Where neither can be written (a read-only installation run by a user
without a writable home), numba refuses at import with "no locator available"; the cache
then goes to a folder of this user in the system's temporary directory, and
:data:`FALLBACK` says so for the command line to warn once. Where no temporary folder can
be written either (a read-only container), nothing is set: the compiled module needs no
cache, and a command that needs numba's kernels ends in :func:`no_cache_error`.
"""

from __future__ import annotations

import os
from pathlib import Path

#: Subpackages with functions cached by numba: each is cached in its own ``__pycache__``,
#: which may be read-only where the package folder is not.
CACHED_SUBPACKAGES = ("sim", "path", "mechanics")
#: The temporary cache folder chosen by :func:`ensure_cache_dir`, or ``None`` [-].
FALLBACK: list[str] = []
#: The folders tried where none could take the cache, else empty [-].
NO_CACHE: list[str] = []


def writable(folder: Path) -> bool:
    """Whether files can be made in ``folder``, or it can be created."""
    for p in (folder, *folder.parents):
        if p.exists():
            return p.is_dir() and os.access(p, os.W_OK | os.X_OK)
    return False


def ensure_cache_dir() -> str | None:
    """Set ``NUMBA_CACHE_DIR`` to a temporary folder when neither the package folder nor
    the user's cache folder can be written; returns the folder set, or ``None``."""
    if os.environ.get("NUMBA_CACHE_DIR"):
        return None
    pkg = Path(__file__).parent
    if all(writable(pkg / sub / "__pycache__") for sub in CACHED_SUBPACKAGES):
        return None
    home = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    if writable(Path(home)):
        return None
    import tempfile  # only here: 10 ms of every command's start

    uid = os.getuid() if hasattr(os, "getuid") else "user"
    try:
        folder = Path(tempfile.gettempdir()) / f"tcpmm-numba-cache-{uid}"
        folder.mkdir(mode=0o700, exist_ok=True)
    except OSError as exc:
        # no folder at all: the compiled module, read where it is, needs none, and only
        # numba's kernels, where they run, are refused (:func:`no_cache_error`)
        NO_CACHE[:] = [f"{pkg / '__pycache__'}, {home} and the temporary folders "
                       f"({exc.strerror or exc})"]
        return None
    FALLBACK[:] = [str(folder)]
    os.environ["NUMBA_CACHE_DIR"] = str(folder)
    import sys

    if "numba" in sys.modules:  # already read its configuration
        sys.modules["numba"].config.CACHE_DIR = str(folder)
    return str(folder)


def no_cache_error(exc: BaseException) -> str | None:
    """What to tell the user of ``exc`` where it is numba's refusal to compile a cached
    function for want of a folder to cache it in, else ``None`` [-]."""
    if not (NO_CACHE and isinstance(exc, RuntimeError) and "no locator" in str(exc)):
        return None
    return (f"the simulation kernel needs a folder to cache its compiled code in, and none "
            f"can be written: {NO_CACHE[0]}; set TMPDIR or NUMBA_CACHE_DIR to a folder "
            "you can write")
