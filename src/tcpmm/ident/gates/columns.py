"""Columns in the wrong unit, refused before identification: a current in mA, a motor
angle in degrees. Numbers a thousand or sixty times too large overflowed the fits into
tracebacks, or gave models of absurd parameters that named no column; here the error
names the file, the column and why it looks wrong.
"""

from __future__ import annotations

import math

import numpy as np

from ...errors import InputError
from ...io.checks import _ratio

#: A current command beyond this many times the drive's current limit is not one the
#: drive gave: the drive clips its command at the limit [-].
CURRENT_OVER_LIMIT = 1.5
#: The scale following the motor angle times lead/(2 pi) by more than this factor, or by
#: less than its inverse, is a column in another unit, not a wrong lead or a loose screw [-].
MOTOR_SCALE_FACTOR = 5.0
#: Correlation of scale and motor angle above which their ratio is taken as meaningful [-].
MIN_CORRELATION = 0.8


def check_record_units(bundle) -> None:
    """Refuse a bundle whose records hold a column in the wrong unit.

    Parameters
    ----------
    bundle : Bundle
        Read with :func:`tcpmm.io.bundle.read_bundle` [-].

    Raises
    ------
    InputError
        Naming the file and the column: a current command far beyond the drive's current
        limit (mA for A), or a scale that does not follow the motor angle times
        lead/(2 pi) within a factor :data:`MOTOR_SCALE_FACTOR` (degrees for radians).
    """
    for name, rec in bundle.axes.items():
        cfg = bundle.machine.axes[name]
        for record in (rec.sweep, rec.friction):
            if record is not None:
                _check_current(record, cfg.servo.current_limit_A)
                _check_motor_angle(record, cfg)


def _check_current(record, limit: float) -> None:
    """The current command within :data:`CURRENT_OVER_LIMIT` times the current limit [-]."""
    peak = float(np.max(np.abs(record.current_cmd_A)))
    if peak > CURRENT_OVER_LIMIT * limit:
        raise InputError(
            f"the current command peaks at {peak:.4g} A, {peak / limit:.3g} times the drive's "
            f"current_limit_A of {limit:g} A in machine.yaml, beyond what it can command: "
            "is the column in mA? Write it in A (or correct current_limit_A)",
            file=record.source, column="current_cmd_A")


def _check_motor_angle(record, cfg) -> None:
    """The scale following the motor angle times lead/(2 pi) within a factor
    :data:`MOTOR_SCALE_FACTOR` [-]."""
    x_motor = np.asarray(record.motor_angle_rad) * cfg.screw_ratio_m_per_rad
    if np.ptp(x_motor) < 20 * cfg.sensors.scale_resolution_m:
        return
    slope, corr = _ratio(np.asarray(record.scale_m, dtype=float), x_motor)
    if not abs(corr) > MIN_CORRELATION or 1 / MOTOR_SCALE_FACTOR <= abs(slope) <= (
            MOTOR_SCALE_FACTOR):
        return
    said = f"scale_mm moves {slope:.3g} times motor_angle_rad * lead/(2 pi), about 1 expected"
    if abs(abs(slope) * 180 / math.pi - 1) < 0.05:
        raise InputError(f"{said}: the motor angle looks like degrees; write it in radians",
                         file=record.source, column="motor_angle_rad")
    raise InputError(f"{said}: check the units of motor_angle_rad (rad) and scale_mm (mm), "
                     "and lead_mm in machine.yaml", file=record.source, column="scale_mm")
