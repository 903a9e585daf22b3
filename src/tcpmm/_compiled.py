"""The compiled functions of :data:`FUNCTIONS` (the axis kernel, the matrix exponential,
the interpolator's, the G-code lexer's, the contour's nearest-segment search and corner
figures) built ahead of time, so that a command starts without numba.

numba compiles them on their first call and caches the machine code, but loading a
cached function costs its import and the set-up of its compiler (0.5 s and more of every
command that simulates or measures a contour). The first run on a machine therefore also
builds them, from the same source, into a Python extension module (numba's ``pycc``, for
this CPU, each releasing the GIL); later runs import it in about a millisecond and never
import numba. It gives the same numbers to the bit: the same code compiled by the same compiler.

The module is kept beside numba's cache (the package's ``__pycache__``, else the
user's cache folder, else ``NUMBA_CACHE_DIR``) under a name keyed on the sources,
numba's and Python's versions and the CPU, so an edit, an upgrade or another machine
builds a new one; one in the package's ``__pycache__`` is used whether that can be
written or not (an install its users cannot write). The build needs a C compiler; where
it fails, the reason is kept beside it for a day (:func:`describe` says it, and
``tcpmm --version``) and the functions run through numba as before.
``TCPMM_COMPILED=0`` in the environment uses numba's always.

It sits at the foot of the package: the packages whose functions it compiles call them
through it, and it imports none of them (numba's entry points are imported by name when
called, the sources read as files), so that it adds no import between them.
"""

from __future__ import annotations

import hashlib
import importlib.machinery
import importlib.util
import logging
import os
import sys
import threading
import time
import warnings
from contextlib import contextmanager
from pathlib import Path

from ._compiled_table import FUNCTIONS, KERNEL_SOURCES
from ._numba_cache import writable
from ._pycc import build_apart, prune_builds
from .errors import BuildNotice

#: A failed build is not tried again for this long [s]; a build lock older than
#: :data:`LOCK_STALE_S` is taken to be left by a process that died [s].
RETRY_AFTER_S = 86400.0
LOCK_STALE_S = 900.0
#: Builds for other sources, numba, Python or CPUs kept beside a new one (the most
#: recently used; a folder shared by machines of several CPUs keeps one each); older
#: ones are deleted when a new one is built.
KEEP_OTHER_BUILDS = 4
_PKG = Path(__file__).resolve().parent
_LOG = logging.getLogger(__name__)
_LOCK = threading.Lock()
_chosen: list = []  # [module or None, description] once chosen
_SPECS: dict = {}  # kinds -> :func:`_spec`, once numpy is imported
_NUMBA = "numba's kernels"
_OFF = _NUMBA + " (TCPMM_COMPILED=0)"


def call(name: str, *args):
    """Function ``name`` of :data:`FUNCTIONS` from the module compiled ahead of time where
    there is one (built on the first call where there is none) and the arguments are of
    the kinds it was built for, else numba's; the same arguments and results [SI].

    A strided array is given to either as a contiguous copy, written back after the call
    where it may be an output: the compiled module would read it as contiguous, and numba
    would compile the function anew for that layout (about two minutes for the kernel)."""
    import numpy as np

    strided = [i for i, a in enumerate(args)
               if type(a) is np.ndarray and not a.flags.c_contiguous]
    given = args
    if strided:
        args = tuple(np.ascontiguousarray(a) if i in strided else a
                     for i, a in enumerate(args))
    mod = (_chosen or _choose())[0]
    if mod is not None and _fits(FUNCTIONS[name][3], args):
        out = getattr(mod, name)(*args)
    else:
        module, entry = FUNCTIONS[name][:2]
        out = getattr(importlib.import_module(f"tcpmm.{module}"), entry)(*args)
    for i in strided:
        if given[i].flags.writeable:
            given[i][...] = args[i]
    return out


def run_axis(*args):
    """:func:`tcpmm.sim.kernel.run_axis` through :func:`call` [SI]."""
    return call("run_axis", *args)


def lookahead(*args):
    """:func:`tcpmm.path.lookahead.lookahead` through :func:`call` [SI]."""
    return call("lookahead", *args)


def backward(*args):
    """:func:`tcpmm.path.lookahead.backward` through :func:`call` [SI]."""
    return call("backward", *args)


def segment_profiles(*args):
    """:func:`tcpmm.path.profile.segment_profiles` through :func:`call` [SI]."""
    return call("segment_profiles", *args)


def timeline(*args):
    """:func:`tcpmm.path.sampling.timeline` through :func:`call` [SI]."""
    return call("timeline", *args)


def sample(*args):
    """:func:`tcpmm.path.sampling.sample` through :func:`call` [SI]."""
    return call("sample", *args)


def scan_lines(*args):
    """:func:`tcpmm.path.gcode_scan.scan_lines` through :func:`call` [-]."""
    return call("scan_lines", *args)


def run_plain(*args):
    """:func:`tcpmm.path.gcode_scan.run_plain` through :func:`call` [SI]."""
    return call("run_plain", *args)


def arc_ends(*args):
    """:func:`tcpmm.path.gcode_arcscan.arc_ends` through :func:`call` [SI]."""
    return call("arc_ends", *args)


def arc_centres(*args):
    """:func:`tcpmm.path.gcode_arcscan.arc_centres` through :func:`call` [-]."""
    return call("arc_centres", *args)


def nearest_segments(*args):
    """:func:`tcpmm.path.nearest.nearest_segments` through :func:`call` [m], [-]."""
    return call("nearest_segments", *args)


def search_blocks(*args):
    """:func:`tcpmm.path.nearest.search_blocks` through :func:`call` [m], [-]."""
    return call("search_blocks", *args)


def nearest_segments_in(*args):
    """:func:`tcpmm.path.nearest.nearest_segments_in` through :func:`call` [m], [-]."""
    return call("nearest_segments_in", *args)


def hessenberg_response(*args):
    """:func:`tcpmm.sim.hessenberg.hessenberg_response` through :func:`call` [-]."""
    return call("hessenberg_response", *args)


def expm(A):
    """The matrix exponential ``exp(A)`` (:func:`tcpmm.sim.expm.expm`, compiled like
    :func:`run_axis`).

    Parameters
    ----------
    A : array_like (n, n)
        A real square matrix, finite [-].

    Returns
    -------
    ndarray (n, n)
        ``exp(A)`` [-].
    """
    import numpy as np

    A = np.ascontiguousarray(A, dtype=np.float64)
    if A.ndim != 2 or A.shape[0] != A.shape[1]:
        raise ValueError(f"expm needs a square matrix, not one of shape {A.shape}")
    if not np.all(np.isfinite(A)):
        raise ValueError("expm needs a finite matrix")
    return call("expm", A)


def status() -> str:
    """Which kernel this process runs, and why (after its first run, else chooses now)."""
    return (_chosen or _choose())[1]


def describe() -> str:
    """Which kernel a command would run, without building anything [-]."""
    if _chosen:
        return _chosen[1]
    if _switched_off():
        return _OFF
    try:
        path = module_path()
        if path.exists():
            return f"compiled module {path}"
        failure = _recent_failure(path)
        if failure:
            return f"{_NUMBA} ({failure})"
    except OSError as exc:
        return f"{_NUMBA} (no place for the compiled module: {exc})"
    return f"{_NUMBA} until the first run builds the compiled module {path}"


def _choose():
    with _LOCK:
        if not _chosen:
            _chosen.extend(_compiled_or_jit())
        return _chosen


def _compiled_or_jit():
    """``(module, description)``: the compiled module, or ``None`` (numba's kernels) and
    why."""
    if _switched_off():
        return None, _OFF
    try:
        path = module_path()
        if not path.exists():
            reason = _build_once(path)
            if reason:
                return None, f"{_NUMBA} ({reason})"
        mod = _import(path)
    except Exception as exc:  # a tool chain can fail in many ways; the kernel still runs
        _LOG.debug("compiled kernel not used", exc_info=True)
        return None, f"{_NUMBA} (the compiled module failed: {type(exc).__name__}: {exc})"
    return mod, f"compiled module {path}"


def _fits(kinds, args) -> bool:
    """Whether ``args`` are of the ``kinds`` a function was built for: the module's
    wrappers check types and dimensions; the memory layout is :func:`call`'s (it gives
    contiguous arrays only: a wrapper would read a strided one as if it were contiguous)."""
    import numpy as np

    if len(args) != len(kinds):
        return False
    spec = _SPECS.get(kinds) or _SPECS.setdefault(kinds, _spec(kinds))
    for a, (ndim, want) in zip(args, spec, strict=True):
        if ndim:
            if type(a) is not np.ndarray or a.ndim != ndim or a.dtype != want:
                return False
        elif isinstance(a, (bool, np.bool_)) or not isinstance(a, want):
            return False
    return True


def _spec(kinds) -> list:
    """Per kind: dimensions and dtype of an array, or 0 and the types a number may be."""
    import numpy as np

    number = {"i": (int, np.integer), "f": (int, float, np.integer, np.floating)}
    dtype = {"i": np.dtype(np.int64), "u": np.dtype(np.uint8), "f": np.dtype(np.float64)}
    return [(int(k[1]), dtype[k[0]]) if len(k) == 2 else (0, number[k]) for k in kinds]


def module_path() -> Path:
    """Where the compiled module for this kernel, numba, Python and CPU is kept: the
    package's ``__pycache__`` where it holds one, writable or not (an install the user
    cannot write, built by whoever could), else where one is built [-]."""
    name = f"_kernels_{_key()}" + importlib.machinery.EXTENSION_SUFFIXES[0]
    built = _package_cache() / name
    return built if built.is_file() else _folder() / name


def _package_cache() -> Path:
    """The package's ``__pycache__`` [-]."""
    return _PKG / "__pycache__"


def _folder() -> Path:
    """Where a module is built: ``NUMBA_CACHE_DIR``, else the package's ``__pycache__``
    where it is writable, else the user's cache folder [-]."""
    env = os.environ.get("NUMBA_CACHE_DIR")
    if env:
        return Path(env) / "tcpmm-compiled"
    here = _package_cache()
    if writable(here):
        return here
    home = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(home) / "tcpmm" / "compiled"


def _key() -> str:
    """Hash of the kernel's sources, numba's, llvmlite's and Python's versions and the
    CPU (which the module is compiled for)."""
    h = hashlib.sha256()
    for rel in KERNEL_SOURCES:
        h.update((_PKG / rel).read_bytes())
    for package in ("numba", "llvmlite"):
        h.update((Path(importlib.util.find_spec(package).origin).parent
                  / "_version.py").read_bytes())
    h.update(f"{sys.version}|{_cpu()}".encode())
    return h.hexdigest()[:20]


def _cpu() -> str:
    """The CPU: model and instruction-set flags from ``/proc/cpuinfo`` where there is one
    (a millisecond), else the name and features LLVM finds (loading LLVM, 50 ms)."""
    try:
        with open("/proc/cpuinfo", encoding="utf-8", errors="replace") as f:
            first = f.read().split("\n\n", 1)[0]
    except OSError:
        first = ""
    wanted = ("vendor_id", "model name", "cpu family", "model", "flags", "features",
              "cpu implementer", "cpu part", "isa")
    lines = sorted(ln.strip() for ln in first.splitlines()
                   if ln.split(":", 1)[0].strip().lower() in wanted)
    if any(ln.lower().startswith(("flags", "features", "isa")) for ln in lines):
        return "\n".join(lines)
    import llvmlite.binding as ll

    return f"{ll.get_host_cpu_name()}|{ll.get_host_cpu_features().flatten()}"


def _import(path: Path):
    name = path.name.split(".")[0]
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _build_once(path: Path) -> str:
    """Build the module unless a build failed lately or runs in another process; returns
    why the module is not there, or ``""`` once it is."""
    failure = _recent_failure(path)
    if failure:
        return failure
    path.parent.mkdir(parents=True, exist_ok=True)
    with _build_lock(path.with_suffix(".lock")) as mine:
        if not mine:
            return "the compiled module is being built by another process"
        if path.exists():
            return ""
        warnings.warn(BuildNotice("compiling the simulation kernel for this CPU: once after "
                                  "an install or an upgrade, a few minutes"), stacklevel=2)
        try:
            build(path)
        except Exception as exc:  # no C compiler, a full disk, ...
            _LOG.debug("building the compiled kernel failed", exc_info=True)
            path.with_suffix(".failed").write_text(f"{type(exc).__name__}: {exc}\n")
            return _recent_failure(path)
        prune_builds(path, KEEP_OTHER_BUILDS)
    return ""


def _recent_failure(path: Path) -> str:
    """Why the build of the module ``path`` failed, where it failed less than
    :data:`RETRY_AFTER_S` ago (kept beside it); else ``""``."""
    failed = path.with_suffix(".failed")
    if not (failed.exists() and time.time() - failed.stat().st_mtime < RETRY_AFTER_S):
        return ""
    return (f"its build failed: {failed.read_text().strip()}; it is tried again a day "
            f"later, or at once after deleting {failed}")


def _switched_off() -> bool:
    """Whether ``TCPMM_COMPILED=0`` asks for numba's kernels always [-]."""
    return os.environ.get("TCPMM_COMPILED", "1").strip() == "0"


@contextmanager
def _build_lock(lock: Path):
    """Hold ``lock`` (a file made exclusively) for the build; yields whether it was had."""
    try:
        if time.time() - lock.stat().st_mtime > LOCK_STALE_S:
            lock.unlink(missing_ok=True)
    except FileNotFoundError:
        pass
    try:
        os.close(os.open(lock, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o600))
    except FileExistsError:
        yield False
        return
    try:
        yield True
    finally:
        lock.unlink(missing_ok=True)


def build(path: Path) -> None:
    """Compile :data:`FUNCTIONS` into the extension module ``path``, in an interpreter of
    its own (:func:`tcpmm._pycc.build_apart`).

    Parameters
    ----------
    path : Path
        The module's file; its name up to the first dot is the module's name [-].
    """
    build_apart(path)
