"""Threads: BLAS kept single-threaded (on small matrices, threads cost far more than they
give), the cores this process may use, and reading ahead in a thread."""

from __future__ import annotations

import functools
import os
import queue
import sys
import threading
from collections.abc import Iterator

#: The variables by which OpenBLAS, MKL, BLIS, Accelerate and OpenMP read their thread
#: count when they load [-].
THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "BLIS_NUM_THREADS",
                    "VECLIB_MAXIMUM_THREADS", "OMP_NUM_THREADS")
_from_start: list = []


def single_threaded_from_start() -> bool:
    """Have BLAS start on one thread, where numpy is not loaded yet: the command line
    calls this first, so that :func:`limit_blas_threads` need not load threadpoolctl
    (25 ms) to change the pools afterwards. A count the user set is kept. The variables
    reach the processes the command starts (a sweep's workers), which limit BLAS to one
    thread anyway.

    Returns
    -------
    bool
        Whether every BLAS starts single-threaded [-].
    """
    if not _from_start:
        if "numpy" in sys.modules:
            _from_start.append(False)
        else:
            for name in THREAD_VARIABLES:
                os.environ.setdefault(name, "1")
            _from_start.append(all(os.environ[n].strip() == "1" for n in THREAD_VARIABLES))
    return _from_start[0]


@functools.cache
def limit_blas_threads(n: int = 1):
    """Limit BLAS/OpenMP thread pools to ``n`` threads for the rest of the process.

    Parameters
    ----------
    n : int
        Number of threads [-].
    """
    if n == 1 and _from_start and _from_start[0]:
        return None
    from threadpoolctl import threadpool_limits

    return threadpool_limits(limits=n)


def usable_cores() -> int:
    """The cores this process may run on (its CPU affinity where the system says it, as a
    container or ``taskset`` limits it), at least 1 [-]."""
    if hasattr(os, "sched_getaffinity"):
        return max(1, len(os.sched_getaffinity(0)))
    return os.cpu_count() or 1


def read_ahead(items: Iterator) -> Iterator:
    """The items of ``items``, the next one produced in a thread of its own while the
    caller works on the last: for an iterator that reads (a file's next chunk) and lets go
    of the interpreter lock as it does. An error it raises is raised where its item would
    have come; closed early, the thread stops after the item it is on [-]."""
    q: queue.Queue = queue.Queue(maxsize=1)
    stop = threading.Event()

    def produce():
        try:
            for item in items:
                q.put((True, item))
                if stop.is_set():
                    return
            q.put((True, _END))
        except BaseException as exc:  # handed to the caller, raised there
            q.put((False, exc))

    t = threading.Thread(target=produce, daemon=True, name="read-ahead")
    t.start()
    try:
        while True:
            ok, item = q.get()
            if not ok:
                raise item
            if item is _END:
                return
            yield item
    finally:
        stop.set()
        while t.is_alive():  # let a producer blocked on a full queue finish
            try:
                q.get(timeout=0.05)
            except queue.Empty:
                pass
        t.join()


_END = object()
