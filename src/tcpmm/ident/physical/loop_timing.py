"""Computation delay and velocity estimate of a drive, from its own servo-excitation record.

A digital velocity loop computes its current from encoder samples and applies it some
velocity periods later; its speed is the shaft's, or the backward difference of the encoder
angle, which lags by half a period. Neither is written on the drive's data sheet, and both
set the loop's phase, hence how far it overshoots after a reversal. The sweep record holds
what the controller did: with the gains known, its output ``u = i_c - r`` (current command
minus excitation) follows from the recorded encoder angle and scale,

    u(f) = -exp(-j w tau) C_v(f) (j w theta(f) + (K_pp / R_L) x_fb(f) exp(-j w T_p / 2)),

``C_v = K_vp + K_vi / (j w)``, with the delay ``tau`` the only unknown. ``tau`` in velocity
periods is the computation delay, plus one half for a differenced velocity, plus one half
when the record is not sampled in step with the drive (a held current read at a random phase
of its period). The integer and half-integer parts therefore give both the delay and the
kind of velocity estimate; ``tau`` is fitted as the least-squares delay over the band where
the loop's own response dominates the position loop's.

Below that band the position term dominates, and with ``tau`` known the same relation gives
``K_pp``, the median size of the position term over :data:`POSITION_BAND_HZ`: the gain the
drive's position loop really has, which a mistyped ``position_gain_1_per_s`` would
otherwise carry, unnoticed, into every path the model predicts.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from ...errors import InputError
from ...servo.currentfilters import filters_freqresp
from ..frf.response import frf_against_reference

__all__ = ["COMPUTATION_DELAY", "POSITION_GAIN_TOL", "LoopTiming", "identify_loop_timing",
           "sampled_in_step"]

#: Computation delay taken where the sweep does not show it: the current a digital velocity
#: loop computes from the samples of one period is applied in the next [velocity-loop
#: periods].
COMPUTATION_DELAY = 1

#: Band of the fit: above it the drive's sample rate distorts the continuous model, below
#: it the position loop's share grows [Hz].
BAND_HZ = (40.0, 800.0)
#: Largest distance of the fitted delay from the nearest structure still taken as that
#: structure [velocity periods].
MATCH_TOL = 0.2
#: Fewest coherent bins for a fit [-].
MIN_BINS = 20
#: Range of the fitted factor on the declared gains within which the record is read as
#: the declared controller: outside it the gains or the lead in machine.yaml are not the
#: drive's, and the fitted delay means nothing. (A wrong torque constant scales the
#: identified inertias with it, and the loop it closes stays the same: no sweep shows it.)
#: [-].
GAIN_RANGE = (0.8, 1.25)
#: Departure of the fitted factor from 1 beyond which, though the record still reads as
#: the declared controller, the sweep is said to disagree with it: the reference drives
#: fit within 0.7 % of 1; a time base a quarter off (a record stamped at 8 kHz that was
#: sampled at 10 kHz) fits 1.24 and scales every mass and inertia by its square [-].
GAIN_WARN = 0.05
#: Largest relative residual of the fit for the same reason [-].
MAX_RESIDUAL = 0.3
#: Factor by which the fit's residual with the position fed back from the other sensor
#: must be smaller than with the declared one to say the declaration is wrong: above the
#: axial mode the scale and the motor part, and on the reference drives the sensor
#: declared fits 1.5 to 4.9 times better than the other (H: 1.06-1.08, which this check
#: cannot tell) [-].
FEEDBACK_RATIO = 1.25
#: Band of the position gain's reading: from the FRFs' lowest band to where the position
#: term is still most of the controller output; above it what is left of the velocity term
#: leaks in (over 2-40 Hz the reference drives read 1-2.4 % low) [Hz].
POSITION_BAND_HZ = (2.0, 15.0)
#: Relative departure of the position gain the sweep reads from the declared one beyond
#: which the declared gain is said to be contradicted: the twelve reference drives read
#: within 0.6 % of theirs, the built-in machine's within 1.1 %; a gain typed 45 for 30
#: reads 0.666 of it, and each per cent of a gain off moves a circle's raw spikes by some
#: 10-16 um (the axes' lags differ) [-].
POSITION_GAIN_TOL = 0.025
#: The position feedback other than the one declared, and each in words [-].
OTHER_SENSOR = {"scale": "encoder", "encoder": "scale"}


@dataclass(frozen=True)
class LoopTiming:
    """Timing of a velocity loop read from a sweep.

    Parameters
    ----------
    delay_samples : int
        Computation delay [velocity periods].
    velocity_feedback : {"state", "difference"}
        Kind of velocity estimate [-].
    tau_periods : float
        Fitted delay of the controller output behind the recorded signals [velocity
        periods].
    gain : float
        Fitted factor on the declared velocity-loop gains (1 when they are right) [-].
    determined : bool
        Whether the fit reads the declared controller (:data:`GAIN_RANGE`,
        :data:`MAX_RESIDUAL`) and its delay lies within :data:`MATCH_TOL` of one
        structure [-].
    residual, other_feedback_residual : float
        Relative residual of the fit with the position fed back from the declared sensor,
        and from the other one (motor encoder or linear scale) [-].
    position_gain : float
        Position-loop gain the sweep's controller output reads over
        :data:`POSITION_BAND_HZ`; NaN where the record does not show it [1/s].
    position_residual, declared_position_residual : float
        Relative residual of that relation with the gain read and with the declared one [-].
    """

    delay_samples: int
    velocity_feedback: str
    tau_periods: float
    gain: float
    determined: bool
    residual: float = float("nan")
    other_feedback_residual: float = float("nan")
    position_gain: float = float("nan")
    position_residual: float = float("nan")
    declared_position_residual: float = float("nan")

    def position_contradicted(self, declared: float) -> bool:
        """Whether the position gain the sweep reads departs from ``declared`` [1/s] by
        more than :data:`POSITION_GAIN_TOL` (``False`` where it reads none) [-]."""
        return bool(abs(self.position_gain / declared - 1.0) > POSITION_GAIN_TOL)

    def position_words(self, declared: float, by: str) -> str:
        """What the sweep reads of the position gain against ``declared`` [1/s], which
        ``by`` declares, in words, for the warning and the open range alike [-]."""
        return (f"reads a position gain of {self.position_gain:.4g} 1/s below "
                f"{POSITION_BAND_HZ[1]:g} Hz, not the {declared:.4g} 1/s {by} declares "
                f"(relative residual {self.position_residual:.3f} against "
                f"{self.declared_position_residual:.3f})")

    def other_sensor_reads_better(self) -> bool:
        """Whether the fit with the position fed back from the other sensor leaves a
        residual :data:`FEEDBACK_RATIO` times smaller than with the declared one [-]."""
        return bool(self.other_feedback_residual * FEEDBACK_RATIO < self.residual)

    def to_dict(self) -> dict:
        """Plain dictionary for the JSON report [-]."""
        return dataclasses.asdict(self)


def _controller_frfs(sweep, cfg, lo_hz: float, hi_hz: float):
    """The FRFs of the controller output ``u``, the encoder angle ``th`` and the scale
    ``x`` against the excitation over ``lo_hz`` to ``hi_hz``, their angular frequencies and
    the velocity controller's response ``C_v`` there; or ``None`` [SI]."""
    s = cfg.servo
    sig = {"u": sweep.current_cmd_A - sweep.excitation_A, "th": sweep.motor_angle_rad,
           "x": sweep.scale_m}
    try:
        frfs = frf_against_reference(sweep.excitation_A, sig, sweep.fs_hz,
                                     fmin_hz=lo_hz, fmax_hz=hi_hz)
    except InputError:  # no excitation in the band
        return None
    f = np.asarray(frfs["u"].freq_hz)
    w = 2.0 * math.pi * f
    c_v = s.velocity_gain_A_s_per_rad + s.velocity_integral_gain_A_per_rad / (1j * w)
    c_v = c_v * filters_freqresp(s.current_setpoint_filters, f, s.velocity_loop_period_s)
    return w, frfs, c_v


def _feedback(frfs, sensor: str, R: float):
    """The FRF of the position fed back from ``sensor`` (``scale`` or ``encoder``) [m/A]."""
    return frfs["x"].H if sensor == "scale" else R * frfs["th"].H


def _controller_ratio(sweep, cfg):
    """``u / (C_v (j w theta + K_pp/R_L x_fb))`` per bin, with its weights, and the same
    ratio with the position fed back from the other sensor; or ``None``."""
    s = cfg.servo
    R = cfg.lead_m / (2.0 * math.pi)
    top = min(BAND_HZ[1], 0.2 * sweep.fs_hz)
    if top < 2.0 * BAND_HZ[0]:
        return None  # sampled too slowly to show the loop's timing
    got = _controller_frfs(sweep, cfg, BAND_HZ[0], top)
    if got is None:
        return None
    w, frfs, c_v = got
    dens = {}
    for fb in ("scale", "encoder"):
        pos = (s.position_gain_1_per_s / R * _feedback(frfs, fb, R)
               * np.exp(-0.5j * w * s.position_loop_period_s))
        dens[fb] = c_v * (1j * w * frfs["th"].H + pos)
    den, den_other = dens[s.position_feedback], dens[OTHER_SENSOR[s.position_feedback]]
    coh = np.minimum(frfs["u"].coherence, frfs["th"].coherence)
    good = (coh > 0.9) & (np.abs(den) > 0) & (np.abs(den_other) > 0)
    if int(good.sum()) < MIN_BINS:
        return None
    return (w[good], -frfs["u"].H[good] / den[good], coh[good],
            -frfs["u"].H[good] / den_other[good])


def _fit_position_gain(sweep, cfg, tau: float):
    """The position gain the controller output reads over :data:`POSITION_BAND_HZ` with
    the velocity loop's delay ``tau`` [s]: ``(K_pp, residual, residual of the declared)``
    [1/s], [-], [-]; NaN where the record does not show it. The position term
    ``(K_pp/R_L) x_fb exp(-j w T_p/2)`` is what is left of ``-u exp(j w tau) / C_v``
    after the velocity ``j w theta``; the gain is the median of its size over the bins."""
    none = (math.nan,) * 3
    s = cfg.servo
    R = cfg.lead_m / (2.0 * math.pi)
    got = _controller_frfs(sweep, cfg, POSITION_BAND_HZ[0], POSITION_BAND_HZ[1])
    if got is None:
        return none
    w, frfs, c_v = got
    a = -frfs["u"].H * np.exp(1j * w * tau) / c_v - 1j * w * frfs["th"].H
    b = (_feedback(frfs, s.position_feedback, R) / R
         * np.exp(-0.5j * w * s.position_loop_period_s))
    coh = np.minimum.reduce([frfs[k].coherence for k in ("u", "th", "x")])
    good = (coh > 0.9) & np.isfinite(a) & np.isfinite(b)
    if int(good.sum()) < MIN_BINS:
        return none
    weight = np.minimum(coh / (1.0 - coh + 1e-6), 1e4)[good]
    a, b = a[good], b[good]
    norm = float(np.sum(weight * np.abs(a) ** 2))
    if not norm > 0.0:
        return none
    k = float(np.median(np.abs(a / b)))  # a bin the velocity term's remains spoil counts once

    def resid(g):
        return math.sqrt(float(np.sum(weight * np.abs(a - g * b) ** 2)) / norm)

    return k, resid(k), resid(s.position_gain_1_per_s)


def _fit_delay(w, h, weight):
    """Least-squares ``tau``, real gain and relative residual of ``h = g exp(-j w tau)``
    [s], [-], [-]."""
    # the factors that do not depend on the delay, formed once for the ~800 tried
    jw, total = -1j * w, np.sum(weight)

    def cost(tau):
        e = np.exp(jw * tau)
        g = max(float(np.sum(weight * np.real(h * np.conj(e))) / total), 0.0)
        return float(np.sum(weight * np.abs(h - g * e) ** 2)), g

    grid = np.linspace(0.0, 6.0 * math.pi / (2.0 * w.max()), 601)
    costs = np.array([cost(t)[0] for t in grid])
    k = int(np.argmin(costs))
    lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)]
    fine = np.linspace(lo, hi, 201)
    tau = float(fine[int(np.argmin([cost(t)[0] for t in fine]))])
    c, g = cost(tau)
    return tau, g, math.sqrt(c / float(np.sum(weight * np.abs(h) ** 2)))


def identify_loop_timing(sweep, cfg) -> LoopTiming | None:
    """Computation delay and velocity estimate from a closed-loop sweep.

    Parameters
    ----------
    sweep : SweepRecord
        Closed-loop servo-excitation record (SI) [-].
    cfg : AxisConfig
        The axis's bundle configuration (gains, periods, lead) [-].

    Returns
    -------
    LoopTiming or None
        ``None`` when the record has too few coherent bins in :data:`BAND_HZ` [-].
    """
    got = _controller_ratio(sweep, cfg)
    if got is None:
        return None
    w, h, coh, h_other = got
    weight = np.minimum(coh / (1.0 - coh + 1e-6), 1e4)
    tau, gain, resid = _fit_delay(w, h, weight)
    resid_other = _fit_delay(w, h_other, weight)[2]
    T_v = cfg.servo.velocity_loop_period_s
    periods = tau / T_v - (0.0 if sampled_in_step(sweep.fs_hz, T_v) else 0.5)
    half = round(2.0 * periods)
    delay, diff = max(half // 2, 0), half % 2 == 1
    determined = (abs(periods - 0.5 * half) <= MATCH_TOL and half >= 0
                  and GAIN_RANGE[0] < gain < GAIN_RANGE[1] and resid < MAX_RESIDUAL)
    k_pp = _fit_position_gain(sweep, cfg, tau) if determined else (math.nan,) * 3
    return LoopTiming(int(delay), "difference" if diff else "state", float(tau / T_v),
                      float(gain), bool(determined), float(resid), float(resid_other),
                      *(float(v) for v in k_pp))


def sampled_in_step(fs_hz: float, T_v: float) -> bool:
    """Whether a record samples the drive at its velocity-loop ticks: one sample every
    whole number of velocity periods.

    Parameters
    ----------
    fs_hz : float
        Sample rate of the record [Hz].
    T_v : float
        Velocity-loop period [s].

    Returns
    -------
    bool
        ``True`` when the samples fall on the ticks; ``False`` for a record that reads the
        held current at other instants (a DAQ on its own clock, or faster than the loop)
        [-].
    """
    ratio = T_v * fs_hz
    return ratio <= 1.0 and abs(1.0 / ratio - round(1.0 / ratio)) < 1e-6
