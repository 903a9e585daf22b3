"""How finely a run's command samples its path.

The contour error is measured against the polyline through the command's samples. Where
the path bends between two samples the polyline cuts the bend, by up to its chords' sag
(:func:`.contour_windows.chord_sags`: ``L sin(phi / 2) / 4`` for a chord of length ``L``
turning by ``phi``). At the position loop's period that is a fraction of a micrometre; a
run recorded every second cuts a square's corners by millimetres, and its contour error
is measured against corners it cut off. :class:`CommandSag` keeps the largest sag of a
command given in pieces, in order.
"""

from __future__ import annotations

import numpy as np

from .._rows import dot_rows
from .contour_windows import chord_sags, travel

#: A sag that may move the contour error by this much or more is said, or by this share
#: of its largest value where that is more [m], [-].
SAG_SAID_M = 1e-6
SAG_SAID_SHARE = 0.05


class CommandSag:
    """The largest chord sag of a command's polyline, fed its samples in pieces, in
    order (:meth:`add`)."""

    def __init__(self):
        self.largest_m = 0.0
        self._tail = None

    def add(self, cmd: np.ndarray) -> None:
        """Take the next command samples, shape (n, d) [m]."""
        p = cmd if self._tail is None else np.concatenate([self._tail, cmd])
        self._tail = p[-2:]
        seg = np.diff(p, axis=0)
        if p.shape[0] < 3 or not np.any(dot_rows(seg, seg) > 0):
            return
        seg, ln2, tdir, _ = travel(p)
        self.largest_m = max(self.largest_m, float(np.max(chord_sags(seg, ln2, tdir))))


def sag_note(sag_m: float, largest_error_m: float) -> str | None:
    """A note where the command's samples cut its bends by enough to move the contour
    error (:data:`SAG_SAID_M`, :data:`SAG_SAID_SHARE`); None where they do not.

    Parameters
    ----------
    sag_m : float
        The command's largest chord sag (:class:`CommandSag`) [m].
    largest_error_m : float
        The largest contour error of any sensor [m].
    """
    if not sag_m > max(SAG_SAID_M, SAG_SAID_SHARE * largest_error_m):
        return None
    return (f"the run's command samples cut the path's bends by up to {sag_m * 1e6:.3g} µm "
            f"(a chord's sag): the contour error is measured against the polyline through "
            f"them and may be off by as much; record the run at the position loop's period "
            f"(tcpmm simulate --record-period-s)")
