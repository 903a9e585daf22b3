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
from .covariance import held_at_bound, log_covariance
from .fitdata import FRFData, band_model, fit_weight, log_binned, log_residual
from .greybox import TIGHT
from .jacobian import residual_jacobian

__all__ = ["STIFFNESS_FLOOR", "STRUCTURE", "beyond_band_starts", "fit_structure"]

#: Parameters that ``G_tcp`` fixes relative to ``M_t`` (``C_t`` is fitted with them but
#: not kept: it is the table's damping, which the nut also sees).
STRUCTURE = ("M_b", "C_b", "K_b", "M_h", "C_h", "K_h")
_FREE = ("C_t", *STRUCTURE)
#: Damping ratio of a structure started out of the band: that of bolted and guided
#: machine structures, within the range they span [-].
START_ZETA = 0.05
#: Least stiffness of a structure started out of the band, per structure: a slender
#: column's (10 N/um) and a bed's on soft levelling elements (100 N/um). Below the band a
#: mode's stiffness barely shows, and the fit would soften it without end [N/m].
STIFFNESS_FLOOR = {"h": 1e7, "b": 1e8}


def fit_structure(data: FRFData, starts, max_nfev: int = 200):
    """Bed and TCP structure relative to the table mass from ``G_tcp`` alone.

    Where the best start leaves a structure's mass or stiffness at a bound of the fit (a
    mode the band does not show, collapsed onto the table or the bed), the structure is
    also started with its mode below and above the band (:func:`beyond_band_starts`):
    below, its mass line still shows in the band, and a fit that collapsed the head puts
    its inertia into the bed instead. The lower cost is kept.

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
    fit = _StructureFit(FRFData(f, H, w, None if d.spread_hz is None
                                else d.spread_hz[good]).band_points(), H, w)
    r, base = fit.best(starts, max_nfev)
    collapsed = _collapsed(r)
    if collapsed:
        moved = beyond_band_starts(fit.mech(r.x, base), collapsed, f[0], f[-1])
        again, again_base = fit.best(moved, max_nfev, floor=True)
        if again.cost < r.cost:
            r, base = again, again_base
    vals = fit.values(r.x)
    ratios = {p: float(vals[p] / base["M_t"]) for p in STRUCTURE}
    m = fit.mech(r.x, base)
    return ratios, rel_error(H, model_frfs(m, {"G_tcp": f})["G_tcp"]), _ratio_log_std(r)


class _StructureFit:
    """The log residual of ``G_tcp`` at ``points`` (the bins' two points) against the
    measured ``H`` with weights ``w``, and its Jacobian, in the logarithms of
    :data:`_FREE` about a base mechanics; the model and residual at the last point are
    kept, where the Jacobian is taken."""

    def __init__(self, points, H, w):
        self.points, self.H, self.w = points, H, w
        self.last = {}

    @staticmethod
    def values(theta) -> dict:
        """The free parameters at ``theta`` [SI]."""
        return dict(zip(_FREE, np.exp(theta), strict=True))

    def mech(self, theta, base):
        """The mechanics ``base`` with the free parameters at ``theta``, unchecked [SI]."""
        return AxisMechanics.model_construct(**{**base, **self.values(theta)})

    def resid(self, theta, base):
        g = model_frfs(self.mech(theta, base), {"G_tcp": self.points})["G_tcp"]
        self.last.update(x=np.array(theta), base=base, g=g,
                         r=log_residual(band_model(g), self.H, self.w))
        return self.last["r"]

    def jac(self, theta, base):
        if self.last.get("base") is not base or not np.array_equal(self.last["x"], theta):
            self.resid(theta, base)
        return residual_jacobian(self.mech(theta, base), {"G_tcp": self.points},
                                 {"G_tcp": self.w}, self.last["r"], _FREE, {},
                                 pairs={"G_tcp": self.last["g"]})

    def best(self, starts, max_nfev: int, floor: bool = False):
        """A short run from every start (each parameter within a factor 1e3 of it, and
        with ``floor`` the stiffnesses above :data:`STIFFNESS_FLOOR`), the best refined:
        the ``least_squares`` result and its base mechanics [-]."""
        best = None
        for mech in starts:
            base = mech.model_dump()
            theta0 = np.log([max(base[p], 1e-12) for p in _FREE])
            bounds = (theta0 - np.log(1e3), theta0 + np.log(1e3))
            if floor:
                for s, k in STIFFNESS_FLOOR.items():
                    i = _FREE.index(f"K_{s}")
                    bounds[0][i] = max(bounds[0][i], min(np.log(k), theta0[i]))
            r = least_squares(self.resid, theta0, jac=self.jac, args=(base,), bounds=bounds,
                              max_nfev=40, method="trf")
            if best is None or r.cost < best[0].cost:
                best = (r, base, bounds)
        r, base, bounds = best
        r = least_squares(self.resid, r.x, jac=self.jac, args=(base,), bounds=bounds,
                          max_nfev=max_nfev, method="trf", **TIGHT)
        r.bounds = bounds
        return r, base


def _collapsed(r) -> list:
    """The structures (``"h"`` head, ``"b"`` bed) whose mass or stiffness the fit ``r``
    holds at a bound [-]."""
    at = dict(zip(_FREE, held_at_bound(r), strict=True))
    return [s for s in ("h", "b") if at[f"M_{s}"] or at[f"K_{s}"]]


def beyond_band_starts(mech, structures, f_lo_hz: float, f_hi_hz: float) -> list:
    """Starts with each structure of ``structures`` (``"h"``, ``"b"``) moved out of the
    band: its mode at half the band's lowest frequency and at twice its highest, with a
    mass of half and of twice the table's, damped at :data:`START_ZETA`.

    Parameters
    ----------
    mech : AxisMechanics
        The mechanics the others are kept from [SI].
    structures : sequence of str
        Which structures to move [-].
    f_lo_hz, f_hi_hz : float
        The band of the fitted bins [Hz].
    """
    starts = []
    for s in structures:
        for f_hz in (0.5 * f_lo_hz, 2.0 * f_hi_hz):
            for mass in (0.5 * mech.M_t, 2.0 * mech.M_t):
                k = mass * (2 * np.pi * f_hz) ** 2
                starts.append(mech.model_copy(update={
                    f"M_{s}": mass, f"K_{s}": k,
                    f"C_{s}": 2 * START_ZETA * np.sqrt(k * mass)}))
    return starts


def _ratio_log_std(r) -> dict:
    """The deviation of the logarithm of each ratio of :data:`STRUCTURE` at the
    ``least_squares`` result ``r``; ``nan`` where it is held at a bound, where the cost
    does not rise across it and its linearised deviation says nothing [-]."""
    sd_log, _ = log_covariance(r)
    sd_log = np.where(held_at_bound(r), np.nan, sd_log)
    return {p: float(x) for p, x in zip(_FREE, sd_log, strict=True) if p in STRUCTURE}
