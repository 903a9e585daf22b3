"""What a sweep's controller output says against machine.yaml, as warnings: the declared
gains it does not read (:func:`sweep_timing`), a position gain it contradicts
(:func:`position_gain_message`), a position loop closed on the other sensor, and an
excitation recorded with its sign reversed, the loop's timing then read with it negated.
The fit itself is :mod:`~tcpmm.ident.physical.loop_timing`'s."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ...io.csvutil import warn_input
from .loop_timing import (
    COMPUTATION_DELAY,
    GAIN_WARN,
    OTHER_SENSOR,
    LoopTiming,
    identify_loop_timing,
)

__all__ = ["FLIP_RATIO", "position_gain_message", "sweep_timing"]

#: Factor by which the controller fit's residual with the excitation negated must be
#: smaller than with it as recorded to say its sign is reversed: a reversed excitation
#: fits the reference drives as well as a right one, and with the recorded sign not at
#: all (relative residual 0.02 with it negated, 1.0 as recorded, on
#: bench C) [-].
FLIP_RATIO = 3.0
_SENSOR_NAMES = {"scale": "linear scale", "encoder": "motor encoder"}


def sweep_timing(name: str, sweep, cfg) -> LoopTiming | None:
    """The drive's timing from a closed-loop sweep (:func:`identify_loop_timing`), with a
    warning when a sweep with the loops closed does not match the declared controller.

    Parameters
    ----------
    name : str
        Axis name [-].
    sweep : SweepRecord
        The sweep record (SI) [-].
    cfg : AxisConfig
        The axis's bundle configuration [-].

    Returns
    -------
    LoopTiming or None
        ``None`` for a torque-mode sweep or too little of the loop's response [-].
    """
    timing = identify_loop_timing(sweep, cfg)
    if timing is None:
        return None
    flipped = _reversed_excitation(name, sweep, cfg, timing)
    timing = flipped or timing
    if flipped is None and not timing.determined:
        warn_input(
            f"axis {name}: the controller output in the sweep does not match the declared "
            f"velocity-loop gains with any computation delay (fitted gain factor "
            f"{timing.gain:.2f}, delay {timing.tau_periods:.2f} periods); check the gains "
            "and the lead in machine.yaml. The model assumes a delay of "
            f"{COMPUTATION_DELAY} period and a differenced encoder velocity",
            file=getattr(sweep, "source", None))
    elif abs(timing.gain - 1.0) > GAIN_WARN:
        warn_input(
            f"axis {name}: the controller output in the sweep is {timing.gain:.3g} times "
            "what the declared velocity-loop gains give: the record's time base (its "
            f"sample rate, {sweep.fs_hz:.6g} Hz), or the gains or the lead in machine.yaml, "
            "are not the drive's; the identified masses and inertias scale with the square "
            "of a time base that is off. Check the time column and the gains",
            file=getattr(sweep, "source", None))
    _check_feedback(name, sweep, cfg, timing)
    if timing.position_contradicted(cfg.servo.position_gain_1_per_s):
        warn_input(position_gain_message(name, timing, cfg.servo.position_gain_1_per_s),
                   file=getattr(sweep, "source", None))
    return timing


def _reversed_excitation(name: str, sweep, cfg, timing: LoopTiming) -> LoopTiming | None:
    """The timing read with ``excitation_A`` negated, said as a reversed excitation, where
    the declared controller does not read with the column as recorded but does with it
    negated, :data:`FLIP_RATIO` times closer; else ``None``. ``u = i_c - r`` holds the
    controller output only with the excitation's own sign: with it reversed ``u`` carries
    ``2 r`` besides, which reads as gains and a lead that are not the drive's, while the
    mechanics, read from the current command, are unchanged [-]."""
    if timing.determined or np.asarray(sweep.excitation_A).size == 0:
        return None
    flipped = identify_loop_timing(
        dataclasses.replace(sweep, excitation_A=-np.asarray(sweep.excitation_A)), cfg)
    if flipped is None or not flipped.determined or not (
            flipped.residual * FLIP_RATIO < timing.residual or math.isnan(timing.residual)):
        return None
    warn_input(
        f"axis {name}: the excitation's sign is reversed: current_cmd_A minus excitation_A "
        "is not the controller output the declared gains give (gain factor "
        f"{timing.gain:.2f}, relative residual {timing.residual:.3f}), but current_cmd_A "
        f"plus excitation_A is (gain factor {flipped.gain:.3f}, relative residual "
        f"{flipped.residual:.3f}); the loop's timing is read with the column negated. "
        "Negate excitation_A (or record the excitation with the sign the drive adds it "
        "to its current command)",
        file=getattr(sweep, "source", None), column="excitation_A")
    return flipped


def position_gain_message(name: str, timing: LoopTiming, declared: float) -> str:
    """What the sweep says of a declared position gain it contradicts [-].

    Parameters
    ----------
    name : str
        Axis name [-].
    timing : LoopTiming
        The sweep's timing, with the position gain it reads [-].
    declared : float
        The bundle's ``position_gain_1_per_s`` [1/s].
    """
    return (f"axis {name}: the controller output in the sweep "
            f"{timing.position_words(declared, 'machine.yaml')}; "
            "check servo.position_gain_1_per_s, and that the position loop was closed "
            "during the sweep: the model follows its path with the declared gain, and the "
            "figures that depend on it are left open")


def _check_feedback(name, sweep, cfg, timing) -> None:
    """Warn where the sweep reads as a position loop closed on the other sensor."""
    if not timing.other_sensor_reads_better():
        return
    said = cfg.servo.position_feedback
    warn_input(
        f"axis {name}: the controller output in the sweep reads as a position loop closed "
        f"on the {_SENSOR_NAMES[OTHER_SENSOR[said]]}, not on the {_SENSOR_NAMES[said]} "
        "machine.yaml declares "
        f"(relative residual {timing.other_feedback_residual:.3f} against "
        f"{timing.residual:.3f}); check servo.position_feedback: the model closes its "
        "loop where it is told, and its path follows from that",
        file=getattr(sweep, "source", None))
