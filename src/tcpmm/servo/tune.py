"""Servo tuning for stability margins, as a drive's auto-tuning does it.

For each axis, on the sampled loops of :mod:`tcpmm.servo.sampled`:

1. **Velocity loop.** The largest proportional gain ``K_vp`` whose open loop meets the
   gain and phase margins, with the PI corner tied to the gain (integral action
   ``K_vi = K_vp w_c / 4``, ``w_c = K_vp K_tc / J_total`` the rigid-body crossover), its
   sampled closed loop stable with a position loop too slow to move its poles (the
   settings' own ``K_pp``, which step 3 replaces, does not decide it). The gain is scanned
   upwards in steps of 1.25 until the margins fail, then bisected.
2. **Notches.** When the crossing that limits the gain lies within 20 % of a lightly
   damped plant mode (damping below 0.1), a notch is placed on that mode (bandwidth
   0.3 f0, depth ``20 log10(4 zeta)`` within -40..-10 dB: deep enough to flatten the
   resonance peak of height ``1/(2 zeta)``) and step 1 is repeated; it is kept if the
   gain rises by 10 % or more. At most four filters per axis, the drive's own counted.
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
gain crossover lies above a plant mode of damping below :data:`LIGHT_ZETA` gets a
warning: its margins there rest on that mode's frequency and damping, which an
identified model rarely has right.

A proposal is checked once more at the end: both loops meet the margins and the
spectral radius of the sampled closed loop is below 1; an axis for which no gain meets
the margins keeps its settings and is reported as not met.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..mechanics.export import reduced_ss
from ..mechanics.lumped import AxisMechanics
from .currentfilters import MAX_FILTERS, Notch
from .margins import axis_margins, position_margins, velocity_margins
from .params import ServoParams
from .sampled import sampled_spectral_radius

#: Scan step of the gains, and the relative resolution of the bisection [-].
_STEP, _RESOLUTION = 1.25, 0.005
#: Lightly damped modes that notches may target, and how near the limiting crossing [-].
_NOTCH_ZETA, _NOTCH_NEAR = 0.1, 0.2
#: A loop crossing over above a mode damped less than this gets a warning [-].
LIGHT_ZETA = 0.01


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


def _largest(ok, start: float, cap: float = math.inf):
    """Largest ``g <= cap`` with ``ok(g)``, scanning from ``start``; ``None`` if none."""
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
        for _ in range(40):
            nxt = hi / _STEP
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


#: Position gain the velocity loop's own stability is judged with: a position loop this
#: slow leaves the velocity loop's poles where they are, where the settings' own K_pp
#: (which step 3 replaces) would make the velocity gain depend on it [1/s].
VELOCITY_ONLY_K_PP = 1.0


def _velocity_gain(mech, servo, gm, pm):
    def ok(k):
        s = _pi(mech, servo, k)
        alone = _with(s, K_pp=min(servo.K_pp, VELOCITY_ONLY_K_PP))
        return velocity_margins(mech, s).meets(gm, pm) and sampled_spectral_radius(
            mech, alone) < 1
    return _largest(ok, servo.K_vp)


def _modes(mech: AxisMechanics):
    """Frequencies [Hz] and damping ratios [-] of the lightly damped modes of G_M."""
    ev = np.linalg.eigvals(reduced_ss(mech, "G_M").A)
    ev = ev[ev.imag > 0]
    zeta = np.maximum(-ev.real / np.abs(ev), 0.0)  # an undamped mode's rounding is no sign
    keep = zeta < _NOTCH_ZETA
    return np.abs(ev[keep]) / (2 * np.pi), zeta[keep]


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
        notes.append("velocity loop: no gain meets the margins; settings kept")
        return None
    best = _pi(mech, servo, K)
    freqs, zetas = _modes(mech)
    while len(best.filters) < MAX_FILTERS:
        f0 = _limiting_mode(mech, best, freqs)
        if f0 is None:
            break
        zeta = float(zetas[np.argmin(np.abs(freqs - f0))])
        # an undamped mode (zeta 0, or a rounding below) takes the deepest notch
        depth = float(np.clip(20 * np.log10(4 * max(zeta, 1e-9)), -40.0, -10.0))
        notch = Notch(f_hz=f0, bandwidth_hz=0.3 * f0, depth_db=round(depth, 1))
        trial = _with(best, filters=[*best.filters, notch])
        K2 = _velocity_gain(mech, trial, gm, pm)
        if K2 is None or K2 < 1.1 * best.K_vp:
            notes.append(f"notch at {f0:.1f} Hz does not raise the gain; not used")
            break
        notes.append(f"notch at {f0:.1f} Hz (bandwidth {0.3 * f0:.1f} Hz, {notch.depth_db} dB) "
                     "raises "
                     f"K_vp from {best.K_vp:.4g} to {K2:.4g} A s/rad")
        best = _pi(mech, trial, K2)
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
        return k, f"a quarter of the velocity-loop bandwidth ({bw:.1f} Hz)"
    return k, "the position loop's " + _limit(
        lambda g: position_margins(mech, _with(servo, K_pp=g)), None, k, gm, pm)


def _limit(margins, radius, k, gm, pm) -> str:
    """What fails just above the gain ``k``: the gain or phase margin (with its value at
    ``k`` and crossover) or the stability of the sampled loop [-]."""
    m, above = margins(k), margins(k * (1 + 3 * _RESOLUTION))
    if above.gain_margin_db < gm:
        return (f"gain margin ({m.gain_margin_db:.1f} dB at its phase crossover "
                f"{m.phase_crossover_hz:.0f} Hz)")
    if above.phase_margin_deg < pm:
        return (f"phase margin ({m.phase_margin_deg:.1f} deg at its gain crossover "
                f"{m.gain_crossover_hz:.0f} Hz)")
    if radius is not None and radius(k * (1 + 3 * _RESOLUTION)) >= 1:
        return "stability of the sampled loop (spectral radius reaching 1)"
    return (f"margins ({m.gain_margin_db:.1f} dB, {m.phase_margin_deg:.1f} deg; the scan "
            "found no larger gain meeting them)")


def velocity_limit(mech, servo, gm, pm) -> str:
    """What limits the velocity gain of a proposal (see :func:`_limit`) [-]."""
    return "the velocity loop's " + _limit(
        lambda g: velocity_margins(mech, _pi(mech, servo, g)),
        lambda g: sampled_spectral_radius(mech, _pi(mech, servo, g)), servo.K_vp, gm, pm)


def light_mode_warnings(mech, margins: dict, servo=None) -> list[str]:
    """Warnings for loops whose last gain crossover lies above a mode of damping below
    :data:`LIGHT_ZETA`: one per loop, naming its modes.

    Parameters
    ----------
    mech : AxisMechanics
        The axis [SI].
    margins : dict of str to LoopMargins
        ``velocity`` and ``position`` margins of the settings judged [dB, deg, Hz].
    servo : ServoParams, optional
        The settings judged: a mode they already notch is not advised a notch [-].

    Returns
    -------
    list of str
        One warning per loop [-].
    """
    freqs, zetas = _modes(mech)
    notched = [f.f_hz for f in (servo.filters if servo is not None else ())
               if f.type == "notch"]
    out = []
    for loop, m in margins.items():
        # the last crossover, not the one of the least phase margin: a loop that crosses
        # back above 1 at a resonance holds every mode below its last crossover
        fc = m.last_crossover_hz if np.isfinite(m.last_crossover_hz) else m.gain_crossover_hz
        below = [(f0, z) for f0, z in sorted(zip(freqs, zetas, strict=True))
                 if z < LIGHT_ZETA and np.isfinite(fc) and fc > f0]
        if not below:
            continue
        modes = _listed([f"the {f0:.0f} Hz mode of damping {z:.2g}" if z >= 1e-9 else
                         f"the {f0:.0f} Hz mode of no damping" for f0, z in below])
        bare = [f0 for f0, _ in below if not any(abs(n - f0) < 0.05 * f0 for n in notched)]
        advice = (f", or notch {_listed([f'the {f0:.0f} Hz mode' for f0 in bare])}"
                  if bare else " (the notches placed flatten these modes, not take them out)")
        out.append(f"the {loop} loop crosses over at {fc:.0f} Hz, above {modes}: its margins "
                   "there rest on those modes' frequencies and damping, which the model may "
                   "have wrong; measure the loop's frequency response on the machine before "
                   f"using these gains{advice}")
    return out


def _listed(items: list) -> str:
    """``a``, ``a and b``, ``a, b and c`` [-]."""
    return items[0] if len(items) == 1 else f"{', '.join(items[:-1])} and {items[-1]}"


def gain_notes(before, after, limits) -> list[str]:
    """A note per changed gain saying why it changed and what limits it [-]."""
    notes = []
    if not math.isclose(after.K_vp, before.K_vp, rel_tol=1e-9):
        notes.append(f"K_vp {before.K_vp:.4g} -> {after.K_vp:.4g} A s/rad: the largest "
                     f"velocity gain meeting the margins, limited by {limits['K_vp']}")
    if not math.isclose(after.K_vi, before.K_vi, rel_tol=1e-9):
        notes.append(f"K_vi {before.K_vi:.4g} -> {after.K_vi:.4g} A/rad: the integral action "
                     "follows K_vp (PI corner at a quarter of the rigid-body crossover "
                     "K_vp K_tc / J)")
    if not math.isclose(after.K_pp, before.K_pp, rel_tol=1e-9):
        notes.append(f"K_pp {before.K_pp:.4g} -> {after.K_pp:.4g} 1/s: {limits['K_pp']}")
    return notes


def tune_machine(machine, gm_db: float, pm_deg: float) -> dict:
    """Tuning proposals of every axis (see the module docstring).

    Parameters
    ----------
    machine : Machine
        The model [SI].
    gm_db : float
        Required gain margin of both loops [dB].
    pm_deg : float
        Required phase margin of both loops [deg].

    Returns
    -------
    dict of str to AxisTuning
    """
    vel, notes = {}, {}
    for name, a in machine.axes.items():
        notes[name] = []
        vel[name] = tune_velocity(a.mechanics, a.servo, gm_db, pm_deg, notes[name])
    kpp = {n: tune_position(machine.axes[n].mechanics, s, gm_db, pm_deg)
           for n, s in vel.items() if s is not None}
    found = {n: kr for n, kr in kpp.items() if kr[0] is not None}
    lead = _lead(machine, vel, found, gm_db, pm_deg)
    out = {}
    for name, a in machine.axes.items():
        m, s = a.mechanics, vel[name]
        if s is not None and lead is not None:
            s = _with(s, K_pp=found[lead][0])
        after = s if s is not None else a.servo
        mg_after = axis_margins(m, after)
        rho = sampled_spectral_radius(m, after)
        met = (s is not None and all(v.meets(gm_db, pm_deg) for v in mg_after.values())
               and rho < 1.0)
        if s is not None and not met:
            why = "margins" if rho < 1.0 else f"stability (sampled loop spectral radius " \
                                              f"{rho:.4f}, not below 1)"
            notes[name].append(f"the combined proposal misses the {why}; settings kept")
            after, mg_after = a.servo, axis_margins(m, a.servo)
        elif met:
            limits = {"K_vp": velocity_limit(m, after, gm_db, pm_deg),
                      "K_pp": _kpp_reason(name, lead, found, list(machine.axes))}
            notes[name] = gain_notes(a.servo, after, limits) + notes[name]
        out[name] = AxisTuning(a.servo, after, axis_margins(m, a.servo), mg_after, met,
                               notes[name], light_mode_warnings(m, mg_after, after))
    return out


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
    """Both loops meet the margins and the sampled loop is stable [-]."""
    return (all(v.meets(gm_db, pm_deg) for v in axis_margins(m, servo).values())
            and sampled_spectral_radius(m, servo) < 1.0)


def _kpp_reason(name, lead, found, names) -> str:
    """Why an axis has the common position gain of the axes ``names`` [-]."""
    if len(names) == 1:
        return f"the largest position gain of this axis, limited by {found[lead][1]} (no " \
               "other axis to match)"
    why = (f"the common position gain of axes {', '.join(names)} (equal gains keep a "
           "contour's shape: a circle round)")
    if name == lead:
        return f"{why}, set by this axis: {found[lead][1]}"
    return f"{why}, set by axis {lead}: {found[lead][1]}; this axis alone would take " \
           f"{found[name][0]:.4g} 1/s"
