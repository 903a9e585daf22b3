"""The corners of a streamed contour, kept as columns of numbers.

A CAM program has hundreds of thousands of corners, and as dicts (a corner's head and
its figures per sensor, some 1.6 kB with three sensors) they grew with the program: 0.8 GB
on a zig-zag of 10 M blocks. A batch of corners of the usual shape (``number``, ``index``,
``point_m``, ``turn_rad`` and, where samples came to it, per sensor the figures of
:data:`FIGURES` in that order) is packed as arrays, about 150 bytes a corner; a batch of
any other shape is kept as it came. Read back, each corner is the dict it was: the same
keys in the same order, the same float64 values.
"""

from __future__ import annotations

import bisect
from collections.abc import Sequence

import numpy as np

#: a corner's head, in order [-]
HEAD = ("number", "index", "point_m", "turn_rad")
#: a sensor's figures of a corner, in order [-]
FIGURES = ("overshoot_m", "rounding_m", "settle_s", "settle_m")


class CornerRows(Sequence):
    """Corners added a batch at a time (:meth:`extend`), read as a sequence of dicts."""

    def __init__(self):
        self._parts: list = []  # per batch: a list of dicts, or its columns
        self._starts: list = []  # the number of corners before each batch
        self._n = 0

    def extend(self, rows) -> None:
        """Add the corners ``rows`` (dicts), in order [-]."""
        rows = list(rows)
        if rows:
            self._add(_packed(rows) or rows)

    def extend_columns(self, index, point_m, turn_rad, fed, figs, names) -> None:
        """Add corners given as columns, numbered on from the last: their ``index``,
        ``point_m`` (a row each), ``turn_rad``, whether samples came to each (``fed``)
        and per sensor of ``names`` its :data:`FIGURES` (shape (n, sensors, 4), read
        where ``fed``) [SI]."""
        n = len(index)
        if n:
            self._add({"number": np.arange(self._n + 1, self._n + n + 1, dtype=np.int64),
                       "index": np.array(index, np.int64),
                       "point_m": np.array(point_m, float).reshape(n, -1),
                       "turn_rad": np.array(turn_rad, float), "fed": np.array(fed, bool),
                       "figs": np.array(figs, float)[:, :len(names)], "names": tuple(names)})

    def _add(self, part) -> None:
        """Append a batch: a list of dicts, or the columns of one [-]."""
        self._starts.append(self._n)
        self._parts.append(part)
        self._n += _size(part)

    def __len__(self) -> int:
        return self._n

    def __getitem__(self, i):
        if isinstance(i, slice):
            return [self[j] for j in range(*i.indices(self._n))]
        j = int(i) + self._n if int(i) < 0 else int(i)
        if not 0 <= j < self._n:
            raise IndexError("corner index out of range")
        b = bisect.bisect_right(self._starts, j) - 1
        part, k = self._parts[b], j - self._starts[b]
        return part[k] if isinstance(part, list) else _row(part, k)

    def __iter__(self):
        for part in self._parts:
            if isinstance(part, list):
                yield from part
            else:
                for k in range(_size(part)):
                    yield _row(part, k)

    def figure(self, sensor: str, name: str):
        """Figure ``name`` of ``sensor`` of every corner, where every batch is columns and
        every corner has it (``None`` else: read the dicts) [SI]."""
        out = []
        for part in self._parts:
            if (isinstance(part, list) or sensor not in part["names"]
                    or not part["fed"].all()):
                return None
            out.append(part["figs"][:, part["names"].index(sensor), FIGURES.index(name)])
        return np.concatenate(out) if out else np.empty(0)

    def blank(self, sensors, names) -> None:
        """Make the figures ``names`` (of :data:`FIGURES`) of ``sensors`` NaN (n/a) in
        every corner, in place [-]."""
        for part in self._parts:
            if isinstance(part, list):
                for c in part:
                    for s in (s for s in sensors if s in c):
                        c[s].update(dict.fromkeys(names, np.nan))
                continue
            for s in (s for s in sensors if s in part["names"]):
                for name in names:
                    part["figs"][:, part["names"].index(s), FIGURES.index(name)] = np.nan

    def indices(self) -> list:
        """Each corner's ``index`` (command sample), in order [-]."""
        return [i for part in self._parts for i in
                ([c["index"] for c in part] if isinstance(part, list)
                 else part["index"].tolist())]

    def kept(self, keep) -> CornerRows:
        """The corners where ``keep`` (one bool a corner) is true, as a new table [-]."""
        out, k = CornerRows(), 0
        for part in self._parts:
            n = _size(part)
            mask = np.asarray(keep[k:k + n], bool)
            k += n
            if isinstance(part, list):
                out.extend(c for c, m in zip(part, mask.tolist(), strict=True) if m)
            elif mask.any():
                out._add({key: (v[mask] if isinstance(v, np.ndarray) else v)
                          for key, v in part.items()})
        return out


def _size(part) -> int:
    """Corners in a batch, a list of dicts or its columns [-]."""
    return len(part) if isinstance(part, list) else int(part["number"].size)


def _packed(rows: list) -> dict | None:
    """The columns of ``rows`` where every corner has the usual shape (module docstring)
    and the same sensors, else ``None`` [-]."""
    first = rows[0]
    names = next((tuple(list(r)[len(HEAD):]) for r in rows if len(r) > len(HEAD)), ())
    for r in rows:
        keys = tuple(r)
        if keys[:len(HEAD)] != HEAD or keys[len(HEAD):] not in ((), names):
            return None
        if type(r["number"]) is not int or type(r["index"]) is not int:
            return None
        if not isinstance(r["turn_rad"], float) or type(r["point_m"]) is not list:
            return None
        if len(r["point_m"]) != len(first["point_m"]):
            return None
        for s in keys[len(HEAD):]:
            fig = r[s]
            if type(fig) is not dict or tuple(fig) != FIGURES:
                return None
            if not all(isinstance(v, float) for v in fig.values()):
                return None
    fed = np.array([len(r) > len(HEAD) for r in rows], bool)
    figs = np.full((len(rows), len(names), len(FIGURES)), np.nan)
    for k in np.flatnonzero(fed).tolist():
        figs[k] = [list(rows[k][s].values()) for s in names]
    return {"number": np.array([r["number"] for r in rows], np.int64),
            "index": np.array([r["index"] for r in rows], np.int64),
            "point_m": np.array([r["point_m"] for r in rows], float).reshape(len(rows), -1),
            "turn_rad": np.array([r["turn_rad"] for r in rows], float),
            "fed": fed, "figs": figs, "names": names}


def _row(part: dict, k: int) -> dict:
    """Corner ``k`` of a packed batch, as the dict it was [-]."""
    row = {"number": int(part["number"][k]), "index": int(part["index"][k]),
           "point_m": part["point_m"][k].tolist(), "turn_rad": float(part["turn_rad"][k])}
    if part["fed"][k]:
        for s, fig in zip(part["names"], part["figs"][k].tolist(), strict=True):
            row[s] = dict(zip(FIGURES, fig, strict=True))
    return row
