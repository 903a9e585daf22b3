"""Diagnostics of a circle (or arc) run in one direction only.

One direction determines the radius, the centre, the scale mismatch, the straightness of
each axis, the cyclic errors and the backlash (its steps at the reversals, read outside the
20 deg of the reversal's transient). It does not tell apart what only the change of
direction tells apart: squareness and servo mismatch are one ellipse at 45 deg in one
direction (squareness keeps its sign in the other direction, a servo mismatch turns it),
reported together as ``squareness_or_servo``; lateral play's radial error in one direction
is nearly a radius and a scale mismatch, and it turns sign with the direction; hysteresis,
G(b) and the pair's radial deviation are of both directions.
"""

from __future__ import annotations

import numpy as np

from .._threads import limit_blas_threads
from ..errors import InputError
from .circle_alias import alias_terms
from .circle_arcs import check_arc
from .circle_centre import centred_arcs
from .circle_cyclic_terms import cyclic_terms, cyclic_unresolved
from .circle_display import rename_axes
from .circle_ellipse import open_by_ellipse
from .circle_feeds import command_radius
from .circle_model import angle_step
from .circle_open import open_terms
from .circle_ranking import deviations, per_circle_terms, rank_terms
from .circle_sigma import term_sigma
from .circle_spikes import reversal_spikes
from .circle_stable import ARC_WHY, arc_fit, leave_open
from .circle_tails import sign_open, tail_shift
from .circle_takeup import noise_extremes, width_follows_backlash, width_terms, width_why
from .diagnostics import (
    CircleDiagnostics,
    circle_diagnostics,
    pick_passes,
    pick_sensor,
    undetermined_terms,
)

#: The terms fitted to one direction; lateral play is not among them: in one direction
#: only 7 % of its column is independent of the radius and the scale mismatch
SINGLE = ("backlash_X", "backlash_Y", "squareness", "scale_mismatch", "straightness_X",
          "straightness_Y")
#: Not fitted to one direction (``SINGLE``), but the fitted terms depend on them
UNSEEN = ("lateral_play_X", "lateral_play_Y")
_ELLIPSE = ("one direction shows squareness and servo mismatch as one ellipse at 45 deg "
            "(squareness or servo); the other direction tells them apart: squareness keeps "
            "its sign, a servo mismatch turns it")
#: Terms of the pair one direction cannot give, and why
NEEDS_PAIR = {"squareness": _ELLIPSE, "servo_mismatch": _ELLIPSE,
              "lateral_play_X": "in one direction its radial error is nearly a radius and a "
                                "scale mismatch; the other direction, where it turns sign, "
                                "tells it apart",
              "hysteresis": "the difference between the CCW and the CW circle",
              "circularity_pair": "G(b) is taken over both directions",
              "radial_deviation_pair": "the mean of both directions"}
NEEDS_PAIR["lateral_play_Y"] = NEEDS_PAIR["lateral_play_X"]


def diagnose_single(angle, e, direction, radius_m, axes=("X", "Y"),
                    sensor="tcp", command_radius_m=None) -> CircleDiagnostics:
    """The terms one direction determines (module docstring), and why the others need the
    pair (``undetermined``).

    Parameters
    ----------
    angle : ndarray
        Angle about the nominal centre, CCW from the first axis, unwrapped: a full turn,
        or an arc [rad].
    e : ndarray
        Radial error about the nominal centre [m].
    direction : {"ccw", "cw"}
        Direction of travel [-].
    radius_m : float
        Nominal radius [m].
    axes : tuple of str
        The plane's first and second axis [-].
    sensor : str
        Sensor the path is from, for the record [-].
    command_radius_m : float, optional
        The radius the command runs on, where it is not the nominal one [m].
    """
    if not radius_m > 0:
        raise InputError(f"the circle radius must be positive (got {radius_m})")
    if direction not in ("ccw", "cw"):
        raise InputError(f"the direction must be ccw or cw (got {direction!r})")
    a, e = check_arc(angle, e, direction, arc_ok=True)
    limit_blas_threads()
    arcs = centred_arcs([(a, e)], (1.0 if direction == "ccw" else -1.0,), radius_m)
    fit, left_out = arc_fit(arcs, radius_m, SINGLE, unseen=UNSEEN)
    curves, grids = per_circle_terms(fit, arcs, radius_m, SINGLE, (direction,))
    terms = _terms(fit, grids, deviations([(a, e)], radius_m)[0][0], curves,
                   radius_m / (command_radius_m or radius_m))
    terms["residual_rms"] = (fit.residual_rms, "m")
    why = {rename_axes(k, axes): v for k, v in NEEDS_PAIR.items()}
    why.update({rename_axes("squareness_or_servo" if k == "squareness" else k, axes): ARC_WHY
                for k in undetermined_terms(fit) if k not in NEEDS_PAIR or k == "squareness"})
    # the ellipse read again before the backlash is left open, so that its other reading
    # keeps the backlash's columns: without them the scale mismatch took the backlash;
    # a backlash left open for both reasons is said for the reversals' placing
    ellipse = open_by_ellipse(fit, terms, arcs, radius_m, SINGLE)
    for said in (ellipse, _unplaced(fit, terms, a), cyclic_unresolved(fit), width_why(fit)):
        why.update({rename_axes(k, axes): v for k, v in said.items()})
    leave_open(why, terms, left_out, arcs, axes, {"squareness": "squareness_or_servo"})
    width_follows_backlash(terms, why, lambda k: rename_axes(k, axes),
                           noise_extremes(terms, fit.residual_rms))
    shift = tail_shift(fit, arcs, radius_m, SINGLE, terms, axes,
                       rename={"squareness": "squareness_or_servo"})
    ranking = rank_terms(fit, arcs, radius_m, SINGLE, terms, axes,
                         {"squareness": "squareness_or_servo"},
                         sign_open({rename_axes(k, axes): v for k, v in terms.items()}, shift,
                                   radius_m))
    return CircleDiagnostics(float(radius_m), tuple(axes), sensor,
                             {rename_axes(k, axes): (float(v), u) for k, (v, u) in terms.items()},
                             curves, why, ranking, shift,
                             alias_terms(fit, 1, SINGLE, terms, radius_m, axes,
                                         rename={"squareness": "squareness_or_servo"}),
                             term_sigma(fit, 1, SINGLE, terms, axes,
                                        rename={"squareness": "squareness_or_servo"}))


def _unplaced(fit, terms, angle) -> dict:
    """Where the ellipse, were it a servo mismatch, would move the axes' reversals by half a
    sample or more, the backlash and the spikes after the terms are left open (a step
    placed a sample off reads partly as backlash, partly as a spike: 12 % of a backlash and
    a spike of 2.6 um with a 1 ms mismatch at F10000): their values become NaN, and the
    fit's too, so that the ranking leaves them out; the reasons [-]."""
    step = angle_step(angle)
    shift = abs(fit["squareness"])  # the ellipse as a servo mismatch angle [rad]
    if not shift >= 0.5 * step:
        return {}
    why = (f"one direction cannot place the axes' reversals: its ellipse at 45 deg, were it a "
           f"servo mismatch, moves them by {shift / step:.1f} samples, and a step placed off "
           "reads partly as backlash, partly as a spike; the other direction tells the "
           "mismatch from a squareness and places them")
    out = open_terms(terms, ("backlash_X", "backlash_Y"), why, fit=fit)
    open_terms(terms, [k for k in terms if k.startswith("spike_")], why)
    out["reversal_spikes"] = why
    return out


def _terms(fit, grids, g, curves, per_command=1.0):
    """The terms one direction gives, ``name -> (value, unit)``; those that scale with the
    command's radius ``per_command`` times their fit, on the nominal one [SI]."""
    [(d, grid)] = grids.items()
    terms = {f"radial_deviation_{d}": (float(np.mean(grid)), "m"),
             f"circularity_{d}": (g, "m")}
    terms.update({f"centre_offset_{a}": (fit[f"centre_{a}_0"], "m") for a in "XY"})
    terms.update({k: (fit[k], "m") for k in SINGLE[:2]})
    terms.update(width_terms(fit))
    terms.update({f"lateral_play_{a}": (float("nan"), "m") for a in "XY"})
    # the ellipse, were it a servo mismatch, puts the reversals that far off the points
    # where the fit steps: a sample between the two reads the whole backlash as a spike
    shift_deg = float(np.degrees(abs(fit["squareness"])))
    for d, (a, e, model) in curves.items():
        spikes = reversal_spikes(a, e - model, d, skip_deg=shift_deg)
        terms.update({f"spike_{q}_{d}": (v, "m") for q, v in spikes.items()})
    terms["squareness_or_servo"] = (fit["squareness"] * per_command, "m/m")
    terms["scale_mismatch"] = (fit["scale_mismatch"] * per_command, "-")
    terms["straightness_X"] = (fit["straightness_X"], "m")
    terms["straightness_Y"] = (fit["straightness_Y"], "m")
    terms.update(cyclic_terms(fit))
    return terms


def one_direction_diagnostics(result, sensor=None, axes=None) -> CircleDiagnostics:
    """:func:`diagnose_single` of the first pass of a circle analysis that has one
    direction only.

    Parameters
    ----------
    result : CircleResult
        The analysis [-].
    sensor : str, optional
        Sensor to diagnose; default the first of tcp, scale, motor, cmd [-].
    axes : tuple of str, optional
        The plane's axes; default that of ``result`` [-].
    """
    axes = tuple(axes) if axes is not None else tuple(getattr(result, "plane", ("X", "Y")))
    pick = pick_passes(result)
    if not pick:
        raise InputError("the analysis holds no circle to diagnose")
    d = next(iter(pick))
    sensor = pick_sensor({d: pick[d]}, sensor)
    sc = pick[d].sensors[sensor]
    return diagnose_single(sc.angle_rad, sc.radial_error, d, result.radius, axes, sensor,
                           command_radius(pick[d], pick[d], result.radius))


def scale_diagnostics(diag, result):
    """The linear scale's diagnostics of the circles whose ``diag`` are the TCP's, made as
    ``diag`` were (the pair, or one direction), to tell what lies between the scale and
    the tool; ``None`` where the circles have no scale or they cannot be made.

    Parameters
    ----------
    diag : CircleDiagnostics or None
        The TCP's diagnostics [-].
    result : CircleResult
        The circles they come from [-].
    """
    import warnings

    if diag is None or diag.sensor != "tcp" or not all("scale" in p.sensors
                                                        for p in result.passes):
        return None
    make = circle_diagnostics if len(diag.directions) == 2 else one_direction_diagnostics
    with warnings.catch_warnings():  # the TCP's own diagnostics have said what they lack
        warnings.simplefilter("ignore")
        try:
            return make(result, sensor="scale")
        except InputError:
            return None
