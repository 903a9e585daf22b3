"""The friction pulse's dependence on the acceleration at the reversal, as a quadrant-error
compensation's adaptation characteristic takes it (Sinumerik: MD32510
``FRICT_COMP_ADAPT_ENABLE``, MD32520/32530 ``FRICT_COMP_CONST_MAX``/``_MIN``,
MD32550-32570 ``FRICT_COMP_ACCEL1``-``3``).

The pulse a reversal needs depends on how fast the axis reverses: on a circle the axis's
acceleration at its quadrant points is ``v^2 / r``. The characteristic gives the pulse's
amplitude as a function of that acceleration ``a``, with ``a1 < a2 < a3``:

- ``a < a1``: ``A_max * a / a1``;
- ``a1 <= a <= a2``: ``A_max``;
- ``a2 < a < a3``: from ``A_max`` straight to ``A_min``;
- ``a >= a3``: ``A_min``.

A commissioning engineer finds it by trial, circle after circle at several feeds. Here it
is computed from the model: the programmed circle is run at feed overrides
(:data:`OVERRIDES`); at each, the axis's largest spike at its own quadrant points is taken
over pulse amplitudes (:data:`AMPLITUDE_SHARES` of its Coulomb current, the decay as tuned
at the programmed feed); the characteristic kept is the one whose amplitudes lose least
against the best amplitude at every override, and only where that beats the pulse of one
amplitude by more than the spikes' margin (:func:`.robust.margin`).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np
from scipy.interpolate import Akima1DInterpolator

from ..path.command import Command
from ..sim.simulate import simulate
from ..whatif.draws import drawn_machines
from .drive import reversal_pulses
from .robust import margin
from .scores import circle_figures
from .turns import reversal_accelerations, reversals

__all__ = ["AMPLITUDE_SHARES", "CHECKED", "DRAWS", "OVERRIDES", "Characteristic", "SpikeCurves",
           "adaptation_steps", "axis_pulses", "best_characteristic", "holds_on_draws",
           "quadrant_acceleration", "spike_curves", "time_scaled"]

#: Feed overrides the circle is run at: accelerations at the reversals of 1/16, 1/4 and 1
#: times the programmed; none above it, which the axes' limits may not allow [-].
OVERRIDES = (0.25, 0.5, 1.0)
#: Feed overrides the characteristic is checked at: those tuned at and one between each
#: two, where the characteristic interpolates what was tuned [-].
CHECKED = (0.25, 0.375, 0.5, 0.75, 1.0)
#: Pulse amplitudes tried at each override, shares of the axis's Coulomb current [-].
AMPLITUDE_SHARES = tuple(float(s) for s in np.arange(0.0, 3.001, 0.25))
#: Machines drawn from the model's uncertainty the characteristic is checked on [-].
DRAWS = 6


@dataclass(frozen=True)
class Characteristic:
    """An adaptation characteristic: the pulse's amplitude relative to its largest, as a
    function of the acceleration at the reversal.

    Parameters
    ----------
    accel_m_per_s2 : tuple of float
        ``(a1, a2, a3)``, increasing [m/s^2].
    low_ratio : float
        The amplitude at and beyond ``a3`` over the largest, ``A_min / A_max`` [-].
    """

    accel_m_per_s2: tuple
    low_ratio: float

    def factor(self, accel_m_per_s2) -> np.ndarray:
        """The amplitude over ``A_max`` at the accelerations given [-]."""
        a1, a2, a3 = self.accel_m_per_s2
        a = np.abs(np.asarray(accel_m_per_s2, dtype=float))
        slope = (self.low_ratio - 1.0) * (a - a2) / (a3 - a2)
        return np.where(a < a1, a / a1, np.where(a <= a2, 1.0,
                                                 np.where(a < a3, 1.0 + slope, self.low_ratio)))


def time_scaled(command: Command, override: float) -> Command:
    """The command run at ``override`` times its speed, on its own sample period: the same
    path, every acceleration ``override**2`` times as large; positions from a modified
    Akima spline through the samples, which stays flat where the command rests (a cubic
    spline rings there, and every ripple would be a reversal firing a pulse) [m]."""
    if override == 1.0:
        return command
    t, T = command.time_s, command.period_s
    n = math.floor((t[-1] - t[0]) / override / T + 1e-9) + 1
    new_t = t[0] + T * np.arange(n)
    at = np.minimum(t[0] + override * (new_t - t[0]), t[-1])  # not past the end by rounding
    # held for three samples either side: the spline's ends then see the rests the command
    # starts and ends at, where its own end slopes would ripple into a reversal
    pad = T * np.arange(1, 4)
    tt = np.concatenate([t[0] - pad[::-1], t, t[-1] + pad])
    pos = {a: Akima1DInterpolator(tt, np.concatenate([[x[0]] * 3, x, [x[-1]] * 3]),
                                  method="makima")(at)
           for a, x in command.positions.items()}
    return Command(new_t, pos, {**command.meta, "feed_override": override})


@dataclass(frozen=True)
class SpikeCurves:
    """The axis's largest spike at its own quadrant points over pulse amplitudes, at each
    feed override.

    Parameters
    ----------
    accel_m_per_s2 : ndarray
        The acceleration at the axis's reversals at each override [m/s^2].
    amplitude_A : ndarray
        The amplitudes tried [A].
    spike_um : ndarray
        Overrides by amplitudes [um].
    """

    accel_m_per_s2: np.ndarray
    amplitude_A: np.ndarray
    spike_um: np.ndarray

    def lost_um(self, amplitudes_A) -> float:
        """The largest spike over the best's, over the overrides, with one amplitude per
        override (interpolated between those tried) [um]."""
        got = [np.interp(a, self.amplitude_A, s) for a, s in zip(
            np.broadcast_to(amplitudes_A, self.accel_m_per_s2.shape), self.spike_um,
            strict=True)]
        return float(np.max(np.asarray(got) - self.spike_um.min(axis=1)))


def _points(plane, axis: str) -> tuple:
    """The quadrant points where ``axis`` reverses: A and C for the plane's first axis,
    B and D for its second [-]."""
    return ("A", "C") if axis == plane[0] else ("B", "D")


def _axis_spike(circle: dict, points: tuple) -> float:
    """The largest spike at ``points`` over the passes of a circle's figures
    (:func:`.scores.circle_figures`); infinite where none is a number, so that such a
    trial never wins [um]."""
    v = [abs(p["spikes_um"].get(k, math.nan)) for p in circle.get("passes", ())
         for k in points]
    v = [x for x in v if math.isfinite(x)]
    return max(v) if v else math.inf


def axis_pulses(command: Command, params: dict) -> dict:
    """The current pulses of ``params`` (per axis ``(amplitude [A], decay [s],
    Characteristic or None)``) at the reversals of ``command`` [A]."""
    return {a: reversal_pulses(command, a, *p) for a, p in params.items() if p[0] != 0.0}


def _spikes(machine, cmd: Command, axis: str, trials: list, others: dict, judge_args):
    """The axis's largest spike at its quadrant points with each of ``trials`` (its
    ``(amplitude, decay, characteristic)``), the other axes' pulses ``others`` as they are
    and their runs kept across the trials [um]."""
    fixed = axis_pulses(cmd, others)
    points, kept = _points(judge_args[2], axis), {}

    def spike(trial) -> float:
        run = simulate(machine, cmd, axis_runs=kept,
                       current_feedforward_A={**fixed, **axis_pulses(cmd, {axis: trial})})
        # the circle's figures alone: the path's contour error (:func:`.scores.judge`),
        # which no spike reads, took most of each trial's time in its search for the
        # nearest segment
        return _axis_spike(circle_figures(run, *judge_args), points)

    return [spike(t) for t in trials]


def spike_curves(machine, command: Command, axis: str, decay_s: float, coulomb_A: float,
                 judge_args: tuple, others: dict | None = None,
                 progress=None) -> SpikeCurves | None:
    """The axis's spikes over pulse amplitudes at each feed override; ``None`` where the
    axis does not reverse at every override.

    Parameters
    ----------
    machine : Machine
        The model [SI].
    command : Command
        The programmed circle [m].
    axis : str
        The axis [-].
    decay_s : float
        The pulse's decay [s].
    coulomb_A : float
        The axis's Coulomb current, the unit of :data:`AMPLITUDE_SHARES` [A].
    judge_args : tuple
        ``(radius_m, centre_m, plane)`` [m, m, -].
    others : dict, optional
        The pulses of the axes tuned before, as :func:`axis_pulses` takes them: the
        circle's terms are fitted to both axes, so another axis's pulse moves this one's
        spikes after the terms [-].
    progress : callable, optional
        Called with no argument after each feed override of :data:`OVERRIDES` run [-].
    """
    amps = coulomb_A * np.asarray(AMPLITUDE_SHARES)
    accel, spikes = [], []
    for k in OVERRIDES:
        cmd = time_scaled(command, k)
        turns = reversals(cmd, axis)[0]
        if turns.size == 0:
            return None
        accel.append(quadrant_acceleration(reversal_accelerations(cmd, axis, turns)))
        spikes.append(_spikes(machine, cmd, axis, [(a, decay_s, None) for a in amps],
                              others or {}, judge_args))
        if progress is not None:
            progress()
    s = np.asarray(spikes)
    return None if not np.all(np.isfinite(s)) else SpikeCurves(np.asarray(accel), amps, s)


def holds_on_draws(machine, command: Command, axis: str, pulses: tuple, others: dict,
                   judge_args: tuple, n_draws: int = DRAWS, seed: int = 0,
                   progress=None) -> bool:
    """Whether the characteristic's pulse makes the axis's spikes no larger than the pulse
    of one amplitude does, beyond the spikes' margin, at every feed override of
    :data:`CHECKED` on the model
    and on ``n_draws`` machines drawn from its uncertainty (with the floors of
    ``tcpmm spread``): one tuned on the model alone may gain at one override what the
    machine loses at another.

    Parameters
    ----------
    machine : Machine
        The model with its uncertainty [SI].
    command : Command
        The programmed circle [m].
    axis : str
        The axis [-].
    pulses : tuple
        ``(flat, adapted)``, each ``(amplitude [A], decay [s], Characteristic or None)``.
    others : dict
        The pulses of the other axes, as :func:`axis_pulses` takes them [-].
    judge_args : tuple
        ``(radius_m, centre_m, plane)`` [m, m, -].
    n_draws : int
        Machines drawn; none where the model carries no uncertainty [-].
    seed : int
        Seed of the draws [-].
    progress : callable, optional
        Called with no argument after each machine at each override checked; not for
        those left once one fails [-].
    """
    machines = drawn_machines(machine, _drawn(machine, n_draws), seed)
    for k in CHECKED:
        cmd = time_scaled(command, k)
        for m in machines:
            flat, adapted = _spikes(m, cmd, axis, list(pulses), others, judge_args)
            if progress is not None:
                progress()
            if adapted > flat + float(margin(np.array([flat * 1e-6]))[0]) * 1e6:
                return False
    return True


def _drawn(machine, n_draws: int) -> int:
    """The machines :func:`holds_on_draws` draws: ``n_draws``, none where the model
    carries no uncertainty [-]."""
    return n_draws if any(a.uncertainty is not None for a in machine.axes.values()) else 0


def adaptation_steps(machine, n_draws: int = DRAWS) -> int:
    """The calls to ``progress`` of one axis's characteristic where nothing stops it
    early: one per feed override of :func:`spike_curves`, one per machine and override of
    :func:`holds_on_draws` [-]."""
    return len(OVERRIDES) + len(CHECKED) * (1 + _drawn(machine, n_draws))


def quadrant_acceleration(accel: np.ndarray) -> float:
    """The acceleration at a circle's quadrant reversals from that at each of the axis's
    reversals: the median of those above half the largest, leaving out the reversals from
    and to rest at the circle's ends, which the feed hardly sets [m/s^2]."""
    a = np.asarray(accel, dtype=float)
    return float(np.median(a[a >= 0.5 * a.max()]))


def _candidates(accel: np.ndarray):
    """Breakpoints ``(a1, a2, a3)`` from the overrides' accelerations, the geometric
    means between them, one beyond the largest and one far below the smallest (so that
    the ramp from zero may lie below every override tuned) [m/s^2]."""
    a = np.unique(accel)
    mids = np.sqrt(a[1:] * a[:-1])
    pts = np.unique(np.concatenate([[a[0] / 16.0], a, mids, [2.0 * a[-1]]]))
    return itertools.combinations(pts.tolist(), 3)


def best_characteristic(curves: SpikeCurves, constant_A: float):
    """The characteristic that loses least against each override's best amplitude, with
    its largest amplitude; ``None`` where it does not beat ``constant_A`` at every
    override by more than the spikes' margin.

    Parameters
    ----------
    curves : SpikeCurves
        From :func:`spike_curves` [-].
    constant_A : float
        The pulse of one amplitude it is to beat [A].

    Returns
    -------
    tuple
        ``(Characteristic or None, A_max [A], lost [um])``; ``A_max`` is ``constant_A``
        where none is kept, ``lost`` what the kept pulse loses against the best [-].
    """
    flat = curves.lost_um(constant_A)
    amps = curves.amplitude_A[curves.amplitude_A > 0.0]
    best = (math.inf, None, constant_A)
    for acc in _candidates(curves.accel_m_per_s2):
        for top in amps:
            for low in curves.amplitude_A:
                ch = Characteristic(tuple(acc), float(low / top))
                lost = curves.lost_um(top * ch.factor(curves.accel_m_per_s2))
                if lost < best[0] - 1e-9:
                    best = (lost, ch, float(top))
    need = float(np.max(margin(curves.spike_um.min(axis=1) * 1e-6))) * 1e6
    if best[1] is None or best[0] >= flat - need:
        return None, constant_A, flat
    return best[1], best[2], best[0]
