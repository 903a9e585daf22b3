"""The outputs of one command put in place together: each is written to a temporary file
beside it, and all are renamed only once every one is written (:func:`together`)."""

from __future__ import annotations

import contextlib
import os
from pathlib import Path

#: The outputs written within :func:`together` but not yet in place, each as its path,
#: what puts it there and what removes it; None outside [-]
_PENDING: list | None = None
#: The process that opened :func:`together`: a forked child's writes are its own [-]
_PENDING_PID: list = []
#: The temporary folders of a staged output folder being filled: what goes into one is
#: moved with it, not held back on its own [-]
_STAGING: list = []


def held_back(path) -> bool:
    """Whether the output ``path`` waits for the end of :func:`together` [-]."""
    if _PENDING is None or _PENDING_PID != [os.getpid()]:
        return False
    where = Path(os.path.abspath(path))
    return not any(where.is_relative_to(s) for s in _STAGING)


def hold(path, put, remove) -> None:
    """Hold back the output ``path``: ``put`` puts it in place at the end of
    :func:`together` (an InputError where it cannot), ``remove`` removes what it left
    where the command fails [-]."""
    _PENDING.append((path, put, remove))


@contextlib.contextmanager
def at_once(folder):
    """Within: the outputs written into ``folder`` go there at once: a staged folder's,
    or a scratch folder's read back by the command itself [-]."""
    _STAGING.append(Path(os.path.abspath(folder)))
    try:
        yield
    finally:
        _STAGING.pop()


@contextlib.contextmanager
def together(keep=None):
    """Hold back every output written inside until all of them are written, then put
    them in place: a command whose last output fails (a full disk) leaves none of its
    outputs written and the files they would have replaced unchanged. Nested, the
    outermost puts them in place.

    Parameters
    ----------
    keep : callable, optional
        Whether an exception that ends the block still leaves the outputs written (an
        exit on purpose after they were); default: none does [-].
    """
    global _PENDING
    if _PENDING is not None:
        yield
        return
    _PENDING, _PENDING_PID[:] = [], [os.getpid()]
    try:
        yield
    except BaseException as exc:
        pending, _PENDING = _PENDING, None
        if keep is not None and keep(exc):
            _put_all(pending)
        else:
            for _, _, remove in reversed(pending):
                remove()
        raise
    pending, _PENDING = _PENDING, None
    _put_all(pending)


def _put_all(pending: list) -> None:
    """Put the outputs held back in place; where one cannot be (a rename refused: its
    ``put`` raises the error to show), the rest are removed and the error says which
    were written [-]."""
    from ..errors import InputError

    for k, (path, put, _) in enumerate(pending):
        try:
            put()
        except InputError as err:
            for _, _, rest in reversed(pending[k:]):
                rest()
            if k == 0:
                raise
            done = ", ".join(str(p) for p, _, _ in pending[:k])
            raise InputError(err.message.replace("nothing was written",
                                                 f"only {done} written"),
                             file=path) from None
