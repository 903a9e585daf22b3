"""What an identified axis knows of its own accuracy: one standard deviation of each
determined quantity, from the fits that produced it.

- Mechanics: the physical fit's standard deviations, leaving out what the sweep does not
  determine. Where the friction runs replaced a value, their standard deviation replaces
  the fit's: the nut stiffness ``K_t`` from the nut estimate, the table damping ``C_t``
  from the speed-proportional deflection, the motor-side ``B_L`` from the Stribeck slope
  less ``C_t``; ``B_m``, taken as zero, is not varied. Each is then scaled by
  :data:`FIT_DEVIATION_SCALE`: a fit's deviation counts the noise of its bins as
  independent, while neighbouring bins of a Welch estimate are not and the model's own
  structure leaves residuals that are not noise.
- Friction: the relative standard deviation of the fitted Coulomb level, the guideway
  share (``inf`` when the runs do not determine it and the prior is used, 0 when the user
  gave it) and the lost motion.
"""

from __future__ import annotations

import math

from ..._datafile import read_data_json
from ...model import AxisUncertainty

__all__ = ["FIT_DEVIATION_SCALE", "axis_uncertainty"]


def _fit_deviation_scale() -> dict:
    """The factors of :data:`FIT_DEVIATION_SCALE` from the package's data file, which records
    their provenance."""
    return {k: float(v) for k, v in read_data_json("fit_deviation.json")["scale"].items()}


#: Factor per mechanical quantity on the standard deviation its fit reports, so that it
#: matches the real error: the median of |ln(identified/true)| over the relative deviation
#: is the normal's 0.674 on a drawn population whose truth is known
#: (``python -m studies.fit_deviation``; values and provenance in
#: ``tcpmm/data/fit_deviation.json``) [-].
FIT_DEVIATION_SCALE = _fit_deviation_scale()


def _finite(x) -> bool:
    return x is not None and math.isfinite(float(x))


def axis_uncertainty(phys, mechanics, curve=None, split=None,
                     presliding_fit=None) -> AxisUncertainty:
    """Standard deviations of an identified axis.

    Parameters
    ----------
    phys : PhysicalFit
        The physical fit the mechanics came from [-].
    mechanics : AxisMechanics
        The identified mechanics as they go into the model [SI].
    curve : ParameterEstimate, optional
        The Stribeck curve of the friction runs [-].
    split : FrictionSplit, optional
        Guideway share, lost motion and their estimates [-].
    presliding_fit : PreslidingFit, optional
        The pre-sliding fit; its range taken as four standard deviations of the
        logarithm [-].

    Returns
    -------
    AxisUncertainty
        One standard deviation of every determined quantity [SI].
    """
    names = [p for p in (phys.names or phys.std) if p not in phys.undetermined]
    mech = {p: float(phys.std[p]) for p in names
            if p in type(mechanics).model_fields and _finite(phys.std.get(p))}
    level = share = play = 0.0
    if curve is not None and split is not None:
        v = dict(zip(curve.names, curve.values, strict=True))
        sd = dict(zip(curve.names, curve.std, strict=True))
        fc = v["Fc+"] + v["Fc-"]
        if fc > 0 and _finite(sd["Fc+"]) and _finite(sd["Fc-"]):
            level = math.hypot(sd["Fc+"], sd["Fc-"]) / fc
        if split.source == "given":
            share = 0.0
        elif split.source in ("data", "sweep") and _finite(split.guideway_share_std):
            share = float(split.guideway_share_std)
        else:  # the prior, or a share whose spread is not known
            share = math.inf
        if split.backlash > 0 and _finite(split.backlash_std):
            play = float(split.backlash_std)
        if split.nut is not None and _finite(split.nut.stiffness_std):
            mech["K_t"] = float(split.nut.stiffness_std)
        ct = split.table_viscous_std
        if split.source != "prior" and _finite(ct) and _finite(sd.get("Fv")):
            mech["C_t"] = ct
            mech["B_L"] = math.hypot(sd["Fv"], ct) * mechanics.R_L**2
            mech.pop("B_m", None)
    mech = {p: sd * FIT_DEVIATION_SCALE.get(p, 1.0) for p, sd in mech.items()}
    return AxisUncertainty(mechanics=mech, friction_level=level, guideway_share=share,
                           backlash=play, presliding=_presliding_sd(presliding_fit))


def _presliding_sd(fit) -> float:
    """A quarter of the logarithm of the range a determined pre-sliding fit leaves, else 0
    (a distance given or assumed is not drawn) [-]."""
    if fit is None or not fit.determined:
        return 0.0
    lo, hi = fit.presliding_range
    return math.log(hi / lo) / 4.0 if _finite(lo) and _finite(hi) and 0 < lo <= hi else 0.0

