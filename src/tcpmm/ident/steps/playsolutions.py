"""The refits with the play of the nut as one fit: the solutions of their own describing
functions found from several starts, with the fits that explain the FRFs as well as them
(:func:`tcpmm.ident.steps.playrefit.rival_fits`) in the spread their parameters carry."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ...io.csvutil import warn_input
from ..identification import AxisFit
from ..physical.uncertainty import FIT_DEVIATION_SCALE
from .fitcontext import FitContext, friction_on


def log_spread(centre: float, values: list) -> float:
    """Root-mean-square distance of the logarithms of ``values`` from ``centre``, over one
    less than their number: their sample deviation where ``centre`` is their mean [-]."""
    x = np.log(np.asarray(values, dtype=float))
    return float(np.sqrt(np.sum((x - centre) ** 2) / (x.size - 1)))


def joint_fit(ctx: FitContext, modelled: list, rivals: list = ()) -> AxisFit:
    """Distinct solutions of their own describing functions as one fit: each fitted
    parameter at their geometric mean, its standard deviation widened by its spread over
    the solutions and the rivals, the describing function of the solution nearest in table
    mass, and the friction runs on it; a warning where they are more than one.

    Parameters
    ----------
    ctx : FitContext
        The axis's known values, TF fits, hold and friction runs [-].
    modelled : list of AxisFit
        The refits with the play, each a solution of its own describing function, their
        table masses more than 5 % apart [SI].
    rivals : list of PhysicalFit
        Refits with the play that are not solutions of their describing functions and
        explain the FRFs as well as the solutions [SI].
    """
    if len(modelled) == 1 and not rivals:
        return modelled[0]
    mid = modelled[0].physical
    mean, spread = {}, {}
    for p in mid.names:
        v = np.array([getattr(m.physical.mechanics, p, np.nan) for m in modelled])
        w = [getattr(r.mechanics, p, np.nan) for r in rivals]
        if v.size and np.all(v > 0) and np.all(np.asarray(w) > 0):
            centre = np.mean(np.log(v))
            # one solution is kept as it is, not through its logarithm's rounding
            mean[p] = float(v[0] if v.size == 1 else np.exp(centre))
            spread[p] = mean[p] * log_spread(centre, [*v, *w])
    near = min(modelled, key=lambda m: abs(math.log(m.physical.mechanics.M_t / mean["M_t"])))
    phys = near.physical
    # the reported deviation is the fit's scaled to the real error; the spread is one
    std = {p: math.hypot(sd, spread.get(p, 0.0) / FIT_DEVIATION_SCALE.get(p, 1.0))
           for p, sd in phys.std.items()}
    wide = sorted({*phys.undetermined,
                   *(p for p in mean if std.get(p, 0.0) > 0.5 * mean[p])})
    fused = dataclasses.replace(phys, mechanics=phys.mechanics.replace(**mean), std=std,
                                undetermined=wide)
    kept = AxisFit(fused, *friction_on(ctx, fused))
    split = kept.split
    if split.nut is not None and len(modelled) > 1:
        kt = np.log([m.mechanics.K_t for m in modelled])
        nut = dataclasses.replace(split.nut, stiffness_std=math.hypot(
            split.nut.stiffness_std,
            kept.mechanics.K_t * float(np.std(kt, ddof=1)) / FIT_DEVIATION_SCALE["K_t"]))
        kept = dataclasses.replace(kept, split=dataclasses.replace(split, nut=nut))
    warn_play_solutions(ctx.name, [m.physical.mechanics.M_t for m in modelled],
                        [r.mechanics.M_t for r in rivals], mean["M_t"],
                        std["M_t"] * FIT_DEVIATION_SCALE["M_t"])
    return kept


def warn_play_solutions(name: str, masses: list, rivals: list, mean: float,
                        std: float) -> None:
    """Warn that the refits with the play settle on table masses the FRFs cannot tell
    apart, and that their spread is in the reported uncertainty.

    Parameters
    ----------
    name : str
        Axis name [-].
    masses : list of float
        Table masses of the solutions [kg].
    rivals : list of float
        Table masses of the fits that explain the FRFs as well without being solutions [kg].
    mean : float
        The solutions' geometric mean, the table mass kept [kg].
    std : float
        Its reported standard deviation, the spread included [kg].
    """
    settle = (f"settle on table masses from {min(masses):.3g} to {max(masses):.3g} kg: the "
              "describing function of the play has several solutions"
              if len(masses) > 1 else f"settle on a table mass of {masses[0]:.3g} kg")
    also = (f"; refits with the play at other table masses explain the FRFs as well with "
            f"{min(rivals):.3g} to {max(rivals):.3g} kg" if rivals else "")
    warn_input(
        f"axis {name}: the refits with the play of the nut {settle}{also}, and the sweep "
        "does not tell them apart. M_t is reported as "
        f"{'their mean' if len(masses) > 1 else 'that solution'}, {mean:.3g} +/- {std:.2g} "
        "kg, their spread included, with the parameters held to it; a larger excitation "
        "amplitude (within the current limit) makes the play a smaller part of the "
        "vibration")
