"""Learning control on the identified model: the position command iterated until the
predicted TCP follows the programmed path.

Per axis ``u_{k+1} = u_k + g L (r_d - y_tcp,k)``, with ``L`` the Q-filtered inverse of the
model's linear response (:mod:`.inverse`), ``g`` a learning gain below one because friction
and play make the model's response differ from its linear part, and ``r_d`` the programmed
path delayed by the model's mean lag: a common delay leaves the path as it is and spares
the command the steep lead it would need to cancel the lag outright. After every step the
correction is scaled back to the axis's limits (:mod:`.bounds`), so the iteration converges
to the best command that keeps them; the best is then held to the drive's current
(:mod:`.currentlimit`).

Where an axis's path has stood still for :data:`REST_TIME_CONSTANTS` of its position
loop's time constants, the correction fades out (:func:`at_rest`): by then the servo has
brought the axis to rest, and what error is left there is held by friction. Pushed on
against it, the learning hunts: the correction swings by micrometres through a hold, and
the TCP with it, past the path's end and past the corners where one axis stops.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..path.command import Command
from ..sim.simulate import simulate_axis
from .bounds import fit_within, machine_bounds, scaled_within, shrink
from .currentlimit import CurrentHold, within_current
from .inverse import (
    apply_filter,
    fft_length,
    impulse_response,
    lag_samples,
    learning_filter,
    settle_samples,
)
from .outcome import Compensation
from .turns import held_to, holds, pieces

#: Default corner of the Q-filter: friction transients and the lag lie below it, the
#: head and bed modes that identification places least firmly lie around and above it [Hz].
CUTOFF_HZ = 40.0

#: Samples over which the correction fades in at the start [-].
FADE_SAMPLES = 5

#: Longest hold after the program for the TCP to settle [s].
TAIL_S = 0.6


def extended(command: Command, delay: int, tail: int) -> tuple[Command, Command]:
    """The programmed command held ``delay + tail`` samples longer, and the path the TCP is
    to follow: the same delayed by ``delay`` samples [-]."""
    n = command.time_s.size + delay + tail
    t = command.time_s[0] + np.arange(n) * command.period_s

    def held(x):
        return np.concatenate([x, np.full(delay + tail, x[-1])])

    def delayed(x):
        return np.concatenate([np.full(delay, x[0]), x, np.full(tail, x[-1])])

    # a program's block of each sample, held and delayed with it: its G0 rapids stay out
    # of the contour error, as tcpmm contour leaves them out
    blocks = dict(zip(("nc_line", "rapid"), command.blocks() or (), strict=False))
    return tuple(Command(t, {a: f(p) for a, p in command.positions.items()},
                         {**command.meta, **{k: f(b) for k, b in blocks.items()}})
                 for f in (held, delayed))


def fade(n: int, tail: int) -> np.ndarray:
    """Window that is 0 at the first and last sample and 1 between, with raised-cosine
    edges: a few samples at the start (the axis starts at rest on the first command) and
    the second half of the hold at the end."""
    w = np.ones(n)
    k, m = min(FADE_SAMPLES, n // 4), max(2, min(tail // 2, n // 4))
    w[:k] = 0.5 - 0.5 * np.cos(np.pi * np.arange(k) / k)
    w[n - m:] = 0.5 + 0.5 * np.cos(np.pi * np.arange(1, m + 1) / m)
    return w


#: Position-loop time constants over which the correction fades out once the path stands
#: still, the same again before it moves [-]: after the first the servo has brought the
#: lag down to about a seventh.
REST_TIME_CONSTANTS = 2.0


def at_rest(target: np.ndarray, period_s: float, rest_s: float) -> np.ndarray:
    """Window that is 1 where the path moves and falls to 0 as a raised cosine over the
    first ``2 rest_s`` of a stretch it stands still for, rising back over the last ``2
    rest_s`` before it moves again (none where the path ends); a stretch too short to
    reach 0 dips less, and one within the path shorter than ``2 rest_s``, or at its end
    shorter than ``rest_s``, not at all; 1 everywhere where ``rest_s`` is infinite [-]."""
    if not np.isfinite(rest_s):
        return np.ones(target.size)
    n, k = target.size, max(2, round(rest_s / period_s))
    keep = np.ones(n)
    for a, b in holds(target):  # the path arrives at a, stands still from a + 1
        lo, hi = a + 1 + k, (b - k if b < n else n)
        if hi > lo:
            keep[lo:hi] = 0.0
    ramp = np.hanning(2 * k + 1)
    return np.minimum(1.0, np.convolve(np.pad(keep, k, mode="edge"), ramp / ramp.sum(), "valid"))


def plain(axis, time_s, position_m, quantise_feedback: bool = False):
    """The axis run on a position command alone, feedback unquantised unless asked [-]."""
    return simulate_axis(axis, time_s, position_m, quantise_feedback=quantise_feedback)


def learn_axis(axis, time_s, reference, target, gain_filter, bounds, iterations: int,
               gain: float, tail: int, plant=plain, progress=None, keep_slow: bool = True):
    """Learning control of one axis on its model.

    Parameters
    ----------
    axis : Axis
        The model axis [SI].
    time_s : ndarray
        Time line [s].
    reference, target : ndarray
        Programmed command and the path the TCP is to follow [m].
    gain_filter : ndarray
        Learning operator (:func:`.inverse.learning_filter`) [-].
    bounds : AxisBounds
        The axis's limits [-].
    iterations, gain : int, float
        Learning steps and the learning gain ``g`` [-].
    tail : int
        Samples of the hold after the program [-].
    plant : callable
        ``(axis, time_s, position_m, quantise_feedback=False) -> AxisRun``: how the axis
        runs a command, with the controller's own compensation where it has one
        (:func:`.drive.axis_plant`); where its attribute ``fires_pulses`` is true, the
        corrected command turns the axis back only where the program does, within
        ``pulse_s`` of it, or at the ends of a hold (:mod:`.turns`) [-].
    progress : callable, optional
        Called with no argument after each learning step, ``iterations + 1`` times [-].
    keep_slow : bool
        :func:`.bounds.fit_within`, else :func:`.bounds.scaled_within` [-].

    Returns
    -------
    tuple
        The correction of the best iterate [m] and the largest TCP error per
        iteration [m].
    """
    T, within = float(time_s[1] - time_s[0]), fit_within if keep_slow else scaled_within
    keep_turns = turn_keeper(plant, reference, T)
    fit = lambda c: keep_turns(within(reference, c, T, bounds))  # noqa: E731
    # the velocity loop's peaks between samples, which a drive's clamp meets
    current_of = lambda x, q: plant(axis, time_s, x, quantise_feedback=q).peak_current()  # noqa: E731
    hold = CurrentHold.of(current_of, reference, bounds.current)
    pad = (2 * (gain_filter.size - 1) - reference.size) // 2
    window = fade(reference.size, tail) * at_rest(target, T,
                                                  REST_TIME_CONSTANTS / axis.servo.K_pp)
    corr, history, best = np.zeros_like(reference), [], (np.inf, None)
    for _ in range(iterations + 1):
        run = plant(axis, time_s, reference + corr)
        err = target - run.tcp
        history.append(float(np.max(np.abs(err))))
        rms = float(np.sqrt(np.mean(err ** 2)))  # the max may sit where no command can help
        if rms < best[0]:
            best = (rms, corr)
        step = gain * apply_filter(gain_filter, err, pad)
        corr = fit(shrink((corr + step) * window, hold.keep(run.peak_current()), T))
        if progress is not None:
            progress()
    corr = within_current(hold, current_of, reference, best[1], fit, T)
    return corr, history


def turn_keeper(plant, reference, period_s: float):
    """``correction -> correction``: with a plant that fires the friction pulse at each
    reversal, the correction held to turn the axis back only where the program does
    (:func:`.turns.without_new_turns`, within the pulse's decay time of its reversals),
    the program's pieces found once for every learning step; without one, as it is [m]."""
    if not getattr(plant, "fires_pulses", False):
        return lambda c: c
    parts = pieces(reference, period_s, plant.pulse_s)
    return lambda c: held_to(parts, reference + c) - reference


def _check(machine, command: Command, iterations: int, gain: float, cutoff_hz: float):
    """Refuse settings the learning cannot run with [-]."""
    T = command.period_s
    if not 0.0 < gain <= 1.0 or iterations < 1:
        raise InputError("the learning gain must lie in (0, 1] and iterations be >= 1")
    if not 0.0 < cutoff_hz <= 0.25 / T:
        raise InputError(f"the Q-filter corner must lie in (0, {0.25 / T:g}] Hz, a quarter "
                         f"of the command rate; got {cutoff_hz:g} Hz")
    unknown = [a for a in command.axes if a not in machine.axes]
    if unknown:
        raise InputError(f"the command drives axis {', '.join(unknown)} that the model lacks")


def compensate(machine, command: Command, *, iterations: int = 30, gain: float = 0.5,
               cutoff_hz: float = CUTOFF_HZ, bounds=None, progress=None,
               plants=None, step=None, keep_slow: bool = True) -> Compensation:
    """Pre-compensated position command: the command whose predicted TCP path follows the
    programmed one, within the axes' limits.

    Parameters
    ----------
    machine : Machine
        The identified model [SI].
    command : Command
        The programmed command, at the interpolator's period [m].
    iterations : int
        Learning steps per axis [-].
    gain : float
        Learning gain, in (0, 1] [-].
    cutoff_hz : float
        Corner of the Q-filter; at most a quarter of the command's sample rate [Hz].
    bounds : dict of str to AxisBounds, optional
        Limits of the compensated command per axis; default the model's
        (:func:`.bounds.machine_bounds`) [-].
    progress : callable, optional
        Called with ``(axis_name, done, total)`` after each axis [-].
    plants : dict of str to callable, optional
        Per axis how it runs a command (:func:`learn_axis`); default the command alone.
        With the controller's pulse and feed-forward it learns what they leave [-].
    step : callable, optional
        Called with no argument after each learning step, ``iterations + 1`` times per axis [-].
    keep_slow : bool
        Scale back the fast part of the correction first, or the whole (:func:`learn_axis`) [-].

    Returns
    -------
    Compensation
        The programmed and the compensated command on one time line, held for the TCP to
        settle; every axis's factor 1 (:func:`.robust.robust_factors` scales it back) [-].
    """
    _check(machine, command, iterations, gain, cutoff_hz)
    T = command.period_s
    h = {a: impulse_response(machine.axes[a], T) for a in command.axes}
    delay = round(float(np.mean([lag_samples(v) for v in h.values()])))
    tail = delay + min(max(settle_samples(v) for v in h.values()), int(TAIL_S / T))
    ref, tgt = extended(command, max(delay, 0), tail)
    n = ref.time_s.size
    n_fft = fft_length(n, max(v.size for v in h.values()))
    bounds = machine_bounds(machine) if bounds is None else bounds
    corr, history = {}, {}
    for k, a in enumerate(command.axes):
        gf = learning_filter(h[a], n_fft, T, cutoff_hz)
        corr[a], history[a] = learn_axis(machine.axes[a], ref.time_s, ref.positions[a],
                                         tgt.positions[a], gf, bounds[a], iterations, gain,
                                         tail, (plants or {}).get(a, plain), step, keep_slow)
        if progress is not None:
            progress(a, k + 1, len(command.axes))
    factors = {a: np.ones(n) for a in command.axes}
    return Compensation(ref, tgt, corr, factors, max(delay, 0) * T, history,
                        {a: bounds[a] for a in command.axes},
                        {"iterations": iterations, "gain": gain, "cutoff_hz": cutoff_hz,
                         "hold_samples": max(delay, 0) + tail,
                         "limits_keep_slow_part": keep_slow})
