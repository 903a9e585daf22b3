"""The same BLAS kernels and numpy loops on every x86-64 CPU.

The OpenBLAS of numpy's and scipy's wheels picks its kernels by the CPU it loads on:
Haswell's (AVX2) on an AMD EPYC, SkylakeX's (AVX-512) on an Intel Xeon. They sum in
different orders, so a least-squares fit rounds differently on the two: the models that
identification wrote from one bundle differed in their last bits, and the figures after
them with those bits. Naming the core type before OpenBLAS loads (``OPENBLAS_CORETYPE``)
has every CPU with AVX2 and FMA (both makers' since 2015) run Haswell's kernels; MKL,
where numpy was built with it, is held to its AVX2 path likewise (``MKL_CBWR``).

numpy picks its loops by the CPU as well: on a CPU with AVX-512 (Intel's server parts,
AMD's since Zen 4) its ``exp``, ``log``, ``power``, ``tan``, ``arctan`` and more run
AVX-512 code that rounds otherwise than its AVX2 code, which every other CPU with AVX2
runs. Its AVX-512 targets are therefore switched off before numpy loads
(``NPY_DISABLE_CPU_FEATURES``, with the names the installed numpy gives them).

A value the user set is kept. Where numpy is loaded before tcpmm, or on a CPU without AVX2
or whose flags cannot be read (outside Linux), BLAS and numpy run as they chose; the
figures may then differ from another CPU's in their last bits.
"""

from __future__ import annotations

import os
import re
import sys

#: The OpenBLAS core type every CPU with AVX2 and FMA runs [-].
CORE = "Haswell"
#: The variables named before BLAS loads, and their values [-].
VARIABLES = {"OPENBLAS_CORETYPE": CORE, "MKL_CBWR": "AVX2"}


def cpu_flags() -> set[str]:
    """The CPU's feature flags as Linux gives them (the first processor's), empty where
    they cannot be read [-]."""
    try:
        with open("/proc/cpuinfo", encoding="utf-8", errors="replace") as f:
            for line in f:
                if line.startswith("flags"):
                    return set(line.partition(":")[2].split())
    except OSError:
        pass
    return set()


#: Why the kernels were not named, where :func:`pin_blas_kernels` did not name them [-].
_NOT_NAMED: list[str] = []


def pin_blas_kernels() -> bool:
    """Name the BLAS kernels of :data:`VARIABLES` for the libraries to load, where numpy
    is not loaded yet and the CPU runs them; whether they are named [-]."""
    machine = os.uname().machine if hasattr(os, "uname") else ""
    flags = cpu_flags() if machine == "x86_64" and "numpy" not in sys.modules else set()
    why = ("numpy was loaded before tcpmm" if "numpy" in sys.modules else
           "not an x86-64 CPU" if machine != "x86_64" else
           "the CPU's flags cannot be read here" if not flags else
           "the CPU has no AVX2 and FMA" if not {"avx2", "fma"} <= flags else "")
    _NOT_NAMED[:] = [why] if why else []
    if why:
        return False
    for name, value in pinned_variables().items():
        if name == "NPY_DISABLE_CPU_FEATURES" and "NPY_ENABLE_CPU_FEATURES" in os.environ:
            continue  # numpy refuses the two together
        os.environ.setdefault(name, value)
    return True


def pinned_variables() -> dict[str, str]:
    """The variables :func:`pin_blas_kernels` names and their values: :data:`VARIABLES`
    and numpy's AVX-512 targets switched off, where the installed numpy's are known [-]."""
    targets = numpy_avx512_targets()
    return {**VARIABLES, **({"NPY_DISABLE_CPU_FEATURES": " ".join(targets)} if targets else {})}


def numpy_version(paths=None) -> tuple[int, ...]:
    """The version of the numpy that ``import numpy`` would load, read from its
    ``version.py`` without loading it; ``()`` where none is found [-]."""
    for folder in sys.path if paths is None else paths:
        try:
            with open(os.path.join(folder or ".", "numpy", "version.py"), encoding="utf-8") as f:
                text = f.read(4096)
        except OSError:
            continue
        found = re.search(r'^version\s*(?::\s*str\s*)?=\s*["\'](\d+)\.(\d+)', text, re.M)
        return tuple(map(int, found.groups())) if found else ()
    return ()


def numpy_avx512_targets(version: tuple[int, ...] | None = None) -> tuple[str, ...]:
    """numpy's AVX-512 dispatch targets by the names its ``version`` gives them (the
    installed numpy's where not given); ``()`` where it is not known [-]."""
    version = numpy_version() if version is None else version
    if not version:
        return ()
    if version >= (2, 4):  # the x86-64-v4 group and the two targets beyond it
        return ("X86_V4", "AVX512_ICL", "AVX512_SPR")
    older = ("AVX512F", "AVX512CD", "AVX512_KNL", "AVX512_KNM", "AVX512_SKX", "AVX512_CLX",
             "AVX512_CNL", "AVX512_ICL")
    return (*older, "AVX512_SPR") if version >= (2, 3) else older


def describe() -> str:
    """Which BLAS kernels this process runs, in words (``tcpmm --version``) [-]."""
    core = os.environ.get("OPENBLAS_CORETYPE", "")
    if _NOT_NAMED:
        return (f"as OpenBLAS chose for this CPU ({_NOT_NAMED[0]}): figures may differ "
                "from another CPU's in their last digits")
    if core != CORE:
        return f"OpenBLAS's {core} kernels, as OPENBLAS_CORETYPE says"
    return f"OpenBLAS's {CORE} kernels, the same on every CPU with AVX2 and FMA"


def describe_numpy() -> str:
    """Which of numpy's loops this process runs, in words (``tcpmm --version``) [-]."""
    import numpy as np

    dispatch, features = _numpy_cpu()
    off = [t for t in numpy_avx512_targets() if t in dispatch]
    if _NOT_NAMED or not off or any(features.get(t) for t in off):
        return (f"numpy {np.__version__}'s loops as it chose for this CPU: figures may "
                "differ from another CPU's in their last digits")
    return (f"numpy {np.__version__}'s loops without AVX-512, the same on every CPU with "
            "AVX2 and FMA")


def described() -> str:
    """The lines ``blas:`` and ``numpy:`` of ``tcpmm --version`` [-]."""
    return f"blas: {describe()}\nnumpy: {describe_numpy()}"


def kernels() -> tuple[tuple[str, ...], tuple[str, ...]]:
    """What this process runs: the loaded BLAS libraries with their kernels (``openblas
    Haswell``) and numpy's AVX-512 targets that its loops use (none where switched off);
    the two a Dask worker is compared by with the command's process [-]."""
    from threadpoolctl import threadpool_info

    features = _numpy_cpu()[1]
    blas = {f"{i.get('internal_api')} {i.get('architecture') or '?'}"
            for i in threadpool_info() if i.get("user_api") == "blas"}
    return (tuple(sorted(blas)),
            tuple(t for t in numpy_avx512_targets() if features.get(t)))


def _numpy_cpu() -> tuple:
    """numpy's dispatch targets and, by name, which of its CPU features it runs [-]."""
    try:
        from numpy._core._multiarray_umath import __cpu_dispatch__, __cpu_features__
    except ImportError:  # numpy before 2.0
        from numpy.core._multiarray_umath import __cpu_dispatch__, __cpu_features__
    return __cpu_dispatch__, __cpu_features__
