"""A command's large arrays taken from memory it freed before, not from fresh pages.

A streamed command (``simulate --gcode ... -o RUN.parquet``, ``contour RUN.parquet
--chunk-rows``) makes and frees arrays of some megabytes for every chunk: the columns
read, the command's segments, the axes' records. glibc's allocator hands an array of more
than its threshold (128 kB at first, at most 32 MB as it adapts) pages mapped afresh and
gives them back when it is freed, and gives back the free memory at the top of its heap
beyond its trim threshold; Arrow's own allocator gives its pages back as well. Each chunk
then faults in and zeroes its pages again: a tenth of the CPU of ``contour`` on a 1 M-block
program was the system's, clearing pages. The command line keeps what it frees for the
next chunk instead: the process holds no more than its largest chunk's arrays took.
"""

from __future__ import annotations

import os
import sys

#: ``mallopt``'s parameters: the trim threshold and the size above which an allocation
#: is mapped on its own (glibc's ``malloc.h``) [-]
_M_TRIM_THRESHOLD, _M_MMAP_THRESHOLD = -1, -3
#: Largest allocation taken from the heap, the most glibc allows (half its 64 MB heaps):
#: a chunk's columns of 200 000 rows are 1.6 MB each, its point arrays some 10 MB [B]
MMAP_ABOVE = 32 << 20
#: Free memory at the top of the heap kept for the next chunk [B]
KEEP_FREED = 512 << 20


def keep_freed_memory() -> bool:
    """Have glibc keep freed memory for the next allocations (:data:`MMAP_ABOVE`,
    :data:`KEEP_FREED`) and Arrow allocate from it too, where Arrow is not loaded yet (a
    pool the user chose with ``ARROW_DEFAULT_MEMORY_POOL`` is kept). Elsewhere than on
    glibc (macOS, Windows, musl) nothing changes.

    Returns
    -------
    bool
        Whether glibc took both settings [-].
    """
    if not sys.platform.startswith("linux"):
        return False
    import ctypes

    try:
        mallopt = ctypes.CDLL(None).mallopt
    except (OSError, AttributeError):  # a C library without mallopt
        return False
    if "pyarrow" not in sys.modules:
        os.environ.setdefault("ARROW_DEFAULT_MEMORY_POOL", "system")
    mallopt.argtypes = (ctypes.c_int, ctypes.c_int)
    return bool(mallopt(_M_MMAP_THRESHOLD, MMAP_ABOVE)) and bool(
        mallopt(_M_TRIM_THRESHOLD, KEEP_FREED))
