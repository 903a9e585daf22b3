"""Spread of a circular-test prediction over what identification left uncertain.

An identified model carries one standard deviation of every quantity its data determine
(:class:`tcpmm.model.AxisUncertainty`). :func:`circle_spread` draws machines from it,
simulates the command on each and analyses the circle: per direction and quadrant point,
the nominal spike, its range over the draws and how often it has the nominal sign.

Each quantity is drawn normal about the identified value (log-normal for the mechanics and
the friction level, which stay positive). The guideway share moves the friction between
guideway and screw at the same total. With the floors of :data:`MODEL_ERROR`, the quantities
it names are drawn with the correlation their errors have on the unseen machines (the table
mass and the nut stiffness err together, the share against the lost motion); the others,
and all of them with the fits' deviations alone, each on its own.

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

from .._datafile import read_data_json
from ..analysis.circular import QUADRANTS, analyse_circle
from ..errors import InputError
from ..model import Axis, Machine
from ..sim.simulate import simulate

__all__ = ["MODEL_ERROR", "SETTLED_FRACTION", "TOLERANCE", "SpikeSpread", "circle_spread",
           "draw_axis", "draw_machine", "longer_presliding", "scaled_contact"]

#: Share of the draws that must give the nominal sign for a spike to count as settled, and
#: that must lie within the tolerance of it for it to count as firm [-].
SETTLED_FRACTION = 0.9
#: Default tolerance of a spike: the largest measured-minus-predicted reversal spike of
#: the paper's Table 2 (4.1 um) [m].
TOLERANCE = 4.1e-6

def _model_error() -> dict:
    """The floors of :data:`MODEL_ERROR` from the package's data file, which records their
    provenance."""
    doc = read_data_json("model_error.json")
    return {k: doc[k] for k in ("mechanics", "friction_level", "guideway_share", "backlash",
                                "correlation")}


#: Floors of the standard deviations drawn from: the robust spread of identified over true
#: values on the axes with lost motion of the unseen-machine study; the fits' own standard
#: deviations count noise only and are often ten times smaller. Relative for the mechanics
#: and the friction level, absolute for the share [-] and the lost motion [m];
#: ``correlation`` holds the rank correlation of those errors. Values and provenance:
#: ``tcpmm/data/model_error.json``.
MODEL_ERROR = _model_error()


def _normals(floors: dict, rng):
    """The standard normal number of each quantity, as a function of its name: correlated
    as ``floors["correlation"]`` says for the quantities it names, drawn on its own for the
    others."""
    corr = floors.get("correlation")
    z = {}
    if corr is not None:
        L = np.linalg.cholesky(np.asarray(corr["matrix"], dtype=float))
        z = dict(zip(corr["quantities"], L @ rng.standard_normal(L.shape[0]), strict=True))

    def normal(name: str) -> float:
        return z[name] if name in z else rng.standard_normal()

    return normal


def scaled_contact(c, k: float):
    """A friction contact with its levels and viscous coefficients times ``k``.

    A LuGre contact keeps its pre-sliding displacement (``sigma0`` times ``k``) and its
    bristle damping ratio (``sigma1`` times ``sqrt(k)``).

    Parameters
    ----------
    c : StribeckFriction or LuGreFriction or None
        The contact [-].
    k : float
        Factor, 0 or more [-].

    Returns
    -------
    StribeckFriction or LuGreFriction or None
        The scaled contact; ``None`` for ``None`` or ``k == 0`` [-].
    """
    if c is None or k <= 0.0:
        return None
    d = c.model_dump()
    for n in ("fc_pos", "fc_neg", "fs_pos", "fs_neg", "fv_pos", "fv_neg"):
        d[n] = d[n] * k
    if "sigma0" in d:
        d["sigma0"] *= k
        d["sigma1"] *= math.sqrt(k)
    return type(c)(**d)


def _friction(fr, u, floors, rng, normal):
    """Friction with a drawn level, guideway share, lost motion and pre-sliding distance
    (``normal``: the standard normal number of a quantity, :func:`_normals`)."""
    if fr.guideway is None and fr.screw is None:
        return fr
    level = math.exp(max(u.friction_level, floors.get("friction_level", 0.0))
                     * normal("friction_level"))
    size = [0.0 if c is None else c.fc_pos + c.fc_neg for c in (fr.guideway, fr.screw)]
    share = size[0] / sum(size) if sum(size) > 0 else 0.5
    if math.isinf(u.guideway_share):
        new = float(rng.uniform(0.0, 1.0))
    else:
        sd = max(u.guideway_share, floors.get("guideway_share", 0.0))
        new = min(max(share + sd * normal("guideway_share"), 0.0), 1.0)
    # each contact keeps its shape; one that carried nothing borrows the other's
    g = fr.guideway if fr.guideway is not None else scaled_contact(fr.screw, 1e-9)
    w = fr.screw if fr.screw is not None else scaled_contact(fr.guideway, 1e-9)
    if sum(size) > 0.0:
        size = [max(x, 1e-9 * sum(size)) for x in size]
        k_g, k_s = level * new * sum(size) / size[0], level * (1.0 - new) * sum(size) / size[1]
    else:
        k_g = k_s = level
    sd = max(u.backlash, floors.get("backlash", 0.0)) if fr.backlash > 0 else u.backlash
    play = max(fr.backlash + sd * normal("backlash"), 0.0)
    k_z = math.exp(u.presliding * normal("presliding")) if u.presliding > 0 else 1.0
    return fr.model_copy(update={"guideway": longer_presliding(scaled_contact(g, k_g), k_z),
                                 "screw": longer_presliding(scaled_contact(w, k_s), k_z),
                                 "backlash": min(play, 1e-3)})


def longer_presliding(c, k: float):
    """A LuGre contact with its pre-sliding distance times ``k`` and its bristle damping
    ratio kept (``sigma0 / k``, ``sigma1 / sqrt(k)``); others as they are.

    Parameters
    ----------
    c : LuGreFriction or None
        The contact; anything without ``sigma0`` is returned as it is [-].
    k : float
        Factor on the pre-sliding distance [-].
    """
    if k == 1.0 or c is None or not hasattr(c, "sigma0"):
        return c
    return c.model_copy(update={"sigma0": c.sigma0 / k, "sigma1": c.sigma1 / math.sqrt(k)})


def draw_axis(axis: Axis, rng: np.random.Generator, floors: dict | None = None) -> Axis:
    """One axis drawn from its identified uncertainty (itself when it has none).

    Parameters
    ----------
    axis : Axis
        An identified axis [SI].
    rng : numpy.random.Generator
        Random numbers [-].
    floors : dict, optional
        Smallest standard deviations and their correlation, laid out as
        :data:`MODEL_ERROR`; ``None``: the identified ones alone, each drawn on its own [-].

    Returns
    -------
    Axis
        The drawn axis, without an uncertainty of its own [SI].
    """
    u = axis.uncertainty
    if u is None:
        return axis
    floors = floors or {}
    normal = _normals(floors, rng)
    m = axis.mechanics
    rel = {p: sd / getattr(m, p) for p, sd in u.mechanics.items() if getattr(m, p) > 0.0}
    for p, f in floors.get("mechanics", {}).items():
        rel[p] = max(rel.get(p, 0.0), f)
    upd = {p: getattr(m, p) * math.exp(r * normal(p))
           for p, r in rel.items() if r > 0.0 and getattr(m, p) > 0.0}
    fr = axis.friction
    if fr is not None:
        fr = _friction(fr, u, floors, rng, normal)
    return axis.replace(mechanics=m.replace(**upd), friction=fr, uncertainty=None)


def draw_machine(machine: Machine, rng: np.random.Generator,
                 floors: dict | None = None) -> Machine:
    """Every axis of a machine drawn from its uncertainty (:func:`draw_axis`)."""
    return machine.model_copy(update={"axes": {n: draw_axis(a, rng, floors)
                                               for n, a in machine.axes.items()}})


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
    """

    nominal: object
    directions: list
    spikes: np.ndarray
    contour_error: np.ndarray
    sensor: str
    tolerance: float = TOLERANCE

    def rows(self) -> list[dict]:
        """One row per pass and quadrant point, in um: nominal spike, rise and fall,
        lowest and highest over the draws; the share of the draws with the nominal sign
        (``same_sign``, ``settled`` when it reaches :data:`SETTLED_FRACTION`) and the share
        within the tolerance of the nominal spike (``within``, ``firm`` likewise)."""
        out = []
        for i, (d, p) in enumerate(zip(self.directions, self.nominal.passes, strict=True)):
            s = p.sensors[self.sensor]
            for j, q in enumerate(QUADRANTS):
                nom, draws = s.spikes[q], self.spikes[:, i, j]
                ok = draws[np.isfinite(draws)]
                same = float(np.mean(np.sign(ok) == np.sign(nom))) if ok.size else math.nan
                near = (float(np.mean(np.abs(ok - nom) <= self.tolerance)) if ok.size
                        else math.nan)
                rise, fall = s.lobes[q]
                out.append({
                    "direction": d, "point": q, "spike_um": nom * 1e6,
                    "rise_um": rise * 1e6, "fall_um": fall * 1e6,
                    "low_um": float(ok.min()) * 1e6 if ok.size else math.nan,
                    "high_um": float(ok.max()) * 1e6 if ok.size else math.nan,
                    "same_sign": same, "settled": bool(same >= SETTLED_FRACTION),
                    "within": near, "firm": bool(near >= SETTLED_FRACTION)})
        return out

    def unsettled(self) -> list[dict]:
        """The rows whose spike sign the draws do not settle (a point without a spike, as
        one on a feed-in, has nothing to settle and is left out)."""
        return [r for r in self.rows() if math.isfinite(r["spike_um"]) and not r["settled"]]

    def loose(self) -> list[dict]:
        """The rows whose sign is settled but whose size too few draws hold within the
        tolerance."""
        return [r for r in self.rows() if r["settled"] and not r["firm"]]

    def to_pandas(self):
        """:meth:`rows` as a table."""
        import pandas as pd

        return pd.DataFrame(self.rows())

    def to_dict(self) -> dict:
        """JSON-ready summary in um."""
        ce = self.contour_error
        return {"sensor": self.sensor, "draws": int(self.spikes.shape[0]),
                "tolerance_um": self.tolerance * 1e6, "spikes": self.rows(),
                "contour_error": [
                    {"direction": d,
                     "nominal_um": p.sensors[self.sensor].contour_error * 1e6,
                     "low_um": float(np.nanmin(ce[:, i])) * 1e6,
                     "high_um": float(np.nanmax(ce[:, i])) * 1e6}
                    for i, (d, p) in enumerate(zip(self.directions, self.nominal.passes,
                                                   strict=True))]}

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
        Number of drawn machines [-].
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
    if n < 1:
        raise InputError(f"the number of draws must be 1 or more, got {n}", column="n")
    if not tolerance_m > 0.0:
        raise InputError(f"the tolerance must be positive, got {tolerance_m} m",
                         column="tolerance")
    if all(a.uncertainty is None for a in machine.axes.values()):
        raise InputError(
            f"machine '{machine.name}' carries no uncertainty: the spread needs a model "
            "written by `tcpmm identify`")

    def circle(m):
        res = analyse_circle(simulate(m, command), radius_m, centre_m)
        if progress is not None:
            progress()
        return res

    nominal = circle(machine)
    if not nominal.passes:
        raise InputError("the command holds no full circle of that radius and centre")
    if sensor not in nominal.passes[0].sensors:
        raise InputError(f"the run has no {sensor} signal; sensors: "
                         f"{', '.join(nominal.passes[0].sensors)}", column="sensor")
    directions = [p.direction for p in nominal.passes]
    spikes = np.full((n, len(directions), len(QUADRANTS)), np.nan)
    ce = np.full((n, len(directions)), np.nan)
    rng = np.random.default_rng(seed)
    for k in range(n):
        res = circle(draw_machine(machine, rng, floors))
        for i, d in enumerate(directions):
            same = [p for p in res.passes if p.direction == d]
            rank = directions[:i].count(d)
            if rank < len(same):
                s = same[rank].sensors[sensor]
                spikes[k, i] = [s.spikes[q] for q in QUADRANTS]
                ce[k, i] = s.contour_error
    return SpikeSpread(nominal, directions, spikes, ce, sensor, tolerance_m)
