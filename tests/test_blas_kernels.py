"""The same BLAS kernels and numpy loops on every x86-64 CPU (tcpmm._blas_kernels):
OpenBLAS chose Haswell's kernels on an AMD EPYC and SkylakeX's on an Intel Xeon, which sum
in other orders, and numpy runs AVX-512 loops for exp, log, power and more on CPUs that
have it, which round otherwise than the AVX2 loops of every other CPU; the models
identified from one bundle differed in their last bits between such CPUs, and so did the
figures after them (docs/validation/same_bits.md). Loaded after tcpmm, on any CPU with
AVX2 and FMA, OpenBLAS runs Haswell's kernels and numpy its AVX2 loops, in the command
line's processes and in this one; a core type or a list of numpy's targets the user names
is kept."""

import os
import subprocess
import sys

import pytest

from tcpmm._blas_kernels import CORE, cpu_flags, numpy_avx512_targets, numpy_version

pytestmark = pytest.mark.skipif(not {"avx2", "fma"} <= cpu_flags(),
                                reason="a CPU without AVX2 and FMA runs the kernels it chose")

PROBE = ("import tcpmm, numpy, scipy.linalg; from threadpoolctl import threadpool_info; "
         "print(sorted({i['architecture'] for i in threadpool_info() "
         "if i['internal_api'] == 'openblas'}))")


NUMPY_PROBE = ("import os, tcpmm, numpy; from numpy._core._multiarray_umath import "
               "__cpu_features__ as f; print(os.environ.get('NPY_DISABLE_CPU_FEATURES')); "
               "print(sorted(k for k in {targets} if f.get(k)))")
#: the variables tcpmm sets, left out of the environment a probe starts from
SET = ("OPENBLAS_CORETYPE", "MKL_CBWR", "NPY_DISABLE_CPU_FEATURES", "NPY_ENABLE_CPU_FEATURES")


def _run(code: str, **env) -> str:
    clean = {k: v for k, v in os.environ.items() if k not in SET}
    out = subprocess.run([sys.executable, "-c", code], env={**clean, **env},
                         capture_output=True, text=True, check=True)
    return out.stdout.strip()


def _architectures(**env) -> str:
    return _run(PROBE, **env)


def _numpy(**env) -> list[str]:
    return _run(NUMPY_PROBE.format(targets=numpy_avx512_targets()), **env).splitlines()


def test_openblas_runs_the_same_kernels_whatever_the_cpu():
    assert _architectures() == f"['{CORE}']"


def test_a_core_type_the_user_names_is_kept():
    assert _architectures(OPENBLAS_CORETYPE="Sandybridge") == "['Sandybridge']"


def test_the_version_says_which_kernels_run():
    """``tcpmm --version`` says which BLAS kernels run, and where they were not named,
    why and what that means for the figures."""
    said = {name: _run(code + "; from tcpmm._blas_kernels import describe, describe_numpy; "
                             "print(describe()); print(describe_numpy())").splitlines()
            for name, code in (("named", "import tcpmm"), ("late", "import numpy, tcpmm"))}
    assert said["named"][0] == f"OpenBLAS's {CORE} kernels, the same on every CPU with AVX2 and FMA"
    assert said["named"][1].endswith("'s loops without AVX-512, the same on every CPU with "
                                     "AVX2 and FMA")
    assert said["late"][0].startswith("as OpenBLAS chose for this CPU (numpy was loaded before")
    assert said["late"][1].endswith("'s loops as it chose for this CPU: figures may differ "
                                    "from another CPU's in their last digits")


def test_numpy_runs_its_avx2_loops_whatever_the_cpu():
    """The variable is set to the installed numpy's AVX-512 targets before numpy loads,
    and numpy then runs none of them (on a CPU without AVX-512 it runs none anyway: the
    variable is what holds the CPUs with it)."""
    targets = numpy_avx512_targets()
    assert targets
    assert _numpy() == [" ".join(targets), "[]"]


def test_every_target_switched_off_is_one_numpy_dispatches():
    """A name the installed numpy does not dispatch would be ignored with a warning and
    leave its AVX-512 loops on: a numpy that renames its targets fails here."""
    try:
        from numpy._core._multiarray_umath import __cpu_dispatch__
    except ImportError:
        from numpy.core._multiarray_umath import __cpu_dispatch__
    assert set(numpy_avx512_targets()) <= set(__cpu_dispatch__)


def test_a_list_of_numpy_targets_the_user_sets_is_kept():
    assert _numpy(NPY_DISABLE_CPU_FEATURES="AVX512_SPR")[0] == "AVX512_SPR"
    # numpy refuses both variables together: one the user sets leaves the other unset
    assert _numpy(NPY_ENABLE_CPU_FEATURES="X86_V3" if numpy_version() >= (2, 4)
                  else "AVX2")[0] == "None"


def test_numpy_targets_by_version(tmp_path):
    """The names by numpy's version, read from the ``version.py`` of the first numpy on
    the path without loading it."""
    (tmp_path / "a" / "numpy").mkdir(parents=True)
    (tmp_path / "a" / "numpy" / "version.py").write_text('\nversion = "2.3.5"\n')
    (tmp_path / "b" / "numpy").mkdir(parents=True)
    (tmp_path / "b" / "numpy" / "version.py").write_text('version: str = "2.4.0rc1"\n')
    assert numpy_version([str(tmp_path / "none"), str(tmp_path / "a"),
                          str(tmp_path / "b")]) == (2, 3)
    assert numpy_version([str(tmp_path / "b")]) == (2, 4)
    assert numpy_version([str(tmp_path / "none")]) == ()
    assert numpy_avx512_targets((2, 4)) == ("X86_V4", "AVX512_ICL", "AVX512_SPR")
    assert numpy_avx512_targets((2, 3))[-1] == "AVX512_SPR"
    assert "AVX512_SPR" not in numpy_avx512_targets((1, 26))
    assert "AVX512_SKX" in numpy_avx512_targets((1, 26))
    assert numpy_avx512_targets(()) == ()


def test_the_tests_run_the_same_kernels():
    from threadpoolctl import threadpool_info

    found = {i["architecture"] for i in threadpool_info() if i["internal_api"] == "openblas"}
    assert found == {os.environ.get("OPENBLAS_CORETYPE", CORE)}
