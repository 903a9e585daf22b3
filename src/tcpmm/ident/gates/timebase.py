"""Gate on the time base of a record: its sample period against plausible DAQ periods, and
the scale's speed over it against plausible feed speeds, so that a time column in the wrong
unit (milliseconds under ``time_s``) is an error, not a model of another machine."""

from __future__ import annotations

import math

import numpy as np

from .finding import Finding, bundle_records

__all__ = ["MAX_DAQ_PERIOD_S", "MAX_FEED_SPEED", "MIN_DAQ_PERIOD_S", "check_time_base",
           "time_base_findings"]

#: Shortest plausible DAQ sample period: 100 kHz, beyond any drive or DAQ that records
#: feed axes [s].
MIN_DAQ_PERIOD_S = 1e-5
#: Longest plausible DAQ sample period: 100 Hz. A sweep sampled slower has its Nyquist
#: frequency (50 Hz) below the axial modes of a feed drive, and friction runs sampled slower
#: do not resolve their reversals; a period beyond this is almost always a time column in
#: the wrong unit (milliseconds under ``time_s`` gives 0.1 s at 10 kHz) [s].
MAX_DAQ_PERIOD_S = 1e-2
#: Fastest plausible feed speed of a measured axis: rapid traverses of machine tools stay
#: below about 2 m/s, linear-motor axes below 5 m/s [m/s].
MAX_FEED_SPEED = 5.0
#: Window over which the feed speed is taken from the position, so that the position's
#: quantisation does not read as speed [s].
SPEED_WINDOW_S = 1e-3
#: Quantile of the windowed speeds taken as the record's top speed, so that a few glitched
#: samples do not count [-].
SPEED_QUANTILE = 0.999


def _top_speed(t, x) -> float:
    """Top feed speed of a position record over windows of :data:`SPEED_WINDOW_S` [m/s]."""
    t = np.asarray(t, dtype=float)
    x = np.asarray(x, dtype=float)
    dt = float(np.median(np.diff(t)))
    k = min(max(1, math.ceil(SPEED_WINDOW_S / dt)), x.size - 1)
    v = np.abs(x[k:] - x[:-k]) / (t[k:] - t[:-k])
    return float(np.quantile(v, SPEED_QUANTILE))


def check_time_base(axis: str, record, kind: str) -> list[Finding]:
    """The time column of a record against plausible DAQ periods and feed speeds.

    A DAQ rate is free, but its sample period must lie within [:data:`MIN_DAQ_PERIOD_S`,
    :data:`MAX_DAQ_PERIOD_S`], and the scale's rate of change over that time must be a
    feed speed (at most :data:`MAX_FEED_SPEED`). Time in milliseconds or microseconds
    under ``time_s`` fails one of the two.

    Parameters
    ----------
    axis : str
        Axis name [-].
    record : SweepRecord or FrictionRecord
        The record, SI [-].
    kind : str
        Its file name, e.g. ``sweep.csv``, for messages [-].

    Returns
    -------
    list of Finding
        Empty when the time base is plausible [-].
    """
    t = np.asarray(record.time_s, dtype=float)
    dt = float(np.median(np.diff(t)))
    data = f"{getattr(record, 'source', None) or kind}, column time_s"
    remedy = (f"time_s must be in seconds: check the unit of the time column of {kind} "
              "(milliseconds give 1000 times the sample period)")
    out = []
    if not MIN_DAQ_PERIOD_S <= dt <= MAX_DAQ_PERIOD_S:
        out.append(Finding(axis, f"{kind} sample period", dt, "s",
                           f"outside the plausible DAQ periods {MIN_DAQ_PERIOD_S:g} to "
                           f"{MAX_DAQ_PERIOD_S:g} s", data, remedy))
    speed = _top_speed(t, record.scale_m)
    if speed > MAX_FEED_SPEED:
        out.append(Finding(axis, f"{kind} feed speed", speed, "m/s",
                           f"above the fastest plausible feed speed {MAX_FEED_SPEED:g} m/s",
                           f"{data} and scale_mm", remedy + " and of scale_mm (mm)"))
    return out


def time_base_findings(bundle) -> list[Finding]:
    """:func:`check_time_base` on every sweep and friction record of a bundle.

    Parameters
    ----------
    bundle : Bundle
        Read with :func:`tcpmm.io.bundle.read_bundle` [-].

    Returns
    -------
    list of Finding
        Empty when every time base is plausible [-].
    """
    return [f for name, record, kind in bundle_records(bundle)
            for f in check_time_base(name, record, kind)]
