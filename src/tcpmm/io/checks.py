"""Checks of a measurement record against what identification needs."""

from __future__ import annotations

import itertools

import numpy as np

from tcpmm.errors import InputError
from tcpmm.io.csvutil import warn_input

#: Fewest periods of the lowest frequency asked that a record must hold [-].
MIN_PERIODS = 3.0
#: Band level below this, relative to the strongest band, counts as "no power" [dB].
FLOOR_DB = -30.0
#: The column the messages name [-].
_COLUMN = "excitation_A"
#: Relative difference of the scale's travel from the motor angle's through the lead
#: beyond which it is said: a ball screw's lead errs by some 3e-5, the screw's heat and
#: its deflection under the drive's force by 1e-4 at most; 2 % is a lead_mm or a scale
#: resolution set wrong, which identification reads as a deflection that grows with the
#: travel (a TCP device "drifting by 3 mm" over the sweep) [-].
LEAD_TOLERANCE = 5e-3


def _excitation_of(record) -> tuple[np.ndarray, float, str | None]:
    x = getattr(record, "excitation_A", None)
    if x is None:
        x = record.signal_A
    return np.asarray(x, dtype=float), float(record.fs_hz), getattr(record, "source", None)


def band_edges(fmin_hz: float, fmax_hz: float, df_hz: float) -> np.ndarray:
    """Third-octave band edges over [fmin, fmax], each band at least fmin and 4 bins wide.

    Parameters
    ----------
    fmin_hz : float
        Lower band limit [Hz].
    fmax_hz : float
        Upper band limit [Hz].
    df_hz : float
        Frequency resolution of the spectrum [Hz].

    Returns
    -------
    ndarray
        Increasing edges, first fmin, last fmax [Hz].
    """
    edges = [fmin_hz]
    while edges[-1] < fmax_hz:
        e = edges[-1]
        edges.append(max(e * 2 ** (1 / 3), e + fmin_hz, e + 4 * df_hz))
    if len(edges) > 2 and (fmax_hz - edges[-2]) < 0.5 * (edges[-2] - edges[-3]):
        edges.pop(-2)
    edges[-1] = fmax_hz
    return np.asarray(edges)


def _check_covers(n: int, fs: float, fmin_hz: float, fmax_hz: float, min_periods: float,
                  source) -> None:
    """Refuse a band that is not one, or that a record of ``n`` samples cannot resolve.

    Parameters
    ----------
    n : int
        Samples in the record [-].
    fs : float
        Sampling frequency [Hz].
    fmin_hz, fmax_hz : float
        The band wanted [Hz].
    min_periods : float
        Periods of fmin the record must hold [-].
    source : str or None
        The record's file, for the messages [-].
    """
    col = _COLUMN
    if not (np.isfinite(fmin_hz) and np.isfinite(fmax_hz) and 0 < fmin_hz < fmax_hz):
        raise InputError(
            f"band [{fmin_hz:g}, {fmax_hz:g}] Hz: need 0 < fmin < fmax", file=source, column=col
        )
    if fmax_hz > fs / 2:
        raise InputError(
            f"fmax {fmax_hz:g} Hz is above the Nyquist frequency {fs / 2:g} Hz of a record "
            f"sampled at {fs:g} Hz; lower fmax or sample faster",
            file=source,
            column=col,
        )
    duration = n / fs
    need = min_periods / fmin_hz
    if duration < need:
        raise InputError(
            f"record is {duration:.4g} s long; the lowest frequency asked, {fmin_hz:g} Hz, "
            f"needs at least {min_periods:g} periods = {need:.4g} s. Record longer or "
            f"raise fmin to at least {min_periods / duration:.4g} Hz",
            file=source,
            column=col,
        )


def _quiet_bands(x, fs: float, fmin_hz: float, fmax_hz: float,
                 floor_db: float) -> list[tuple[float, float]]:
    """The third-octave bands of [fmin, fmax] where a signal has no power, neighbours joined.

    Parameters
    ----------
    x : ndarray
        The excitation, mean removed [A].
    fs : float
        Sampling frequency [Hz].
    fmin_hz, fmax_hz : float
        The band wanted [Hz].
    floor_db : float
        Band level below this, relative to the strongest band, counts as no power [dB].

    Returns
    -------
    list of (float, float)
        Lower and upper edge of each quiet stretch, increasing [Hz].
    """
    n = x.size
    # Rectangular periodogram of the whole record: exact for periodic signals (multisine,
    # whole PRBS periods) and it does not suppress the band edges that a sweep visits
    # only at the start and end of the record, as a tapered window would.
    psd = np.abs(np.fft.rfft(x)) ** 2
    f = np.fft.rfftfreq(n, 1 / fs)
    edges = band_edges(fmin_hz, fmax_hz, fs / n)
    idx = np.searchsorted(f, edges)
    density = np.array([psd[a : max(b, a + 1)].mean() for a, b in itertools.pairwise(idx)])
    # Weight by sqrt(f), between per-Hz and per-octave, so that linear sweeps (flat per Hz)
    # and logarithmic sweeps (flat per octave) both read within 5 dB per decade.
    density = density * np.sqrt(np.sqrt(edges[:-1] * edges[1:]))
    empty = density < density.max() * 10 ** (floor_db / 10)
    gaps: list[tuple[float, float]] = []
    for k in np.flatnonzero(empty):
        lo, hi = float(edges[k]), float(edges[k + 1])
        if gaps and gaps[-1][1] == lo:
            gaps[-1] = (gaps[-1][0], hi)
        else:
            gaps.append((lo, hi))
    return gaps


def check_excitation_band(record, fmin_hz: float, fmax_hz: float, *,
                          min_periods: float = MIN_PERIODS, floor_db: float = FLOOR_DB,
                          ) -> list[tuple[float, float]]:
    """Check that a record can give an FRF over [fmin, fmax].

    Raises when the record is too short for the lowest frequency; warns, naming the
    frequencies, when the excitation column has no power in part of the band.

    Parameters
    ----------
    record : SweepRecord or Excitation
        Anything with ``excitation_A`` (or ``signal_A``) and ``fs_hz`` [-].
    fmin_hz : float
        Lowest frequency wanted [Hz].
    fmax_hz : float
        Highest frequency wanted [Hz].
    min_periods : float
        Periods of fmin the record must hold [-].
    floor_db : float
        Band level (power per Hz times sqrt(f)) below this, relative to the strongest
        band, counts as "no power" [dB].

    Returns
    -------
    list of (float, float)
        Sub-bands without excitation power, empty when the band is covered [Hz].

    Raises
    ------
    InputError
        Bad band, band above Nyquist, record too short, constant excitation.
    """
    x, fs, source = _excitation_of(record)
    _check_covers(x.size, fs, fmin_hz, fmax_hz, min_periods, source)
    x = x - x.mean()
    if not np.any(x):
        raise InputError("excitation is constant: nothing was excited", file=source,
                         column=_COLUMN)
    gaps = _quiet_bands(x, fs, fmin_hz, fmax_hz, floor_db)
    if gaps:
        text = ", ".join(f"{lo:.4g}-{hi:.4g} Hz" for lo, hi in gaps)
        warn_input(
            f"the excitation has no power in {text} (more than {-floor_db:g} dB below the "
            f"strongest part of {fmin_hz:g}-{fmax_hz:g} Hz); the FRF there is noise. Extend "
            "the excitation band or narrow the identification band",
            file=source,
            column=_COLUMN,
        )
    return gaps


def slope_and_correlation(y, x) -> tuple[float, float]:
    """Least-squares slope of ``y`` on ``x`` and their correlation, both mean-removed; NaN
    and 0 where either is constant.

    Parameters
    ----------
    y, x : array_like
        Two signals of the same length [any].
    """
    y = np.asarray(y, dtype=float)
    x = np.asarray(x, dtype=float)
    y = y - y.mean()
    x = x - x.mean()
    sxx, syy = float(x @ x), float(y @ y)
    if sxx == 0 or syy == 0:
        return float("nan"), 0.0
    sxy = float(x @ y)
    return sxy / sxx, sxy / np.sqrt(sxx * syy)


def lead_ratio(record, R_L: float) -> float:
    """The scale's travel over the motor angle's through the lead, ``R_L`` [m/rad]: 1
    where ``lead_mm`` and the scale agree; NaN where the record does not move [-]."""
    return slope_and_correlation(record.scale_m,
                                 np.asarray(record.motor_angle_rad, dtype=float) * R_L)[0]


def _refuse_standing_still(record) -> None:
    """Refuse a sweep whose motor angle does not change at all: the axis was clamped, or
    its position channels were not recorded; no frequency response is in it."""
    if np.ptp(record.motor_angle_rad) == 0.0:
        raise InputError("motor_angle_rad holds one value over the whole sweep: the axis did "
                         "not move (clamped, or its position channels not recorded), and no "
                         "frequency response can be read from it; record the sweep with the "
                         "axis free and its encoder, scale and TCP channels logged",
                         file=record.source, column="motor_angle_rad")


def _check_resolutions(record, axis) -> None:
    """Warn where a position column's typical change between two samples (the median of
    those that are not nil) is under a tenth of a step of the resolution ``machine.yaml``
    declares for its sensor (a resolution in the wrong unit, 50 for 0.05 um): the sensor's
    rounding in the model would then be a thousand times the measured one. A sensor that
    rounds changes by whole steps, and a record finer than its steps is another's."""
    pairs = [("scale_mm", record.scale_m, axis.sensors.scale_resolution_m,
              "scale_resolution_um")]
    if record.tcp_m is not None and axis.sensors.tcp_resolution_m:
        pairs.append(("tcp_mm", record.tcp_m, axis.sensors.tcp_resolution_m,
                      "tcp_resolution_um"))
    for name, x, res, key in pairs:
        steps = np.abs(np.diff(x))
        steps = steps[steps > 1e-12]  # the file's own rounding is no step of the sensor
        typical = float(np.median(steps)) if steps.size else 0.0
        if res and typical and res > 10.0 * typical:
            warn_input(f"{name} changes by {typical * 1e6:.3g} um between two samples "
                       f"(median), under a tenth of a step of the declared {key} "
                       f"{res * 1e6:g}: check it (in micrometres)", file=record.source,
                       column=name)


def check_sweep_plausibility(record, axis) -> None:
    """Refuse a sweep that did not move; warn about records that contradict
    ``machine.yaml``.

    Warns when the current command reaches the current limit (the record is then
    nonlinear), and when the linear scale does not follow motor angle times lead/(2 pi)
    or the TCP does not follow the scale at low frequency (wrong lead, unit or sign).

    Parameters
    ----------
    record : SweepRecord
        Record to check [-].
    axis : AxisConfig
        The axis description from machine.yaml [-].
    """
    src = record.source
    _refuse_standing_still(record)
    _check_resolutions(record, axis)
    limit = axis.servo.current_limit_A
    peak = np.abs(record.current_cmd_A)
    if peak.max() >= 0.999 * limit:
        i = int(np.argmax(peak >= 0.999 * limit))
        warn_input(
            f"the current command reaches the current limit {limit:g} A at t = "
            f"{record.time_s[i]:.6g} s; the drive saturates and the FRF is not linear. "
            "Reduce the excitation amplitude",
            file=src,
            column="current_cmd_A",
        )
    res = axis.sensors.scale_resolution_m
    x_motor = record.motor_angle_rad * axis.screw_ratio_m_per_rad
    pairs = [
        (
            "scale_mm",
            record.scale_m,
            x_motor,
            "motor_angle_rad * lead/(2 pi)",
            "lead_mm, the unit of scale_mm (mm), the sign of the encoder or the scale",
        )
    ]
    if record.tcp_m is not None:
        pairs.append(
            ("tcp_mm", record.tcp_m, record.scale_m, "scale_mm", "the unit (mm) and sign of tcp_mm")
        )
    for name, y, x, ref, what in pairs:
        if np.ptp(x) < 20 * res:
            continue
        slope, corr = slope_and_correlation(y, x)
        if abs(corr) > 0.8 and not 0.5 <= slope <= 2.0:
            warn_input(
                f"{name} moves {slope:.3g} times {ref}; about 1 is expected. Check {what}",
                file=src,
                column=name,
            )
