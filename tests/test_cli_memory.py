"""A command's process keeps the memory it frees for its next chunk: the pages of a chunk's
arrays are not given back to the system and faulted in and zeroed again for the next
(:mod:`tcpmm.cli._memory`)."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

#: Allocates and frees eight blocks of 4 MB, touching every page, ten times over, after
#: importing the command line; prints the page faults of the first round and of
#: the nine after it, and Arrow's memory pool as the environment names it.
_ROUNDS = """
import ctypes, json, resource, sys
import tcpmm.cli
libc = ctypes.CDLL(None)
libc.malloc.restype, libc.malloc.argtypes = ctypes.c_void_p, (ctypes.c_size_t,)
libc.free.argtypes = (ctypes.c_void_p,)
size, faults = 4 << 20, []
for _ in range(10):
    before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
    blocks = [libc.malloc(size) for _ in range(8)]
    for b in blocks:
        ctypes.memset(b, 1, size)
    for b in reversed(blocks):
        libc.free(b)
    faults.append(resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before)
import os
print(json.dumps([faults[0], sum(faults[1:]), os.environ.get("ARROW_DEFAULT_MEMORY_POOL")]))
"""


def _rounds(pool: str | None = None) -> list:
    env = {k: v for k, v in os.environ.items() if k != "ARROW_DEFAULT_MEMORY_POOL"}
    if pool is not None:
        env["ARROW_DEFAULT_MEMORY_POOL"] = pool
    out = subprocess.run([sys.executable, "-c", _ROUNDS], capture_output=True,
                         text=True, check=True, env=env)
    return json.loads(out.stdout)


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="glibc's allocator")
def test_memory_freed_is_reused_not_faulted_in_again():
    """Eight blocks of 4 MB freed together leave 32 MB free at the top of the heap, more
    than glibc's trim threshold (twice the largest block it has mapped on its own, 8 MB
    here): it gives them back, and the next round faults all its pages in again. Under
    the command line the nine rounds after the first take their pages from the first's:
    a tenth of one round's faults at most, and a few pages of Python's own (glibc's
    defaults take nine rounds' worth; where huge pages serve the heap a round is 16
    faults, nine rounds 144). Arrow allocates through the same allocator, unless the user
    chose a pool."""
    first, later, pool = _rounds()
    assert first > 0
    assert later < 0.1 * first + 50
    assert pool == "system"
    assert _rounds("jemalloc")[2] == "jemalloc"
