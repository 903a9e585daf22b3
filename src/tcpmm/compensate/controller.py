"""Controller-side compensation computed from the identified model: per axis a friction
pulse at each reversal (the quadrant-error compensation of a CNC: a current, or velocity
setpoint, pulse that decays) and a cross-talk feed-forward (a position offset proportional
to the axis's commanded acceleration, cancelling the structure's deflection at the TCP).

Both are simulated as the drive applies them: the pulse is added to the current command
(:func:`tcpmm.sim.simulate.simulate`, ``current_feedforward_A``), the offset to the position
setpoint. The pulse's amplitude and decay are those that minimise the model's largest TCP
reversal spike of the circle given, among amplitudes up to the axis's Coulomb friction and
decays of a few milliseconds; a pulse that does not lower it is not applied.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..path.command import Command
from ..sim.simulate import simulate, simulate_axis
from .drive import reversal_pulses, with_cross_talk
from .scores import judge

#: Shares of the Coulomb current tried as the pulse amplitude [-].
PULSE_SHARES = (0.25, 0.5, 1.0, 1.5, 2.0)
#: Decay time constants tried [s].
PULSE_DECAYS_S = (0.003, 0.01, 0.03, 0.1, 0.3)
#: Probe of the cross-talk gain: a sine of this amplitude and frequency, slow against every
#: mode of the structure, whose deflection then follows the acceleration [m], [Hz].
PROBE_AMPLITUDE_M, PROBE_HZ = 5e-3, 2.0


@dataclass(frozen=True)
class AxisController:
    """The controller-side compensation of one axis.

    Parameters
    ----------
    pulse_A : float
        Amplitude of the current pulse at a reversal, signed with the new direction [A].
    decay_s : float
        Its exponential decay time [s].
    velocity_pulse_m_per_s : float
        The same pulse as a velocity setpoint pulse (current over the velocity loop's
        proportional gain), as a quadrant-error compensation takes it [m/s].
    cross_talk_s2 : float
        TCP deflection relative to the scale per commanded acceleration; the position
        setpoint is offset by minus this times the acceleration [m/(m/s^2)].
    """

    pulse_A: float
    decay_s: float
    velocity_pulse_m_per_s: float
    cross_talk_s2: float

    def to_dict(self) -> dict:
        """The parameters in the units a commissioning engineer types, under the names of
        the file :meth:`ControllerCompensation.parameter_text` writes [-]."""
        return {"friction_pulse_A": self.pulse_A, "friction_pulse_decay_ms": self.decay_s * 1e3,
                "FRICT_COMP_CONST_MAX_mm_per_min": self.velocity_pulse_m_per_s * 6e4,
                "FRICT_COMP_TIME_s": self.decay_s,
                "cross_talk_um_per_m_per_s2": self.cross_talk_s2 * 1e6}


def velocity_per_ampere(axis) -> float:
    """The velocity setpoint pulse a quadrant-error compensation gives for one ampere of
    current pulse: through the velocity loop's proportional gain, at the table [m/s/A]."""
    return axis.mechanics.R_L / axis.servo.K_vp


@dataclass
class ControllerCompensation:
    """Controller-side compensation of every axis and what the model predicts of it.

    Parameters
    ----------
    axes : dict of str to AxisController
        Per axis [-].
    scores : dict
        Predicted TCP figures ``before`` and ``after`` (:func:`.scores.judge`) [-].
    robustness : dict
        The share kept over draws of the model and their verdict
        (:func:`.controller_robust.robust_controller`); empty where not judged [-].
    """

    axes: dict
    scores: dict = field(default_factory=dict)
    robustness: dict = field(default_factory=dict)

    def to_pandas(self):
        """One row per axis with its parameters [-]."""
        import pandas as pd

        return pd.DataFrame([{"axis": a, **c.to_dict()} for a, c in self.axes.items()])

    def to_dict(self) -> dict:
        """JSON-ready: the parameters per axis and the figures before and after [-]."""
        return {"axes": {a: c.to_dict() for a, c in self.axes.items()},
                "scores": self.scores, "robustness": self.robustness}

    def plot(self, ax=None, path=None):
        """The predicted figures before and after, as bars; the figure [-]."""
        from ..plot.compensation import (
            plot_controller_compensation,  # tcpmm.plot is a floor above this one
        )

        return plot_controller_compensation(self, path=path, ax=ax)

    def parameter_text(self) -> str:
        """The parameters as a commissioning engineer types them, per axis [-]."""
        lines = ["# Controller-side compensation computed by tcpmm from the model.",
                 "# Friction pulse at each reversal: current feed-forward (Fanuc-style) or",
                 "# velocity setpoint pulse (Sinumerik quadrant error compensation:",
                 "# FRICT_COMP_CONST_MAX [mm/min], FRICT_COMP_TIME [s]); cross-talk",
                 "# feed-forward: position setpoint offset = -gain * commanded acceleration."]
        def num(x):  # + 0.0: a gain of -0 reads as a sign to a reader
            return f"{x + 0.0:.4g}"

        for a, c in self.axes.items():
            d = c.to_dict()
            off = "  # no pulse kept: the time does nothing" if d["friction_pulse_A"] == 0 else ""
            lines += [f"{a}:",
                      f"  friction_pulse_A: {num(d['friction_pulse_A'])}",
                      f"  friction_pulse_decay_ms: {num(d['friction_pulse_decay_ms'])}{off}",
                      f"  FRICT_COMP_CONST_MAX_mm_per_min: "
                      f"{num(d['FRICT_COMP_CONST_MAX_mm_per_min'])}",
                      f"  FRICT_COMP_TIME_s: {num(d['FRICT_COMP_TIME_s'])}{off}",
                      f"  cross_talk_um_per_m_per_s2: {num(d['cross_talk_um_per_m_per_s2'])}"]
        return "\n".join(lines) + "\n"


def coulomb_current(axis) -> float:
    """The motor current that balances the axis's Coulomb friction, the mean of both
    directions, guideway and screw [A]; 0 without friction."""
    fr = axis.friction
    if fr is None:
        return 0.0
    force = sum(0.5 * (c.fc_pos + c.fc_neg) for c in (fr.guideway, fr.screw) if c is not None)
    m = axis.mechanics
    return force * m.R_L / m.K_tc


def cross_talk_gain(axis) -> float:
    """The TCP's deflection relative to the scale per commanded acceleration, from a slow
    sine run on the model: the least-squares slope of ``tcp - scale`` on the commanded
    acceleration [m/(m/s^2)]."""
    T = axis.servo.T_p
    t = np.arange(0.0, 3.0 / PROBE_HZ, T)
    w = 2 * math.pi * PROBE_HZ
    x = PROBE_AMPLITUDE_M * (1.0 - np.cos(w * t))
    run = simulate_axis(axis.replace(friction=None), t, x, quantise_feedback=False)
    n = min(run.tcp.size, t.size)
    a = PROBE_AMPLITUDE_M * w * w * np.cos(w * t[:n])
    d = run.tcp[:n] - run.scale[:n]
    keep = t[:n] >= 1.0 / PROBE_HZ  # after the start's transient
    a, d = a[keep] - np.mean(a[keep]), d[keep] - np.mean(d[keep])
    return float(a @ d / (a @ a)) if a @ a > 0 else 0.0


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


def controller_compensation(machine, command: Command, radius_m: float,
                            centre_m=(0.0, 0.0), plane=("X", "Y")) -> ControllerCompensation:
    """Friction pulses and cross-talk feed-forward for the axes of a circle, from the
    model, with the figures it predicts before and after.

    The cross-talk feed-forward is kept where it lowers the model's contour error; each
    axis's pulse is tuned in turn on the circle's largest TCP spike (:func:`tune_pulse`).

    Parameters
    ----------
    machine : Machine
        The identified model [SI].
    command : Command
        The circle's programmed command [m].
    radius_m : float
        Its radius [m].
    centre_m : tuple of float
        Its centre [m].
    plane : tuple of str
        Its axes [-].

    Returns
    -------
    ControllerCompensation
        The parameters per axis and the scores before and after [-].
    """
    axes = [a for a in plane if a in command.axes]
    args = (command, radius_m, centre_m, plane)
    before = controller_figures(machine, command, command, {}, *args[1:])
    gains = {a: cross_talk_gain(machine.axes[a]) for a in axes}
    ctc = with_cross_talk(command, gains)
    if (controller_figures(machine, ctc, command, {}, *args[1:])["path"]["contour_error_um"]
            >= before["path"]["contour_error_um"]):
        gains, ctc = dict.fromkeys(axes, 0.0), command
    pulses, params = {}, {}
    for a in axes:
        amp, tau = tune_pulse(machine, ctc, a, pulses, args)
        pulses[a] = reversal_pulses(ctc, a, amp, tau)
        ax = machine.axes[a]
        params[a] = AxisController(amp, tau, amp * velocity_per_ampere(ax), gains[a])
    after = controller_figures(machine, ctc, command, pulses, *args[1:])
    return ControllerCompensation(params, {"before": before, "after": after})
