"""The friction pulse of one axis tuned on the model: its amplitude and decay on the
circle's largest TCP reversal spike (:func:`tune_pulse`), then its dependence on the
acceleration at the reversal (:func:`adapted_pulse`, :mod:`.adaptation`), each tried as
the drive applies it, added to the current command
(:func:`tcpmm.sim.simulate.simulate`, ``current_feedforward_A``).
"""

from __future__ import annotations

import math

from ..path.command import Command
from ..sim.simulate import simulate
from .adaptation import (
    DRAWS,
    adaptation_steps,
    best_characteristic,
    holds_on_draws,
    spike_curves,
)
from .drive import reversal_pulses
from .scores import judge

#: Shares of the Coulomb current tried as the pulse amplitude [-].
PULSE_SHARES = (0.25, 0.5, 1.0, 1.5, 2.0)
#: Decay time constants tried [s]. Longer decays turn the pulse into a standing current
#: offset between reversals: on the benches they lowered a spike by at most 1.3 um while
#: raising the contour error, and lost a pulse where they won the decay's pass
#: (docs/validation/compensation.md, "Decays beyond 300 ms").
PULSE_DECAYS_S = (0.003, 0.01, 0.03, 0.1, 0.3)


def coulomb_current(axis) -> float:
    """The motor current that balances the axis's Coulomb friction, the mean of both
    directions, guideway and screw [A]; 0 without friction."""
    fr = axis.friction
    if fr is None:
        return 0.0
    force = sum(0.5 * (c.fc_pos + c.fc_neg) for c in (fr.guideway, fr.screw) if c is not None)
    m = axis.mechanics
    return force * m.R_L / m.K_tc


def controller_figures(machine, command: Command, programmed: Command, pulses: dict, radius_m,
             centre_m, plane) -> dict:
    """The model's TCP figures of ``command`` run with the current pulses, judged against
    the programmed path [-]."""
    run = simulate(machine, command, current_feedforward_A=pulses or None)
    return judge(run, programmed, radius_m, centre_m, plane)


def largest_spike(fig: dict) -> float:
    """The largest TCP reversal spike of figures from :func:`.scores.judge`; infinite where
    the circle gave none, so that such a trial never wins [um]."""
    v = fig.get("circle", {}).get("largest_spike_um", math.nan)
    return v if math.isfinite(v) else math.inf


def tune_pulse(machine, command: Command, axis: str, pulses: dict, judge_args: tuple):
    """The amplitude and decay of ``axis``'s pulse that give the smallest largest TCP
    spike with the other axes' ``pulses``; ``(0, shortest decay)`` where that does not
    lower the spike, or raises the contour error.

    Parameters
    ----------
    machine : Machine
        The identified model [SI].
    command : Command
        The command run [m].
    axis : str
        The axis tuned [-].
    pulses : dict of str to ndarray
        The pulses of the axes tuned before [A].
    judge_args : tuple
        ``(programmed, radius_m, centre_m, plane)`` of :func:`controller_figures` [-].

    Returns
    -------
    tuple of float
        ``(amplitude [A], decay [s])`` [-].
    """
    i_c = coulomb_current(machine.axes[axis])

    seen = {}

    def figures(share: float, tau: float) -> dict:
        key = (share, tau if share else 0.0)  # without a pulse the decay does not matter
        if key not in seen:
            trial = {**pulses, axis: reversal_pulses(command, axis, share * i_c, tau)}
            seen[key] = controller_figures(machine, command, judge_args[0], trial, *judge_args[1:])
        return seen[key]

    def spike(share: float, tau: float) -> float:
        return largest_spike(figures(share, tau))

    if i_c <= 0.0:
        return 0.0, PULSE_DECAYS_S[0]
    # one coordinate at a time: the amplitude at a middle decay, the decay at that
    # amplitude, then the amplitude again
    tau = PULSE_DECAYS_S[len(PULSE_DECAYS_S) // 2]
    share = min(PULSE_SHARES, key=lambda k: spike(k, tau))
    tau = min(PULSE_DECAYS_S, key=lambda d: spike(share, d))
    share = min(PULSE_SHARES, key=lambda k: spike(k, tau))
    none, got = figures(0.0, tau), figures(share, tau)
    better = (largest_spike(got) < largest_spike(none) and got["path"]["contour_error_um"]
              <= none["path"]["contour_error_um"])
    return (share * i_c, tau) if better else (0.0, PULSE_DECAYS_S[0])


def adapted_pulse(machine, command: Command, axis: str, pulse: tuple, tuned: tuple,
                  judge_args: tuple, n_draws: int = DRAWS, progress=None) -> tuple:
    """The pulse of ``axis`` with its adaptation characteristic (:mod:`.adaptation`), where
    one beats the tuned amplitude at the circle's feed overrides, loses against it at
    none of them on draws of the model (:func:`.adaptation.holds_on_draws`), and does not
    make the programmed circle's largest spike or contour error worse.

    Parameters
    ----------
    machine : Machine
        The identified model [SI].
    command : Command
        The command run [m].
    axis : str
        The axis [-].
    pulse : tuple of float
        ``(amplitude [A], decay [s])`` tuned at the programmed feed (:func:`tune_pulse`).
    tuned : tuple
        The axes tuned before: their parameters, as :func:`.adaptation.axis_pulses` takes
        them, and their pulses on ``command`` [-, A].
    judge_args : tuple
        ``(programmed, radius_m, centre_m, plane)`` of :func:`controller_figures` [-].
    n_draws : int
        Draws of the model the characteristic is checked on [-].
    progress : callable, optional
        Called with no argument :func:`.adaptation.adaptation_steps` times, as the
        characteristic's runs go, however early a guard ends them [-].

    Returns
    -------
    tuple
        ``(largest amplitude [A], Characteristic or None)`` [-].
    """
    done = [0]

    def step():
        done[0] += 1
        if progress is not None:
            progress()

    got = _adapted(machine, command, axis, (pulse, tuned), judge_args, n_draws, step)
    # the steps a guard left out, at once: the bar's total was counted before the work
    for _ in range(adaptation_steps(machine, n_draws) - done[0]):
        step()
    return got


def _adapted(machine, command: Command, axis: str, given: tuple, judge_args: tuple,
             n_draws: int, step) -> tuple:
    """:func:`adapted_pulse` of ``given``, its ``(pulse, tuned)``, calling ``step`` after
    each override and draw run [-]."""
    (amp, tau), (others, pulses) = given
    if amp == 0.0:
        return amp, None
    curves = spike_curves(machine, command, axis, tau, coulomb_current(machine.axes[axis]),
                          judge_args[1:], others, step)
    ch, top, _ = (None, amp, 0.0) if curves is None else best_characteristic(curves, amp)
    if ch is None:
        return amp, None
    if ch.low_ratio == 1.0 and ch.accel_m_per_s2[0] <= curves.accel_m_per_s2.min():
        ch = None  # one amplitude at every override tuned: a better one, not a shape
    flat, adapted = (controller_figures(machine, command, judge_args[0], {
        **pulses, axis: reversal_pulses(command, axis, a, tau, c)}, *judge_args[1:])
        for a, c in ((amp, None), (top, ch)))
    if (largest_spike(adapted) <= largest_spike(flat) and adapted["path"]["contour_error_um"]
            <= flat["path"]["contour_error_um"] and holds_on_draws(
                machine, command, axis, ((amp, tau, None), (top, tau, ch)), others,
                judge_args[1:], n_draws, progress=step)):
        return top, ch
    return amp, None  # the tuned amplitude, not one the guards could not vouch for
