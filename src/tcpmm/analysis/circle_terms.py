"""Reversal spikes of one circle after its error terms.

The raw spike ``e - b`` (docs/formats.md section 4) holds whatever else changes the radius
over the 50 deg about a quadrant point: a centre offset of 10 um makes 6.5 um at B and D of
an R35 circle, a servo mismatch of 1 ms at 7.2 s a turn 18.6 um at all four. The spike a
reader wants is the transient after the reversal, so the headline spike is taken on the
residual of a least-squares fit to the circle alone of the terms one circle determines:
radius, centre, the ellipse at 45 deg (servo mismatch and squareness, which one circle
cannot tell apart) and the ellipse along the axes (scale mismatch). As in
:mod:`tcpmm.analysis.diagnostics`, the 20 deg after each quadrant point are left out of the
fit. Backlash and lateral play are not fitted here: in one circle their steps at the
reversals have the shape of the reversal's own transient and take part of it, turning a
spike's sign; the diagnostics of a CCW and a CW circle, where backlash changes sign with the
direction and the transient does not, fit them, and cyclic errors too. An arc is fitted
with the terms it determines (:func:`tcpmm.analysis.circle_model.determined`).
"""

from __future__ import annotations

import numpy as np

from .circle_model import determined, is_full
from .circle_noise import coef_covariance
from .circle_spike_sigma import spike_uncertainty
from .circle_spikes import AFTER_DEG, QUADRANTS, reversal_spikes

#: Fewest samples on a circle for the fit [-].
_MIN_SAMPLES = 100


def _fit_mask(angle_rad, direction):
    """Samples outside the 20 deg after every quadrant point in the travel direction [-]."""
    u = (1.0 if direction == "ccw" else -1.0) * np.degrees(angle_rad)
    keep = np.ones(u.size, bool)
    for deg in QUADRANTS.values():
        d = (u - (1.0 if direction == "ccw" else -1.0) * deg) % 360.0
        keep &= ~((d >= AFTER_DEG[0]) & (d <= AFTER_DEG[1]))
    return keep


def _fit(angle_rad, e, direction: str):
    """``(residual, design matrix, covariance of the coefficients)`` of the fit of the
    error terms to one circle (module docstring); None when the circle is too short, not a
    full turn, or not finite to fit [m, m/unit, unit^2]."""
    a, e = np.asarray(angle_rad, float), np.asarray(e, float)
    if a.size < _MIN_SAMPLES or not (np.all(np.isfinite(a)) and np.all(np.isfinite(e))):
        return None
    if not is_full(a):
        return None
    # radius, centre, the 45 deg ellipse, the ellipse along the axes
    basis = np.column_stack([np.ones_like(a), np.cos(a), np.sin(a), np.sin(2 * a),
                             np.cos(2 * a)])
    keep = _fit_mask(a, direction)
    # a turn with gaps determines fewer of them
    basis = basis[:, determined(basis[keep], protect=[0])]
    coef = np.linalg.lstsq(basis[keep], e[keep], rcond=None)[0]
    rest = e - basis @ coef
    return rest, basis, coef_covariance(basis[keep], rest[keep], [int(keep.sum())])


def spikes_with_uncertainty(angle_rad, e, direction: str) -> tuple[dict, dict, dict]:
    """Signed reversal spike at A-D of the residual after the fitted terms, its 95 %
    uncertainty and that from the noise from sample to sample alone
    (:func:`.circle_spike_sigma.spike_uncertainty`); NaN where the raw spike is left out
    or the circle cannot be fitted, an arc among them (module docstring) [m].

    Parameters
    ----------
    angle_rad : ndarray
        Angle about the nominal centre, CCW from the first axis, unwrapped [rad].
    e : ndarray
        Radial error about the nominal centre [m].
    direction : {"ccw", "cw"}
        Direction of travel [-].
    """
    fitted = _fit(angle_rad, e, direction)
    if fitted is None:
        nan = {q: float("nan") for q in reversal_spikes(angle_rad, e, direction)}
        return nan, dict(nan), dict(nan)
    rest, basis, cov = fitted
    return (reversal_spikes(angle_rad, rest, direction),
            *spike_uncertainty(angle_rad, rest, direction, columns=basis, cov=cov))
