"""Measured against predicted circular tests: the paper's Table 2, and point by point."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .circular import QUADRANTS, CircleResult


@dataclass
class Comparison:
    """Differences measured minus predicted per direction and sensor.

    Parameters
    ----------
    rows : list of dict
        Per direction and sensor: spike differences A-D, contour error difference, and the
        RMS / max of the point-by-point radial-error difference, all [um].
    """

    rows: list

    def to_pandas(self):
        """The Table-2 layout (um)."""
        import pandas as pd

        return pd.DataFrame(self.rows)

    def to_dict(self) -> dict:
        """JSON-ready rows (um)."""
        return {"rows": self.rows}


def _on_grid(angle, e, direction, grid):
    a = angle - angle[0]
    if direction == "cw":
        a = -a
    order = np.argsort(a)
    return np.interp(grid, a[order], e[order])


def compare_circles(measured: CircleResult, predicted: CircleResult) -> Comparison:
    """Table 2: for every direction and sensor in both, measured minus predicted.

    Parameters
    ----------
    measured, predicted : CircleResult
        Analyses of the measured and the predicted run [-].
    """
    rows = []
    for pm in measured.passes:
        try:
            pp = predicted.pass_for(pm.direction)
        except InputError:
            continue
        for name, sm in pm.sensors.items():
            if name not in pp.sensors or name == "cmd":
                continue
            sp = pp.sensors[name]
            row = {"direction": pm.direction.upper(), "sensor": name}
            for q in QUADRANTS:
                row[f"spike_{q}_um"] = (sm.spikes[q] - sp.spikes[q]) * 1e6
            row["contour_error_um"] = (sm.contour_error - sp.contour_error) * 1e6
            # Point by point on a common grid of travel angle from a common start angle.
            grid = np.linspace(0, 2 * np.pi, 721)[:-1]
            start = np.angle(np.exp(1j * sm.angle_rad[0]))
            em = _on_grid(sm.angle_rad - start, sm.radial_error, pm.direction, grid)
            ap = np.angle(np.exp(1j * (sp.angle_rad - start)))
            ap = np.unwrap(np.where(ap < -np.pi + 1e-9, ap + 2 * np.pi, ap))
            ep = _on_grid(ap, sp.radial_error, pm.direction, grid)
            d = em - ep
            row["radial_rms_um"] = float(np.sqrt(np.mean(d**2)) * 1e6)
            row["radial_max_um"] = float(np.max(np.abs(d)) * 1e6)
            rows.append(row)
    if not rows:
        raise InputError("the two runs share no circle direction and sensor to compare")
    return Comparison(rows)
