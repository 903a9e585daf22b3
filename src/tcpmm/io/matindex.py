"""References to MATLAB variables in a signal map: a name, a struct field, an element of a
struct array, and a column (``data(:,k)``) or a row (``data(k,:)``) of a matrix, 1-based
as in MATLAB.

A logger that stacks its signals as rows (``[t; exc; icmd; ...]``, 6 x N) is as common as
one that puts them in columns; the column of such a matrix holds one sample of each
signal, so it is refused where the matrix is wider than tall, with the row to map.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from tcpmm.errors import InputError

#: A variable reference: the dotted name, then ``(:,k)`` (a column) or ``(k,:)`` (a row).
REFERENCE = re.compile(r"^\s*([A-Za-z]\w*(?:\(\d+\))?(?:\.[A-Za-z]\w*(?:\(\d+\))?)*)\s*"
                       r"(?:\(\s*(?::\s*,\s*(\d+)|(\d+)\s*,\s*:)\s*\))?\s*$")
#: What a reference may be, for the message that refuses one [-].
FORMS = ("name, struct.field, struct(k).field (an element of a struct array), name(:,k) "
         "(a column) or name(k,:) (a row)")


def parse_reference(spec: str, path: Path) -> tuple[str, str | None, int]:
    """The dotted name of a reference, whether it takes a ``"column"`` or a ``"row"`` (or
    ``None``, the whole variable) and which, 1-based [-].

    Parameters
    ----------
    spec : str
        The reference as the map gives it (``data(:,3)``) [-].
    path : Path
        The .mat file, for the message [-].
    """
    m = REFERENCE.match(spec)
    if m is None:
        raise InputError(f"'{spec}' is not a variable reference; write {FORMS}", file=path)
    if m.group(2) is not None:
        return m.group(1), "column", int(m.group(2))
    if m.group(3) is not None:
        return m.group(1), "row", int(m.group(3))
    return m.group(1), None, 0


def pick(value: np.ndarray, spec: str, part: str | None, k: int, path: Path) -> np.ndarray:
    """Column or row ``k`` (1-based) of the matrix ``value``, as ``part`` says; a vector
    is its own column 1 and row 1.

    Parameters
    ----------
    value : ndarray
        The variable, in MATLAB's shape (rows, columns) [-].
    spec : str
        The reference, for the messages [-].
    part : {"column", "row"} or None
        What to take; ``None`` the whole variable [-].
    k : int
        Which column or row, from 1 [-].
    path : Path
        The .mat file, for the messages [-].

    Returns
    -------
    ndarray
        The samples [-].
    """
    if part is None:
        return value
    if value.ndim == 2 and 1 in value.shape:  # a vector: v5 and v7.3 alike
        value = value.reshape(-1)
    if value.ndim == 1 and k == 1:
        return value
    axis = 1 if part == "column" else 0
    if value.ndim != 2 or not 1 <= k <= value.shape[axis]:
        raise InputError(f"'{spec}': variable has shape {value.shape}; {part} {k} does not "
                         "exist", file=path)
    if value.shape[1 - axis] < value.shape[axis]:
        name = spec[: spec.rindex("(")].rstrip()
        other = f"{name}({k},:)" if part == "column" else f"{name}(:,{k})"
        raise InputError(
            f"'{spec}': the matrix is {value.shape[0]} x {value.shape[1]}, its signals in the "
            f"{'rows' if part == 'column' else 'columns'} (a {part} holds "
            f"{value.shape[1 - axis]} samples); map {other}, or save {name}.' and map its "
            f"{part}s", file=path)
    return value[:, k - 1] if part == "column" else value[k - 1, :]
