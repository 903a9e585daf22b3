"""The same BLAS kernels on every x86-64 CPU (tcpmm._blas_kernels): OpenBLAS chose
Haswell's kernels on an AMD EPYC and SkylakeX's on an Intel Xeon, which sum in other
orders, and the models identified from one bundle differed in their last bits between
the two (docs/validation/same_bits.md). Loaded after tcpmm, on any CPU with AVX2 and FMA,
it runs Haswell's, in the command line's processes and in this one; a core type the user
names is kept."""

import os
import subprocess
import sys

import pytest

from tcpmm._blas_kernels import CORE, cpu_flags

pytestmark = pytest.mark.skipif(not {"avx2", "fma"} <= cpu_flags(),
                                reason="a CPU without AVX2 and FMA runs the kernels it chose")

PROBE = ("import tcpmm, numpy, scipy.linalg; from threadpoolctl import threadpool_info; "
         "print(sorted({i['architecture'] for i in threadpool_info() "
         "if i['internal_api'] == 'openblas'}))")


def _architectures(**env) -> str:
    clean = {k: v for k, v in os.environ.items() if k not in ("OPENBLAS_CORETYPE", "MKL_CBWR")}
    out = subprocess.run([sys.executable, "-c", PROBE], env={**clean, **env},
                         capture_output=True, text=True, check=True)
    return out.stdout.strip()


def test_openblas_runs_the_same_kernels_whatever_the_cpu():
    assert _architectures() == f"['{CORE}']"


def test_a_core_type_the_user_names_is_kept():
    assert _architectures(OPENBLAS_CORETYPE="Sandybridge") == "['Sandybridge']"


def test_the_version_says_which_kernels_run():
    """``tcpmm --version`` says which BLAS kernels run, and where they were not named,
    why and what that means for the figures."""
    clean = {k: v for k, v in os.environ.items() if k not in ("OPENBLAS_CORETYPE", "MKL_CBWR")}
    said = {}
    for name, code in (("named", "import tcpmm"), ("late", "import numpy, tcpmm")):
        out = subprocess.run([sys.executable, "-c", code + "; from tcpmm._blas_kernels "
                              "import describe; print(describe())"], env=clean,
                             capture_output=True, text=True, check=True)
        said[name] = out.stdout.strip()
    assert said["named"] == f"OpenBLAS's {CORE} kernels, the same on every CPU with AVX2 and FMA"
    assert said["late"].startswith("as OpenBLAS chose for this CPU (numpy was loaded before")


def test_the_tests_run_the_same_kernels():
    from threadpoolctl import threadpool_info

    found = {i["architecture"] for i in threadpool_info() if i["internal_api"] == "openblas"}
    assert found == {os.environ.get("OPENBLAS_CORETYPE", CORE)}
