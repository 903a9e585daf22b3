"""The sweep's processes keep freed memory in their heap (``tcpmm._heap``)."""

import subprocess
import sys
import textwrap

import pytest

from tcpmm._heap import keep_freed_memory

#: Twenty arrays of 96 kB (below glibc's first mapping threshold, so from the heap), freed
#: together, as a variant frees its run: then the faults of the next round [-].
PROBE = textwrap.dedent("""
    import resource, sys
    import numpy as np
    if sys.argv[1] == "keep":
        from tcpmm._heap import keep_freed_memory
        assert keep_freed_memory()
    def work():
        a = [np.ones(12_000) for _ in range(20)]
        return sum(x[0] for x in a)
    for _ in range(5):
        work()
    r0 = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
    for _ in range(50):
        work()
    print((resource.getrusage(resource.RUSAGE_SELF).ru_minflt - r0) / 50)
""")


def faults_per_round(mode: str) -> float:
    out = subprocess.run([sys.executable, "-c", PROBE, mode], capture_output=True, text=True,
                         check=True)
    return float(out.stdout.strip())


def test_freed_arrays_come_back_without_page_faults():
    if not keep_freed_memory():
        pytest.skip("the C library is not glibc")
    before = faults_per_round("default")
    if before < 100:
        pytest.skip(f"this C library keeps the memory by itself ({before:g} faults a round)")
    # 1.9 MB a round is some 470 pages handed back and faulted in again
    assert faults_per_round("keep") < 10
