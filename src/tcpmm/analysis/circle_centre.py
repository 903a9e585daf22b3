"""A circle's radial error with its centre offset made exactly first order.

The terms of :mod:`.diagnostics` are each the first-order radial effect of a position
error. For a centre offset ``c`` the radial error about the nominal centre is, to second
order, ``c . u - (|c|^2 - (c . u)^2) / (2 R)`` (``u`` the unit vector at the angle): its
second part is a constant and an ellipse along ``c``, and a ballbar's centre offset of
300 um on an R 35 mm circle (0.8 um of it) reads as 37 um/m of squareness and 28 ppm of
scale mismatch. A circle of radius ``R`` about ``c`` lies, at the angle of ``u``, exactly
``c . u + sqrt(R^2 - |c|^2 + (c . u)^2)`` from the nominal centre: the data keep the first
part, which the fit's centre columns take, and lose the rest, whatever the offset. What
remains is of the order of ``|c| / R`` of the other terms: they are functions of the
command's angle, and the samples come at the tool's (docs/circle_diagnostics.md).
"""

from __future__ import annotations

import numpy as np

from .circle_fit import Arc
from .circle_model import is_full

#: Shortest arc whose centre is read beside the ellipses (module docstring); a shorter
#: one does not tell them apart from the centre [deg]
ELLIPSE_ARC_DEG = 180.0


def centre_linear(angle, e, radius):
    """``e`` with the second and higher orders of the circle's centre offset taken off.

    Parameters
    ----------
    angle : ndarray
        Angle about the nominal centre, CCW from the first axis [rad].
    e : ndarray
        Radial error about the nominal centre [m].
    radius : float
        Nominal radius [m].

    Returns
    -------
    ndarray
        ``e + R - sqrt(R^2 - |c|^2 + (c . u)^2)``, ``c`` the least-squares centre offset
        of the samples (radius and centre, and the ellipses over an arc) [m].
    """
    cos, sin = np.cos(angle), np.sin(angle)
    cols = [np.ones_like(angle), cos, sin]
    if not is_full(angle) and np.ptp(angle) >= np.radians(ELLIPSE_ARC_DEG):
        # over an arc the ellipses at 45 deg and along the axes (a servo mismatch's,
        # a squareness's, a scale mismatch's) lean on the centre's columns: a 1 ms lag
        # on R 20 mm moved it so, and the offset's second order read 16 um/m squareness
        cols += [np.sin(2.0 * angle), np.cos(2.0 * angle)]
    _, cx, cy = np.linalg.lstsq(np.column_stack(cols), e, rcond=None)[0][:3]
    cu = cx * cos + cy * sin
    return e + radius - np.sqrt(radius**2 - (cx**2 + cy**2) + cu**2)


def centred_arcs(paths, signs, radius, ratios=None) -> list:
    """The :class:`~tcpmm.analysis.circle_fit.Arc` of each ``(angle, radial error)`` of
    ``paths``, its radial error :func:`centre_linear`, of direction ``signs`` (+1 CCW, -1
    CW) and angular speed ``ratios`` over the mean (default 1) [rad, m, -]."""
    ratios = np.ones(len(paths)) if ratios is None else ratios
    return [Arc(a, centre_linear(a, e, radius), s, r)
            for (a, e), s, r in zip(paths, signs, ratios, strict=True)]
