"""Circular test command: feed-in, full circle(s), feed-out, through the interpolator.

Geometry (identical to ``examples/circle_r35_f5000.nc``): start at rest at the centre;
feed-in along a semicircle of radius R/2 that joins the circle tangentially at the
start angle, turning the same way as the circle; ``turns`` turns of the circle; feed-out
along a semicircle of radius R/2 back to the centre, tangential, same sense; at rest.
"""

from __future__ import annotations

import math
import warnings

from .._validate import finite_number, nonnegative_number, plane_point, positive_number
from ..errors import InputError, InputWarning
from .command import Command
from .interpolate import interpolate_detailed
from .segments import AXES, Arc, Dwell
from .settings import InterpolatorSettings

#: Radius beyond which a circle is taken for one given in mm as m, and warned of: circular
#: test devices measure radii up to about 1.3 m (a ballbar with its extensions), and a
#: circle of 5 m needs 10 m of travel on both axes of its plane, which only the largest
#: gantry machines have; a 35 mm circle typed as 35 is a 35 m one [m].
PLAUSIBLE_RADIUS_M = 5.0


def _point(plane_axes, a, b, rest=0.0):
    p = [rest, rest, rest]
    p[AXES.index(plane_axes[0])] = a
    p[AXES.index(plane_axes[1])] = b
    return tuple(p)


def _check(
    radius_m, feed_m_per_s, direction, turns, plane_axes, dwell_s, centre_m, start_angle_rad
):
    if positive_number("radius_m", radius_m, "m") > PLAUSIBLE_RADIUS_M:
        warnings.warn(f"radius_m={radius_m!r}: a circle of {radius_m:g} m, beyond the "
                      f"{PLAUSIBLE_RADIUS_M:g} m of any circular test; radius_m is in "
                      f"m: for {radius_m:g} mm give radius_m={radius_m * 1e-3:g}",
                      InputWarning, stacklevel=4)
    positive_number("feed_m_per_s", feed_m_per_s, "m/s")
    if direction not in ("cw", "ccw"):
        raise InputError(f"direction must be 'cw' or 'ccw', got {direction!r}")
    positive_number("turns", turns, "-")
    pa = tuple(str(a).upper() for a in plane_axes)
    if len(pa) != 2 or pa[0] == pa[1] or any(a not in AXES for a in pa):
        raise InputError(f"plane_axes must be two different axes of X, Y, Z, got {plane_axes}")
    nonnegative_number("dwell_s", dwell_s, "s")
    plane_point("centre_m", centre_m)
    finite_number("start_angle_rad", start_angle_rad, "rad")
    return pa


def circle_segments(
    radius_m,
    feed_m_per_s,
    centre_m=(0.0, 0.0),
    direction="ccw",
    start_angle_rad=0.0,
    turns=1.0,
    plane_axes=("X", "Y"),
    feed_in=True,
    dwell_s=0.0,
):
    """Tool path of the circular test, for :func:`~tcpmm.path.interpolate.interpolate`.

    Parameters are those of :func:`circle_command`.

    Returns
    -------
    list of Arc, Dwell
        Dwell, feed-in arc, circle, feed-out arc, dwell (dwells only if ``dwell_s`` > 0;
        no feed-in/out arcs if ``feed_in`` is false) [-].
    """
    pa = _check(
        radius_m, feed_m_per_s, direction, turns, plane_axes, dwell_s, centre_m, start_angle_rad
    )
    ca, cb = float(centre_m[0]), float(centre_m[1])
    R, phi = float(radius_m), float(start_angle_rad)
    sign = 1.0 if direction == "ccw" else -1.0
    phi_end = phi + sign * 2.0 * math.pi * turns
    centre = _point(pa, ca, cb)
    start = _point(pa, ca + R * math.cos(phi), cb + R * math.sin(phi))
    end = _point(pa, ca + R * math.cos(phi_end), cb + R * math.sin(phi_end))
    whole = abs(turns - round(turns)) < 1e-6
    extra = round(turns) - 1 if whole else math.ceil(turns) - 1
    if whole:
        end = start
    segs = []
    first = centre if feed_in else start
    if dwell_s > 0:
        segs.append(Dwell(first, dwell_s))
    if feed_in:
        c_in = _point(pa, ca + 0.5 * R * math.cos(phi), cb + 0.5 * R * math.sin(phi))
        segs.append(Arc(centre, start, c_in, pa, direction, feed_m_per_s))
    segs.append(Arc(start, end, centre, pa, direction, feed_m_per_s, extra_turns=extra))
    last = end
    if feed_in:
        c_out = _point(pa, ca + 0.5 * R * math.cos(phi_end), cb + 0.5 * R * math.sin(phi_end))
        segs.append(Arc(end, centre, c_out, pa, direction, feed_m_per_s))
        last = centre
    if dwell_s > 0:
        segs.append(Dwell(last, dwell_s))
    return segs


def circle_settings(
    accel_limit_m_per_s2=1.0,
    jerk_limit_m_per_s3=None,
    smoothing_time_s=0.0,
    smoothing="linear",
    period_s=1e-3,
) -> InterpolatorSettings:
    """Interpolator settings that :func:`circle_command` uses.

    Interpolating ``examples/circle_r35_f5000.nc`` with these settings gives the same
    samples as :func:`circle_command`. Parameters as in :func:`circle_command`.

    Returns
    -------
    InterpolatorSettings
        Tangential acceleration ``a``, each axis ``sqrt(2)*a`` (so the tangential and the
        centripetal acceleration may each reach ``a``), no slow-down for the filter [-].
    """
    if smoothing not in ("linear", "bell"):
        raise InputError(f"smoothing must be 'linear' or 'bell', got {smoothing!r}")
    if not (math.isfinite(accel_limit_m_per_s2) and accel_limit_m_per_s2 > 0):
        raise InputError(f"accel_limit_m_per_s2 must be positive, got {accel_limit_m_per_s2}")
    if jerk_limit_m_per_s3 is not None and not jerk_limit_m_per_s3 > 0:
        raise InputError(f"jerk_limit_m_per_s3 must be positive, got {jerk_limit_m_per_s3}")
    if not (math.isfinite(smoothing_time_s) and smoothing_time_s >= 0):
        raise InputError(f"smoothing_time_s must be >= 0 s, got {smoothing_time_s}")
    if not (math.isfinite(period_s) and 0 < period_s <= 1.0):
        raise InputError(f"period_s must be a positive time up to 1 s, got {period_s}")
    a = float(accel_limit_m_per_s2)
    return InterpolatorSettings(
        period_s=period_s,
        profile="trapezoid" if jerk_limit_m_per_s3 is None else "scurve",
        path_accel_m_per_s2=a,
        path_jerk_m_per_s3=jerk_limit_m_per_s3 or 1.0,
        axis_accel_m_per_s2={ax: math.sqrt(2.0) * a for ax in AXES},
        filter_kind="none" if smoothing_time_s == 0 else smoothing,
        filter_time_s=smoothing_time_s,
        # the radius loss of the filter is part of the test: do not slow down for it
        corner_tolerance_m=1.0,
    )


def _circle_meta(radius_m, feed_m_per_s, centre_m, direction, start_angle_rad, turns,
                 plane_axes) -> dict:
    """What a circle command's ``meta`` says of the test, beside the interpolator's keys.

    Parameters
    ----------
    radius_m, feed_m_per_s, centre_m, direction, start_angle_rad, turns, plane_axes
        As in :func:`circle_command` [m], [m/s], [m], [-], [rad], [-], [-].

    Returns
    -------
    dict
        ``source`` "circle" and the parameters as plain floats and strings, the plane
        axes upper case [-].
    """
    return dict(
        source="circle",
        radius_m=float(radius_m),
        centre_m=(float(centre_m[0]), float(centre_m[1])),
        direction=direction,
        start_angle_rad=float(start_angle_rad),
        plane_axes=tuple(str(a).upper() for a in plane_axes),
        turns=float(turns),
        feed_m_per_s=float(feed_m_per_s),
    )


def circle_command(
    radius_m, feed_m_per_s, centre_m=(0.0, 0.0), direction="ccw", start_angle_rad=0.0,
    turns=1.0, plane_axes=("X", "Y"), accel_limit_m_per_s2=1.0, jerk_limit_m_per_s3=None,
    smoothing_time_s=0.0, smoothing="linear", period_s=1e-3, feed_in=True, dwell_s=0.0,
) -> Command:
    """Position command of a circular test (feed-in, circle, feed-out), from rest to rest.

    Parameters
    ----------
    radius_m : float
        Circle radius [m].
    feed_m_per_s : float
        Programmed feed, reached on the circle [m/s].
    centre_m : tuple of float
        Centre in the plane (first axis, second axis) [m].
    direction : {"ccw", "cw"}
        Sense of rotation: counter-clockwise turns the first plane axis into the second [-].
    start_angle_rad : float
        Where the circle starts, from the first plane axis [rad].
    turns : float
        Number of turns of the circle [-].
    plane_axes : tuple of str
        The two axes of the plane, e.g. ``("X", "Y")`` (G17) or ``("Z", "X")`` (G18) [-].
    accel_limit_m_per_s2 : float
        Tangential acceleration limit; also the limit of the centripetal acceleration
        [m/s^2].
    jerk_limit_m_per_s3 : float, optional
        Tangential jerk limit; given, the feed profile is an S-curve, else a trapezoid
        [m/s^3].
    smoothing_time_s : float
        Length of the post-interpolation filter; 0 for none. The feed is not reduced
        for the radius loss the filter causes: that loss is part of the test [s].
    smoothing : {"linear", "bell"}
        Post-interpolation filter kind [-].
    period_s : float
        Interpolation period [s].
    feed_in : bool
        Add the feed-in and feed-out semicircles from and to the centre [-].
    dwell_s : float
        Rest before and after the motion [s].

    Returns
    -------
    Command
        The position command. ``meta`` holds ``radius_m`` [m], ``centre_m`` [m],
        ``direction``, ``start_angle_rad`` [rad], ``plane_axes``, ``turns``,
        ``feed_m_per_s`` [m/s] and ``circle_index_range`` (first, stop) of the samples
        on the circle (shifted by the filter delay when smoothed) [-].
    """
    segs = circle_segments(radius_m, feed_m_per_s, centre_m, direction, start_angle_rad,
                           turns, plane_axes, feed_in, dwell_s)
    settings = circle_settings(accel_limit_m_per_s2, jerk_limit_m_per_s3, smoothing_time_s,
                               smoothing, period_s)
    result = interpolate_detailed(segs, settings)
    circle = int(dwell_s > 0) + int(bool(feed_in))  # the arcs before the circle [-]
    meta = _circle_meta(radius_m, feed_m_per_s, centre_m, direction, start_angle_rad, turns,
                        plane_axes)
    result.command.meta.update(meta, circle_index_range=result.sample_range(circle))
    return result.command
