"""The corners' overshoot on every draw of the model, which the contour error of a corner's
region does not bound.

Uncorrected, a lagging TCP cuts a corner inside the path. A correction that takes the
rounding away can carry it past the corner, outside the path, while the region's largest
error falls: on a square whose one axis only the draws vouch a correction for, the corner
where that axis stops led the other, and the TCP overshot it where it had not before. The
largest error, the rounding, fell; the new error is of another kind, on the other side of
the path. So the robust choice (:mod:`.robust`) also holds every corner's overshoot, as
``tcpmm contour`` reads it (:func:`tcpmm.analysis.contour.contour_error`), the path's end
included: no draw's may rise by more than the sensors' resolution. The overshoot is no
figure the correction claims to improve, so a fall of any size is no rise. It is read
only of the choices that would be kept otherwise: a corner's figures cost a contour
analysis per draw.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np

from ..analysis.contour import contour_error
from ..result import AxisRun, Run


@dataclass
class CornerGuard:
    """The corners of the path a compensated TCP is to follow, and their overshoot
    without the correction on every draw.

    Parameters
    ----------
    path : Command
        The path the TCP is to follow, against which its figures are read [m].
    labels : ndarray of int
        Region per sample of ``path`` (:func:`.robust.regions`) [-].
    before : ndarray
        Overshoot per machine and corner without the correction, shape (machines,
        corners) [m].
    index : ndarray of int
        Each corner's sample on ``path`` [-].
    held : dict or None
        The largest rise the guard held back: where, on which machine (0 the model, then
        the draws), the overshoot before and with the shares refused; ``None`` where it
        held none back [mm, -, um].
    """

    path: object
    labels: np.ndarray
    before: np.ndarray = field(default_factory=lambda: np.empty((0, 0)))
    index: np.ndarray = field(default_factory=lambda: np.empty(0, dtype=int))
    held: dict | None = None

    @classmethod
    def of(cls, path, labels: np.ndarray, errors: np.ndarray) -> CornerGuard:
        """The guard of ``path``, from the TCP errors without the correction.

        Parameters
        ----------
        path : Command
            The path to follow [m].
        labels : ndarray of int
            Region per sample [-].
        errors : ndarray
            TCP error per machine, axis and sample without the correction, the path
            less the TCP, shape (machines, axes, n) [m].
        """
        guard = cls(path, labels)
        before, index = guard.overshoots(errors)
        guard.before, guard.index = before, index
        return guard

    def overshoots(self, errors: np.ndarray) -> tuple:
        """Per machine and corner the TCP's overshoot past the corner, 0 where none is
        read (a TCP still moving there, NaN in ``tcpmm contour``), and each corner's
        sample: ``(shape (machines, corners) [m], shape (corners,) [-])``.

        Parameters
        ----------
        errors : ndarray
            TCP error per machine, axis and sample, the path less the TCP, shape
            (machines, axes, n) [m].
        """
        over, index = [], None
        for e in errors:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # said of the program's own run, not each draw's
                res = contour_error(self._run(e), command=self.path)
            if index is None:  # the corners are the path's: the same on every machine
                index = np.array([c["index"] for c in res.corners], dtype=int)
            over.append([c["tcp"]["overshoot_m"] for c in res.corners])
        index = np.empty(0, dtype=int) if index is None else index
        return np.nan_to_num(np.array(over, dtype=float).reshape(len(errors), -1)), index

    def _run(self, e: np.ndarray) -> Run:
        """A run whose TCP is the path less ``e`` (axes, n), with the path's G0 rapids."""
        p = self.path.positions
        axes = {a: AxisRun(p[a], tcp=p[a] - e[j]) for j, a in enumerate(self.path.axes)}
        blocks = self.path.blocks()
        nc_line, rapid = (None, None) if blocks is None else blocks
        return Run(self.path.time_s, axes, nc_line=nc_line, rapid=rapid)

    def holds(self, errors: np.ndarray, equal_m: float) -> bool:
        """Whether no corner's overshoot rises on any machine by more than ``equal_m``,
        the machines read one by one until one does (the arguments of :meth:`rising`) [-].
        """
        if self.index.size == 0:
            return True
        return not any(self._rises(errors[k:k + 1], equal_m, k).any()
                       for k in range(len(errors)))

    def _rises(self, errors: np.ndarray, equal_m: float, first: int = 0) -> np.ndarray:
        """Per corner whether its overshoot rises on some of the machines of ``errors``,
        from machine ``first`` on, over theirs without the correction; every corner where
        a corner is seen on one run only. The largest rise is kept in :attr:`held` [-]."""
        before = self.before[first:first + len(errors)]
        after, _ = self.overshoots(errors)
        if after.shape != before.shape:
            return np.ones(self.index.size, dtype=bool)
        up = after - before
        k, c = np.unravel_index(np.argmax(up), up.shape)
        if up[k, c] > equal_m and (self.held is None
                                   or up[k, c] * 1e6 > self.held["rise_um"]):
            p = self.path.positions
            self.held = {"at_mm": {a: float(p[a][self.index[c]] * 1e3) for a in p},
                         "machine": int(first + k), "before_um": float(before[k, c] * 1e6),
                         "refused_um": float(after[k, c] * 1e6),
                         "rise_um": float(up[k, c] * 1e6)}
        return np.any(up > equal_m, axis=0)

    def rising(self, errors: np.ndarray, equal_m: float) -> list[int]:
        """The regions of the corners whose overshoot rises on some machine by more than
        ``equal_m`` over its own without the correction [-].

        Parameters
        ----------
        errors : ndarray
            TCP error per machine (as without the correction), axis and sample [m].
        equal_m : float
            The rise below which an overshoot counts as the same: the sensors'
            resolution [m].
        """
        if self.index.size == 0:
            return []
        up = self._rises(errors, equal_m)
        return sorted(set(self.labels[self.index[up]].tolist()))


def held_entry(guard) -> dict:
    """``{"corner_held": guard.held}`` for a compensation's ``robustness`` where the guard
    held a rise back, else empty [-]."""
    return {} if guard is None or guard.held is None else {"corner_held": guard.held}


def mm_text(values_mm) -> str:
    """Coordinates in millimetres to the micrometre, ``x, y``, never ``-0.000`` [-]."""
    return ", ".join(f"{round(v, 3) + 0.0:.3f}" for v in values_mm)


def corner_place(at_mm) -> str:
    """`` at (x, y) mm`` of a corner's position, empty where it is not known [-]."""
    return "" if at_mm is None else f" at ({mm_text(at_mm)}) mm"


def held_words(held: dict) -> str:
    """What the guard held back (:attr:`CornerGuard.held`), as the console and the report
    say it [-]."""
    at = mm_text(held["at_mm"].values())
    on = "the model" if held["machine"] == 0 else f"draw {held['machine']}"
    return (f"held back at a corner: more of the correction runs the TCP past the corner at "
            f"({at}) mm by {held['refused_um']:.2f} µm on {on}, against "
            f"{held['before_um']:.2f} µm uncorrected; no share is kept that raises a "
            "corner's overshoot on any draw")
