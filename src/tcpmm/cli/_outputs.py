"""Checks of a command's outputs taken together, before any work."""

from __future__ import annotations

import os

import typer


def distinct_outputs(*named) -> None:
    """Refuse two outputs of one command that name the same file: the one written last
    would replace the other.

    Parameters
    ----------
    *named : tuple of (str, Path or None)
        Each output's option and its file, None where not asked [-].
    """
    seen = {}
    for option, path in named:
        if path is None:
            continue
        # a link and its target, or two spellings of one path, are one file
        key = os.path.normcase(os.path.realpath(path))
        if key in seen:
            first, given = seen[key]
            raise typer.BadParameter(f"{given} is given to both {first} and {option}: one "
                                     "would replace the other; give each output its own name")
        seen[key] = (option, path)


def outputs_together():
    """The command's outputs put in place together, once all are written
    (:func:`tcpmm.io.atomic.together`); used as the command function's decorator."""
    from ..io.atomic import together

    return together(keep=_ended_on_purpose)


def _ended_on_purpose(exc: BaseException) -> bool:
    """Whether the command ended after its outputs were written: ``--strict``'s exit
    code, or the reader of the standard output gone (``| head``) while the result was
    printed [-]."""
    from ._app import READER_GONE

    if isinstance(exc, SystemExit):
        return exc.code == READER_GONE
    return isinstance(exc, typer.Exit)


#: Whether the command said itself what a stop by a signal left (``sweep`` keeps the
#: variants computed): the command line then says no more [-]
STOP_SAID: list = []
