"""Machines drawn from what identification left uncertain.

An identified model carries one standard deviation of every quantity its data determine
(:class:`tcpmm.model.AxisUncertainty`). Each quantity is drawn normal about the identified
value (log-normal for the mechanics and the friction level, which stay positive). The
guideway share moves the friction between guideway and screw at the same total. With the
floors of :data:`MODEL_ERROR`, the quantities it names are drawn with the correlation their
errors have on the unseen machines (the table mass and the nut stiffness err together, the
share against the lost motion); the others, and all of them with the fits' deviations
alone, each on its own.
"""

from __future__ import annotations

import math

import numpy as np

from .._datafile import read_data_json
from ..model import Axis, Machine

__all__ = ["MODEL_ERROR", "draw_axis", "draw_machine", "drawn_machines", "longer_presliding",
           "scaled_contact"]


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


def drawn_machines(machine: Machine, n_draws: int, seed: int) -> list[Machine]:
    """The model and ``n_draws`` machines drawn from its uncertainty with the floors of
    ``tcpmm spread`` (:data:`MODEL_ERROR`), from ``seed`` [-]."""
    rng = np.random.default_rng(seed)
    return [machine] + [draw_machine(machine, rng, MODEL_ERROR) for _ in range(n_draws)]
