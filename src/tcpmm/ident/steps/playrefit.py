"""Lost-motion step: where the friction runs find play in the nut that the sweep crosses,
the mechanics fitted again with the nut as soft as the sweep saw it (the describing
function of the play at the measured nut deflection, the guideway friction holding the nut
on one flank; :mod:`tcpmm.ident.friction.playdf`), and the fit kept that explains the FRFs
best and is a solution of its own describing function; or a warning where the play cannot
be modelled."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from ... import _compiled
from ...io.csvutil import warn_input
from ...mechanics.friction import friction_params_array
from ..friction.nutstiffness import LOST_MOTION_Z
from ..friction.playdf import (
    dead_zone_gain,
    nut_deflection_amplitude,
    play_gain,
    sweep_motion,
)
from ..identification import AxisFit
from ..physical.greybox import SweepPlay
from .fitcontext import FitContext, fit_values, friction_on, physical_fit
from .playsolutions import joint_fit

if TYPE_CHECKING:
    from ..chain import AxisRun
    from ..options import IdentifyOptions
    from .frictionfit import FrictionFit

#: Most refits with the play: each takes the nut deflection through the torsion of the fit
#: before it, so they can swing about their fixed point a few times before they settle [-].
PLAY_ITERATIONS = 8
#: A refit counts only when its table mass and the runs' nut stiffness on it come back
#: within this to those its describing function assumed: only then is it a solution of it [-].
SELF_CONSISTENT_REL = 0.05
#: ... and when the nut stiffness the FRFs give through the play's factor is within this of
#: the one the factor assumed: a nut fitted far stiffer marks a false fixed point [-].
FITTED_STIFFNESS_REL = 0.25
#: Refits stop once one comes back within this of the fit before it: the next would
#: repeat it [-].
CONVERGED_REL = 0.01
#: A refit with the play replaces the linear fit only when it explains the FRFs better by
#: more than this share of the linear fit's cost: a tie is not decided by rounding [-].
COST_MARGIN_REL = 0.01
#: Table masses, relative to the linear fit's, of the first describing functions of the
#: refits with the play: the play makes the linear fit read a heavier table, and each
#: start may settle on another solution [-].
START_SCALES = (1.0, 0.8, 0.65, 0.5)
#: A chain of refits ends where a refit's table mass falls below this share of the linear
#: fit's: half the lightest start. Where the FRFs barely fix it the chains wander down to
#: 0.01-0.03 of the truth, each such fit some 20 s, and none comes back [-].
LIGHTEST_TABLE_REL = 0.25
#: Table masses, relative to the linear fit's, at which one refit each looks for rivals of
#: the solutions (:func:`rival_fits`): from the lightest start's down a fifth further to the
#: linear fit's, evenly in logarithm [-].
RIVAL_SCALES = tuple(float(s) for s in np.geomspace(0.4, 1.0, 9))


def keep_fit(run: AxisRun, options: IdentifyOptions) -> AxisFit:
    """The fit kept for one axis: the linear one without friction runs, otherwise the one
    :func:`fit_with_play` keeps.

    Parameters
    ----------
    run : AxisRun
        The axis with its excitation check, FRFs, linear fit and friction fit [-].
    options : IdentifyOptions
        Not read by this step [-].
    """
    if run.friction is None:
        return AxisFit(run.linear.physical, run.linear.physical.mechanics)
    return fit_with_play(run.context, run.sweep, run.friction, run.excitation.travel_speed,
                         run.frfs.band)


def fit_with_play(ctx: FitContext, sweep, start: FrictionFit, v_travel: float,
                  band: tuple) -> AxisFit:
    """The fit kept for an axis with friction runs: where they find lost motion and the
    sweep travels, the refits with the play (:func:`refit_with_play`); a warning where
    the sweep crossed the play and no refit models it.

    Parameters
    ----------
    ctx : FitContext
        The axis's known values, TF fits, hold and friction runs [-].
    sweep : SweepRecord
        The sweep record [-].
    start : FrictionFit
        The fit with the friction runs on it [SI].
    v_travel : float
        Steady travel speed of the sweep, 0 when it stands [m/s].
    band : tuple
        ``(fmin_hz, fmax_hz)`` of the FRFs [Hz].
    """
    kept = start.kept
    bias = bias_force(v_travel, kept.mechanics, kept.friction)
    if not (play_significant(kept.split) or kept.split.nut is not None):
        return kept
    motion = sweep_motion(sweep, *band)
    if play_significant(kept.split) and bias > 0:
        kept = refit_with_play(ctx, start, v_travel, bias, motion)
        if kept.physical.nut_gain is not None:
            return kept
        warn_sweep_crosses_play(ctx.name, sweep, kept.split, modelled=True)
    else:
        warn_sweep_crosses_play(ctx.name, sweep, kept.split)
    kept.physical.crossed_play_gain = lowest_nut_gain(motion, kept, bias)
    return kept


def lowest_nut_gain(motion, kept: AxisFit, bias: float) -> float:
    """The lowest factor the play puts on the nut's stiffness at the axial modes (table on
    the nut, bed, head), as the kept fit's mechanics and lost motion give it from the
    sweep's motion there: near 1 the play is a small part of the nut's vibration where
    the modes' masses and damping are fitted, near 0 the nut mostly floats in it [-].

    Parameters
    ----------
    motion : tuple of ndarray
        The sweep's frequencies, motor angle and scale (:func:`sweep_motion`) [Hz, rad, m].
    kept : AxisFit
        The fit kept, with its mechanics and lost motion [SI].
    bias : float
        Friction force holding the nut on one flank [N].
    """
    freq, theta_m, scale = motion
    m = kept.mechanics
    amp = nut_deflection_amplitude(freq, theta_m, scale, m)
    g = dead_zone_gain(amp, kept.split.backlash, bias / m.K_t)
    modes = [math.sqrt(k / mass) / (2 * math.pi) for k, mass in
             ((m.K_t, m.M_t), (m.K_b, m.M_b + m.M_h), (m.K_h, m.M_h)) if k > 0 and mass > 0]
    inside = [f for f in modes if freq[0] <= f <= freq[-1]]
    if not inside or g.size < 2:
        return 1.0
    return float(min(np.interp(np.log(inside), np.log(freq), g)))


def refit_with_play(ctx: FitContext, start: FrictionFit, v_travel: float, bias: float,
                    motion) -> AxisFit:
    """Refit with the nut as soft as the sweep saw it, from the linear fit and from lighter
    tables (:data:`START_SCALES`); the linear fit where no refit is a solution of its own
    describing function, otherwise the solutions found as one fit with the rivals that
    explain the FRFs as well in their spread (:func:`rival_fits`,
    :func:`~tcpmm.ident.steps.playsolutions.joint_fit`).

    The describing function can have several solutions: on one axis with 4.6 um of play,
    records that differ only by the rounding of the simulation settled on a table mass of
    0.71 or of 1.0-1.1 of the truth, the two within a tenth of each other in cost. The
    data do not choose between them, so the fit kept stands for all that are found.

    Parameters
    ----------
    ctx : FitContext
        The axis's known values, TF fits, hold and friction runs [-].
    start : FrictionFit
        The linear fit with the friction on it, the FRFs it was fitted to and the
        structure it held [SI].
    v_travel : float
        Steady travel speed of the sweep [m/s].
    bias : float
        Friction force holding the nut on one flank on the linear fit [N].
    motion : tuple of ndarray
        The sweep's frequencies, motor angle and scale (:func:`sweep_motion`) [Hz, rad, m].
    """
    found = []
    for scale in START_SCALES:
        fit = play_chain(ctx, start.data, start.structure, start.kept, v_travel, bias,
                         motion, scale, start.structure_log_std)
        if fit is not None and not any(
                abs(fit.mechanics.M_t / f.mechanics.M_t - 1.0) <= SELF_CONSISTENT_REL
                for f in found):
            found.append(fit)
    if not found:
        return start.kept
    return joint_fit(ctx, found, rival_fits(ctx, start, bias, motion, found))


def refit_as_seen(ctx: FitContext, data: dict, seen, backlash: float, bias: float, motion,
                  initial: dict | None, structure: dict | None = None,
                  structure_log_std: dict | None = None) -> tuple:
    """One refit of the FRFs ``data`` with the nut as soft as the sweep saw it on the
    mechanics ``seen``: ``(physical fit, the play's factor on K_t, the nut's deflection
    amplitude per frequency)`` [SI, -, m].

    Parameters
    ----------
    ctx : FitContext
        The axis's known values, TF fits, hold and friction runs [-].
    data : dict
        The FRFs to fit [SI].
    seen : AxisMechanics
        The mechanics the describing function is computed with [SI].
    backlash : float
        Lost motion in the nut [m].
    bias : float
        Friction force holding the nut on one flank [N].
    motion : tuple of ndarray
        The sweep's frequencies, motor angle and scale (:func:`sweep_motion`) [Hz, rad, m].
    initial : dict or None
        Starting values, used where the structure is held [SI].
    structure, structure_log_std : dict, optional
        The bed and TCP structure held in proportion to ``M_t`` and the deviation of the
        logarithm of each ratio [SI / kg, -].
    """
    freq, theta_m, scale_m = motion
    amp = nut_deflection_amplitude(freq, theta_m, scale_m, seen)
    gain = play_gain(freq, amp, backlash, bias, seen.K_t)
    phys = physical_fit(ctx, data, initial=initial if structure else None, nut_gain=gain,
                        structure=structure, structure_log_std=structure_log_std)
    return phys, gain, amp


def rival_fits(ctx: FitContext, start: FrictionFit, bias: float, motion,
               solutions: list) -> list:
    """Refits with the play as the sweep saw it at the table masses of
    :data:`RIVAL_SCALES`, one each from the linear fit, that explain the FRFs within
    :data:`COST_MARGIN_REL` of the least cost of the ``solutions`` or better, without
    being solutions of their describing functions: more than :data:`SELF_CONSISTENT_REL`
    in table mass from each (one nearer is that solution found again).

    The refits that are solutions are found by following each fit's describing function,
    which settles only on the solutions it is drawn to; others can lie between. On one
    axis whose chains all settled at 0.72-0.80 of the true table mass, single refits with
    the describing function of another table mass came out at 0.8-1.2 of it and explained
    the FRFs as well: the data hold those too, so their spread is in the deviation
    reported.

    Parameters
    ----------
    ctx : FitContext
        The axis's known values, TF fits, hold and friction runs [-].
    start : FrictionFit
        The linear fit with the friction on it and the FRFs it was fitted to [SI].
    bias : float
        Friction force holding the nut on one flank on the linear fit [N].
    motion : tuple of ndarray
        The sweep's frequencies, motor angle and scale (:func:`sweep_motion`) [Hz, rad, m].
    solutions : list of AxisFit
        The refits with the play that are solutions [SI].
    """
    linear = start.kept
    cost = min(f.physical.cost for f in solutions)
    found = []
    for scale in RIVAL_SCALES:
        seen = linear.mechanics.replace(M_t=scale * linear.mechanics.M_t)
        phys = refit_as_seen(ctx, start.data, seen, linear.split.backlash, bias, motion,
                             {**fit_values(linear.physical), "M_t": seen.M_t},
                             start.structure, start.structure_log_std)[0]
        m = phys.mechanics.M_t
        if (phys.cost <= (1.0 + COST_MARGIN_REL) * cost
                and m >= LIGHTEST_TABLE_REL * linear.mechanics.M_t
                and all(abs(m / f.mechanics.M_t - 1.0) > SELF_CONSISTENT_REL
                        for f in solutions)):
            found.append(phys)
    return found


def play_chain(ctx: FitContext, data: dict, structure: dict | None, linear: AxisFit,
               v_travel: float, bias: float, motion, scale: float = 1.0,
               structure_log_std: dict | None = None) -> AxisFit | None:
    """The refits with the play of the FRFs ``data`` from their linear fit ``linear``,
    each with the describing function of the one before, until they settle; the best that
    explains the FRFs better than the linear fit and is a solution of its own describing
    function (:data:`SELF_CONSISTENT_REL`), ``None`` without one. ``structure``, the bed
    and TCP structure held in proportion to ``M_t`` [SI / kg], ``structure_log_std`` the
    deviation of the logarithm of each ratio [-]; the others as :func:`refit_with_play`."""
    best, current = None, linear
    seen = linear.mechanics.replace(M_t=scale * linear.mechanics.M_t)
    initial = {**fit_values(linear.physical), "M_t": seen.M_t}
    freq = motion[0]
    for _ in range(PLAY_ITERATIONS):
        phys, gain, amp = refit_as_seen(ctx, data, seen, current.split.backlash, bias,
                                        motion, initial, structure, structure_log_std)
        if phys.mechanics.M_t < LIGHTEST_TABLE_REL * linear.mechanics.M_t:
            break  # past the table masses the starts search: no solution there to keep
        current = AxisFit(phys, *friction_on(ctx, phys))
        if (phys.cost < (1.0 - COST_MARGIN_REL) * (best or linear).cost
                and self_consistent(seen, current.mechanics, fitted=phys.mechanics)):
            g = gain(freq)
            lowest = int(np.argmin(g))
            phys.sweep_play = SweepPlay(bias_force_N=bias, lowest_nut_gain=float(g[lowest]),
                                        at_hz=float(freq[lowest]),
                                        nut_amplitude_there_m=float(amp[lowest]))
            best = current
        bias = bias_force(v_travel, current.mechanics, current.friction)
        converged = self_consistent(seen, current.mechanics, CONVERGED_REL)
        if converged or not (play_significant(current.split) and bias > 0):
            break
        seen, initial = current.mechanics, fit_values(phys)
    return best


def self_consistent(seen, mech, rel: float = SELF_CONSISTENT_REL, fitted=None) -> bool:
    """Whether a refit with the play's describing function came back to the table mass
    and nut stiffness the describing function was computed with, within ``rel`` [-].

    ``fitted``, the mechanics as the FRFs gave them before the friction runs replaced the
    nut stiffness, must also have the contact stiffness the describing function assumed:
    the fit scales ``K_t`` by the factor per frequency, and a fit that needs a nut several
    times stiffer than the one the factor was computed for is not a solution of it, even
    where the runs then hand back the same stiffness and table mass."""
    same = all(abs(getattr(mech, p) / getattr(seen, p) - 1.0) <= rel for p in ("M_t", "K_t"))
    return same and (fitted is None
                     or abs(fitted.K_t / seen.K_t - 1.0) <= FITTED_STIFFNESS_REL)


def play_significant(split, z: float = LOST_MOTION_Z) -> bool:
    """Whether the friction runs found lost motion beyond ``z`` standard deviations."""
    if split is None or not split.backlash > 0:
        return False
    if split.nut is not None:
        return split.nut.lost_motion_found(z)
    lm = split.estimate
    return bool(lm is not None and lm.determined and split.backlash > z * lm.backlash_std)


def bias_force(v: float, mech, fr) -> float:
    """Friction force on the table at travel speed ``v``: it holds the nut on one flank of
    its play [N]. Zero without travel or guideway friction."""
    if v <= 0 or fr is None or fr.guideway is None:
        return 0.0
    level = _compiled.call("sliding_friction", float(v), friction_params_array(fr.guideway))
    return float(level) + mech.C_t * v


def warn_sweep_crosses_play(name: str, sweep, split, modelled: bool = False) -> None:
    """Warn that the sweep crossed the nut's play and the mechanics fitted to it are
    those of a linear axis.

    Parameters
    ----------
    name : str
        Axis name [-].
    sweep : SweepRecord
        The sweep, for the file named in the warning [-].
    split : FrictionSplit
        The split of the kept fit: its lost motion and that estimate's std [m].
    modelled : bool
        The play was modelled in refits, none of which was kept [-].
    """
    remedy = ("no refit with the play modelled both fitted the FRFs better and came back to "
              "the table mass and nut stiffness its describing function was computed with, "
              "so the linear fit is kept"
              if modelled else "a sweep recorded while the axis travels at constant speed "
              "lets the play be modelled (the guideway friction holds the nut on one flank)")
    stiffness = ("The nut stiffness is taken from the friction runs" if split.nut is not None
                 else "The friction runs do not determine the nut stiffness either: K_t is "
                 "the sweep's, as soft as the play made it look")
    warn_input(
        f"axis {name}: the friction runs show {split.backlash * 1e6:.2f} +/- "
        f"{split.backlash_std * 1e6:.2f} um of lost motion in the nut, which the sweep crosses "
        "every cycle; around the axial modes its FRFs are not those of a linear axis, and "
        "the fitted split of inertia between motor side and table (M_t, and with it the "
        f"structure's M_b, K_b, M_h, K_h) can be off by tens of per cent. {stiffness}; "
        f"{remedy}. A larger excitation amplitude (within "
        "the current limit) makes the play a smaller part of the vibration; a smaller one "
        "makes it worse", file=getattr(sweep, "source", None))
