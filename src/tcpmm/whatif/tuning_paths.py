"""The figures a tuning proposal is judged by: the path of the model simulated with its
settings, reduced to the TCP's reversal spikes, contour error and G on a circle, or to its
distance from the commanded path on a program; NaN, with the fault, where the run is no
prediction.
"""

from __future__ import annotations

import warnings

import numpy as np

from ..analysis.circular import analyse_circle
from ..errors import InputError, InputWarning
from ..machines.paper import RADIUS_MM
from ..model import Machine
from ..servo.sampled import is_stable_radius, radius_text, sampled_spectral_radius
from ..sim.simulate import simulate
from ..units import mm_to_m

#: Command samples either side searched for the nearest command segment [-].
_WINDOW = 400


def polyline_distance(points, path) -> np.ndarray:
    """Distance of each point to the nearest segment of a path sampled alongside it.

    Parameters
    ----------
    points, path : ndarray (n, d)
        Actual and commanded positions at the same instants [m].

    Returns
    -------
    numpy.ndarray
        Distance per point to the commanded path within :data:`_WINDOW` samples [m].
    """
    n = path.shape[0]
    best = np.full(points.shape[0], np.inf)
    idx = np.arange(points.shape[0])
    for k in range(-_WINDOW, _WINDOW):
        i = np.clip(idx + k, 0, n - 2)
        a, b = path[i], path[i + 1]
        d = b - a
        L2 = np.einsum("ij,ij->i", d, d)
        t = np.where(L2 > 0, np.einsum("ij,ij->i", points - a, d) / np.where(L2 > 0, L2, 1), 0)
        q = a + np.clip(t, 0, 1)[:, None] * d
        best = np.minimum(best, np.linalg.norm(points - q, axis=1))
    return best


#: The figures of a circle pass and of a program's path [um].
CIRCLE_KEYS = ("spike_um", "contour_error_um", "circular_deviation_um")
PROGRAM_KEYS = ("max_deviation_um", "rms_deviation_um")


class PathFigures(dict):
    """:func:`path_figures`, and ``faults``: where the run is no prediction, what went
    wrong, per axis, in a few words; ``limited``: whether that is a current held at its
    limit [-]."""

    faults: tuple = ()
    limited: bool = False


def fault_words(f: dict) -> str:
    """A run's fault on one axis in a few words: the current held at its limit, else the
    axis running away [-]."""
    if f.get("saturated_s", 0.0) > 0.0:
        return f"axis {f['axis']} holds its current at the limit of {f['current_limit_A']:g} A"
    return f"axis {f['axis']} runs away from its command"


def path_figures(machine: Machine, command, circle: bool) -> dict:
    """Simulate and reduce to figures in um (:class:`PathFigures`): per circle pass the
    largest reversal spike, the contour error and G of the TCP; for a program the largest
    and RMS distance of the TCP path from the commanded path. NaN where the run is no
    prediction: a sampled loop is unstable, or an axis runs away or holds its current at
    the limit (:mod:`tcpmm.analysis.runaway`)."""
    keys = {"ccw": CIRCLE_KEYS, "cw": CIRCLE_KEYS} if circle else {"program": PROGRAM_KEYS}
    unstable = [f"axis {n}'s sampled servo loop is unstable (spectral radius {radius_text(rho)})"
                for n, a in machine.axes.items()
                if not is_stable_radius(rho := sampled_spectral_radius(a.mechanics, a.servo))]
    with warnings.catch_warnings():  # tune's trial runs: what they find is in its notes
        warnings.simplefilter("ignore", InputWarning)
        run = simulate(machine, command) if not unstable else None
    none = PathFigures({case: dict.fromkeys(k, float("nan")) for case, k in keys.items()})
    if unstable or run.meta.get("faults"):
        none.faults = unstable or [fault_words(f) for f in run.meta["faults"]]
        none.limited = not unstable and any(f.get("saturated_s", 0.0) > 0.0
                                            for f in run.meta["faults"])
        return none
    if circle:
        try:
            with warnings.catch_warnings():  # of tune's own circle, which the user runs not
                warnings.simplefilter("ignore", InputWarning)
                res = analyse_circle(run, mm_to_m(RADIUS_MM), sensors=("cmd", "tcp"),
                                     settling=False)
        except InputError:  # the command holds no circle: no figure of it
            return none
        out = PathFigures()
        for p in res.passes:
            s = p.sensors["tcp"]
            spikes = [abs(v) for v in s.spikes.values() if np.isfinite(v)]
            out[p.direction] = {"spike_um": max(spikes, default=float("nan")) * 1e6,
                                "contour_error_um": s.contour_error * 1e6,
                                "circular_deviation_um": s.circular_deviation * 1e6}
        return out
    names = [n for n in command.positions if n in run.axes]  # an axis held still may lack
    act = np.column_stack([run.axes[n].tcp for n in names])
    ref = np.column_stack([run.axes[n].cmd for n in names])
    d = polyline_distance(act, ref)
    blocks = command.blocks()  # the feed moves, as contour measures them: no G0 rapid
    if blocks is not None and blocks[1].size == d.size and not blocks[1].all():
        d = d[blocks[1] == 0]
    return PathFigures({"program": {"max_deviation_um": float(d.max()) * 1e6,
                                    "rms_deviation_um": float(np.sqrt(np.mean(d * d))) * 1e6}})
