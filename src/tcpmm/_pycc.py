"""The build of the compiled module of :mod:`tcpmm._compiled` with numba's ``pycc``, and
the compiler setting the axis kernel is compiled with wherever it is compiled.

Apart from :mod:`tcpmm._compiled`, so that choosing and calling the functions (every
command) reads none of the build (the first run on a machine, and after an edit).
"""

from __future__ import annotations

import importlib
import os
import threading
from contextlib import contextmanager
from pathlib import Path

_COMPILING = threading.Lock()


def build_module(path: Path, functions: dict) -> None:
    """Compile ``functions`` into the extension module ``path`` (written beside, then
    renamed: a reader never sees half a module).

    Parameters
    ----------
    path : Path
        The module's file; its name up to the first dot is the module's name [-].
    functions : dict
        name -> (module of tcpmm, numba's entry point, the function compiled, argument
        kinds, result kinds), as :data:`tcpmm._compiled.FUNCTIONS` [-].
    """
    import shutil
    import tempfile
    import warnings

    import numba

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # pycc is marked as pending deprecation
        import numba.pycc.compiler as pcc
        from numba.pycc import CC
    name = path.name.split(".")[0]
    tmp = tempfile.mkdtemp(prefix=f".{name}-", dir=path.parent)
    try:
        cc = CC(name)
        cc.output_dir, cc.target_cpu, cc.verbose = tmp, "host", False
        for fname, (module, _, source, kinds, result) in functions.items():
            fn = getattr(importlib.import_module(f"tcpmm.{module}"), source)
            sig = _numba_type(numba, result)(*(_numba_type(numba, k) for k in kinds))
            cc.export(fname, sig)(fn.py_func)
        with vectorised(), _releasing_the_gil(pcc):
            cc.compile()
        os.replace(Path(tmp) / cc.output_file, path)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def build_apart(path: Path) -> None:
    """:func:`build_module` of :data:`tcpmm._compiled_table.FUNCTIONS` into ``path`` in an
    interpreter of its own.

    The module is named by the hash of the sources on disk, and a fresh interpreter
    compiles those. A process that has run since before an upgrade holds the former
    modules in memory: built there, they would be filed under the new sources' name, and
    every later process would run the former kernel with the new code around it.

    Parameters
    ----------
    path : Path
        The module's file [-].
    """
    import subprocess
    import sys

    root = str(Path(__file__).resolve().parents[1])  # the tcpmm this process runs
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(
        p for p in (root, os.environ.get("PYTHONPATH", "")) if p)}
    code = ("import sys; from pathlib import Path; from tcpmm._pycc import build_module; "
            "from tcpmm._compiled_table import FUNCTIONS; "
            "build_module(Path(sys.argv[1]), FUNCTIONS)")
    done = subprocess.run([sys.executable, "-c", code, str(path)], env=env,
                          capture_output=True, text=True, check=False)
    if done.returncode != 0:
        said = done.stderr.strip().splitlines() or [f"exit status {done.returncode}"]
        raise OSError(f"the build stopped: {said[-1]}")


def _numba_type(numba, kind):
    """numba's type for a kind of :data:`tcpmm._compiled.FUNCTIONS`."""
    if isinstance(kind, tuple):
        return numba.types.Tuple(tuple(_numba_type(numba, k) for k in kind))
    scalar = {"i": numba.int64, "u": numba.uint8, "f": numba.float64}[kind[0]]
    return numba.types.Array(scalar, int(kind[1]), "C") if len(kind) == 2 else scalar


@contextmanager
def vectorised():
    """Compilations in this block with LLVM's SLP vectoriser on, one at a time in the
    process (numba's setting is global): the axis kernel's, when numba compiles it on its
    first call, and the build of the module here."""
    import numba

    with _COMPILING:
        before = numba.config.SLP_VECTORIZE
        numba.config.SLP_VECTORIZE = 1
        try:
            yield
        finally:
            numba.config.SLP_VECTORIZE = before


@contextmanager
def _releasing_the_gil(pcc):
    """pycc's compilation with wrappers that release the GIL (so that axes run in parallel
    threads)."""

    class Flags(pcc.Flags):
        def __init__(self, *args, **kwargs):
            super().__init__(*args, **kwargs)
            self.release_gil = True

    plain, pcc.Flags = pcc.Flags, Flags
    try:
        yield
    finally:
        pcc.Flags = plain


def prune_builds(path: Path, keep: int) -> None:
    """Delete the builds beside ``path`` other than it and the ``keep`` most recently used
    (modules and failure records; an upgrade or an edit leaves a module of about 1 MB
    each time). A module still loaded elsewhere stays usable where the system allows its
    deletion, and stays where it does not."""
    builds: dict[str, float] = {}
    mine = path.name.split(".")[0]
    for p in path.parent.glob("_kernels_*"):
        stem = p.name.split(".")[0]
        if stem != mine and p.suffix != ".lock" and p.is_file():
            st = p.stat()
            builds[stem] = max(builds.get(stem, 0.0), st.st_atime, st.st_mtime)
    old = sorted(builds, key=builds.get, reverse=True)[keep:]
    for p in path.parent.glob("_kernels_*"):
        if p.name.split(".")[0] in old and p.suffix != ".lock":
            try:
                p.unlink()
            except OSError:
                pass
