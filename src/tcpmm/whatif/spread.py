"""Spread of a circular-test prediction over what identification left uncertain.

An identified model carries one standard deviation of every quantity its data determine
(:class:`tcpmm.model.AxisUncertainty`). :func:`circle_spread` draws machines from it
(:mod:`tcpmm.whatif.draws`), simulates the command on each and analyses the circle: per
direction and quadrant point, the nominal spike, its range over the draws and how often it
has the nominal sign.

Where lost motion or friction makes the spike the larger of an outward and an inward lobe
of similar size, a small change of the model turns its sign, and a measured spike can then
differ from the prediction by the sum of the lobes: such quadrant points are reported as
not settled. Where the sign holds, the size can still hang on what is uncertain (with lost
motion, the friction share decides when the nut leaves its flank): points where fewer than
nine in ten draws lie within a tolerance of the nominal spike (:data:`TOLERANCE`) are
reported as not firm.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..analysis.circle_inputs import sensor_name
from ..analysis.circular import QUADRANTS, analyse_circle
from ..errors import InputError
from ..model import Machine
from ..result import json_ready
from ..sim.simulate import simulate
from .draws import MODEL_ERROR, draw_axis, draw_machine, longer_presliding, scaled_contact

# the draws are named here too: the sweep, the studies and the tests take them from here
__all__ = ["MIN_DRAWS", "MODEL_ERROR", "SETTLED_FRACTION", "TOLERANCE", "SpikeSpread",
           "circle_spread", "draw_axis", "draw_machine", "longer_presliding", "scaled_contact"]

#: Share of the draws that must give the nominal sign for a spike to count as settled, and
#: that must lie within the tolerance of it for it to count as firm [-].
SETTLED_FRACTION = 0.9
#: Fewest draws a spread takes: nine in ten of them must agree for a point to be settled
#: or firm, and fewer than ten cannot show nine in ten (two of two would call every point
#: settled) [-].
MIN_DRAWS = 10
#: How the draws and the verdicts differ, said beside the draws' table (command line and
#: report): the same spike has an interval of each, and they answer different questions.
DRAWS_NOTE = ("The draws and the verdicts answer two questions: the draws widen every "
              "quantity to at least the error identification made on machines it had not "
              "seen (the floors), whatever this model's own fit says, and are held to the "
              "spread's tolerance (4.1 µm unless given); the verdicts are this model's 90 % "
              "intervals, calibrated on machines of known truth, count what the data leave "
              "open (as the pre-sliding), which the draws do not vary, and call a figure "
              "firm only within 1 µm (or 1 %); so either may flag a figure the other passes")
#: Default tolerance of a spike: the largest measured-minus-predicted reversal spike of
#: the paper's Table 2 (4.1 um) [m].
TOLERANCE = 4.1e-6


@dataclass
class SpikeSpread:
    """Reversal spikes of a circular test: nominal and over draws of the model.

    Parameters
    ----------
    nominal : CircleResult
        Circular test of the model as identified [-].
    directions : list of str
        Direction of each pass of the nominal circle [-].
    spikes : numpy.ndarray
        Signed spike per draw, pass and quadrant point A-D, shape ``(n, passes, 4)``;
        NaN where a draw's run has no such pass [m].
    contour_error : numpy.ndarray
        Contour error per draw and pass, shape ``(n, passes)`` [m].
    sensor : str
        The sensor analysed [-].
    tolerance : float
        Distance from the nominal spike within which a draw counts as agreeing [m].
    faulted : int
        Draws whose run is no prediction (a servo loop ran away, or the current held at
        its limit): their figures are NaN, so they count against every point [-].
    """

    nominal: object
    directions: list
    spikes: np.ndarray
    contour_error: np.ndarray
    sensor: str
    tolerance: float = TOLERANCE
    faulted: int = 0

    def rows(self) -> list[dict]:
        """One row per pass and quadrant point, in um: nominal spike, rise and fall,
        lowest and highest over the draws; the share of the draws with the nominal sign
        (``same_sign``, ``settled`` when it reaches :data:`SETTLED_FRACTION`) and the share
        within the tolerance of the nominal spike (``within``, ``draws_agree`` likewise;
        ``firm``, the same, is deprecated: the verdict's firm is another question)."""
        out = []
        for i, (d, p) in enumerate(zip(self.directions, self.nominal.passes, strict=True)):
            s = p.sensors[self.sensor]
            for j, q in enumerate(QUADRANTS):
                nom, draws = s.spikes[q], self.spikes[:, i, j]
                ok = draws[np.isfinite(draws)]
                n = ok.size + self.faulted  # a draw that is no prediction holds nothing
                same = float(np.sum(np.sign(ok) == np.sign(nom))) / n if n else math.nan
                near = (float(np.sum(np.abs(ok - nom) <= self.tolerance)) / n if n
                        else math.nan)
                rise, fall = s.lobes[q]
                out.append({
                    "direction": d, "point": q, "spike_um": nom * 1e6,
                    "rise_um": rise * 1e6, "fall_um": fall * 1e6,
                    "low_um": float(ok.min()) * 1e6 if ok.size else math.nan,
                    "high_um": float(ok.max()) * 1e6 if ok.size else math.nan,
                    "same_sign": same, "settled": bool(same >= SETTLED_FRACTION),
                    "within": near, **dict.fromkeys(("draws_agree", "firm"),
                                                     bool(near >= SETTLED_FRACTION))})
        return out

    def unsettled(self) -> list[dict]:
        """The rows whose spike sign the draws do not settle (a point without a spike, as
        one on a feed-in, has nothing to settle and is left out)."""
        return [r for r in self.rows() if math.isfinite(r["spike_um"]) and not r["settled"]]

    def loose(self) -> list[dict]:
        """The rows whose sign is settled but whose size too few draws hold within the
        tolerance."""
        return [r for r in self.rows() if r["settled"] and not r["draws_agree"]]

    def to_pandas(self):
        """:meth:`rows` as a table."""
        import pandas as pd

        return pd.DataFrame(self.rows())

    def to_dict(self) -> dict:
        """JSON-ready summary in um; a figure left out (NaN) is ``None``."""
        ce = self.contour_error
        return json_ready({"sensor": self.sensor, "draws": int(self.spikes.shape[0]),
                "faulted_draws": int(self.faulted),
                "tolerance_um": self.tolerance * 1e6, "spikes": self.rows(),
                "contour_error": [
                    {"direction": d,
                     "nominal_um": p.sensors[self.sensor].contour_error * 1e6,
                     "low_um": _extreme(np.nanmin, ce[:, i]) * 1e6,
                     "high_um": _extreme(np.nanmax, ce[:, i]) * 1e6}
                    for i, (d, p) in enumerate(zip(self.directions, self.nominal.passes,
                                                   strict=True))]})

    def plot(self, ax=None, path=None):
        """Nominal spikes with their range over the draws, per direction; the figure.

        Parameters
        ----------
        ax : matplotlib Axes or array-like of Axes, optional
            One per direction; a new figure when omitted [-].
        path : str or Path, optional
            Also save it there (PNG/PDF/SVG) [-].
        """
        from ..plot.spread import plot_spike_spread  # tcpmm.plot is a floor above this one

        return plot_spike_spread(self, path, ax=ax)


def _check_spread(machine: Machine, n: int, tolerance_m: float) -> None:
    """Refuse a spread of fewer than :data:`MIN_DRAWS` draws, a tolerance that is not
    positive, or a model without uncertainty to draw from.

    Parameters
    ----------
    machine : Machine
        The model [SI].
    n : int
        Number of drawn machines [-].
    tolerance_m : float
        Distance within which a draw agrees with the nominal spike [m].
    """
    if n < MIN_DRAWS:
        raise InputError(
            f"the number of draws must be {MIN_DRAWS} or more, got {n}: a point is settled "
            f"where nine in ten draws agree, which fewer than {MIN_DRAWS} cannot show",
            column="n")
    if not tolerance_m > 0.0:
        raise InputError(f"the tolerance must be positive, got {tolerance_m} m",
                         column="tolerance")
    if all(a.uncertainty is None for a in machine.axes.values()):
        raise InputError(
            f"machine '{machine.name}' carries no uncertainty: the spread needs a model "
            "written by `tcpmm identify`")


def _drawn_figures(circle, machine: Machine, directions: list, n: int, seed: int, floors,
                   sensor: str) -> tuple[np.ndarray, np.ndarray]:
    """The spikes and contour errors of ``n`` machines drawn from a model's uncertainty.

    Parameters
    ----------
    circle : callable
        The circular test of a machine's run of the command, ``None`` where the run is
        no prediction [-].
    machine : Machine
        The model [SI].
    directions : list of str
        The nominal run's passes, in order [-].
    n : int
        Number of drawn machines [-].
    seed : int
        Seed of the draws [-].
    floors : dict or None
        Smallest standard deviations drawn from [SI].
    sensor : str
        Sensor whose figures are taken [-].

    Returns
    -------
    spikes : ndarray, shape (n, passes, quadrants)
        Each draw's spike per pass and quadrant point, NaN where the draw lacks the
        pass [m].
    ce : ndarray, shape (n, passes)
        Each draw's contour error per pass, NaN where it lacks the pass [m].
    faulted : int
        Draws whose run is no prediction (``circle`` gives ``None``): all NaN [-].
    """
    spikes = np.full((n, len(directions), len(QUADRANTS)), np.nan)
    ce = np.full((n, len(directions)), np.nan)
    rng = np.random.default_rng(seed)
    faulted = 0
    for k in range(n):
        res = circle(draw_machine(machine, rng, floors))
        if res is None:  # no prediction: NaN, which agrees with no nominal figure
            faulted += 1
            continue
        for i, d in enumerate(directions):
            same = [p for p in res.passes if p.direction == d]
            rank = directions[:i].count(d)
            if rank < len(same):
                s = same[rank].sensors[sensor]
                spikes[k, i] = [s.spikes[q] for q in QUADRANTS]
                ce[k, i] = s.contour_error
    return spikes, ce, faulted


def _nominal(nominal, sensor: str):
    """The model's own circle, refused where it is no prediction or holds no circle [-]."""
    if nominal is None:
        raise InputError("the model's run of the circle is no prediction: a servo loop runs "
                         "away or the current holds at its limit (tcpmm simulate says "
                         "which); check the gains, the current limit and the load")
    if not nominal.passes:
        raise InputError("the command holds no full circle of that radius and centre")
    if sensor not in nominal.passes[0].sensors:
        raise InputError(f"the run has no {sensor} signal; sensors: "
                         f"{', '.join(nominal.passes[0].sensors)}", column="sensor")
    return nominal


def _extreme(f, values: np.ndarray) -> float:
    """``f`` (nanmin, nanmax) of the finite ``values``, NaN where there are none [-]."""
    return float(f(values)) if np.isfinite(values).any() else math.nan


def circle_spread(machine: Machine, command, radius_m: float, centre_m=(0.0, 0.0),
                  n: int = 16, seed: int = 0, sensor: str = "tcp",
                  floors: dict | None = MODEL_ERROR, tolerance_m: float = TOLERANCE,
                  progress=None) -> SpikeSpread:
    """Circular test of a model and of ``n`` machines drawn from its uncertainty.

    Parameters
    ----------
    machine : Machine
        The model, with the uncertainty identification gave its axes [SI].
    command : Command
        The position command of the circle [m].
    radius_m : float
        Nominal radius [m].
    centre_m : tuple of float
        Nominal centre [m].
    n : int
        Number of drawn machines, at least :data:`MIN_DRAWS` [-].
    seed : int
        Seed of the draws [-].
    sensor : str
        Sensor whose spikes are reported: ``tcp``, ``scale``, ``motor`` or ``cmd`` [-].
    floors : dict, optional
        Smallest standard deviations drawn from (:data:`MODEL_ERROR`); ``None``: the
        identified ones alone [-].
    tolerance_m : float
        Distance from the nominal spike within which a draw agrees with it
        (:data:`TOLERANCE`) [m].
    progress : callable, optional
        Called with no argument after each simulation [-].

    Returns
    -------
    SpikeSpread
        Nominal figures and their spread [-].
    """
    _check_spread(machine, n, tolerance_m)
    sensor = sensor_name(sensor)

    def circle(m):
        """The circle of ``m``, ``None`` where its run is no prediction."""
        run = simulate(m, command)
        if progress is not None:
            progress()
        # the sensor alone, as the verdict analyses it: a point one other sensor's window
        # misses by a sample is left out for all, and the verdict gave a spike the table
        # said was not there
        return None if run.meta.get("faults") else analyse_circle(
            run, radius_m, centre_m, sensors=tuple(dict.fromkeys(("cmd", sensor))),
            settling=False)

    nominal = _nominal(circle(machine), sensor)
    directions = [p.direction for p in nominal.passes]
    spikes, ce, faulted = _drawn_figures(circle, machine, directions, n, seed, floors, sensor)
    return SpikeSpread(nominal, directions, spikes, ce, sensor, tolerance_m, faulted)
