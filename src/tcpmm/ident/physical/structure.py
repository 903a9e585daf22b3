"""The structure of an axis from ``G_tcp`` alone: bed and TCP structure relative to the table.

``G_tcp = X_TCP / X_LS = (G_t - G_h) / (G_t - G_b)`` (physics.md section 1) holds whatever
the nut force is: the nut force drives table, bed and structure alike and cancels. So
``G_tcp`` is the one response of a sweep that lost motion in the nut does not distort,
while ``G_M`` and ``G_T`` see a nut that is softer the more the vibration crosses the play.
In a joint fit of all three, a distorted ``G_T`` can pull the bed (whose motion the scale
reads) far from what ``G_tcp`` says; on axes with a few micrometres of play ``M_b`` came out
at a tenth of the truth although the measured ``G_tcp`` matched the true one within 2 %.

``G_tcp`` is unchanged when all masses, dampings and stiffnesses are scaled alike, so it
gives the structure relative to the table mass: ``M_b/M_t``, ``C_b/M_t``, ``K_b/M_t`` and the
same for the TCP structure. :func:`fit_structure` fits them with ``M_t`` held; a joint fit
can then keep them (``structure=`` of :func:`tcpmm.ident.physical.greybox.fit_physical`).
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import least_squares

from ...mechanics.lumped import AxisMechanics
from ..lti.goodness import rel_error
from .axisfrfs import model_frfs
from .fitdata import FRFData, band_model, fit_weight, log_binned, log_residual
from .greybox import TIGHT, log_covariance
from .jacobian import residual_jacobian

__all__ = ["STRUCTURE", "fit_structure"]

#: Parameters that ``G_tcp`` fixes relative to ``M_t`` (``C_t`` is fitted with them but
#: not kept: it is the table's damping, which the nut also sees).
STRUCTURE = ("M_b", "C_b", "K_b", "M_h", "C_h", "K_h")
_FREE = ("C_t", *STRUCTURE)


def fit_structure(data: FRFData, starts, max_nfev: int = 200):
    """Bed and TCP structure relative to the table mass from ``G_tcp`` alone.

    Parameters
    ----------
    data : FRFData
        Measured ``G_tcp`` with its weights [-].
    starts : sequence of AxisMechanics
        Starting points (e.g. the joint fit and its start values); each is refined and the
        one that fits ``G_tcp`` best is kept [SI].
    max_nfev : int
        Function evaluations of the refinement of the best start [-].

    Returns
    -------
    ratios : dict
        ``{p: value / M_t}`` for ``p`` in :data:`STRUCTURE` [1, 1/s, 1/s^2].
    rel_error : float
        RMS relative complex error of ``G_tcp`` at the fit [-].
    log_std : dict
        Deviation of the logarithm of each ratio, ``nan`` where held at a bound [-].
    """
    d = log_binned(data)
    good = np.asarray(d.weight) > 0
    f, H, w = d.freq_hz[good], d.H[good], fit_weight(d)[good]
    points = FRFData(f, H, w, None if d.spread_hz is None else d.spread_hz[good]).band_points()

    def mech_of(theta, base):
        return AxisMechanics.model_construct(**{**base, **dict(zip(_FREE, np.exp(theta),
                                                                   strict=True))})

    last = {}  # the model and residual at the last point: the Jacobian is taken there

    def resid(theta, base):
        g = model_frfs(mech_of(theta, base), {"G_tcp": points})["G_tcp"]
        last.update(x=np.array(theta), base=base, g=g, r=log_residual(band_model(g), H, w))
        return last["r"]

    def jac(theta, base):
        if last.get("base") is not base or not np.array_equal(last["x"], theta):
            resid(theta, base)
        return residual_jacobian(mech_of(theta, base), {"G_tcp": points}, {"G_tcp": w},
                                 last["r"], _FREE, {}, pairs={"G_tcp": last["g"]})

    best = None
    for mech in starts:
        base = mech.model_dump()
        theta0 = np.log([max(base[p], 1e-12) for p in _FREE])
        bounds = (theta0 - np.log(1e3), theta0 + np.log(1e3))
        r = least_squares(resid, theta0, jac=jac, args=(base,), bounds=bounds, max_nfev=40,
                          method="trf")
        if best is None or r.cost < best[0].cost:
            best = (r, base, bounds)
    r, base, bounds = best
    r = least_squares(resid, r.x, jac=jac, args=(base,), bounds=bounds, max_nfev=max_nfev,
                      method="trf", **TIGHT)
    vals = dict(zip(_FREE, np.exp(r.x), strict=True))
    ratios = {p: float(vals[p] / base["M_t"]) for p in STRUCTURE}
    m = AxisMechanics.model_construct(**{**base, **vals})
    return ratios, rel_error(H, model_frfs(m, {"G_tcp": f})["G_tcp"]), _ratio_log_std(r)


def _ratio_log_std(r) -> dict:
    """The deviation of the logarithm of each ratio of :data:`STRUCTURE` at the
    ``least_squares`` result ``r``; ``nan`` where it is held at a bound, where the cost
    does not rise across it and its linearised deviation says nothing [-]."""
    sd_log, _ = log_covariance(r)
    sd_log = np.where(np.asarray(r.active_mask) != 0, np.nan, sd_log)
    return {p: float(x) for p, x in zip(_FREE, sd_log, strict=True) if p in STRUCTURE}
