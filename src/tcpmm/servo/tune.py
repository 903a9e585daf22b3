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
   At most four filters per axis, the drive's own counted.
3. **Position loop.** The largest ``K_pp`` meeting the margins and at most a quarter of
   the velocity loop's bandwidth; every axis given then takes the smallest of them (equal
   position gains keep a circle round). :func:`tune_machine` matches the axes of the
   machine it is given: :func:`tcpmm.whatif.tuning.tune_and_predict` gives it the axes the
   path moves, and tunes any other on its own (:mod:`tcpmm.servo.tunealone`).
4. **Feedforward** is left as it is here: it does not change the margins, and its best
   value depends on friction and the path, so :func:`tcpmm.whatif.tuning.tune_and_predict`
   chooses it by simulating the path.

Every changed setting gets a note saying why it changed and what limits it: the margin
(and its crossover frequency) that fails just above a gain, the quarter of the velocity
bandwidth, or the axis whose position loop sets the common ``K_pp``. A loop whose last
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
from dataclasses import dataclass, field

import numpy as np

from .._forked import results_in_order, usable_jobs
from ..mechanics.lumped import AxisMechanics
from .currentfilters import MAX_FILTERS, Notch
from .margins import axis_margins, position_margins, velocity_margins
from .modeshift import (
    VELOCITY_ONLY_K_PP,
    light_mode_warnings,
    light_modes,
    robustly_stable,
    shift_words,
    slower_warnings,
    worst_shift,
)
from .params import ServoParams
from .sampled import sampled_spectral_radius
from .tunewords import gain_notes, kpp_reason

#: Scan step of the gains, and the relative resolution of the bisection [-].
_STEP, _RESOLUTION = 1.25, 0.005
#: Step of the velocity gain's scan down from above, and its steps: down to 1e-8 of
#: where it starts [-].
_DESCENT = 1.5
_DESCENT_TRIES = math.ceil(math.log(1e8) / math.log(_DESCENT))
#: How near the limiting crossing a lightly damped mode takes a notch [-].
_NOTCH_NEAR = 0.2


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


def _with(servo: ServoParams, **changes) -> ServoParams:
    return ServoParams.create(**{**servo.model_dump(), **changes})


def _pi(mech: AxisMechanics, servo: ServoParams, K_vp: float) -> ServoParams:
    w_c = K_vp * mech.K_tc / mech.J_total
    return _with(servo, K_vp=K_vp, K_vi=K_vp * w_c / 4.0)


def _largest(ok, start: float, cap: float = math.inf, down: float = _STEP,
             tries: int = 40):
    """Largest ``g <= cap`` with ``ok(g)``, scanning from ``start``: upwards in steps of
    :data:`_STEP` while it holds, else downwards in steps of ``down``, at most ``tries``
    of them; ``None`` if none."""
    g = min(start, cap)
    if ok(g):
        lo, hi = g, None
        while hi is None and lo < cap:
            nxt = min(lo * _STEP, cap)
            if ok(nxt):
                lo = nxt
            else:
                hi = nxt
        if hi is None:
            return lo
    else:
        hi, lo = g, None
        for _ in range(tries):
            nxt = hi / down
            if ok(nxt):
                lo = nxt
                break
            hi = nxt
        if lo is None:
            return None
    while hi / lo > 1 + _RESOLUTION:
        mid = math.sqrt(lo * hi)
        lo, hi = (mid, hi) if ok(mid) else (lo, mid)
    return lo


def velocity_loop_ok(mech, servo, gm, pm) -> bool:
    """Whether the velocity loop of ``servo`` meets the margins and, with the position
    gain at most :data:`VELOCITY_ONLY_K_PP`, stays stable with its modes off the model's
    frequencies (:func:`~tcpmm.servo.modeshift.robustly_stable`) [-]."""
    alone = _with(servo, K_pp=min(servo.K_pp, VELOCITY_ONLY_K_PP))
    return velocity_margins(mech, servo).meets(gm, pm) and robustly_stable(mech, alone, gm)


def _velocity_gain(mech, servo, gm, pm, start=None):
    """Largest velocity gain meeting the margins, robustly stable; ``None`` if none.

    The margins are not monotone in the gain: a lightly damped mode meets them at a tiny
    gain that puts the crossover on its peak, fails them above, and a notch can let them
    be met again higher up. The scan therefore comes down from well above ``start`` (the
    settings' gain) in steps of :data:`_DESCENT` to the first gain that meets them.
    """
    def ok(k):
        return velocity_loop_ok(mech, _pi(mech, servo, k), gm, pm)
    top = _DESCENT ** 6 * (start if start is not None else servo.K_vp)
    return _largest(ok, top, down=_DESCENT, tries=_DESCENT_TRIES)


def _limiting_mode(mech, servo, modes):
    """The lightly damped mode nearest the crossing that limits the velocity gain."""
    m = velocity_margins(mech, servo)
    at = [f for f in (m.gain_crossover_hz, m.phase_crossover_hz) if np.isfinite(f)]
    best = None
    for f0 in modes:
        if any(n.type == "notch" and abs(n.f_hz - f0) < 0.05 * f0 for n in servo.filters):
            continue  # already notched
        if any(abs(f - f0) <= _NOTCH_NEAR * f0 for f in at):
            if best is None or min(abs(f - f0) for f in at) < min(abs(f - best) for f in at):
                best = float(f0)
    return best


def tune_velocity(mech, servo, gm, pm, notes):
    """Velocity-loop gains and notches (steps 1 and 2 of the module docstring)."""
    K = _velocity_gain(mech, servo, gm, pm)
    if K is None:
        case = worst_shift(mech, servo, gm)
        why = "" if case is None else f" (at the settings' gains it is {shift_words(case)})"
        notes.append("velocity loop: no gain meets the margins with the loop stable, also with "
                     f"its modes off the model's frequencies{why}; settings kept")
        return None
    best = _pi(mech, servo, K)
    freqs, zetas = light_modes(mech)
    while len(best.filters) < MAX_FILTERS:
        f0 = _limiting_mode(mech, best, freqs)
        if f0 is None:
            break
        zeta = float(zetas[np.argmin(np.abs(freqs - f0))])
        K2, notch = _best_notch(mech, best, f0, zeta, gm, pm, servo.K_vp)
        if K2 is None or K2 < 1.1 * best.K_vp:
            notes.append(f"notch at {f0:.1f} Hz does not raise the gain; not used")
            break
        notes.append(f"notch at {f0:.1f} Hz (bandwidth {0.3 * f0:.1f} Hz, {notch.depth_db} dB) "
                     "raises "
                     f"K_vp from {best.K_vp:.4g} to {K2:.4g} A s/rad")
        best = _pi(mech, _with(best, filters=[*best.filters, notch]), K2)
    f0 = _limiting_mode(mech, best, freqs) if len(best.filters) >= MAX_FILTERS else None
    if f0 is not None:
        notes.append(f"the {f0:.1f} Hz mode limits the velocity gain and gets no notch: all "
                     f"{MAX_FILTERS} filter slots of the drive are taken; free one in the model "
                     "and tune again")
    return best


def _best_notch(mech, servo, f0, zeta, gm, pm, start):
    """The notch on the mode at ``f0`` that lets the velocity gain rise furthest, and that
    gain (``None`` if no depth lets any gain meet the margins) [A s/rad, -].

    The depth that flattens the peak, ``20 log10(4 zeta)`` within -40..-10 dB, is tried
    with the shallower -20 and -10 dB: a deep notch's phase turns within a fraction of
    a percent of ``f0``, and a mode kept stable by its phase is kept so only by a notch
    whose phase does not turn where the machine's mode may lie."""
    # an undamped mode (zeta 0, or a rounding below) takes the deepest notch
    flat = round(float(np.clip(20 * np.log10(4 * max(zeta, 1e-9)), -40.0, -10.0)), 1)
    best = (None, None)
    for depth in sorted({flat, max(flat, -20.0), -10.0}):
        notch = Notch(f_hz=f0, bandwidth_hz=0.3 * f0, depth_db=depth)
        K = _velocity_gain(mech, _with(servo, filters=[*servo.filters, notch]), gm, pm,
                           start)
        if K is not None and (best[0] is None or K > best[0] * (1 + _RESOLUTION)):
            best = (K, notch)
    return best


def tune_position(mech, servo, gm, pm):
    """Largest position gain meeting the margins, at most a quarter of the velocity-loop
    bandwidth, and what limits it; ``(None, reason)`` if none [1/s, -]."""
    bw = velocity_margins(mech, servo).bandwidth_hz
    cap = 2 * math.pi * bw / 4 if np.isfinite(bw) else math.inf

    def ok(k):
        return position_margins(mech, _with(servo, K_pp=k)).meets(gm, pm)
    k = _largest(ok, servo.K_pp, cap)
    if k is None:
        return None, "no position gain meets the margins"
    if k >= cap * (1 - _RESOLUTION):
        return k, f"a quarter of the velocity-loop bandwidth ({bw:.3g} Hz)"
    return k, "the position loop's " + _limit(
        lambda g: position_margins(mech, _with(servo, K_pp=g)), None, k, gm, pm)


def _limit(margins, radius, k, gm, pm) -> str:
    """What fails just above the gain ``k``: the gain or phase margin (with its value at
    ``k`` and crossover) or the stability of the sampled loop [-]."""
    m, above = margins(k), margins(k * (1 + 3 * _RESOLUTION))
    if above.gain_margin_db < gm:
        at, there = _crossing(m, above, "gain_margin_db", "phase_crossover_hz")
        return (f"gain margin ({at.gain_margin_db:.1f} dB at its phase crossover "
                f"{_hz(at.phase_crossover_hz)} Hz{there})")
    if above.phase_margin_deg < pm:
        at, there = _crossing(m, above, "phase_margin_deg", "gain_crossover_hz")
        return (f"phase margin ({at.phase_margin_deg:.1f} deg at its gain crossover "
                f"{_hz(at.gain_crossover_hz)} Hz{there})")
    if radius is not None and radius(k * (1 + 3 * _RESOLUTION)) >= 1:
        return "stability of the sampled loop (spectral radius reaching 1)"
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
        lambda g: velocity_margins(mech, _pi(mech, servo, g)),
        lambda g: sampled_spectral_radius(mech, _pi(mech, servo, g)), servo.K_vp, gm, pm)


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
            s = _with(s, K_pp=found[lead][0])
        after = s if s is not None else a.servo
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
                               light_mode_warnings(m, mg_after, after)
                               + slower_warnings(mg_before, mg_after))
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
                                                        _with(vel[n], K_pp=k), gm_db, pm_deg)]
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
