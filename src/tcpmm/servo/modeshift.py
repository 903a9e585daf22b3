"""Stability that holds where the plant's modes lie off the model's frequencies.

A lightly damped mode inside a loop (its peak above ``|L| = 1``) is held stable by its
phase. That holds on the machine only if the phase there is the model's: a deep, narrow
notch swings the phase by 180 deg within a fraction of a percent of its frequency, so a
mode the model places 0.5 % off the machine's can turn a loop that meets its margins in
the model into one that oscillates on the machine. Identified frequencies are that far
off on the reference machines, and a machine's modes move with the axis position and the
load by more.

The check: the sampled closed loop stays stable with every mode of the mechanics moved
by a common factor ``s`` within ``1 +- MODE_TOLERANCE`` (every stiffness scaled by
``s**2`` and every damping by ``s``: the frequencies scale by ``s``, the damping ratios
stay), and so it does with the velocity controller's gain raised and lowered by the gain
margin. The factors are taken on a grid fine enough (steps of at most 0.5 %, 21 factors
at least) to catch the half of the range where a mode sits on the wrong side of a notch.
:func:`mode_tolerance` sets another band for the proposals judged inside it.

Here too are the warnings of what in a proposal rests on the model: a loop crossing over
above a lightly damped mode (where the loop sees it: a mode above its Nyquist frequency
folds about its sampling), and one slowed to less than half its bandwidth to hold its
margins.
"""

from __future__ import annotations

import contextlib
import contextvars
import math

import numpy as np

from ..errors import InputError
from ..mechanics.export import reduced_ss
from ..mechanics.lumped import AxisMechanics
from .params import ServoParams
from .sampled import (
    is_stable_radius,
    position_open_loop,
    radius_text,
    sampled_spectral_radius,
    velocity_open_loop,
)

#: A loop crossing over above a mode damped less than this gets a warning [-].
LIGHT_ZETA = 0.01
#: A mode above a loop's Nyquist frequency, folded below its last crossover, counts where
#: its peak alone reaches this loop gain there: a tenth of ``|L| = 1``. The built-in X
#: with a stiff screw sees its 7288 Hz torsion mode at 712 Hz with a peak of 12 in the
#: velocity loop; its position loop sees the 1995 Hz mode at 5 Hz with 1e-5 [-].
FOLDED_PEAK = 0.1
#: Lightly damped modes: those notches may target [-].
NOTCH_ZETA = 0.1
#: Position gain the velocity loop is judged with alone: a position loop this slow leaves
#: the velocity loop's poles where they are [1/s].
VELOCITY_ONLY_K_PP = 1.0
#: How far the machine's mode frequencies may lie from the model's, by default [-].
MODE_TOLERANCE = 0.05
_TOLERANCE = contextvars.ContextVar("mode_tolerance", default=MODE_TOLERANCE)
#: Largest step between the mode shifts checked: a -10 dB notch's phase turns within
#: +-1.5 % of its frequency [-].
_STEP = 0.005
#: What a shift scales: every stiffness by ``s**2``, every damping by ``s`` [-].
_STIFFNESSES = ("K_L", "K_t", "K_b", "K_h")
_DAMPINGS = ("B_m", "B_L", "C_t", "C_b", "C_h")


@contextlib.contextmanager
def mode_tolerance(tolerance: float):
    """Judge proposals, inside the ``with`` block, with the modes up to ``tolerance`` off
    the model's frequencies instead of :data:`MODE_TOLERANCE`.

    Parameters
    ----------
    tolerance : float
        Relative band of the mode frequencies, in [0, 0.5) [-].
    """
    if not 0.0 <= tolerance < 0.5:
        raise InputError(f"the mode tolerance must lie in [0, 50) %, got {100 * tolerance:g} %")
    token = _TOLERANCE.set(float(tolerance))
    try:
        yield
    finally:
        _TOLERANCE.reset(token)


def current_tolerance() -> float:
    """The mode tolerance proposals are judged with now (:func:`mode_tolerance`) [-]."""
    return _TOLERANCE.get()


def shifted(mech: AxisMechanics, s: float) -> AxisMechanics:
    """The mechanics with every mode's frequency multiplied by ``s`` and its damping
    ratio kept: stiffnesses times ``s**2``, dampings times ``s`` [SI]."""
    return mech.scaled(**{k: s * s for k in _STIFFNESSES}, **{c: s for c in _DAMPINGS})


def _factors(tolerance: float) -> np.ndarray:
    if tolerance == 0.0:
        return np.ones(1)
    # the model's own frequencies first, then outwards: the first failure is the nearest
    d = tolerance * np.linspace(-1.0, 1.0, 2 * max(10, math.ceil(tolerance / _STEP)) + 1)
    return 1.0 + d[np.argsort(np.abs(d), kind="stable")]


def velocity_only(servo: ServoParams) -> ServoParams:
    """The settings with the position gain at most :data:`VELOCITY_ONLY_K_PP`: the
    velocity loop as it is judged alone [SI]."""
    return ServoParams.create(**{**servo.model_dump(),
                                 "K_pp": min(servo.K_pp, VELOCITY_ONLY_K_PP)})


def worst_shift(mech: AxisMechanics, servo: ServoParams, gm_db: float,
                tolerance: float | None = None):
    """The first mode shift and controller gain factor at which the loop is unstable.

    Parameters
    ----------
    mech : AxisMechanics
        The axis as identified [SI].
    servo : ServoParams
        The settings judged [SI].
    gm_db : float
        Gain margin the controller's gain is raised and lowered by [dB].
    tolerance : float, optional
        Relative band of the mode frequencies; default :func:`current_tolerance` [-].

    Returns
    -------
    tuple of (float, float, float) or None
        ``(s, gain factor, spectral radius)`` of an unstable case [-], or ``None`` when
        every case is stable.
    """
    g = 10.0 ** (gm_db / 20.0)
    alone = velocity_only(servo)
    cases = [(1.0, servo)] + [(f, ServoParams.create(**{
        **alone.model_dump(), "K_vp": alone.K_vp * f, "K_vi": alone.K_vi * f}))
        for f in (g, 1.0 / g)]
    for s in _factors(current_tolerance() if tolerance is None else tolerance):
        m = mech if s == 1.0 else shifted(mech, float(s))
        for f, sv in cases:
            rho = sampled_spectral_radius(m, sv)
            if not is_stable_radius(rho):
                return float(s), f, rho
    return None


def robustly_stable(mech: AxisMechanics, servo: ServoParams, gm_db: float,
                    tolerance: float | None = None) -> bool:
    """Whether the loop is stable for every mode shift within the tolerance and every
    controller gain within the gain margin (see the module docstring) [-]."""
    return worst_shift(mech, servo, gm_db, tolerance) is None


def shift_words(case) -> str:
    """What a :func:`worst_shift` case means, in words [-]."""
    s, f, rho = case
    gain = "" if f == 1.0 else (f"the velocity gain {'raised' if f > 1 else 'lowered'} by "
                                "the gain margin")
    if s == 1.0 and not gain:
        return f"unstable as modelled (spectral radius {radius_text(rho)})"
    # the modes where the model puts them: no shift of "+0.0 %" to quote
    modes = ("at the model's frequencies" if s == 1.0 else
             f"{100 * (s - 1):+.1f} % off the model's frequencies")
    return (f"unstable with the modes {modes}{' and ' + gain if gain else ''} (spectral "
            f"radius {radius_text(rho)})")


def folded(freqs: np.ndarray, period_s: float) -> np.ndarray:
    """Frequencies as a loop sampled every ``period_s`` sees them: folded into
    ``[0, 1 / (2 period_s)]`` [Hz].

    Parameters
    ----------
    freqs : ndarray
        The modes' frequencies [Hz].
    period_s : float
        The sampling period [s].
    """
    fs = 1.0 / period_s
    f = np.asarray(freqs, float)
    return np.where(f > fs / 2, np.abs(f - np.round(f / fs) * fs), f)


def light_modes(mech: AxisMechanics):
    """Frequencies [Hz] and damping ratios [-] of the lightly damped modes of G_M."""
    ev = np.linalg.eigvals(reduced_ss(mech, "G_M").A)
    ev = ev[ev.imag > 0]
    zeta = np.maximum(-ev.real / np.abs(ev), 0.0)  # an undamped mode's rounding is no sign
    keep = zeta < NOTCH_ZETA
    return np.abs(ev[keep]) / (2 * np.pi), zeta[keep]


def light_mode_warnings(mech, margins: dict, servo=None, kept: bool = False) -> list[str]:
    """Warnings for loops whose last gain crossover lies above a mode of damping below
    :data:`LIGHT_ZETA`: one per loop, naming its modes. A mode above the loop's Nyquist
    frequency is judged where the sampled loop sees it, folded about its sampling, and
    named there and at its own frequency.

    Parameters
    ----------
    mech : AxisMechanics
        The axis [SI].
    margins : dict of str to LoopMargins
        ``velocity`` and ``position`` margins of the settings judged [dB, deg, Hz].
    servo : ServoParams, optional
        The settings judged: a mode they already notch is not advised a notch; their
        periods fold the modes (without them, the modes are judged unfolded) [-].
    kept : bool
        Whether they are the axis's own settings, left as they were: the warning then says
        it is about them, not about gains proposed [-].

    Returns
    -------
    list of str
        One warning per loop [-].
    """
    freqs, zetas = light_modes(mech)
    notched = [f.f_hz for f in (servo.filters if servo is not None else ())
               if f.type == "notch"]
    out, held = [], _held_words(mech, servo)
    for loop, m in margins.items():
        # the last crossover, not the one of the least phase margin: a loop that crosses
        # back above 1 at a resonance holds every mode below its last crossover
        fc = m.last_crossover_hz if np.isfinite(m.last_crossover_hz) else m.gain_crossover_hz
        below = _inside(mech, servo, loop, fc, (freqs, zetas))
        if not below:
            continue
        d = _digits(fc, below[-1][0])
        modes = _listed([_mode_words(f, f0, z, d, loop, _loop_period(servo, loop))
                         for f, f0, z in below])
        # a notch filters the current setpoint: it acts where the velocity loop sees a mode
        at = [f0 if servo is None else float(folded(f0, servo.T_v)) for _, f0, _ in below]
        bare = [f0 for f0 in at if not any(abs(n - f0) < 0.05 * f0 for n in notched)]
        advice = (f", or notch {_listed([f'the {f0:.0f} Hz mode' for f0 in bare])}"
                  if bare else " (the notches placed flatten these modes, not take them out)")
        whose, using = (("the settings kept, as they were: ", "relying on these settings")
                        if kept else ("", "using these gains"))
        out.append(f"{whose}the {loop} loop {_crossover_words(m, fc, d)}, above "
                   f"{modes}: its margins "
                   "there rest on those modes' frequencies and damping, which the model may "
                   f"have wrong{held}; measure the loop's frequency response on the machine "
                   f"before {using}{advice}")
    return out


def _inside(mech, servo, loop: str, fc: float, modes: tuple) -> list:
    """The modes of damping below :data:`LIGHT_ZETA` that lie below the ``loop``'s last
    crossover ``fc`` as it sees them: ``(seen, own frequency, damping)``, by the first
    [Hz, Hz, -]. A mode above the loop's Nyquist frequency is seen folded about its
    sampling, and counts where its peak alone there reaches :data:`FOLDED_PEAK`."""
    freqs, zetas = modes
    period = _loop_period(servo, loop)
    seen = freqs if period is None else folded(freqs, period)
    below = [(float(f), float(f0), float(z))
             for f, f0, z in sorted(zip(seen, freqs, zetas, strict=True))
             if z < LIGHT_ZETA and np.isfinite(fc) and fc > f]
    moved = [i for i, (f, f0, _) in enumerate(below) if abs(f - f0) > 1e-9 * f0]
    peaks = _folded_peaks(mech, servo, loop, [below[i][0] for i in moved]) if moved else []
    low = {i for i, p in zip(moved, peaks, strict=True) if p < FOLDED_PEAK}
    return [m for i, m in enumerate(below) if i not in low]


def _folded_peaks(mech, servo, loop: str, freqs: list) -> list:
    """The peak in the ``loop``'s gain of its lightly damped pole nearest each of ``freqs``
    alone: its residue over its distance from the unit circle; the loop decomposed once
    [-]."""
    period = _loop_period(servo, loop)
    Phi, Gam, C, _ = (velocity_open_loop if loop == "velocity" else position_open_loop)(
        mech, servo)
    lam, V = np.linalg.eig(Phi)
    out_, in_ = C @ V, np.linalg.solve(V, Gam)
    peaks = []
    for f in freqs:
        i = int(np.argmin(np.abs(lam - np.exp(2j * np.pi * f * period))))
        residue = out_[0, i] * in_[i, 0]
        peaks.append(float(abs(residue) / abs(np.exp(1j * np.angle(lam[i])) - lam[i])))
    return peaks


def _loop_period(servo, loop: str):
    """The period the ``loop`` is sampled with, ``None`` without the settings [s]."""
    if servo is None:
        return None
    return servo.T_v if loop == "velocity" else servo.T_p


def _mode_words(f: float, f0: float, z: float, d: int, loop: str, period) -> str:
    """A mode as the ``loop`` sees it, at ``f`` [Hz] to ``d`` decimals: where it is folded
    (sampled every ``period``), from its own frequency ``f0`` [-]."""
    damping = f"damping {z:.2g}" if z >= 1e-9 else "no damping"
    if abs(f - f0) <= 1e-9 * f0:
        return f"the {f:.{d}f} Hz mode of {damping}"
    return (f"the {f:.{d}f} Hz mode of {damping} (the {f0:.0f} Hz mode folded about the "
            f"{loop} loop's sampling at {1 / period:.0f} Hz)")


def _crossover_words(m, fc: float, d: int) -> str:
    """Where a loop crosses over: at ``fc`` [Hz], given to ``d`` decimals; a loop whose
    bandwidth lies lower (a mode's peak lifts its gain above 1 again) with that first, as
    its margins give it [-]."""
    bw = m.bandwidth_hz
    if not np.isfinite(bw) or f"{bw:.1f}" == f"{fc:.1f}":
        return f"crosses over at {fc:.{d}f} Hz"
    return (f"crosses over at {bw:.1f} Hz (its bandwidth) and, lifted above 1 again higher "
            f"up, last at {fc:.{d}f} Hz")


def _digits(f: float, f0: float) -> int:
    """Decimals that tell ``f`` from ``f0`` (none when whole Hz do) [-]."""
    return next((d for d in range(4) if f"{f:.{d}f}" != f"{f0:.{d}f}"), 4)


def _held_words(mech, servo) -> str:
    """How far off the model's frequencies the modes may lie with the loop stable [-]."""
    if servo is None:
        return ""
    case = worst_shift(mech, servo, 0.0)
    if case is None and current_tolerance() == 0.0:
        return (" (not checked with the modes off the model's frequencies: "
                "--mode-tolerance 0)")
    if case is None:
        return (" (checked: the loop stays stable with them up to "
                f"{100 * current_tolerance():g} % off the model's frequencies)")
    return f" (the loop is {shift_words(case)})"



def _listed(items: list) -> str:
    """``a``, ``a and b``, ``a, b and c`` [-]."""
    return items[0] if len(items) == 1 else f"{', '.join(items[:-1])} and {items[-1]}"


def slowed(before: dict, after: dict):
    """The velocity loop's bandwidth before and after when the proposal cuts it to less
    than half, else ``None`` [Hz]."""
    b, a = before["velocity"].bandwidth_hz, after["velocity"].bandwidth_hz
    return (b, a) if np.isfinite(b) and np.isfinite(a) and a < 0.5 * b else None


def bandwidth_text(f_hz: float) -> str:
    """A bandwidth as the tuning table gives it: one decimal, two significant digits below
    1 Hz (never an exponent: 120 Hz is not "1.2e+02") [Hz]."""
    return f"{f_hz:.2g}" if 0 < abs(f_hz) < 1.0 else f"{f_hz:.1f}"


def slower_warnings(before: dict, after: dict, mech=None, servo=None) -> list[str]:
    """A warning when the proposal cuts the velocity loop's bandwidth to less than half:
    the margins are met by giving up most of the loop's speed; with the axis (``mech``,
    ``servo``), naming the lightly damped modes above the velocity loop's Nyquist
    frequency, which fold back below it [-]."""
    cut = slowed(before, after)
    if cut is None:
        return []
    b, a = cut
    where = ""
    if mech is not None and servo is not None:
        fs = 1.0 / servo.T_v
        high = sorted(f for f in light_modes(mech)[0] if f > fs / 2)
        if high:
            where = (" A lightly damped mode lies above the velocity loop's Nyquist "
                     f"frequency of {fs / 2:.4g} Hz and folds back below it, where the "
                     "notches and low-passes were tried too: " + ", ".join(
                         f"{f:.4g} Hz (to {g:.4g} Hz)" for f, g in
                         zip(high, folded(np.array(high), servo.T_v), strict=True)))
    return [f"the margins are met only with the velocity loop's bandwidth cut from "
            f"{bandwidth_text(b)} to {bandwidth_text(a)} Hz: no faster velocity loop of the "
            "notches and low-passes tried meets them with its modes up to "
            f"{100 * current_tolerance():g} % off the model's frequencies, and the position "
            "gain (a quarter of that bandwidth at most, on every axis matched to this one) "
            "falls with it. Check the predicted path; smaller margins (--margins) or filters "
            "tuned on the machine may keep more speed." + where]
