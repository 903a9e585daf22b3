"""Servo tuning for stability margins, as a drive's auto-tuning does it.

For each axis, on the sampled loops of :mod:`tcpmm.servo.sampled`:

1. **Velocity loop.** The largest proportional gain ``K_vp`` whose open loop meets the
   gain and phase margins, with the PI corner tied to the gain (integral action
   ``K_vi = K_vp w_c / 4``, ``w_c = K_vp K_tc / J_total`` the rigid-body crossover), its
   sampled closed loop stable with a position loop too slow to move its poles, also with
   the modes off the model's frequencies (:mod:`tcpmm.servo.modeshift`). The margins are
   not monotone in the gain, so the scan comes down from well above the settings' gain
   to the first that meets them, then bisects.
2. **Notches.** When the crossing that limits the gain lies within 20 % of a lightly
   damped plant mode (damping below 0.1), a notch is placed on that mode (bandwidth
   0.3 f0; of the depths ``20 log10(4 zeta)`` within -40..-10 dB, -20 and -10 dB, the one
   letting the gain rise furthest: a deep notch's phase turns where a mode held by its
   phase may lie) and step 1 is repeated; it is kept if the gain rises by 10 % or more.
   At most four filters per axis, the drive's own counted. Where the notches leave the
   velocity loop less than half the settings' bandwidth (a mode so lightly damped that
   no notch holds it with its frequency a few percent off), a PT2 low-pass below the
   limiting mode is tried in their place (:func:`tcpmm.servo.tunevelocity._low_passed`),
   and the notches are looked for again on top of it.
3. **Position loop.** The largest ``K_pp`` meeting the margins and at most a quarter of
   the velocity loop's bandwidth; every axis given then takes the smallest of them (equal
   position gains keep a circle round). :func:`tune_machine` matches the axes of the
   machine it is given: :func:`tcpmm.whatif.tuning.tune_and_predict` gives it the axes the
   path moves, and tunes any other on its own (:mod:`tcpmm.servo.tunealone`).
4. **Feedforward** is left as it is here: it does not change the margins, and its best
   value depends on friction and the path, so :func:`tcpmm.whatif.tuning.tune_and_predict`
   chooses it by simulating the path.

Every changed setting gets a note saying why it changed and what limits it: the margin
(and its crossover frequency) that fails just above a gain, the loop's stability with the
modes off the model's frequencies, the quarter of the velocity bandwidth, or the axis
whose position loop sets the common ``K_pp``. A loop whose last
gain crossover lies above a plant mode of damping below ``LIGHT_ZETA`` gets a
warning: its margins there rest on that mode's frequency and damping, which an
identified model rarely has right.

A proposal is checked once more at the end: both loops meet the margins and the sampled
closed loop is stable, also with the modes off the model's frequencies; an axis for which
no gain meets the margins keeps its settings and is reported as not met. A proposal that
cuts the velocity loop's bandwidth to less than half gets a warning.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field

import numpy as np

from .._forked import results_in_order, usable_jobs
from ..errors import InputError, InputWarning
from .margins import axis_margins, position_margins, velocity_margins
from .modeshift import (
    VELOCITY_ONLY_K_PP,
    current_tolerance,
    light_mode_warnings,
    robustly_stable,
    shift_words,
    slower_warnings,
    velocity_only,
    worst_shift,
)
from .params import ServoParams
from .sampled import is_stable_radius, sampled_spectral_radius
from .tunevelocity import (
    RESOLUTION,
    changed,
    largest_gain,
    same_gains_kept,
    tune_velocity,
    velocity_loop_ok,
    with_pi,
)
from .tunewords import gain_notes, kpp_reason

__all__ = ["MARGIN_RANGE", "VELOCITY_ONLY_K_PP", "AxisTuning", "check_margins",
           "light_mode_warnings", "margins_valid", "meets_margins", "tune_machine",
           "tune_position", "tune_velocity", "velocity_limit", "velocity_loop_ok"]


@dataclass(frozen=True)
class AxisTuning:
    """Tuning proposal of one axis.

    Parameters
    ----------
    before, after : ServoParams
        Settings as given and as proposed [SI].
    margins_before, margins_after : dict of str to LoopMargins
        Sampled-loop margins, ``velocity`` and ``position`` [dB, deg, Hz].
    met : bool
        Whether the proposal meets the required margins [-].
    notes : list of str
        What was decided and why [-].
    warnings : list of str
        What in the proposal rests on the model being right where it may not be [-].
    """

    before: ServoParams
    after: ServoParams
    margins_before: dict
    margins_after: dict
    met: bool
    notes: list = field(default_factory=list)
    warnings: list = field(default_factory=list)

    def to_dict(self) -> dict:
        """JSON-ready summary (SI gains, margins in dB, deg, Hz)."""
        def servo(s):
            return {"K_vp": s.K_vp, "K_vi": s.K_vi, "K_pp": s.K_pp, "k_ff": s.k_ff,
                    "filters": [f.model_dump() for f in s.filters]}

        return {"met": self.met, "before": servo(self.before), "after": servo(self.after),
                "margins_before": {k: v.to_dict() for k, v in self.margins_before.items()},
                "margins_after": {k: v.to_dict() for k, v in self.margins_after.items()},
                "notes": list(self.notes), "warnings": list(self.warnings)}


def tune_position(mech, servo, gm, pm):
    """Largest position gain meeting the margins, at most a quarter of the velocity-loop
    bandwidth, and what limits it; ``(None, reason)`` if none [1/s, -]."""
    bw = velocity_margins(mech, servo).bandwidth_hz
    cap = 2 * math.pi * bw / 4 if np.isfinite(bw) else math.inf

    def ok(k):
        return position_margins(mech, changed(servo, K_pp=k)).meets(gm, pm)
    # scanned from the cap, not from the settings' own gain: the bisection ends within
    # RESOLUTION of the largest, and where within it must not depend on the gain replaced
    k = largest_gain(ok, cap if np.isfinite(cap) else servo.K_pp, cap)
    if k is None:
        return None, "no position gain meets the margins"
    if k >= cap * (1 - RESOLUTION):
        return k, f"a quarter of the velocity-loop bandwidth ({bw:.3g} Hz)"
    return k, "the position loop's " + _limit(
        lambda g: position_margins(mech, changed(servo, K_pp=g)), None, k, gm, pm)


def _limit(margins, radius, k, gm, pm, shift=None) -> str:
    """What fails just above the gain ``k``: the gain or phase margin (with its value at
    ``k`` and crossover), the stability of the sampled loop, or (``shift``: the gain's
    :func:`~tcpmm.servo.modeshift.worst_shift`) its stability with the modes off the
    model's frequencies [-]."""
    m, above = margins(k), margins(k * (1 + 3 * RESOLUTION))
    if above.gain_margin_db < gm:
        at, there = _crossing(m, above, "gain_margin_db", "phase_crossover_hz")
        return (f"gain margin ({at.gain_margin_db:.1f} dB at its phase crossover "
                f"{_hz(at.phase_crossover_hz)} Hz{there})")
    if above.phase_margin_deg < pm:
        at, there = _crossing(m, above, "phase_margin_deg", "gain_crossover_hz")
        return (f"phase margin ({at.phase_margin_deg:.1f} deg at its gain crossover "
                f"{_hz(at.gain_crossover_hz)} Hz{there})")
    if radius is not None and not is_stable_radius(radius(k * (1 + 3 * RESOLUTION))):
        return "stability of the sampled loop (spectral radius reaching 1)"
    case = None if shift is None else shift(k * (1 + 3 * RESOLUTION))
    if case is not None:  # the margins hold above: the check of the modes' shifts binds
        return (f"stability with its modes up to {100 * current_tolerance():g} % off the "
                f"model's frequencies (just above this gain: {shift_words(case)})")
    return (f"margins ({m.gain_margin_db:.1f} dB, {m.phase_margin_deg:.1f} deg; the scan "
            "found no larger gain meeting them)")


def _hz(f: float) -> str:
    """A crossover frequency in whole Hz, or two significant digits below 10 Hz [Hz]."""
    return f"{f:.0f}" if f >= 10 else f"{f:.2g}"


def _crossing(m, above, margin: str, crossover: str):
    """The margins to quote for a limit: those at the gain, or just above it where the
    loop has no such crossover at the gain (a position loop whose gain stays below 1
    until it is raised: its phase margin infinite, its crossover none), and the words that
    say which [-]."""
    if np.isfinite(getattr(m, margin)) and np.isfinite(getattr(m, crossover)):
        return m, ""
    return above, ", where the loop first crosses over just above this gain"


def velocity_limit(mech, servo, gm, pm) -> str:
    """What limits the velocity gain of a proposal (see :func:`_limit`) [-]."""
    return "the velocity loop's " + _limit(
        lambda g: velocity_margins(mech, with_pi(mech, servo, g)),
        lambda g: sampled_spectral_radius(mech, with_pi(mech, servo, g)), servo.K_vp, gm, pm,
        lambda g: worst_shift(mech, velocity_only(with_pi(mech, servo, g)), gm))


#: The margins a proposal is tuned for, as ``tcpmm tune --margins`` and
#: :func:`tcpmm.tune_servos` take them alike: at 0 dB or 0 deg the loop is at the edge of
#: instability; 90 deg is a pure integrator's phase margin, which a loop with a delay
#: and a rolling-off plant does not reach; and a gain margin beyond 40 dB leaves the loop
#: less than a hundredth of the gain at which it turns unstable [-].
MARGIN_RANGE = "a gain margin in (0, 40] dB and a phase margin in (0, 90) deg"


def margins_valid(gm_db, pm_deg) -> bool:
    """Whether ``gm_db`` [dB] and ``pm_deg`` [deg] are numbers in :data:`MARGIN_RANGE` [-]."""
    numeric = all(isinstance(v, int | float | np.integer | np.floating)
                  and not isinstance(v, bool) for v in (gm_db, pm_deg))
    return numeric and 0 < gm_db <= 40 and 0 < pm_deg < 90  # NaN fails the comparison


def check_margins(gm_db, pm_deg) -> None:
    """Refuse margins outside :data:`MARGIN_RANGE` with an :class:`InputError`.

    Parameters
    ----------
    gm_db : float
        Required gain margin [dB].
    pm_deg : float
        Required phase margin [deg].
    """
    if not margins_valid(gm_db, pm_deg):
        raise InputError(f"gm_db={gm_db!r}, pm_deg={pm_deg!r}: give {MARGIN_RANGE} (the "
                         "phase margin in degrees, not radians)")
    if pm_deg <= math.pi / 2:  # no design asks for 1.6 deg: a margin of 90 deg or less in rad
        warnings.warn(f"pm_deg={pm_deg!r}: a phase margin of {pm_deg:g} deg leaves the loop "
                      "barely stable; if it is in radians, give "
                      f"pm_deg={math.degrees(pm_deg):.3g}", InputWarning, stacklevel=4)


def tune_machine(machine, gm_db: float, pm_deg: float, jobs: int | None = 1) -> dict:
    """Tuning proposals of every axis (see the module docstring).

    Parameters
    ----------
    machine : Machine
        The model [SI].
    gm_db : float
        Required gain margin of both loops [dB].
    pm_deg : float
        Required phase margin of both loops [deg].
    jobs : int, optional
        Axes whose own loops are tuned at once, each in a process of its own (the same
        numbers); default 1, ``None`` or 0: as many as there are cores, or ``TCPMM_JOBS``
        (:func:`~tcpmm._forked.usable_jobs`) [-].

    Returns
    -------
    dict of str to AxisTuning
    """
    pieces = [(a.mechanics, a.servo) for a in machine.axes.values()]
    with results_in_order(_own_loops, pieces, (gm_db, pm_deg),
                          usable_jobs(jobs, len(pieces))) as results:
        own = dict(zip(machine.axes, (r() for r in results), strict=True))
    vel = {n: o[0] for n, o in own.items()}
    notes = {n: o[1] for n, o in own.items()}
    kpp = {n: o[2] for n, o in own.items() if o[0] is not None}
    found = {n: kr for n, kr in kpp.items() if kr[0] is not None}
    lead = _lead(machine, vel, found, gm_db, pm_deg)
    out = {}
    for name, a in machine.axes.items():
        m, s = a.mechanics, vel[name]
        if s is not None and lead is not None:
            s = changed(s, K_pp=found[lead][0])
        after = same_gains_kept(a.servo, s) if s is not None else a.servo
        mg_before, mg_after = axis_margins(m, a.servo), axis_margins(m, after)
        case = worst_shift(m, after, gm_db)
        met = (s is not None and all(v.meets(gm_db, pm_deg) for v in mg_after.values())
               and case is None)
        if s is not None and not met:
            why = "margins" if case is None else f"stability: {shift_words(case)}"
            notes[name].append(f"the combined proposal misses the {why}; settings kept")
            after, mg_after = a.servo, mg_before
        elif met:
            limits = {"K_vp": velocity_limit(m, after, gm_db, pm_deg),
                      "K_pp": kpp_reason(name, lead, found, list(machine.axes))}
            notes[name] = gain_notes(a.servo, after, limits) + notes[name]
        out[name] = AxisTuning(a.servo, after, mg_before, mg_after, met, notes[name],
                               light_mode_warnings(m, mg_after, after,
                                                   kept=after == a.servo)
                               + slower_warnings(mg_before, mg_after, m, after))
    return out


def _own_loops(piece, shared) -> tuple:
    """One axis's velocity loop and position gain tuned on their own (step 1 to 3 before
    the axes are matched): ``(servo or None, notes, (K_pp, reason))`` [-]."""
    (mech, servo), (gm_db, pm_deg) = piece, shared
    notes: list[str] = []
    s = tune_velocity(mech, servo, gm_db, pm_deg, notes)
    return s, notes, None if s is None else tune_position(mech, s, gm_db, pm_deg)


def _lead(machine, vel, found, gm_db, pm_deg):
    """The axis whose position gain all take: the smallest of ``found``, among the axes
    that meet the margins and are stable with it (an axis that misses keeps its settings
    and sets nothing) [-]; ``found`` loses the others."""
    while found:
        lead = min(found, key=lambda n: found[n][0])
        k = found[lead][0]
        misses = [n for n in found if not meets_margins(machine.axes[n].mechanics,
                                                        changed(vel[n], K_pp=k), gm_db, pm_deg)]
        if not misses:
            return lead
        for n in misses:
            del found[n]
    return None


def meets_margins(m, servo, gm_db, pm_deg) -> bool:
    """Both loops meet the margins and the sampled loop is stable, also with the modes
    off the model's frequencies (:mod:`tcpmm.servo.modeshift`) [-]."""
    return (all(v.meets(gm_db, pm_deg) for v in axis_margins(m, servo).values())
            and robustly_stable(m, servo, gm_db))
