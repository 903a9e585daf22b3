"""A place for numba's compiled-function cache wherever the package is installed.

The compiled kernels are cached (``cache=True``) beside their sources, or else in the
user's cache folder. Where neither can be written (a read-only installation run by a user
without a writable home), numba refuses at import with "no locator available"; the cache
then goes to a folder of this user in the system's temporary directory, and
:data:`FALLBACK` says so for the command line to warn once.
"""

from __future__ import annotations

import os
from pathlib import Path

#: Subpackages with functions cached by numba: each is cached in its own ``__pycache__``,
#: which may be read-only where the package folder is not.
CACHED_SUBPACKAGES = ("sim", "path", "mechanics")
#: The temporary cache folder chosen by :func:`ensure_cache_dir`, or ``None`` [-].
FALLBACK: list[str] = []


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
    folder = Path(tempfile.gettempdir()) / f"tcpmm-numba-cache-{uid}"
    folder.mkdir(mode=0o700, exist_ok=True)
    FALLBACK[:] = [str(folder)]
    os.environ["NUMBA_CACHE_DIR"] = str(folder)
    import sys

    if "numba" in sys.modules:  # already read its configuration
        sys.modules["numba"].config.CACHE_DIR = str(folder)
    return str(folder)
