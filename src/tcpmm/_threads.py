"""Keep BLAS single-threaded: on small matrices, threads cost far more than they give."""

from __future__ import annotations

import functools


@functools.cache
def limit_blas_threads(n: int = 1):
    """Limit BLAS/OpenMP thread pools to ``n`` threads for the rest of the process.

    Parameters
    ----------
    n : int
        Number of threads [-].
    """
    from threadpoolctl import threadpool_limits

    return threadpool_limits(limits=n)
