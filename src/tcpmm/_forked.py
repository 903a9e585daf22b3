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
import sys
import warnings
from contextlib import contextmanager
from typing import TYPE_CHECKING

from ._threads import usable_cores
from .errors import InputError, TcpmmError

if TYPE_CHECKING:
    from collections.abc import Callable, Iterator

#: what the forked children do: the function, its pieces and what they share, set before
#: the fork [-]
_WORK: tuple = ()
#: per source file, the record of warnings shown once per place (as Python keeps per
#: module), for the warnings given again in the parent [-]
_SHOWN: dict = {}
#: the signals a child takes otherwise than its parent, held over the fork [-]
_HELD = {signal.SIGINT, signal.SIGTERM}


def usable_jobs(jobs: int | None, pieces: int) -> int:
    """Processes for ``pieces`` pieces of work: ``jobs``, or with ``None`` or 0 the
    environment's ``TCPMM_JOBS`` where it is set (a machine shared with other work, a test
    run that has a process per core already), else the cores this process may run on; at
    most one per piece; 1 where processes cannot be forked.

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
        jobs = _jobs_from_environment() or usable_cores()
    return max(1, min(int(jobs), pieces))


def _jobs_from_environment() -> int:
    """``TCPMM_JOBS`` as a number of processes, 0 where it is not set [-]."""
    text = os.environ.get("TCPMM_JOBS", "").strip()
    if not text:
        return 0
    if not text.isdigit():
        raise InputError(f"TCPMM_JOBS={text!r}: give a whole number of processes (0: one "
                         "per core), or unset it")
    return int(text)


@contextmanager
def results_in_order(work: Callable, pieces: list, shared, jobs: int
                     ) -> Iterator[list[Callable]]:
    """Per piece, a function that gives the warnings of ``work(piece, shared)`` and
    returns its result or raises its error (the package's errors; any other is raised
    too, as a defect); the functions are called in the pieces' order. With ``jobs`` > 1
    the pieces are dealt to that many forked processes (piece ``k`` to process
    ``k % jobs``), which the context ends whatever happens; the results are those of one
    piece after the other. A process that dies
    before it sends a result (killed, out of memory) is an error, not a wait.

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
    for stream in (sys.stdout, sys.stderr):  # a child must not write what is buffered again
        if stream is not None:
            stream.flush()
    context = multiprocessing.get_context("fork")
    children = []
    try:
        for j in range(jobs):
            receive, send = context.Pipe(duplex=False)
            child = context.Process(target=_child, args=(send, range(j, len(pieces), jobs)),
                                    daemon=True)
            held = signal.pthread_sigmask(signal.SIG_BLOCK, _HELD)
            try:  # a child would take an interrupt as its own until it ignores it
                child.start()
            finally:
                signal.pthread_sigmask(signal.SIG_SETMASK, held)
            send.close()
            children.append((child, receive))
        yield [(lambda k=k: _given_back(_received(*children[k % jobs])))
               for k in range(len(pieces))]
    finally:
        _WORK = ()
        for child, receive in children:
            if child.is_alive():
                child.terminate()
            child.join()
            receive.close()


def _child(send, indices) -> None:
    """In a forked process: each piece of ``indices`` in turn, its outcome sent."""
    _quiet_child()
    for index in indices:
        outcome = _do_in_child(index)
        try:
            send.send(outcome)
        except Exception as exc:  # a result or error that cannot be pickled: a defect
            send.send((None, TcpmmError(f"a result could not be sent between processes: "
                                        f"{type(exc).__name__}: {exc}"), outcome[2]))
    send.close()


def _received(child, receive):
    """The next outcome ``child`` sends; an error where it ended without one."""
    try:
        return receive.recv()
    except EOFError:
        child.join()
        raise TcpmmError(
            f"a process of this command ended before its work was done (exit code "
            f"{child.exitcode}: killed, or out of memory); run it again with one process "
            "(--jobs 1)") from None


def _quiet_child() -> None:
    """A child leaves an interrupt to its parent and ends on SIGTERM at once; both signals
    are held from the fork until here, so that one sent meanwhile is taken so too."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, _HELD)


def _do_in_child(index: int):
    """Piece ``index`` of :data:`_WORK` with every warning recorded: ``(result, error,
    warnings)`` [-]."""
    work, pieces, shared = _WORK
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            result, error = work(pieces[index], shared), None
        except Exception as exc:  # the package's errors and defects alike, raised above
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
