"""The velocity loop of a tuning proposal: its largest gain and its notches.

Steps 1 and 2 of :mod:`tcpmm.servo.tune`, and the scans both loops' gains share.
"""

from __future__ import annotations

import math

import numpy as np

from ..mechanics.lumped import AxisMechanics
from .currentfilters import MAX_FILTERS, LowPass, Notch
from .margins import velocity_margins
from .modeshift import (
    current_tolerance,
    folded,
    light_modes,
    robustly_stable,
    shift_words,
    slowed,
    velocity_only,
    worst_shift,
)
from .params import ServoParams

#: Scan step of the gains, and the relative resolution of the bisection [-].
_STEP, RESOLUTION = 1.25, 0.005
#: Step of the velocity gain's scan down from above, and its steps: down to 1e-8 of
#: where it starts [-].
_DESCENT = 1.5
_DESCENT_TRIES = math.ceil(math.log(1e8) / math.log(_DESCENT))
#: How near the limiting crossing a lightly damped mode takes a notch [-].
_NOTCH_NEAR = 0.2
#: Least rise of the velocity gain for which a filter (a notch or the low-pass) is kept [-].
_KEPT_RISE = 1.1
#: Natural frequencies of the low-pass tried where no notch keeps the loop's speed, as
#: shares of the limiting mode's, and its damping ratios (0.7: a drive's default) [-].
LOW_PASS_SHARES = (1 / 2, 1 / 3, 1 / 4, 1 / 6, 1 / 8)
LOW_PASS_ZETAS = (0.7, 1.0)
#: The lowest low-pass tried, in multiples of the settings' velocity bandwidth [-].
LOW_PASS_ABOVE = 3.0


def changed(servo: ServoParams, **changes) -> ServoParams:
    """The settings with ``changes`` (field name to value), validated anew [SI]."""
    return ServoParams.create(**{**servo.model_dump(), **changes})


#: Relative difference within which a gain a tuning finds is the one the axis has: the
#: same search on the loop it tuned before lands a bit or two from where it did [-]
SAME_GAIN = 1e-9


def same_gains_kept(before: ServoParams, after: ServoParams) -> ServoParams:
    """``after`` with each gain (``K_vp``, ``K_vi``, ``K_pp``) within :data:`SAME_GAIN`
    of ``before``'s set to it: a gain kept is said to be kept, and moves no figure [SI]."""
    keep = {k: getattr(before, k) for k in ("K_vp", "K_vi", "K_pp")
            if math.isclose(getattr(after, k), getattr(before, k), rel_tol=SAME_GAIN)}
    return changed(after, **keep) if keep else after


def with_pi(mech: AxisMechanics, servo: ServoParams, K_vp: float) -> ServoParams:
    """The settings with the velocity gain ``K_vp`` [A s/rad] and the PI corner tied to
    it: ``K_vi = K_vp w_c / 4``, ``w_c = K_vp K_tc / J_total`` [SI]."""
    w_c = K_vp * mech.K_tc / mech.J_total
    return changed(servo, K_vp=K_vp, K_vi=K_vp * w_c / 4.0)


def largest_gain(ok, start: float, cap: float = math.inf, down: float = _STEP,
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
    while hi / lo > 1 + RESOLUTION:
        mid = math.sqrt(lo * hi)
        lo, hi = (mid, hi) if ok(mid) else (lo, mid)
    return lo


def velocity_loop_ok(mech, servo, gm, pm) -> bool:
    """Whether the velocity loop of ``servo`` meets the margins and, judged alone
    (:func:`~tcpmm.servo.modeshift.velocity_only`), stays stable with its modes off the
    model's frequencies (:func:`~tcpmm.servo.modeshift.robustly_stable`) [-]."""
    return (velocity_margins(mech, servo).meets(gm, pm)
            and robustly_stable(mech, velocity_only(servo), gm))


def _velocity_gain(mech, servo, gm, pm, start=None):
    """Largest velocity gain meeting the margins, robustly stable; ``None`` if none.

    The margins are not monotone in the gain: a lightly damped mode meets them at a tiny
    gain that puts the crossover on its peak, fails them above, and a notch can let them
    be met again higher up. The scan therefore comes down from well above ``start`` (the
    settings' gain) in steps of :data:`_DESCENT` to the first gain that meets them.
    """
    def ok(k):
        return velocity_loop_ok(mech, with_pi(mech, servo, k), gm, pm)
    top = _DESCENT ** 6 * (start if start is not None else servo.K_vp)
    return largest_gain(ok, top, down=_DESCENT, tries=_DESCENT_TRIES)


def _limiting_mode(mech, servo, modes, notched=False):
    """The lightly damped mode nearest the crossing that limits the velocity gain; with
    ``notched``, also one a notch of the settings lies near (within 5 %) [Hz]."""
    m = velocity_margins(mech, servo)
    at = [f for f in (m.gain_crossover_hz, m.phase_crossover_hz) if np.isfinite(f)]
    best = None
    for f0 in modes:
        if not notched and _near_notch(servo, f0) is not None:
            continue  # already notched
        if any(abs(f - f0) <= _NOTCH_NEAR * f0 for f in at):
            if best is None or min(abs(f - f0) for f in at) < min(abs(f - best) for f in at):
                best = float(f0)
    return best


def tune_velocity(mech, servo, gm, pm, notes):
    """Velocity-loop gains and filters (steps 1 and 2 of :mod:`tcpmm.servo.tune`)."""
    K = _velocity_gain(mech, servo, gm, pm)
    if K is None:
        case = worst_shift(mech, servo, gm)
        why = "" if case is None else f" (at the settings' gains it is {shift_words(case)})"
        notes.append("velocity loop: no gain meets the margins with the loop stable, also with "
                     f"its modes off the model's frequencies{why}; settings kept")
        return None
    true_f, zetas = light_modes(mech)
    # a mode above the velocity loop's Nyquist frequency limits it where it folds to: a
    # filter of the sampled current setpoint acts there
    freqs = folded(true_f, servo.T_v)
    best, f0, unused = _notched(mech, with_pi(mech, servo, K), servo.K_vp, (freqs, zetas),
                                gm, pm, notes)
    at = len(notes)  # where the notch of no use is said, once the low-pass is known
    if f0 is not None and f0 not in true_f:
        notes.append(f"the {f0:.1f} Hz mode that limits the velocity gain is the "
                     f"{true_f[np.argmin(np.abs(freqs - f0))]:.0f} Hz mode folded about the "
                     f"velocity loop's sampling at {1 / servo.T_v:.0f} Hz")
    low = _low_passed(mech, servo, best, f0, gm, pm, notes)
    if unused is not None:  # judged before the low-pass, said as such where one is kept
        notes.insert(at, _unused_words(unused, "" if low is None else " without a low-pass"))
    if low is not None:
        best, _, again = _notched(mech, low, servo.K_vp, (freqs, zetas), gm, pm, notes)
        if again is not None:
            notes.append(_unused_words(again))
    # with every slot taken, the mode that limits the gain is named even where a notch
    # lies near it: that notch does not remove it (four at 700 Hz, the mode at 729 Hz)
    full = len(best.filters) >= MAX_FILTERS
    f0 = _limiting_mode(mech, best, freqs, notched=True) if full else None
    if f0 is not None:
        near = _near_notch(best, f0)
        notes.append(f"the {f0:.1f} Hz mode limits the velocity gain and gets no notch: all "
                     f"{MAX_FILTERS} filter slots of the drive are taken"
                     + ("" if near is None else f" (the notch at {near:g} Hz near it does not "
                        "remove it)") + "; free one in the model and tune again")
    return best


def _near_notch(servo, f0):
    """The frequency of a notch of ``servo`` within 5 % of ``f0``; None for none [Hz]."""
    return next((n.f_hz for n in servo.filters
                 if n.type == "notch" and abs(n.f_hz - f0) < 0.05 * f0), None)


def _unused_words(f0: float, judged: str = "") -> str:
    """The note of a notch at ``f0`` that does not raise the gain, ``judged`` as said [-]."""
    return f"notch at {f0:.1f} Hz does not raise the gain{judged}; not used"


def _notched(mech, best, start, modes, gm, pm, notes):
    """Notches on the lightly damped modes that limit the gain, one at a time while each
    raises it by 10 % or more, each said in ``notes``: the settings, the first limiting
    mode met and the mode whose notch stopped the search by not raising the gain
    (:func:`_unused_words` says it; each ``None`` if none) [SI, Hz, Hz]."""
    freqs, zetas = modes
    first = unused = None
    while len(best.filters) < MAX_FILTERS:
        f0 = _limiting_mode(mech, best, freqs)
        if f0 is None:
            break
        first = f0 if first is None else first
        zeta = float(zetas[np.argmin(np.abs(freqs - f0))])
        K2, notch = _best_notch(mech, best, f0, zeta, gm, pm, start)
        if K2 is None or K2 < _KEPT_RISE * best.K_vp:
            unused = f0
            break
        notes.append(f"notch at {f0:.1f} Hz (bandwidth {0.3 * f0:.1f} Hz, {notch.depth_db} dB) "
                     "raises the largest K_vp that meets the margins from "
                     f"{best.K_vp:.4g} without it to {K2:.4g} A s/rad")
        best = with_pi(mech, changed(best, filters=[*best.filters, notch]), K2)
    return best, first, unused


def _low_passed(mech, servo, best, f0, gm, pm, notes):
    """Step 2b: where the notches leave the velocity loop less than half the settings'
    bandwidth, a PT2 low-pass below the mode ``f0`` that limited the gain, in their place:
    the natural frequency and damping of :data:`LOW_PASS_SHARES` and
    :data:`LOW_PASS_ZETAS` that let the gain rise furthest, kept if it rises by 10 % or
    more; ``None`` where none is tried or kept [SI].

    A mode of damping 0.001 peaks some 50 dB above its line; a notch deep enough to hold
    it turns its phase within a fraction of a percent of its frequency, and with the mode
    a few percent off the model's (:mod:`tcpmm.servo.modeshift`) the loop is held by
    neither. A low-pass well below the mode lowers the loop there whatever its frequency,
    and costs the crossover only its phase."""
    if f0 is None or len(servo.filters) >= MAX_FILTERS:
        return None
    settings = velocity_margins(mech, servo)
    if slowed({"velocity": settings}, {"velocity": velocity_margins(mech, best)}) is None:
        return None
    before = settings.bandwidth_hz
    K, low = best.K_vp, None
    for share in LOW_PASS_SHARES:
        if share * f0 < LOW_PASS_ABOVE * before:
            break
        for zeta in LOW_PASS_ZETAS:
            cand = LowPass(f_hz=share * f0, zeta=zeta)
            k = _velocity_gain(mech, changed(servo, filters=[*servo.filters, cand]), gm, pm,
                               servo.K_vp)
            if k is not None and k > K * (1 + RESOLUTION):
                K, low = k, cand
    if low is None or K < _KEPT_RISE * best.K_vp:
        return None
    instead = ", in place of its notch," if len(best.filters) > len(servo.filters) else ""
    notes.append(f"low-pass {low.f_hz:.1f} Hz (damping {low.zeta:g}) below the {f0:.1f} Hz "
                 f"mode{instead} raises K_vp from {best.K_vp:.4g} to {K:.4g} "
                 f"A s/rad: no notch holds that mode with its frequency up to "
                 f"{100 * current_tolerance():g} % off the model's without the loop losing "
                 "more than half its bandwidth")
    return with_pi(mech, changed(servo, filters=[*servo.filters, low]), K)


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
        K = _velocity_gain(mech, changed(servo, filters=[*servo.filters, notch]), gm, pm,
                           start)
        if K is not None and (best[0] is None or K > best[0] * (1 + RESOLUTION)):
            best = (K, notch)
    return best
