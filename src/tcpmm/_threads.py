"""Keep BLAS single-threaded: on small matrices, threads cost far more than they give."""

from __future__ import annotations

import functools
import os
import sys

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
