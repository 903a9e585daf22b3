"""Gates on the columns of a bundle's records, before any fit: a column swapped with
another, or in the wrong unit, gives a model of absurd masses and friction levels that
the fits alone do not see (a current column holding the motor angle gave a Coulomb level
of 1250 N for 23 N; the excitation swapped with the TCP a head mass of 0.24 kg for 403 kg).

* :func:`check_current_columns` -- ``current_cmd_A`` and ``excitation_A`` within the
  drive's current limit (the drive clips its current command there); a hundred to a
  hundred thousand times it, but within it once divided by 1000: milliamperes;
* :func:`check_position_columns` -- ``motor_angle_rad`` and ``scale_mm`` agree through the
  lead (the scale moves ``lead / 2 pi`` per radian, give or take the screw's deflection),
  and ``tcp_mm`` follows ``scale_mm``; a ratio of ``pi / 180``: the angle in degrees.

:func:`column_findings` runs them on every record of a bundle. A column in the wrong unit
is refused even where suspect findings are accepted (:func:`check_record_units`): numbers a
thousand or sixty times too large overflow the fits into errors that name no column.
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from ...errors import InputError, InputWarning
from ...io.checks import LEAD_TOLERANCE, slope_and_correlation
from .finding import Finding, bundle_records

#: Peak of a current column above this many times the current limit counts as beyond it:
#: the drive clips its command at the limit; the margin covers a limit given rounded [-].
CURRENT_MARGIN = 1.05
#: Ratio of the scale's travel to the motor angle's (through the lead), or of the TCP's to
#: the scale's, taken as agreeing: the screw's and the structure's deflection under the
#: drive's force stay within a few per cent of a travel of millimetres [-].
RATIO_RANGE = (0.8, 1.25)
#: Beyond this relative difference the lead or the scale's resolution is refused, not
#: said: the masses and inertias identified scale with the square of a lead that is off
#: (a lead of 22 mm for 25 gave every mass 27 % too large, read as firm) [-].
LEAD_REFUSE = 0.025
#: Largest relative difference of the TCP's travel from the scale's over a sweep taken as
#: one motion: the reference machines' differ by 1.4e-5 at most (an Abbe offset of 300 mm
#: under 10 urad of pitch is 3e-5); 0.1 % is the TCP device's scale factor or units, whose
#: difference reads as a deflection growing with the travel [-].
TCP_TOLERANCE = 1e-3
#: Smallest correlation of two position columns taken as one motion [-].
MIN_CORRELATION = 0.9
#: Least travel of a record, relative to the scale's resolution and absolute, on which the
#: columns' agreement is judged: below it the deflection and quantisation dominate.
MIN_TRAVEL_M = 1e-3
#: Known unit errors of the scale's ratio to the motor angle: factor -> what it means.
UNIT_RATIOS = {math.pi / 180.0: "the motor angle in degrees (write radians)",
               1e-3: "the scale in metres or the angle in milliradians (write mm, rad)",
               1e3: "the scale in micrometres (write mm)"}
#: The same of the TCP's ratio to the scale: there the TCP is the column in another unit.
TCP_UNIT_RATIOS = {1e-3: "the TCP in metres (write mm)",
                   1e3: "the TCP in micrometres (write mm)"}


def _peak(x) -> float:
    x = np.abs(np.asarray(x, dtype=float))
    x = x[np.isfinite(x)]
    return float(np.max(x)) if x.size else 0.0


def check_current_columns(axis: str, record, kind: str, limit_A: float) -> list[Finding]:
    """The record's current columns against the drive's current limit.

    Parameters
    ----------
    axis : str
        Axis name [-].
    record : SweepRecord or FrictionRecord
        The record, SI [-].
    kind : str
        Its file name, e.g. ``sweep.csv`` [-].
    limit_A : float
        The drive's current limit, ``current_limit_A`` of machine.yaml [A].

    Returns
    -------
    list of Finding
        One per column beyond the limit [-].
    """
    out = []
    source = getattr(record, "source", None) or f"{axis}/{kind}"
    for col in ("current_cmd_A", "excitation_A"):
        x = getattr(record, col, None)
        if x is None:
            continue
        peak = _peak(x)
        if peak <= CURRENT_MARGIN * limit_A:
            continue
        if peak / 1e3 <= CURRENT_MARGIN * limit_A and peak > 100 * limit_A:
            why = ("a unit problem: it reads as milliamperes (within the limit once divided "
                   f"by 1000); write {col} in A")
        else:
            why = ("not a current of this drive: a column swapped with another (a position "
                   "or an angle?); check the header of the file against its columns, and "
                   "current_limit_A in machine.yaml")
        out.append(Finding(axis, f"{kind} column {col}", peak, "A",
                           f"peaks above the drive's current limit {limit_A:g} A",
                           f"{source}, column {col}", why))
    return out


def _disagreement(ratio: float, corr: float, cols: str, units: dict) -> str | None:
    """Why two position columns do not agree, or ``None`` where they do; ``units`` the unit
    errors of this pair, by factor (:data:`UNIT_RATIOS`) [-]."""
    lo, hi = RATIO_RANGE
    if lo <= ratio <= hi and corr >= MIN_CORRELATION:
        return None
    for factor, what in units.items():
        if lo <= ratio / factor <= hi and corr >= MIN_CORRELATION:
            return f"a unit problem: {cols} differ by {ratio:.4g}, as {what}"
    if corr >= MIN_CORRELATION and ratio > 0.0:  # one motion, at another scale
        return (f"{cols} move together (correlation {corr:.2f}) but one travels {ratio:.4g} "
                "times the other: a scale factor set wrong, not a deflection")
    return (f"{cols} do not move together (correlation {corr:.2f}): one of them holds "
            "another quantity, a column swapped with another; check the header of the file "
            "against its columns")


def check_position_columns(axis: str, record, kind: str, R_L: float) -> list[Finding]:
    """The record's position columns against each other: motor angle and scale through
    the lead, the TCP against the scale.

    Parameters
    ----------
    axis : str
        Axis name [-].
    record : SweepRecord or FrictionRecord
        The record, SI [-].
    kind : str
        Its file name, e.g. ``sweep.csv`` [-].
    R_L : float
        Lead over 2 pi of machine.yaml [m/rad].

    Returns
    -------
    list of Finding
        One per pair of columns that disagree, on a record that travels [-].
    """
    scale = np.asarray(record.scale_m, dtype=float)
    if not np.all(np.isfinite(scale)) or np.ptp(scale) < MIN_TRAVEL_M:
        return []
    source = getattr(record, "source", None) or f"{axis}/{kind}"
    pairs = [("motor_angle_rad", np.asarray(record.motor_angle_rad) * R_L, "scale_mm",
              scale, "check lead_mm in machine.yaml", UNIT_RATIOS)]
    tcp = getattr(record, "tcp_m", None)
    if tcp is not None:
        pairs.append(("scale_mm", scale, "tcp_mm", np.asarray(tcp), "", TCP_UNIT_RATIOS))
    out, lead = [], None
    for a, x, b, y, also, units in pairs:
        if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
            continue
        ratio, corr = slope_and_correlation(y, x)
        lead = ratio if a == "motor_angle_rad" else lead
        why = _disagreement(ratio, corr, f"{b} and {a}", units)
        bounds = RATIO_RANGE
        if why is None and a == "motor_angle_rad" and kind.startswith("friction"):
            # judged on the friction runs alone: their plateaus hold the screw's
            # deflection steady, where a sweep's moves it with the modes
            if abs(ratio - 1.0) > LEAD_REFUSE:
                bounds = (1.0 - LEAD_REFUSE, 1.0 + LEAD_REFUSE)
                why = (f"the scale travels {ratio:.4f} times what the motor angle does "
                       "through lead_mm: a screw's lead and deflection differ by 0.01 % at "
                       "most; set lead_mm in machine.yaml to the screw's (per motor turn, "
                       "with any gear) or the scale's resolution in the recorder")
            else:
                _warn_lead(ratio, f"{source}, columns {a} and {b}")
        if why is None and b == "tcp_mm" and lead is not None and abs(lead - 1) <= LEAD_TOLERANCE:
            # the scale follows the lead: the TCP's is the factor off (a scale off the
            # lead is said by the friction runs)
            _warn_tcp_travel(ratio, f"{source}, columns {a} and {b}")
        if why is not None:
            note = f"{why}; {also}" if also else why
            out.append(Finding(axis, f"{kind} columns {b} / {a}", ratio, "",
                               f"outside {bounds[0]:g} to {bounds[1]:g}, the "
                               "ratio of one motion (through the lead for the motor angle)",
                               f"{source}, columns {a} and {b}", note))
    return out


def _warn_travel(ratio: float, tolerance: float, where: str, what: str, check: str) -> None:
    """A warning where one column travels more or less than another by more than
    ``tolerance`` (``ratio`` and ``tolerance`` [-]; ``where``: the record and columns;
    ``what``: which travels what the other does; ``check``: what to check and why) [-]."""
    if abs(ratio - 1.0) > tolerance:
        warnings.warn(InputWarning(
            f"{where}: the {what.format(f'{ratio:.4f}')} ({(ratio - 1.0) * 100:+.2f} %): "
            f"{check}"), stacklevel=4)


def _warn_lead(ratio: float, where: str) -> None:
    """:func:`_warn_travel` of the scale against the motor angle through the lead, beyond
    :data:`LEAD_TOLERANCE` [-]."""
    _warn_travel(ratio, LEAD_TOLERANCE, where,
                 "scale travels {} times what the motor angle does through lead_mm",
                 "check lead_mm in machine.yaml and the scale's resolution; a screw's lead "
                 "and deflection differ by 0.01 % at most, and the difference reads as a "
                 "deflection that grows with the travel")


def _warn_tcp_travel(ratio: float, where: str) -> None:
    """:func:`_warn_travel` of the TCP against the scale, beyond :data:`TCP_TOLERANCE` [-]."""
    _warn_travel(ratio, TCP_TOLERANCE, where, "TCP travels {} times what the scale does",
                 "check the TCP device's scale factor and the unit of tcp_mm; the difference "
                 "reads as a deflection between scale and TCP that grows with the travel, not "
                 "as a drift of the device")


def column_findings(bundle) -> list[Finding]:
    """:func:`check_current_columns` and :func:`check_position_columns` on every record
    of a bundle.

    Parameters
    ----------
    bundle : Bundle
        Read with :func:`tcpmm.io.bundle.read_bundle` [-].

    Returns
    -------
    list of Finding
        Empty when every column is plausible [-].
    """
    out = []
    for name, record, kind in bundle_records(bundle):
        cfg = bundle.machine.axes[name]
        out += check_current_columns(name, record, kind, cfg.servo.current_limit_A)
        out += check_position_columns(name, record, kind, cfg.screw_ratio_m_per_rad)
    return out


#: A current command beyond this many times the drive's current limit is not one the
#: drive gave: the drive clips its command at the limit [-].
CURRENT_OVER_LIMIT = 1.5
#: The scale following the motor angle times lead/(2 pi) by more than this factor, or by
#: less than its inverse, is a column in another unit, not a wrong lead or a loose screw [-].
MOTOR_SCALE_FACTOR = 5.0
#: Correlation of scale and motor angle above which their ratio is taken as meaningful
#: for a refusal [-].
UNIT_CORRELATION = 0.8


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
    for name, record, _ in bundle_records(bundle):
        cfg = bundle.machine.axes[name]
        _check_current(record, cfg.servo.current_limit_A)
        _check_motor_angle(record, cfg)
        _warn_finer_steps(record, cfg.sensors)


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
    slope, corr = slope_and_correlation(record.scale_m, x_motor)
    if not abs(corr) > UNIT_CORRELATION or 1 / MOTOR_SCALE_FACTOR <= abs(slope) <= (
            MOTOR_SCALE_FACTOR):
        return
    said = f"scale_mm moves {slope:.3g} times motor_angle_rad * lead/(2 pi), about 1 expected"
    if abs(abs(slope) * 180 / math.pi - 1) < 0.05:
        raise InputError(f"{said}: the motor angle looks like degrees; write it in radians",
                         file=record.source, column="motor_angle_rad")
    raise InputError(f"{said}: check the units of motor_angle_rad (rad) and scale_mm (mm), "
                     "and lead_mm in machine.yaml", file=record.source, column="scale_mm")


#: A position column whose small steps (:data:`STEP_PERCENTILE`) are under this share of
#: the declared resolution moves finer than that sensor can [-].
FINER_STEP = 0.5
#: Percentile of the differences between a column's distinct values taken as its least
#: step: the least itself may be a rounding of the file's decimals [%].
STEP_PERCENTILE = 1.0


def _warn_finer_steps(record, sensors) -> None:
    """Say where ``motor_angle_rad`` or ``scale_mm`` moves in steps finer than the
    resolution machine.yaml declares for it: the model quantises its sensors as declared
    (an encoder of 4096 counts for one of a million turns its velocity loop into noise,
    and its runs into the current limit), so the declaration is wrong, or the record was
    resampled. A quantised column's distinct values lie whole steps apart [-]."""
    for column, values, quantum, key in (
            ("motor_angle_rad", record.motor_angle_rad, sensors.encoder_resolution_rad,
             "encoder_counts_per_rev"),
            ("scale_mm", record.scale_m, sensors.scale_resolution_m, "scale_resolution_um")):
        steps = np.diff(np.unique(np.asarray(values, dtype=float)))
        steps = steps[steps > 0.0]
        if steps.size < 100:
            continue
        step = float(np.percentile(steps, STEP_PERCENTILE))
        if step < FINER_STEP * quantum:
            unit = "rad" if column == "motor_angle_rad" else "m"
            warnings.warn(f"{record.source or column}: {column} moves in steps of "
                          f"{step:.3g} {unit}, finer than the one step of {quantum:.3g} {unit} "
                          f"that {key} in machine.yaml declares; correct {key} (the model "
                          "quantises the sensor as declared), unless the record was "
                          "resampled", InputWarning, stacklevel=2)
