"""The same BLAS kernels on every x86-64 CPU.

The OpenBLAS of numpy's and scipy's wheels picks its kernels by the CPU it loads on:
Haswell's (AVX2) on an AMD EPYC, SkylakeX's (AVX-512) on an Intel Xeon. They sum in
different orders, so a least-squares fit rounds differently on the two: the models that
identification wrote from one bundle differed in their last bits, and the figures after
them with those bits. Naming the core type before OpenBLAS loads (``OPENBLAS_CORETYPE``)
has every CPU with AVX2 and FMA (both makers' since 2015) run Haswell's kernels; MKL,
where numpy was built with it, is held to its AVX2 path likewise (``MKL_CBWR``). A value
the user set is kept. Where numpy is loaded before tcpmm, or on a CPU without AVX2 or
whose flags cannot be read (outside Linux), BLAS runs as it chose; the figures may then
differ from another CPU's in their last bits.
"""

from __future__ import annotations

import os
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
    for name, value in VARIABLES.items():
        os.environ.setdefault(name, value)
    return True


def describe() -> str:
    """Which BLAS kernels this process runs, in words (``tcpmm --version``) [-]."""
    core = os.environ.get("OPENBLAS_CORETYPE", "")
    if _NOT_NAMED:
        return (f"as OpenBLAS chose for this CPU ({_NOT_NAMED[0]}): figures may differ "
                "from another CPU's in their last digits")
    if core != CORE:
        return f"OpenBLAS's {core} kernels, as OPENBLAS_CORETYPE says"
    return f"OpenBLAS's {CORE} kernels, the same on every CPU with AVX2 and FMA"
