"""Checks of a command's outputs taken together, before any work."""

from __future__ import annotations

import os
from pathlib import Path

import typer

from ._app import checked_output


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


def checked_yaml_output(output: Path, *inputs, json_option: bool = True,
                        what: str = "a model file") -> Path:
    """:func:`checked_output` for a model file or fragment (``what``), which is written as
    YAML: a name ending otherwise (``-o tuned.json``) would hold YAML under a misleading
    name; a folder is named as one. ``json_option``: the command has ``--json``, said as
    the way to JSON."""
    if Path(output).is_dir():
        raise typer.BadParameter(f"{output} is a folder; give the file to write, e.g. "
                                 f"{Path(output) / 'model.yaml'}")
    if Path(output).suffix.lower() not in (".yaml", ".yml"):
        raise typer.BadParameter(f"{output}: {what} is written as YAML; name it "
                                 f"{Path(output).with_suffix('.yaml').name}"
                                 + (" (--json prints the result as JSON)" if json_option
                                    else ""))
    return checked_output(output, *inputs)


def checked_csv_output(output: Path, *inputs, what: str = "a command file") -> Path:
    """:func:`checked_output` for ``what`` (a command file, an excitation), which is
    written as CSV: a name ending otherwise (``-o CMD.parquet``) would hold CSV text that
    the readers of that format refuse."""
    checked_output(output, *inputs)
    suffix = Path(output).suffix.lower()
    if suffix not in ("", ".csv") and (Path(output).is_file() or not Path(output).exists()):
        raise typer.BadParameter(f"{output}: {what} is written as CSV; name it "
                                 f"{Path(output).with_suffix('.csv').name}")
    return output


def checked_json_output(output: Path, *inputs, what: str) -> Path:
    """:func:`checked_output` for a result written as JSON (``what``): a name ending
    otherwise (``-o fit.csv``) would hold JSON that the readers of that format refuse."""
    if Path(output).suffix.lower() != ".json":
        raise typer.BadParameter(f"{output}: {what} is written as JSON; name it "
                                 f"{Path(output).with_suffix('.json').name}")
    return checked_output(output, *inputs)
