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

import json
import math
from dataclasses import dataclass, field, replace

import numpy as np

from ..path.command import Command
from ..sim.simulate import simulate_axis
from .adaptation import DRAWS, Characteristic, adaptation_steps
from .drive import reversal_pulses, with_cross_talk

# the tuning of one pulse has a module of its own; its names stay importable from here
from .pulse_tuning import PULSE_DECAYS_S as PULSE_DECAYS_S
from .pulse_tuning import PULSE_SHARES as PULSE_SHARES
from .pulse_tuning import adapted_pulse as adapted_pulse
from .pulse_tuning import controller_figures as controller_figures
from .pulse_tuning import coulomb_current as coulomb_current
from .pulse_tuning import largest_spike as largest_spike
from .pulse_tuning import tune_pulse as tune_pulse

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
    characteristic : Characteristic or None
        The pulse's dependence on the acceleration at the reversal
        (:mod:`.adaptation`); ``pulse_A`` is then its largest amplitude. ``None``: one
        amplitude at every reversal [-].
    """

    pulse_A: float
    decay_s: float
    velocity_pulse_m_per_s: float
    cross_talk_s2: float
    characteristic: Characteristic | None = None

    def scaled(self, share: float) -> AxisController:
        """The parameters with the pulse and the feed-forward times ``share``, the decay
        and the characteristic's shape as they are [-]."""
        return replace(self, pulse_A=self.pulse_A * share, cross_talk_s2=self.cross_talk_s2
                       * share, velocity_pulse_m_per_s=self.velocity_pulse_m_per_s * share)

    def to_dict(self) -> dict:
        """The parameters in the units a commissioning engineer types, under the names of
        the file :meth:`ControllerCompensation.parameter_text` writes [-]."""
        out = {"friction_pulse_A": self.pulse_A, "friction_pulse_decay_ms": self.decay_s * 1e3,
               "FRICT_COMP_CONST_MAX_mm_per_min": self.velocity_pulse_m_per_s * 6e4,
               "FRICT_COMP_TIME_s": self.decay_s,
               "cross_talk_um_per_m_per_s2": self.cross_talk_s2 * 1e6}
        ch = self.characteristic
        if self.pulse_A != 0.0 and ch is None:  # said off: a controller may have it on
            out["FRICT_COMP_ADAPT_ENABLE"] = 0
        elif self.pulse_A != 0.0:  # no pulse: nothing to adapt
            out.update({"friction_pulse_min_A": self.pulse_A * ch.low_ratio,
                        "FRICT_COMP_ADAPT_ENABLE": 1,
                        "FRICT_COMP_CONST_MIN_mm_per_min":
                            self.velocity_pulse_m_per_s * 6e4 * ch.low_ratio,
                        **{f"FRICT_COMP_ACCEL{i}_m_per_s2": a
                           for i, a in enumerate(ch.accel_m_per_s2, start=1)}})
        return out


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

    def parameter_text(self, model: dict | None = None) -> str:
        """The parameters as a commissioning engineer types them, per axis, with the
        machine data numbers of a Sinumerik quadrant-error compensation; ``model`` the
        name and digest of the model they were computed on
        (:func:`tcpmm.io.modelfile.model_identity`), written first where given [-]."""
        lines = list(PARAMETER_HEAD)
        if model is not None:
            lines += ["model:  # what the parameters were computed on",
                      f"  name: {json.dumps(model['name'])}", f"  digest: {model['digest']}"]

        def num(x):  # + 0.0: a gain of -0 reads as a sign to a reader
            return f"{x + 0.0:.4g}"

        for a, c in self.axes.items():
            d = c.to_dict()
            off = "no pulse kept: the time does nothing" if d["friction_pulse_A"] == 0 else ""
            lines += [f"{a}:",
                      f"  friction_pulse_A: {num(d['friction_pulse_A'])}",
                      f"  friction_pulse_decay_ms: {num(d['friction_pulse_decay_ms'])}"
                      f"{'  # ' + off if off else ''}",
                      f"  FRICT_COMP_CONST_MAX_mm_per_min: "
                      f"{num(d['FRICT_COMP_CONST_MAX_mm_per_min'])}  # MD32520",
                      f"  FRICT_COMP_TIME_s: {num(d['FRICT_COMP_TIME_s'])}  # MD32540"
                      f"{'; ' + off if off else ''}"]
            if d.get("FRICT_COMP_ADAPT_ENABLE") == 0:
                lines.append("  FRICT_COMP_ADAPT_ENABLE: 0  # MD32510")
            elif "FRICT_COMP_ADAPT_ENABLE" in d:
                lines += ["  FRICT_COMP_ADAPT_ENABLE: 1  # MD32510",
                          f"  friction_pulse_min_A: {num(d['friction_pulse_min_A'])}",
                          f"  FRICT_COMP_CONST_MIN_mm_per_min: "
                          f"{num(d['FRICT_COMP_CONST_MIN_mm_per_min'])}  # MD32530"]
                lines += [f"  FRICT_COMP_ACCEL{i}_m_per_s2: "
                          f"{num(d[f'FRICT_COMP_ACCEL{i}_m_per_s2'])}  # MD{32540 + 10 * i}"
                          for i in (1, 2, 3)]
            lines.append(f"  cross_talk_um_per_m_per_s2: {num(d['cross_talk_um_per_m_per_s2'])}")
        return "\n".join(lines) + "\n"


#: The head of the parameter file: what each key is and where it goes [-].
PARAMETER_HEAD = (
    "# Controller-side compensation computed by tcpmm from the model.",
    "# Friction pulse at each reversal, in two forms; give the controller one:",
    "# - a current (torque) feed-forward, friction_pulse_A decaying with",
    "#   friction_pulse_decay_ms, for drives that take a current pulse at a reversal",
    "#   (Fanuc's backlash acceleration and the like: convert it to the drive's own units",
    "#   and parameters, which depend on its servo software);",
    "# - a velocity setpoint pulse, a Sinumerik quadrant error compensation",
    "#   (MD32490 FRICT_COMP_MODE = 1, MD32500 FRICT_COMP_ENABLE = 1): FRICT_COMP_CONST_MAX",
    "#   [mm/min] and FRICT_COMP_TIME [s]. Where the pulse depends on the acceleration at",
    "#   the reversal, FRICT_COMP_ADAPT_ENABLE = 1 with the adaptation characteristic: the",
    "#   amplitude rises from 0 to FRICT_COMP_CONST_MAX (friction_pulse_A) up to ACCEL1,",
    "#   holds it to ACCEL2, goes straight to FRICT_COMP_CONST_MIN (friction_pulse_min_A)",
    "#   at ACCEL3 and holds that beyond [m/s^2].",
    "# Cross-talk feed-forward: position setpoint offset = -gain * commanded acceleration.")


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


def controller_steps(machine, command: Command, plane=("X", "Y"),
                     adapt_draws: int | None = DRAWS) -> int:
    """The calls to ``progress`` of :func:`controller_compensation` with these arguments:
    one for the figures before and the cross-talk feed-forward, one per axis for its
    pulse's amplitude and decay and :func:`.adaptation.adaptation_steps` for its
    characteristic, one for the figures after [-]."""
    per_axis = 1 + (0 if adapt_draws is None else adaptation_steps(machine, adapt_draws))
    return 2 + per_axis * sum(a in command.axes for a in plane)


def controller_compensation(machine, command: Command, radius_m: float,
                            centre_m=(0.0, 0.0), plane=("X", "Y"),
                            adapt_draws: int | None = DRAWS,
                            progress=None) -> ControllerCompensation:
    """Friction pulses and cross-talk feed-forward for the axes of a circle, from the
    model, with the figures it predicts before and after.

    The cross-talk feed-forward is kept where it lowers the model's contour error; each
    axis's pulse is tuned in turn on the circle's largest TCP spike (:func:`tune_pulse`),
    then, unless ``adapt_draws`` is ``None``, its dependence on the acceleration at the reversal
    (:func:`adapted_pulse`).

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
    adapt_draws : int or None
        Also compute each pulse's adaptation characteristic, checked on this many draws
        of the model (:func:`.adaptation.holds_on_draws`); ``None``: one amplitude [-].
    progress : callable, optional
        Called with no argument after each step of the work, :func:`controller_steps`
        times in all [-].

    Returns
    -------
    ControllerCompensation
        The parameters per axis and the scores before and after [-].
    """
    tick = progress if progress is not None else (lambda: None)
    axes = [a for a in plane if a in command.axes]
    args = (command, radius_m, centre_m, plane)
    before = controller_figures(machine, command, command, {}, *args[1:])
    gains = {a: cross_talk_gain(machine.axes[a]) for a in axes}
    ctc = with_cross_talk(command, gains)
    if (controller_figures(machine, ctc, command, {}, *args[1:])["path"]["contour_error_um"]
            >= before["path"]["contour_error_um"]):
        gains, ctc = dict.fromkeys(axes, 0.0), command
    tick()
    pulses, params = {}, {}
    for a in axes:
        amp, tau = tune_pulse(machine, ctc, a, pulses, args)
        tick()
        others = {b: (c.pulse_A, c.decay_s, c.characteristic) for b, c in params.items()}
        amp, ch = (amp, None) if adapt_draws is None else adapted_pulse(
            machine, ctc, a, (amp, tau), (others, pulses), args, adapt_draws, tick)
        pulses[a] = reversal_pulses(ctc, a, amp, tau, ch)
        ax = machine.axes[a]
        params[a] = AxisController(amp, tau, amp * velocity_per_ampere(ax), gains[a], ch)
    after = controller_figures(machine, ctc, command, pulses, *args[1:])
    tick()
    return ControllerCompensation(params, {"before": before, "after": after})
