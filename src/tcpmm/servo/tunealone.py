"""Tuning of an axis the path does not move: its own settings, matched to no other axis.

The position gains of the axes a path moves are matched (:func:`tcpmm.servo.tune.tune_machine`)
so that their lags agree; an axis the path leaves standing has no lag on it to agree with.
It keeps its settings when they meet the margins; otherwise only what misses changes, on
the axis alone: a position gain that misses is lowered to the largest this axis takes with
its own velocity loop, and a velocity loop that misses is tuned as
:func:`tcpmm.servo.tune.tune_velocity` tunes it, its position gain then its own largest.
The feedforward stays as it is: it is judged on the path, which does not move the axis.
"""

from __future__ import annotations

from .margins import axis_margins
from .modeshift import slower_warnings
from .params import ServoParams
from .sampled import radius_text, sampled_spectral_radius
from .tune import (
    AxisTuning,
    light_mode_warnings,
    meets_margins,
    tune_position,
    tune_velocity,
    velocity_limit,
    velocity_loop_ok,
)
from .tunevelocity import same_gains_kept
from .tunewords import gain_notes


def tune_alone(mech, servo: ServoParams, gm_db: float, pm_deg: float) -> AxisTuning:
    """Proposal for an axis the path does not move (see the module docstring).

    Parameters
    ----------
    mech : AxisMechanics
        The axis [SI].
    servo : ServoParams
        Its settings [SI].
    gm_db : float
        Required gain margin of both loops [dB].
    pm_deg : float
        Required phase margin of both loops [deg].

    Returns
    -------
    AxisTuning
        Settings before and after, margins, and a note per changed setting [-].
    """
    before = axis_margins(mech, servo)
    if meets_margins(mech, servo, gm_db, pm_deg):
        return AxisTuning(servo, servo, before, before, True,
                          [f"settings kept: they meet {gm_db:g} dB / {pm_deg:g} deg"],
                          light_mode_warnings(mech, before, servo, kept=True))
    notes = []
    vel = (servo if velocity_loop_ok(mech, servo, gm_db, pm_deg) else
           tune_velocity(mech, servo, gm_db, pm_deg, notes))
    k, why = (None, "") if vel is None else tune_position(mech, vel, gm_db, pm_deg)
    # its own largest may lie above its gain: a gain raised is no margin met, and the
    # path does not move the axis to gain from it
    k = k if k is None else min(k, servo.K_pp)
    after = None if k is None else same_gains_kept(servo, ServoParams.create(
        **{**vel.model_dump(), "K_pp": k}))
    if after is None or not meets_margins(mech, after, gm_db, pm_deg):
        what = "no gain meets" if after is None else "the proposal misses"
        if vel is not None:  # else the velocity loop's note said why, and that they are kept
            notes.append(f"its settings miss {gm_db:g} dB / {pm_deg:g} deg and {what} them "
                         "on this axis alone; settings kept")
        return AxisTuning(servo, servo, before, before, False, notes,
                          light_mode_warnings(mech, before, servo, kept=True))
    limits = {"K_vp": velocity_limit(mech, after, gm_db, pm_deg),
              "K_pp": f"the settings miss {_missed(mech, servo, before, gm_db, pm_deg)}; the "
                      f"largest position gain of this axis alone, limited by {why}"}
    margins = axis_margins(mech, after)
    return AxisTuning(servo, after, before, margins, True,
                      gain_notes(servo, after, limits) + notes,
                      light_mode_warnings(mech, margins, after)
                      + slower_warnings(before, margins, mech, after))


def _missed(mech, servo, margins: dict, gm_db: float, pm_deg: float) -> str:
    """The margins a setting misses, with their values, or the stability of its sampled
    loop [-]."""
    out = []
    for loop, m in margins.items():
        if m.gain_margin_db < gm_db:
            out.append(f"the {loop} loop's gain margin ({m.gain_margin_db:.1f} dB)")
        if m.phase_margin_deg < pm_deg:
            out.append(f"the {loop} loop's phase margin ({m.phase_margin_deg:.1f} deg)")
    if not out:
        rho = sampled_spectral_radius(mech, servo)
        return f"the stability of the sampled loop (spectral radius {radius_text(rho)})"
    return " and ".join(out)
