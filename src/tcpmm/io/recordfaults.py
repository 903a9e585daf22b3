"""Faults of a record's position columns that no fit can read through, refused as the
bundle is read, each naming the file, the line or column and the fix:

* :func:`refuse_dead_tcp` -- a ``tcp_mm`` column that holds one value while the scale
  travels: the TCP device recorded nothing (not connected, or its channel not logged);
* :func:`refuse_wrapped_angle` -- a ``motor_angle_rad`` that jumps by whole turns between
  two samples: the encoder's angle within one turn, not the axis's multi-turn angle.

Both otherwise reach the columns' gates as "a column swapped with another" or "check
lead_mm", which sends the user to the wrong fix.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from tcpmm.errors import InputError

#: Least travel of the scale, in its steps, over which a TCP column that does not move
#: is taken as dead rather than as an axis that stood still [-].
MIN_SCALE_STEPS = 20


def refuse_dead_tcp(record, axis) -> None:
    """Refuse a sweep whose ``tcp_mm`` stays within one step of the TCP device while the
    scale travels: the column holds no measurement, and the fits read its flat line as
    a structure that does not move.

    Parameters
    ----------
    record : SweepRecord
        The sweep, SI [-].
    axis : AxisConfig
        The axis description from machine.yaml [-].

    Raises
    ------
    InputError
        Naming the file and the column, the value it holds and the two fixes.
    """
    tcp = getattr(record, "tcp_m", None)
    if tcp is None:
        return
    tcp, scale = np.asarray(tcp, dtype=float), np.asarray(record.scale_m, dtype=float)
    travel = float(np.ptp(scale))
    if travel < MIN_SCALE_STEPS * axis.sensors.scale_resolution_m:
        return
    spread = float(np.ptp(tcp))
    if spread > (axis.sensors.tcp_resolution_m or 0.0):
        return
    held = (f"holds one value ({tcp[0] * 1e3:.6g} mm)" if spread == 0.0 else
            f"stays within {spread * 1e6:.3g} um, one step of the device,")
    raise InputError(
        f"tcp_mm {held} over the whole sweep while scale_mm travels {travel * 1e3:.4g} mm: "
        "the TCP device recorded nothing (not connected, or its channel not logged). "
        "Record the sweep again with the TCP device logging, or delete the tcp_mm column "
        "(and tcp_resolution_um in machine.yaml) to identify the axis without a TCP device "
        "(then only G_M and G_T are identified)",
        file=record.source, column="tcp_mm")


def refuse_wrapped_angle(record, axis, line_of: Callable[[int], int] | None = None) -> None:
    """Refuse a record whose motor angle jumps by a whole number of turns between two
    samples, the rest of the jump no larger than the angle's other steps plus one
    encoder step: the angle was recorded within one turn (0 to 2 pi), and the scale
    following it through the lead fails as a swapped column or a wrong lead.

    Parameters
    ----------
    record : SweepRecord or FrictionRecord
        The record, SI [-].
    axis : AxisConfig
        The axis description from machine.yaml [-].
    line_of : callable, optional
        Maps a 0-based sample index to a 1-based file line [-].

    Raises
    ------
    InputError
        Naming the file, the line of the first jump, its size and the fix.
    """
    step = np.diff(np.asarray(record.motor_angle_rad, dtype=float))
    turns = np.round(step / (2.0 * math.pi))
    jumps = np.flatnonzero(turns != 0.0)
    if jumps.size == 0 or jumps.size > step.size // 2:  # a record that turns by pi a sample
        return
    others = np.abs(np.delete(step, jumps))
    bound = (float(np.max(others)) if others.size else 0.0) + axis.sensors.encoder_resolution_rad
    wraps = jumps[np.abs(step[jumps] - 2.0 * math.pi * turns[jumps]) <= bound]
    if wraps.size == 0:
        return
    i = int(wraps[0]) + 1
    line = line_of(i) if line_of is not None else None
    at = "" if line is not None else f" at sample {i} (0-based)"
    raise InputError(
        f"motor_angle_rad jumps by {step[i - 1]:+.6g} rad{at}, a whole turn (2 pi) to within "
        f"its other steps and the encoder's, {wraps.size} times in the record "
        f"(between {float(np.min(record.motor_angle_rad)):.4g} and "
        f"{float(np.max(record.motor_angle_rad)):.4g} rad): the angle is the encoder's within "
        "one turn, not the motor's multi-turn angle. Unwrap it before writing the file "
        "(numpy.unwrap, or log the drive's multi-turn position), so that it runs on over "
        "the turns as the scale does",
        file=record.source, line=line, column="motor_angle_rad")
