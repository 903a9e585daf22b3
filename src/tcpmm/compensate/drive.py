"""How a drive applies the controller-side compensation: a current pulse at each reversal of
an axis's commanded velocity, added to its current command, and a position setpoint offset
proportional to its commanded acceleration (the cross-talk feed-forward). A position command
and these parameters together are what the machine runs (:func:`controlled_run`)."""

from __future__ import annotations

import numpy as np

from ..path.command import Command
from ..sim.simulate import simulate, simulate_axis
from .learning import plain
from .turns import reversal_accelerations, reversals

__all__ = ["axis_plant", "controlled_run", "drive_inputs", "extra_reversals", "reversal_pulses",
           "reversals", "with_cross_talk"]


def reversal_pulses(command: Command, axis: str, amplitude_A: float, decay_s: float,
                    characteristic=None):
    """The current feed-forward of one axis: at each reversal of its commanded velocity a
    pulse of ``amplitude_A`` signed with the new direction, decaying with ``decay_s`` until
    the next reversal; per command sample [A].

    ``characteristic`` (a :class:`.adaptation.Characteristic`, or ``None`` for one
    amplitude) scales each pulse by its factor at the acceleration the command has at that
    reversal, as a quadrant-error compensation's adaptation characteristic does.
    """
    x = command.positions[axis]
    out = np.zeros(x.size)
    if amplitude_A == 0.0 or x.size < 3:
        return out
    turns, s = reversals(command, axis)
    amps = np.full(turns.size, float(amplitude_A))
    if characteristic is not None:
        amps = amps * characteristic.factor(reversal_accelerations(command, axis, turns))
    t = command.time_s
    for k, i in enumerate(turns):
        end = turns[k + 1] if k + 1 < turns.size else x.size
        out[i:end] = s[i] * amps[k] * np.exp(-(t[i:end] - t[i]) / decay_s)
    return out


def extra_reversals(compensated: Command, programmed: Command) -> dict:
    """Per axis, the reversals of the compensated command and of the program, where the
    first has more: each fires a friction pulse of the controller-side compensation, also
    where the correction alone turns the axis back (the settling of a mode at a move's
    end), which the program does not ask for [-]."""
    out = {}
    for a in programmed.axes:
        if a in compensated.positions:
            got = reversals(compensated, a)[0].size
            want = reversals(programmed, a)[0].size
            if got > want:
                out[a] = (got, want)
    return out


def with_cross_talk(command: Command, gains: dict) -> Command:
    """The command with each axis's position setpoint offset by minus its cross-talk gain
    times its commanded acceleration [m]."""
    T = command.period_s
    pos = {}
    for a, x in command.positions.items():
        acc = np.gradient(np.gradient(x, T), T)
        pos[a] = x - gains.get(a, 0.0) * acc
    return Command(command.time_s, pos, {**command.meta, "cross_talk_feedforward": True})


def controlled_run(machine, command: Command, params: dict, quantise_feedback: bool = True):
    """The machine run on ``command`` with the controller-side parameters applied as the
    drive applies them: the setpoint offset by the cross-talk feed-forward, the pulses at
    the reversals of that setpoint added to the current command.

    Parameters
    ----------
    machine : Machine
        The machine run [SI].
    command : Command
        The position command the controller receives [m].
    params : dict of str to AxisController
        Per axis; an empty dict runs the command alone [-].
    quantise_feedback : bool
        Quantise the feedback sensors to their resolution [-].
    """
    ctc, pulses = drive_inputs(command, params)
    return simulate(machine, ctc, current_feedforward_A=pulses or None,
                    quantise_feedback=quantise_feedback)


def drive_inputs(command: Command, params: dict, share: float = 1.0):
    """What the drives receive with ``share`` of the controller-side parameters: the
    setpoint offset by the cross-talk feed-forward, and per axis with a pulse the current
    pulses at the reversals of that setpoint [m, A].

    Parameters
    ----------
    command : Command
        The position command the controller receives [m].
    params : dict of str to AxisController
        Per axis [-].
    share : float
        Share of the pulse and the feed-forward applied [-].
    """
    ctc = with_cross_talk(command, {a: share * c.cross_talk_s2 for a, c in params.items()})
    pulses = {a: reversal_pulses(ctc, a, share * c.pulse_A, c.decay_s, c.characteristic)
              for a, c in params.items() if c.pulse_A != 0.0 and a in ctc.positions}
    return ctc, pulses


def axis_plant(params, share: float = 1.0):
    """One axis as its controller runs it with ``share`` of its parameters: a function of
    ``(axis, time_s, position_m)`` giving the axis's run, as
    :func:`tcpmm.sim.simulate.simulate_axis` with unquantised feedback (quantised where its
    ``quantise_feedback`` says so); its attributes ``fires_pulses`` and ``pulse_s`` say
    whether the drive fires a friction pulse at each reversal and how long it acts (its
    decay time) [-, s].

    Parameters
    ----------
    params : AxisController or None
        The axis's parameters; ``None`` runs the command alone [-].
    share : float
        Share of the pulse and the feed-forward applied [-].
    """
    if params is None or share == 0.0:
        return plain

    def run(axis, time_s, position_m, quantise_feedback: bool = False):
        cmd, pulses = drive_inputs(Command(time_s, {"A": position_m}), {"A": params}, share)
        return simulate_axis(axis, time_s, cmd.positions["A"],
                             excitation_A=pulses.get("A", np.zeros(time_s.size)),
                             quantise_feedback=quantise_feedback)
    run.fires_pulses, run.pulse_s = params.pulse_A != 0.0, params.decay_s
    return run
