"""Independent pieces of work done side by side, each in a forked process of its own.

An axis's identification, or the run of one varied model, needs nothing of the others',
and nearly all of it is Python and numpy holding the interpreter lock: threads would not
share the work, processes do. They are forked, so a child starts with the modules the
parent has imported (a new interpreter would import scipy, pydantic and the package
again, some seconds) and with the work's data in its memory. Each child does one piece
with its warnings recorded; the parent takes the pieces in their order and gives each
one's warnings as they were given, then its result or its error, as if it had done them
one after the other itself. The children ignore an interrupt (the terminal sends it to
the whole group: the parent ends them) and end on a termination signal without a word.
"""

from __future__ import annotations

import multiprocessing
import os
import signal
import warnings
from contextlib import contextmanager
from typing import TYPE_CHECKING

from .errors import TcpmmError

if TYPE_CHECKING:
    from collections.abc import Callable, Iterator

#: what the forked children do: the function, its pieces and what they share, set before
#: the fork [-]
_WORK: tuple = ()
#: per source file, the record of warnings shown once per place (as Python keeps per
#: module), for the warnings given again in the parent [-]
_SHOWN: dict = {}


def usable_jobs(jobs: int | None, pieces: int) -> int:
    """Processes for ``pieces`` pieces of work: ``jobs``, or with ``None`` or 0 the cores
    this process may run on; at most one per piece; 1 where processes cannot be forked.

    Parameters
    ----------
    jobs : int or None
        Processes asked for [-].
    pieces : int
        Pieces of work [-].
    """
    if "fork" not in multiprocessing.get_all_start_methods():
        return 1
    if not jobs:
        jobs = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (
            os.cpu_count() or 1)
    return max(1, min(int(jobs), pieces))


@contextmanager
def results_in_order(work: Callable, pieces: list, shared, jobs: int
                     ) -> Iterator[list[Callable]]:
    """Per piece, in order, a function that gives the warnings of ``work(piece, shared)``
    and returns its result or raises its error (the package's errors; any other is
    raised too, as a defect). With ``jobs`` > 1 the pieces are done in forked processes,
    which the context ends whatever happens; the results are those of one piece after
    the other.

    Parameters
    ----------
    work : callable
        ``work(piece, shared)`` [-].
    pieces : list
        The pieces of work [-].
    shared : object
        What the pieces share [-].
    jobs : int
        Processes (:func:`usable_jobs`); 1: here, one piece after the other [-].
    """
    if jobs <= 1 or len(pieces) < 2:
        yield [(lambda piece=piece: work(piece, shared)) for piece in pieces]
        return
    global _WORK
    _WORK = (work, pieces, shared)
    pool = multiprocessing.get_context("fork").Pool(jobs, initializer=_quiet_child)
    try:
        pending = [pool.apply_async(_do_in_child, (i,)) for i in range(len(pieces))]
        yield [(lambda p=p: _given_back(p.get())) for p in pending]
    finally:
        _WORK = ()
        pool.terminate()
        pool.join()


def _quiet_child() -> None:
    """A child leaves an interrupt to its parent and ends on SIGTERM at once."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)


def _do_in_child(index: int):
    """Piece ``index`` of :data:`_WORK` with every warning recorded: ``(result, error,
    warnings)`` [-]."""
    work, pieces, shared = _WORK
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            result, error = work(pieces[index], shared), None
        except TcpmmError as exc:
            result, error = None, exc
    said = [(w.message, w.category, w.filename, w.lineno) for w in caught]
    return result, error, said


def _given_back(outcome):
    """Give a child's warnings here, under this process's filters and once per place as
    Python does, then return its result or raise its error."""
    result, error, said = outcome
    for message, category, filename, lineno in said:
        warnings.warn_explicit(message, category, filename, lineno,
                               registry=_SHOWN.setdefault(filename, {}))
    if error is not None:
        raise error
    return result
