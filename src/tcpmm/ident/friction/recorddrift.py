"""A deflection between encoder and scale that drifts with time over the friction runs.

A scale warming in its mounting, or the screw against it, moves the deflection
``d = R_L th_m - X_LS`` slowly with time. The plateaus of one speed are run one way and then
back a couple of seconds later, so a drift adds to the step between the two directions,
which the split of the friction reads as guideway share or lost motion
(:mod:`.lostmotion`): 3 um over a record of 25 s made 0.25 um of lost motion on a machine
without any, and with a drifting TCP device beside it a guideway share of 0.83 for 0.55.

Within a plateau the deflection is steady, so its slope over time is the drift, except
for a deflection that changes along the travel (the screw's lead error, friction that
varies with the position), which slopes one way on the run out and the other on the run
back over the same stretch. Half the sum of the slopes of the two runs of a speed is
therefore the drift's rate at that time alone; the speeds' estimates, weighted by their
variances, give its mean rate. Where that stands out of its scatter by :data:`DRIFT_Z`
standard deviations the record is taken with the drift off (:func:`without_drift`), and the
user is told. A scale warming after a start slows as it nears its temperature: the drift
taken off follows the speeds' own rates, joined linearly between their times, so that
each speed's two runs lose the drift that passed between them.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

__all__ = ["DRIFT_Z", "RecordDrift", "deflection_drift", "drift_warning", "record_drift",
           "without_drift"]

#: Standard deviations by which the drift rate must stand out of its scatter to be taken
#: off: a record without drift crosses it on one axis in some 400 [-].
DRIFT_Z = 3.0
#: Blocks a plateau is cut into for the slope and its scatter [-].
_BLOCKS = 8
#: Largest relative difference of two plateaus' speeds that pairs them as one speed [-].
_SAME_SPEED = 0.1


@dataclass(frozen=True)
class RecordDrift:
    """The drift of the encoder-to-scale deflection over a friction record.

    Parameters
    ----------
    rate : float
        Rate of the drift; NaN where no speed is run both ways [m/s].
    rate_std : float
        Its standard deviation [m/s].
    span_s : float
        Duration of the record [s].
    pairs : int
        Speeds run both ways that it is read from [-].
    times, rates : tuple of float
        Per such speed, in time order, the middle of its two runs [s] and the drift's rate
        there [m/s].
    start_s : float
        Time of the record's first sample [s].
    """

    rate: float
    rate_std: float
    span_s: float
    pairs: int
    times: tuple = ()
    rates: tuple = ()
    start_s: float = 0.0

    @property
    def found(self) -> bool:
        """The rate stands out of its scatter by :data:`DRIFT_Z` deviations [-]."""
        return bool(np.isfinite(self.rate) and self.rate_std > 0
                    and abs(self.rate) > DRIFT_Z * self.rate_std)

    def drifted(self, t) -> np.ndarray:
        """The drift at the times ``t`` [s] since the first of them, at the rates of the
        speeds run both ways joined linearly (held before the first and after the last)
        [m]."""
        t = np.asarray(t, float)
        rate = np.interp(t, self.times, self.rates)
        return np.concatenate([[0.0], np.cumsum(0.5 * (rate[1:] + rate[:-1]) * np.diff(t))])

    @property
    def over_record_m(self) -> float:
        """The drift over the whole record that :func:`without_drift` takes off; NaN
        where no speed is run both ways [m]."""
        if not self.times:
            return float("nan")
        return float(self.drifted(np.linspace(self.start_s, self.start_s + self.span_s,
                                              1001))[-1])


def _slope(t, d, floor: float) -> tuple:
    """Slope of ``d`` over ``t`` from the means of :data:`_BLOCKS` blocks, and its standard
    deviation from their scatter about the line, at least ``floor`` [m/s]."""
    nb = min(_BLOCKS, t.size // 4)
    if nb < 3:
        return float("nan"), float("nan")
    tb = np.array([b.mean() for b in np.array_split(t, nb)])
    db = np.array([b.mean() for b in np.array_split(d, nb)])
    tc = tb - tb.mean()
    b = float(tc @ (db - db.mean()) / (tc @ tc))
    res = db - db.mean() - b * tc
    sd = math.sqrt(float(res @ res) / (nb - 2) / float(tc @ tc))
    return b, max(sd, floor)


def deflection_drift(t, motor_angle, scale, R_L: float, plateaus,
                     resolution_m: float) -> RecordDrift:
    """The drift of ``R_L th_m - X_LS`` over the record, from its plateaus' slopes.

    Parameters
    ----------
    t : array_like
        Time of the friction record [s].
    motor_angle : array_like
        Motor encoder angle [rad].
    scale : array_like
        Linear scale ``X_LS`` [m].
    R_L : float
        Screw ratio ``lead / 2 pi`` [m/rad].
    plateaus : sequence of Plateau
        Constant-speed plateaus of the record (``find_plateaus``) [-].
    resolution_m : float
        The coarser step of encoder (at the table) and scale: a plateau's slope is known
        no better than one step over its duration [m].

    Returns
    -------
    RecordDrift
        Rate, its standard deviation and how many speeds it is read from [-].
    """
    t = np.asarray(t, float)
    d = R_L * np.asarray(motor_angle, float) - np.asarray(scale, float)
    rows = []
    for p in plateaus:
        a, b = int(p.start), int(p.stop)
        if b - a < 12 or t[b - 1] <= t[a]:
            continue
        floor = resolution_m / (math.sqrt(12.0) * (t[b - 1] - t[a]))
        rows.append((float(p.velocity), 0.5 * (t[a] + t[b - 1]),
                     *_slope(t[a:b], d[a:b], floor)))
    est, var, mid = [], [], []
    for v, tm, s, sd in rows:
        if v <= 0 or not np.isfinite(s):
            continue
        back = [(abs(w + v), tm2, s2, sd2) for w, tm2, s2, sd2 in rows
                if w < 0 and np.isfinite(s2) and abs(w + v) <= _SAME_SPEED * v]
        if back:
            _, tm2, s2, sd2 = min(back)
            est.append(0.5 * (s + s2))
            var.append(0.25 * (sd**2 + sd2**2))
            mid.append(0.5 * (tm + tm2))
    span = float(t[-1] - t[0]) if t.size else 0.0
    if not est:
        return RecordDrift(float("nan"), float("nan"), span, 0)
    w = 1.0 / np.array(var)
    order = np.argsort(mid, kind="stable")
    return RecordDrift(float(w @ np.array(est) / w.sum()), float(1.0 / math.sqrt(w.sum())),
                       span, len(est), tuple(np.array(mid)[order].tolist()),
                       tuple(np.array(est)[order].tolist()), float(t[0]))


def without_drift(record, drift: RecordDrift):
    """The record with the drift taken off its scale (:meth:`RecordDrift.drifted`), where
    it was found; else itself [-]."""
    if not drift.found:
        return record
    return dataclasses.replace(record, scale_m=record.scale_m + drift.drifted(record.time_s))


def record_drift(record, cfg, plateaus) -> RecordDrift:
    """:func:`deflection_drift` of an axis's friction ``record`` with its bundle
    configuration ``cfg`` (lead, sensors) and ``plateaus`` [-]."""
    R_L = cfg.screw_ratio_m_per_rad
    step = max(cfg.sensors.scale_resolution_m, R_L * cfg.sensors.encoder_resolution_rad)
    return deflection_drift(record.time_s, record.motor_angle_rad, record.scale_m, R_L,
                            plateaus, step)


def drift_warning(drift: RecordDrift, axis: str) -> str:
    """What the user is told of a drift found, empty where none is [-]."""
    if not drift.found:
        return ""
    return (f"axis {axis}: the deflection between motor encoder and scale drifts by "
            f"{drift.over_record_m * 1e6:+.2f} um over the friction runs "
            f"(at a mean rate of {drift.rate * 1e6:+.3f} +- {drift.rate_std * 1e6:.3f} um/s, "
            f"read from the {drift.pairs} speeds run both ways: a scale or screw warming); "
            "it is taken "
            "off before the guideway share and the lost motion are read. Let the machine "
            "reach its temperature before the runs")
