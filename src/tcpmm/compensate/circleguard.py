"""The circular test's own figures on every draw of the model: the reversal spikes, each
and the largest, and the circular deviation G, which the contour error per region does
not bound.

A correction limited by the axes' acceleration can lower the contour error of every region
while it moves the TCP's radius unevenly round the circle: G and the spikes, read against
the TCP's own least-squares circle and the radius just before each quadrant point, then
grow although no region got worse. The robust choice (:mod:`.robust`) therefore judges
them as the circle's analysis does (:func:`tcpmm.analysis.circular.analyse_sensor`), on the
passes the command holds: the programmed command's for the uncompensated run, the delayed
path's for the compensated one, as :func:`.scores.runs_before_after` judges them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..analysis.circle_passes import find_stretches, within_span
from ..analysis.circle_spikes import QUADRANTS
from ..analysis.circular import analyse_sensor
from ..errors import InputError


@dataclass(frozen=True)
class CircleGuard:
    """Where a command holds its circles, and how to read their figures.

    Parameters
    ----------
    radius_m : float
        Nominal radius [m].
    centre_m : tuple of float
        Nominal centre in the plane [m].
    plane : tuple of int
        Indices of the plane's two axes in the command's axes [-].
    before, after : list of Stretch
        Passes of the programmed command and of the delayed path [-].
    angles : tuple of list
        Per pass of ``before`` and of ``after``, the path's unwrapped angle over it [rad].
    """

    radius_m: float
    centre_m: tuple
    plane: tuple
    before: list
    after: list
    angles: tuple = ((), ())

    @classmethod
    def of(cls, comp, radius_m: float, centre_m=(0.0, 0.0), plane=("X", "Y")):
        """The guard of a compensation's circle.

        Parameters
        ----------
        comp : Compensation
            The compensation [-].
        radius_m : float
            Nominal radius [m].
        centre_m : tuple of float
            Nominal centre [m].
        plane : tuple of str
            The plane's axes [-].
        """
        axes = list(comp.reference.axes)
        missing = [a for a in plane if a.upper() not in axes]
        if missing:
            raise InputError(f"the command has no axis {', '.join(missing)} of the circle")
        ij = tuple(axes.index(a.upper()) for a in plane)
        passes, angles = [], []
        for path in (comp.reference, comp.target):
            x, y = (path.positions[axes[k]] for k in ij)
            passes.append(find_stretches(x, y, radius_m, centre_m))
            angles.append([np.unwrap(np.arctan2(y[st.index] - centre_m[1],
                                                x[st.index] - centre_m[0]))
                           for st in passes[-1]])
        if not passes[0] or not passes[1]:
            raise InputError(f"the command holds no circle of radius {radius_m * 1e3:g} mm "
                             f"about {tuple(c * 1e3 for c in centre_m)} mm")
        return cls(radius_m, tuple(centre_m), ij, passes[0], passes[1], tuple(angles))

    def figures(self, tcp: np.ndarray, compensated: bool) -> np.ndarray:
        """Each pass's reversal spikes A-D (NaN where the pass does not cross the quadrant
        point), then the largest spike and the largest G over the passes, ``[A, B, C, D,
        ..., spike, G]`` [m].

        Parameters
        ----------
        tcp : ndarray
            TCP position per axis, shape (axes, n) [m].
        compensated : bool
            Judge on the delayed path's passes [-].
        """
        x, y = tcp[self.plane[0]], tcp[self.plane[1]]
        spike = g = 0.0
        each = []
        passes = self.after if compensated else self.before
        for st, ang in zip(passes, self.angles[1 if compensated else 0], strict=True):
            on = within_span(x, y, st.index, self.centre_m, ang)  # as the analysis takes it
            s = analyse_sensor(x[on], y[on], self.radius_m, self.centre_m, st.direction)
            sp = np.abs([s.spikes.get(k, np.nan) for k in QUADRANTS])
            each.extend(sp)
            spike = max(spike, float(np.nanmax(sp)) if np.isfinite(sp).any() else 0.0)
            g = max(g, s.circular_deviation)
        return np.array([*each, spike, g])

    def spike_samples(self) -> list:
        """Per spike of :meth:`figures` (pass by pass, A-D), the samples of the delayed
        path where its pass crosses that quadrant point: where a region's correction makes
        the spike worse [-]."""
        out = []
        for st, ang in zip(self.after, self.angles[1], strict=True):
            first = st.index.start or 0
            for q in np.radians(list(QUADRANTS.values())):
                turn = np.floor((ang - q) / (2.0 * np.pi))  # changes where the pass crosses q
                out.append(first + 1 + np.flatnonzero(np.diff(turn) != 0))
        return out
