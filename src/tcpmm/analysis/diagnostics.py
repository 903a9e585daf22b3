"""Circle diagnostics from a CCW and a CW circle (ISO 230-4 and the ballbar decomposition).

The radial error ``e(theta) = r - R`` of both circles about the nominal centre (angles CCW
from the first plane axis X, the second is Y; ``s = +1`` CCW, ``-1`` CW) is fitted by linear
least squares to a sum of error terms, each the first-order radial effect
``e = dx cos(theta) + dy sin(theta)`` of a position error ``(dx, dy)`` of the tool relative
to the table. ``sx = sign(vx) = -s sign(sin theta)`` and ``sy = sign(vy) = s sign(cos theta)``
are the signs of the axis velocities; X reverses at A and C, Y at B and D (with a servo
mismatch each axis where its own velocity turns, :mod:`.circle_model`).

=====================  ================================  =====================================
term                   position error                    radial error
=====================  ================================  =====================================
radius (per circle)    ``r0`` along the radius           ``r0``
centre (per circle)    ``(cx, cy)``                      ``cx cos + cy sin``
backlash X, Y          ``dx = -bx/2 sx``                 ``-bx/2 sx cos``, ``-by/2 sy sin``
lateral play X, Y      ``dy = +px/2 sx`` (X moves in Y)  ``px/2 sx sin``, ``py/2 sy cos``
squareness             ``dx = -a y``                     ``-a R sin cos``
servo mismatch         ``dx = -tx vx``, ``dy = -ty vy``  ``-s w R (ty - tx) sin cos``
scale mismatch         ``dx = +m/2 x``, ``dy = -m/2 y``  ``m R/2 cos 2theta``
straightness X, Y      ``dy = kx (1 - x^2/R^2)``         ``kx sin^3``, ``ky cos^3``
cyclic error X         ``dx = c sin(2 pi x / L + phi)``  ``dx cos`` (Y alike with ``dy sin``)
=====================  ================================  =====================================

Signs: backlash ``b > 0`` is lost motion, the tool lagging the command along the travel by
``b/2``, so the radius steps outward by ``b`` at the axis' reversal points in the direction of
travel (negative: overcompensated). Lateral play ``p > 0``: moving +X shifts the X axis by
``p/2`` towards +Y (+Y shifts Y towards +X). Squareness ``a > 0``: the angle between +X and
+Y travel exceeds 90 deg, so the radius is short at 45 and 225 deg in both directions.
Servo mismatch ``ty - tx > 0``: Y lags X, an ellipse at 45 deg of opposite sign in CCW and
CW (``w`` the angular speed; ``w (ty - tx)`` is reported too, as an angle, for circles whose
speed is not known). Scale mismatch ``m = ex - ey > 0``: X travels further than Y,
the circle is long along X; the mean of the two scale errors shows only in the radius.
Straightness ``kx > 0``: the X axis bows towards +Y, by ``kx`` in the middle of its travel
over the diameter against its ends (Y alike towards +X).
Cyclic error: amplitude ``c`` and period ``L`` per axis, the period found by a scan.

The 20 deg after each quadrant point in the direction of travel (the reversal spike, whose
transient no term models) are left out of the fit. Reported besides: reversal spikes
(docs/formats.md section 4) of the residual, which the backlash step no longer enters; radial
deviation, the mean radius minus the nominal of the fitted circle; circular deviation G per
direction and bidirectional G(b) about the least-squares centre of both (ISO 230-4);
circular hysteresis H, the largest radial difference between the two circles; the terms
ranked by the radial error each makes alone (:mod:`.circle_ranking`).

Two arcs over the same angles (a ballbar's 220 deg arcs in XZ and YZ) are fitted alike;
the terms they do not determine (:func:`.circle_model.determined`) are NaN and named in
``undetermined``. One direction alone: :mod:`.circle_single`.
"""

from __future__ import annotations

import warnings

import numpy as np

from .._threads import limit_blas_threads
from ..errors import InputError
from .circle_alias import alias_terms
from .circle_arcs import check_arc, same_angles
from .circle_centre import centred_arcs
from .circle_cyclic_terms import cyclic_terms, cyclic_unresolved
from .circle_display import (  # noqa: F401
    DISPLAY_UNITS,
    TERM_NOTES,
    display_terms,
    rename_axes,
    term_note,
)
from .circle_feeds import command_radius, other_feeds
from .circle_model import is_full
from .circle_ranking import deviations, per_circle_terms, rank_terms
from .circle_result import CircleDiagnostics
from .circle_sigma import term_sigma
from .circle_spike_bounds import spikes_in_noise, widened
from .circle_spike_sigma import open_spikes, pair_spikes
from .circle_stable import ARC_WHY, arc_fit, leave_open
from .circle_tail_terms import tail_state, tail_terms
from .circle_tails import open_by_tails, sign_open, tail_shift
from .circle_takeup import width_follows_backlash, width_terms, width_why
from .circle_unfitted import cyclic_slopes

SIGN = {"ccw": 1.0, "cw": -1.0}
SHARED = ("backlash_X", "backlash_Y", "lateral_play_X", "lateral_play_Y", "squareness",
          "servo_angle", "scale_mismatch", "straightness_X", "straightness_Y")
PREFERRED_SENSORS = ("tcp", "scale", "motor", "cmd")
#: What only a CCW and a CW circle together tell, in a sentence
PAIR_ONLY = ("squareness from servo mismatch, the lateral play, the hysteresis and G(b)")


#: Why the servo mismatch is given as an angle only
SPEED_WHY = ("the circles' angular speed is not known, so the mismatch is given as an angle "
             "only (servo_mismatch_angle)")


def diagnose_pair(ccw, cw, radius_m, rates_rad_s=(float("nan"), float("nan")),
                  axes=("X", "Y"), sensor="tcp", command_radius_m=None) -> CircleDiagnostics:
    """Error terms of a CCW and a CW circle by least squares (module docstring).

    Parameters
    ----------
    ccw, cw : tuple of ndarray
        ``(angle, radial error)`` of each circle about the nominal centre, the angle CCW
        from the first axis, unwrapped: a full turn or more, or two arcs alike [rad, m].
    radius_m : float
        Nominal radius [m].
    rates_rad_s : tuple of float
        Angular speed of each circle, the servo mismatch as a time (NaN: its angle) [rad/s].
    axes, sensor : tuple of str, str
        Names of the plane's first and second axis; the paths' sensor, for the record [-].
    command_radius_m : float, optional
        The radius the command runs on, where it is not the nominal one [m].
    """
    if not radius_m > 0:
        raise InputError(f"the circle radius must be positive (got {radius_m})")
    paths = [check_arc(*ccw, "CCW", arc_ok=True), check_arc(*cw, "CW", arc_ok=True)]
    if not all(is_full(a) for a, _ in paths):
        same_angles(paths)
    limit_blas_threads()
    mean_rate, ratios = _mean_rate(rates_rad_s)
    arcs = centred_arcs(paths, (1.0, -1.0), radius_m, ratios)
    fit, left_out = arc_fit(arcs, radius_m, SHARED)
    curves, grids = per_circle_terms(fit, arcs, radius_m, SHARED, tuple(SIGN))
    spikes, spike_u95, spike_fast, moved, together = pair_spikes(
        fit, arcs, radius_m, SHARED, curves, (), parts := {})  # read again as widths open
    terms = _terms(fit, grids, deviations(paths, radius_m), spikes, mean_rate,
                   radius_m / (command_radius_m or radius_m))
    why = {rename_axes(k, axes): v for k, v in (dict.fromkeys(undetermined_terms(fit), ARC_WHY)
                                                | cyclic_unresolved(fit) | width_why(fit)).items()}
    leave_open(why, terms, left_out, arcs, axes)
    if full := all(is_full(a) for a, _ in paths):  # fitted to pairs of full turns alone
        tails, tails_why = tail_terms(fit, mean_rate)
        terms.update(tails)
        why.update({rename_axes(k, axes): v for k, v in tails_why.items()})
    if not np.isfinite(mean_rate) and "servo_mismatch" not in why:
        why["servo_mismatch"] = SPEED_WHY
    shift = tail_shift(fit, arcs, radius_m, SHARED, terms, ("X", "Y"), mean_rate)
    span = max(float(np.ptp(e)) for _, e in paths)
    why.update(open_spikes(terms, moved, span, spike_u95, spike_fast))
    why.update({rename_axes(k, axes): v
                for k, v in open_by_tails(fit, terms, shift, radius_m, span).items()})
    width_follows_backlash(terms, why, lambda k: rename_axes(k, axes), spike_u95,
                           fit.tail_family)
    widened(fit, arcs, radius_m, SHARED, curves, terms, (spike_u95, together), parts)
    quiet = spikes_in_noise(terms, together)
    left = [*sign_open(terms, shift, radius_m), *(("reversal_spikes",) if quiet else ())]
    aliases = alias_terms(fit, 2, SHARED, terms, radius_m, axes, mean_rate, None,
                          cyclic_slopes(fit, arcs, radius_m, SHARED))
    return CircleDiagnostics(float(radius_m), tuple(axes), sensor,
                             {rename_axes(k, axes): (float(v), u) for k, (v, u) in terms.items()},
                             curves, why, rank_terms(fit, arcs, radius_m, SHARED, terms, axes,
                                                     unranked=left),
                             {rename_axes(k, axes): v for k, v in shift.items()}, aliases,
                             term_sigma(fit, 2, SHARED, terms, axes, mean_rate), spike_u95,
                             spike_fast, tail_state(fit) if full else "", quiet)


def _mean_rate(rates_rad_s) -> tuple:
    """The circles' mean angular speed (NaN where one is not known) and each one's share of
    it [rad/s, -]."""
    rates = np.asarray(rates_rad_s, float)
    mean_rate = float(rates.mean()) if np.all(rates > 0) else float("nan")
    return mean_rate, rates / mean_rate if np.isfinite(mean_rate) else np.ones(2)


def undetermined_terms(fit) -> list:
    """The reported terms a fit leaves undetermined [-]."""
    out = []
    for n in fit.undetermined():
        if n.startswith("centre_"):
            out.append(f"centre_offset_{n.split('_')[1]}")
        elif n == "servo_angle":
            out += ["servo_mismatch", "servo_mismatch_angle"]
        elif not n.startswith("radius"):
            out.append(n)
    return list(dict.fromkeys(out))


def _terms(fit, grids, deviations, spikes, mean_rate, per_command=1.0):
    """The reported terms, ``name -> (value, unit)``, axes named X and Y, and what the terms
    leave unexplained; those that scale with the command's radius ``per_command`` times
    their fit, on the nominal one [SI]."""
    g, gb, h = deviations
    terms = {f"radial_deviation_{d}": (float(np.mean(m)), "m") for d, m in grids.items()}
    terms["radial_deviation_pair"] = ((terms["radial_deviation_ccw"][0]
                                       + terms["radial_deviation_cw"][0]) / 2, "m")
    terms.update({"circularity_ccw": (g[0], "m"), "circularity_cw": (g[1], "m"),
                  "circularity_pair": (gb, "m"), "hysteresis": (h, "m")})
    for axis in "XY":
        terms[f"centre_offset_{axis}"] = ((fit[f"centre_{axis}_0"]
                                           + fit[f"centre_{axis}_1"]) / 2, "m")
    terms.update({k: (fit[k], "m") for k in SHARED[:4]})
    terms.update(width_terms(fit))
    terms.update({k: (v, "m") for k, v in spikes.items()})
    mu = fit["servo_angle"] * per_command
    terms["servo_mismatch"] = (mu / mean_rate, "s")
    terms["servo_mismatch_angle"] = (mu, "rad")
    terms["squareness"] = (fit["squareness"] * per_command, "m/m")
    terms["scale_mismatch"] = (fit["scale_mismatch"] * per_command, "-")
    terms["straightness_X"] = (fit["straightness_X"], "m")
    terms["straightness_Y"] = (fit["straightness_Y"], "m")
    terms.update(cyclic_terms(fit))
    terms["residual_rms"] = (fit.residual_rms, "m")
    return terms


def pair_fit(sc) -> tuple:
    """``(diagnostics or None, warnings, error or None)``: :func:`diagnose_pair` of the CCW
    and CW circle ``sc`` belongs to (:meth:`.circular.CircleResult.paired`) in their plane,
    the warnings it gave and the error that stopped it; fitted once for both circles and
    every reader, the headline spikes and the diagnostics alike [-]."""
    other, radius, rates, shared, axes, sensor = sc.pair
    if "fit" not in shared:
        ccw, cw = (sc, other) if sc.direction == "ccw" else (other, sc)
        fit = err = None
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                fit = diagnose_pair((ccw.angle_rad, ccw.radial_error),
                                    (cw.angle_rad, cw.radial_error), radius, rates, axes,
                                    sensor, shared.get("command_radius_m"))
            except (InputError, np.linalg.LinAlgError) as exc:
                err = exc
        shared["fit"] = (fit, [w.message for w in caught], err)
    return shared["fit"]


def _fitted_pair(ccw, cw, axes):
    """:func:`pair_fit` of ``ccw`` and ``cw`` where they are the pair of one analysis in
    the plane ``axes``, its warnings given again and its error raised; None where they are
    not such a pair [-]."""
    if ccw.pair is None or ccw.pair[0] is not cw or tuple(ccw.pair[4]) != tuple(axes):
        return None
    fit, caught, err = pair_fit(ccw)
    for message in caught:
        warnings.warn(message, stacklevel=3)
    if err is not None:
        raise err
    return fit


def pick_passes(result, other=None):
    """The first pass of each direction in two circle analyses, each falling back to the
    other; ``{direction: CirclePass}`` of the directions found [-]."""
    first, second = (result, other or result), (other or result, result)
    pick = {}
    for d, order in (("ccw", first), ("cw", second)):
        found = [p for r in order for p in r.passes if p.direction == d]
        if found:
            pick[d] = found[0]
    return pick


def pick_sensor(pick, sensor=None) -> str:
    """The sensor to diagnose: the one asked for, else the first of tcp, scale, motor,
    cmd in every pass [-]."""
    both = [s for s in PREFERRED_SENSORS if all(s in p.sensors for p in pick.values())]
    sensor = sensor or (both[0] if both else None)
    if sensor not in both:
        where = "both circles" if len(pick) > 1 else "the circle"
        raise InputError(f"the sensor {sensor} is not in {where} (there: {', '.join(both)})")
    return sensor


def circle_diagnostics(result, other=None, sensor=None, axes=None) -> CircleDiagnostics:
    """Diagnostics of the first CCW and the first CW circle of circular-test analyses.

    Parameters
    ----------
    result : CircleResult
        Analysis holding the CCW circle, or both [-].
    other : CircleResult, optional
        Analysis holding the CW circle (a second run); each direction falls back to the
        other analysis when its own has none [-].
    sensor : str, optional
        Sensor to diagnose; default the first of tcp, scale, motor, cmd in both [-].
    axes : tuple of str, optional
        The plane the circles were analysed in, for the term names; default the plane of
        ``result`` [-].
    """
    for name, r in (("result", result), ("other", other or result)):
        # a CircleResult by what it has: tcpmm.analysis.circular imports this module
        if not (hasattr(r, "passes") and hasattr(r, "radius")):
            raise InputError(f"{name} must be a CircleResult (tcpmm.analyse_circle(run, "
                             f"radius_m)), got a {type(r).__name__}")
    axes = tuple(axes) if axes is not None else tuple(getattr(result, "plane", ("X", "Y")))
    pick = pick_passes(result, other)
    for d in ("ccw", "cw"):
        if d not in pick:
            raise InputError(
                f"circle diagnostics need a CCW and a CW circle; no {d.upper()} circle was "
                f"found; give the run of the other direction too (the pair is what tells "
                f"{PAIR_ONLY})")
    if (why := other_feeds(pick["ccw"], pick["cw"], result.radius)) is not None:
        raise InputError(f"{why}; give a CCW and a CW circle run at one feed, or analyse "
                         "each run alone")
    sensor = pick_sensor(pick, sensor)
    sc = {d: p.sensors[sensor] for d, p in pick.items()}
    if (fit := _fitted_pair(sc["ccw"], sc["cw"], axes)) is not None:
        return fit
    return diagnose_pair((sc["ccw"].angle_rad, sc["ccw"].radial_error),
                         (sc["cw"].angle_rad, sc["cw"].radial_error), result.radius,
                         (pick["ccw"].feed_rate_rad_s, pick["cw"].feed_rate_rad_s), axes,
                         sensor, command_radius(pick["ccw"], pick["cw"], result.radius))
