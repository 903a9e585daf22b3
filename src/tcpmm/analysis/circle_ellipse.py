"""What one direction's terms owe to reading its ellipse as a squareness.

One direction shows a squareness and a servo mismatch as one ellipse at 45 deg, and its fit
reads it as a squareness. Read as a servo mismatch, the same ellipse is a lag: the axes
reverse that far from the quadrant points, and the lag's radial error has a part of order
``R mu^2`` beyond the ellipse (:func:`.circle_model.servo_remainder`). Where the ellipse is
large (a lag of a millisecond at a high feed, sampled coarsely), the backlash, the bows and
the centre read differently under the two readings: a lag of 0.93 ms on R 22 mm at F5000
sampled at 250 Hz moves a backlash of 5.45 um by 0.47 um, a bow by 0.19 um. The fit is done
again with the ellipse as a servo mismatch, columns and cyclic errors as they are; a term
that moves by more than 2 % of itself and by more than 0.1 um of the radial error it makes
is not determined by one direction, and both of its readings are said. So is the radial
deviation, the mean radius over the command's angle: the fit that reads a lag as a
squareness takes it over the tool's angle, which the lag moves along its ellipse, and with
1 ms at F10000 on R 35 mm read -0.20 um CCW and -0.24 um CW where the samples' mean is
-0.05 um (-0.74 and -0.98 um for -0.20 um with 2 ms).
"""

from __future__ import annotations

import numpy as np

from .circle_fit import fit_terms
from .circle_open import open_terms
from .circle_ranking import per_circle_terms

#: Terms read again, their names in the report, the radial error per unit of each at the
#: circle's radius ``r`` [m/unit] and how a value is said [-].
READ_AGAIN = {
    "backlash_X": ("backlash_X", lambda r: 0.5, "µm"),
    "backlash_Y": ("backlash_Y", lambda r: 0.5, "µm"),
    "straightness_X": ("straightness_X", lambda r: 1.0, "µm"),
    "straightness_Y": ("straightness_Y", lambda r: 1.0, "µm"),
    "centre_X_0": ("centre_offset_X", lambda r: 1.0, "µm"),
    "centre_Y_0": ("centre_offset_Y", lambda r: 1.0, "µm"),
    "scale_mismatch": ("scale_mismatch", lambda r: r / 2, "ppm"),
}
#: Least move of a term, as a share of it, and as radial error, that leaves it open [-, m].
SHARE, RADIAL_M = 0.02, 0.1e-6


def as_mismatch(fit, arcs, radius_m, shared):
    """The fit of ``fit``'s columns and cyclic errors with the ellipse read as a servo
    mismatch instead of a squareness; the arguments as :func:`open_by_ellipse` takes
    them [-]."""
    columns = [_mismatch(n) for n, c in zip(fit.names, fit.coef, strict=True)
               if np.isfinite(c)]
    return fit_terms(arcs, radius_m, [_mismatch(n) for n in shared], waves=fit.waves,
                     columns=columns, tail=fit.tail)


def _mismatch(name: str) -> str:
    """The column ``name`` with the ellipse read as a servo mismatch [-]."""
    return "servo_angle" if name == "squareness" else name


def open_by_ellipse(fit, terms: dict, arcs, radius_m: float, shared) -> dict:
    """The terms the ellipse's reading moves beyond :data:`SHARE` and :data:`RADIAL_M`:
    their values become NaN, the fit's too, so that the ranking leaves them out; why,
    with both readings [-].

    Parameters
    ----------
    fit : TermFit
        One direction's fit [-].
    terms : dict
        Its terms, ``name -> (value, unit)``, changed in place [SI].
    arcs : list of Arc
        Its circle or arc [-].
    radius_m : float
        Nominal radius [m].
    shared : sequence of str
        The terms it fitted besides radius and centre [-].
    """
    if "squareness" not in fit.names or not np.isfinite(fit["squareness"]) \
            or fit["squareness"] == 0.0:
        return {}
    alt = as_mismatch(fit, arcs, radius_m, shared)
    read = {name: (term, fit[name], alt[name], per_unit(radius_m), unit)
            for name, (term, per_unit, unit) in READ_AGAIN.items()
            if name in fit.names and name in alt.names}
    read["radius"] = _radius_readings(terms, alt, arcs, radius_m, shared)
    out = {}
    for name, (term, a, b, per_unit, unit) in read.items():
        if not (np.isfinite(a) and np.isfinite(b)) or \
                abs(a - b) <= max(SHARE * abs(a), RADIAL_M / per_unit):
            continue
        k = 1e6
        out.update(open_terms(terms, [term], (
            "one direction cannot tell whether its ellipse at 45 deg is a squareness or a "
            f"servo mismatch, and this term rests on it: {a * k:.2f} {unit} as a "
            f"squareness, {b * k:.2f} {unit} as a servo mismatch (which moves the axes' "
            "reversals and adds its remainder); the other direction tells them apart"),
            fit=fit if name != "radius" else None))
    return out


def _radius_readings(terms: dict, alt, arcs, radius_m: float, shared) -> tuple:
    """The radial deviation as ``terms`` give it, the ellipse read as a squareness, and as
    the fit ``alt`` gives it, read as a servo mismatch, in the form of
    :data:`READ_AGAIN`'s readings: over the command's angle, at which the samples come,
    a lag's radius is short by about ``R mu^2 / 16``, and over the tool's, which the
    squareness reads it at, by ``5/16 R mu^2`` (0.05 and 0.25 um at F10000 on R 35 mm with
    1 ms) [-, m, m, m/m, -]."""
    [arc] = arcs
    d = "ccw" if arc.s > 0 else "cw"
    _, grids = per_circle_terms(alt, arcs, radius_m, [_mismatch(n) for n in shared], (d,))
    term = f"radial_deviation_{d}"
    return term, terms[term][0], float(np.mean(grids[d])), 1.0, "µm"
