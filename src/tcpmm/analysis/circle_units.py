"""A run or a radius in another unit than millimetres: a sensor's column whose travel is
its command's times a unit's factor, and a circle not found where the radius asked for is
the run's times one."""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .circle_passes import MIN_ARC_DEG, OFFSET_SHARE

#: Largest radius [m] and feed [m/s] of a machine tool's circular test, and its smallest
#: radius [m]: beyond them a run's positions are in another unit than its columns say
#: (metres or micrometres under ``*_mm``), and every figure is off by 1000 [m, m/s, m].
#: A small bore's circle of 0.5 mm is a machine's own; one of 35 mm logged in metres
#: reads 0.035 mm.
LARGEST_RADIUS_M, FASTEST_M_PER_S, SMALLEST_RADIUS_M = 5.0, 2.0, 1e-4


#: Units a column in mm may hold by mistake: its travel over the reference's, and how to
#: write it in mm [-]
OTHER_UNITS = (("µm", 1e3, "divide {} by 1000"), ("m", 1e-3, "multiply {} by 1000"),
               ("inches", 1 / 25.4, "multiply {} by 25.4"))
#: Share within which a travel's ratio to the reference's is taken for a unit's [-]
UNIT_SHARE = 0.02


def refuse_other_unit(v, rv, column: str, ref: str) -> None:
    """Refuse a sensor's column whose travel is that of its reference ``rv`` (the command)
    times one of :data:`OTHER_UNITS`' factors to within :data:`UNIT_SHARE`: a column in
    another unit under a name in mm, which the checks after read as a column stuck, swapped
    or of the opposite sign [-].

    Parameters
    ----------
    v, rv : ndarray
        The sensor's positions along one axis over the pass, and its reference's [m].
    column, ref : str
        The column's name and the reference's [-].
    """
    if not v.size or not np.ptp(rv) > 0:
        return
    ratio = float(np.ptp(v) / np.ptp(rv))
    other = unit_of(ratio)
    if other is not None:
        unit, _, fix = other
        raise InputError(
            f"{column} travels {np.ptp(v) * 1e3:.6g} where the {ref}'s travels "
            f"{np.ptp(rv) * 1e3:.6g} mm, {ratio:.4g} times as far: it holds {unit}, not "
            f"mm; {fix.format('it')}")


def unit_of(ratio: float):
    """The entry of :data:`OTHER_UNITS` whose factor ``ratio`` (a length read in mm over
    the one it stands for) is to within :data:`UNIT_SHARE`, else None [-]."""
    return next((u for u in OTHER_UNITS if abs(ratio / u[1] - 1.0) < UNIT_SHARE), None)


def not_found_error(radius_m, centre_m, axes, ref, direction, reach_m=None) -> InputError:
    """The error of a run without the circle asked for; where the reference's median
    distance from the centre, ``reach_m`` [m], is the radius times one of
    :data:`OTHER_UNITS`' factors, the unit the run is then in, or, where the run's circle
    is one a machine tool runs and the radius is not, the radius's [-]."""
    ax, ay = axes
    other = unit_of(reach_m / radius_m) if reach_m else None
    if other is not None and _a_test_radius(reach_m) and not _a_test_radius(radius_m):
        return InputError(
            f"the {ref} signals lie {reach_m * 1e3:.6g} mm from the centre; --radius "
            f"{radius_m * 1e3:g} mm is {radius_m / reach_m:.4g} times that: give --radius in "
            f"mm ({reach_m * 1e3:.4g})")
    if other is not None:
        unit, factor, fix = other
        return InputError(
            f"the {ref} signals lie {reach_m * 1e3:.6g} mm from the centre, the radius of "
            f"{radius_m * 1e3:g} mm times {factor:.4g}: the run holds {unit}, not mm; "
            f"{fix.format('every *_mm column')}")
    what = f" {direction.upper()}" if direction else ""
    where = (f"({centre_m[0] * 1e3:g}, {centre_m[1] * 1e3:g}) mm" if (ax, ay) == ("X", "Y")
             else f"{ax} {centre_m[0] * 1e3:g} mm, {ay} {centre_m[1] * 1e3:g} mm")
    return InputError(
        f"no full{what} circle of radius {radius_m * 1e3:g} mm about {where} in the "
        f"{ax}{ay} plane found in the {ref} signals, nor an arc of {MIN_ARC_DEG:g} deg or "
        f"more (a path of constant radius within {OFFSET_SHARE * radius_m * 1e3:.3g} mm of "
        "it); check --radius, --centre and --plane")


def _a_test_radius(radius_m: float) -> bool:
    """Whether a machine tool's circular test runs a circle of this radius
    (:data:`SMALLEST_RADIUS_M` to :data:`LARGEST_RADIUS_M`) [-]."""
    return SMALLEST_RADIUS_M <= radius_m <= LARGEST_RADIUS_M
