"""Channel skew: a recorded channel of the sweep out of step with the others.

A recorder whose channels are not sampled together (an interferometer or a probe at the
tool on an acquisition of its own, a scale read through another interface) puts a pure
delay between them: the FRF of one channel against another gains the phase
``-omega tau``. The model of the axis has no such delay, and its fit takes the lag for
dynamics (damping, the structure's masses), which then predict the reversal spikes
wrongly, by micrometres. The delays the fit can see are those of its ratios: the scale
against the motor encoder (``G_T``) and the TCP against the scale (``G_tcp``); ``G_M``
cannot tell the motor encoder's from the current loop's lag.

:func:`fit_channel_skews` fits both jointly with the mechanics, from the kept fit on (the
fit's own log residual, whose phase rows gain ``-omega tau`` times their weight). A delay
is a skew where it exceeds :data:`SKEW_MIN_SAMPLES` and :data:`SKEW_Z` standard
uncertainties; the uncertainty is the Jacobian's standard deviation with a floor of
:data:`SKEW_FLOOR_SAMPLES` added, for the model's own error (module constants say where
they come from). Where the sweep crossed the nut's play, no delay is judged: the play's
lag reads as one (:data:`PLAY_JUDGED_M`).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np
from scipy.optimize import least_squares

from .fitdata import log_binned
from .greybox import TIGHT, FitObjective, fitted_names

__all__ = ["COLUMNS", "PLAY_JUDGED_M", "SKEWED", "SKEW_FLOOR_SAMPLES", "SKEW_MIN_SAMPLES",
           "SKEW_Z", "ChannelSkew", "SkewedChannel", "fit_channel_skews", "is_skew",
           "skewed_channels"]

#: The FRFs whose delay the fit reads: the channel that is late where the delay is
#: positive, and the one it is read against [-].
SKEWED = {"G_T": ("scale", "motor encoder"), "G_tcp": ("TCP", "scale")}
#: Floor of a delay's standard uncertainty, for the model's own error: on the reference
#: machines recorded in step (bench C, D, E, H, R05, R17; X and Y) the delays read
#: 0.09 samples rms, the largest 0.32 (R05's TCP), where the Jacobian gave 0.1-0.27; and
#: against skews put in, the Jacobian's alone was up to 2.6 times too small [samples].
SKEW_FLOOR_SAMPLES = 0.1
#: Least delay called a skew: a skew of a recorder is a whole number of samples, and a
#: delay below half of one is the model's error as likely [samples].
SKEW_MIN_SAMPLES = 0.5
#: Standard uncertainties a delay must exceed to be called a skew [-].
SKEW_Z = 3.0
#: Least lost motion of the nut for which no delay is judged: on eight machines of
#: :mod:`studies.unseen` (seed 91, every channel in step) a play of 0.58 um read as
#: 0.13 samples, and from 2.7 um on as up to 3.8 samples of the scale late against the motor
#: encoder. A scale one sample late puts a lost motion of 0.5 um into bench D's X, which
#: must not hide it [m].
PLAY_JUDGED_M = 1e-6
#: Largest delay fitted: the phase of the highest bins wraps beyond it [samples].
MAX_SKEW_SAMPLES = 20.0


def is_skew(samples: float, std_samples: float) -> bool:
    """Whether a delay of ``samples`` with the standard uncertainty ``std_samples`` is a
    skew (module docstring); a delay held at the fit's bound has none, and is [-]."""
    n = abs(samples)
    return bool(n > SKEW_MIN_SAMPLES and not n <= SKEW_Z * std_samples)


@dataclass(frozen=True)
class ChannelSkew:
    """The delay of one recorded channel against another, read from the sweep's FRFs.

    Parameters
    ----------
    frf : str
        The FRF it was read from, a key of :data:`SKEWED` [-].
    delay_s : float
        How late the channel is against its reference; negative: early [s].
    std_s : float
        Its standard uncertainty, the floor included [s].
    sample_s : float
        The record's sample period [s].
    not_judged : str
        Why the delay is not judged a skew whatever it reads; empty where it is [-].
    """

    frf: str
    delay_s: float
    std_s: float
    sample_s: float
    not_judged: str = ""

    @property
    def channel(self) -> str:
        """The channel read [-]."""
        return SKEWED[self.frf][0]

    @property
    def reference(self) -> str:
        """The channel it is read against [-]."""
        return SKEWED[self.frf][1]

    @property
    def samples(self) -> float:
        """The delay in samples of the record [-]."""
        return self.delay_s / self.sample_s

    @property
    def skewed(self) -> bool:
        """Whether the delay is a skew (module docstring) [-]."""
        return not self.not_judged and is_skew(self.samples, self.std_s / self.sample_s)

    def words(self) -> str:
        """The delay as a user reads it [-]."""
        side = "late" if self.delay_s > 0 else "early"
        return (f"the {self.channel} channel reads {abs(self.samples):.2f} +- "
                f"{self.std_s / self.sample_s:.2f} samples ({abs(self.delay_s) * 1e6:.0f} +- "
                f"{self.std_s * 1e6:.0f} us) {side} against the {self.reference}")

    def to_dict(self) -> dict:
        """Plain dictionary for the JSON report [SI]."""
        return {**asdict(self), "channel": self.channel, "reference": self.reference,
                "samples": self.samples, "skewed": self.skewed}


#: The column of each channel in a sweep record [-].
COLUMNS = {"motor encoder": "motor_angle_rad", "scale": "scale_mm", "TCP": "tcp_mm"}


@dataclass(frozen=True)
class SkewedChannel:
    """One channel out of step with the others it was read against.

    Parameters
    ----------
    channel : str
        ``"motor encoder"``, ``"scale"`` or ``"TCP"`` [-].
    against : str
        The channels it was read against, which agree [-].
    samples : float
        How late it is; negative: early [samples].
    std_samples : float
        Its standard uncertainty [samples].
    sample_s : float
        The record's sample period [s].
    """

    channel: str
    against: str
    samples: float
    std_samples: float
    sample_s: float

    def words(self) -> str:
        """What a user reads [-]."""
        side = "late" if self.samples > 0 else "early"
        T = self.sample_s * 1e6
        return (f"the {self.channel} channel reads {abs(self.samples):.2f} +- "
                f"{self.std_samples:.2f} samples ({abs(self.samples) * T:.0f} +- "
                f"{self.std_samples * T:.0f} us) {side} against the {self.against}")

    def remedy(self) -> str:
        """The shift of its column that puts it back in step [-]."""
        n = max(round(abs(self.samples)), 1)
        way = "earlier" if self.samples > 0 else "later"
        return f"shift the {COLUMNS[self.channel]} column {n} sample{'s' if n > 1 else ''} {way}"


def skewed_channels(skews) -> list[SkewedChannel]:
    """The channels out of step, from the delays of :func:`fit_channel_skews`: of motor
    encoder, scale and TCP, the one whose delay against the other two, which agree, is a
    skew; where the TCP is not recorded the scale against the motor encoder, either of
    which may be out [-].

    Parameters
    ----------
    skews : tuple of ChannelSkew
        The delays read [s].
    """
    by = {k.frf: k for k in skews}
    t, c = by.get("G_T"), by.get("G_tcp")
    if t is None or not (t.skewed or (c is not None and c.skewed)):
        return []
    T = t.sample_s
    if c is None:
        return [SkewedChannel("scale", "motor encoder (or that against the scale)",
                              t.samples, t.std_s / T, T)]
    if not t.skewed:  # motor and scale agree
        return [SkewedChannel("TCP", "scale and the motor encoder", c.samples, c.std_s / T, T)]
    if not c.skewed:  # scale and TCP agree, and the motor encoder is off
        return [SkewedChannel("motor encoder", "scale and the TCP", -t.samples, t.std_s / T,
                              T)]
    if not is_skew((t.delay_s + c.delay_s) / T, math.hypot(t.std_s, c.std_s) / T):
        # motor and TCP agree
        return [SkewedChannel("scale", "motor encoder and the TCP", t.samples, t.std_s / T,
                              T)]
    return [SkewedChannel("scale", "motor encoder", t.samples, t.std_s / T, T),
            SkewedChannel("TCP", "scale", c.samples, c.std_s / T, T)]


def fit_channel_skews(data: dict, phys, lead: float, K_tc: float, hold_period_s: float,
                      fit_current_loop: bool, fs_hz: float, lost_motion_m: float = 0.0,
                      max_nfev: int = 400) -> tuple[ChannelSkew, ...]:
    """The delays of the scale against the motor encoder and of the TCP against the scale,
    fitted jointly with the mechanics from the fit ``phys`` on (module docstring); none
    without ``G_T`` or a sample rate.

    Parameters
    ----------
    data : dict of str to FRFData
        The FRFs the fit ``phys`` was made to [SI].
    phys : PhysicalFit
        The kept fit: its mechanics (the start, every one free) and nut, and its current
        loop [SI].
    lead : float
        Ball-screw lead [m].
    K_tc : float
        Torque constant [N m/A].
    hold_period_s : float
        Hold of the current command that ``G_M`` carries [s].
    fit_current_loop : bool
        Whether the current loop's bandwidth is fitted [-].
    fs_hz : float
        Sample rate of the sweep's record [Hz].
    lost_motion_m : float
        The nut's lost motion; from :data:`PLAY_JUDGED_M` on, none is judged [m].
    max_nfev : int
        Function evaluations of the joint fit [-].
    """
    frfs = [k for k in SKEWED if k in data]
    if "G_T" not in data or not fs_hz > 0:
        return ()
    # the structure is freed too: held at what G_tcp alone says, it keeps the lag it took
    names, tied, _ = fitted_names(data, None, fit_current_loop)
    obj = FitObjective({k: log_binned(v) for k, v in data.items()}, names, tied,
                     dict(lead=lead, K_tc=K_tc, M_h=1.0, C_h=1.0, K_h=1e9), fit_current_loop,
                     phys.current_bandwidth_hz, hold_period_s, phys.nut_gain)
    start = {**phys.mechanics.model_dump(), "f_i": phys.current_bandwidth_hz or 3000.0}
    theta0 = np.log([start[p] for p in names])
    cols = _delay_columns(obj, frfs, fs_hz)
    n = theta0.size
    lo = np.r_[theta0 - np.log(1e3), np.full(len(frfs), -MAX_SKEW_SAMPLES)]
    hi = np.r_[theta0 + np.log(1e3), np.full(len(frfs), MAX_SKEW_SAMPLES)]
    if fit_current_loop:
        lo[n - 1], hi[n - 1] = np.log(20.0), np.log(1e5)
    x0 = np.clip(np.r_[theta0, np.zeros(len(frfs))], lo, hi)

    def resid(x):
        return obj.resid(x[:n]) + cols @ x[n:]

    if not (np.all(np.isfinite(cols)) and np.all(np.isfinite(resid(x0)))):
        return ()  # a record broken in its time base or its bins: the gates say so
    r = least_squares(resid, x0, jac=lambda x: np.hstack([obj.jac(x[:n]), cols]),
                      bounds=(lo, hi), max_nfev=max_nfev, method="trf", **TIGHT)
    sd = _delay_std(r, n)
    T = 1.0 / fs_hz
    return tuple(ChannelSkew(k, float(r.x[n + i]) * T,
                             math.hypot(sd[i], SKEW_FLOOR_SAMPLES) * T, T,
                             _play_words(lost_motion_m))
                 for i, k in enumerate(frfs))


def _play_words(lost_motion_m: float) -> str:
    """Why no delay of an axis with the lost motion ``lost_motion_m`` is judged: the
    sweep crosses the nut's play, whose lag the model's real-valued softening of the nut
    does not hold and which reads as a delay of the table's channels (:data:`PLAY_JUDGED_M`);
    empty where the play is smaller [-]."""
    if not lost_motion_m >= PLAY_JUDGED_M:
        return ""
    return (f"the sweep crossed the nut's play ({lost_motion_m * 1e6:.2f} um), whose lag reads "
            "as a delay of the scale and the TCP")


def _delay_columns(obj, frfs: list, fs_hz: float) -> np.ndarray:
    """The residual's derivative by each delay of ``frfs`` [1/sample]: a channel late by
    ``tau`` turns the measured phase by ``-omega tau``, which the residual's phase rows
    (the second half of each FRF's rows, :func:`~.fitdata.log_residual`) see with the
    opposite sign of the measurement, times their weight [-]."""
    rows = sum(2 * d.freq_hz.size for d in obj.data.values())
    cols = np.zeros((rows, len(frfs)))
    at = 0
    for k, d in obj.data.items():
        m = d.freq_hz.size
        if k in frfs:
            cols[at + m:at + 2 * m, frfs.index(k)] = -2 * np.pi * d.freq_hz * obj.w[k] / fs_hz
        at += 2 * m
    return cols


def _delay_std(r, n: int) -> np.ndarray:
    """The Jacobian's standard deviation of each delay (the entries after the first ``n``)
    of a ``least_squares`` result, the residual's variance estimated from its cost; NaN
    where a delay is held at a bound [samples]."""
    J = r.jac
    dof = max(1, J.shape[0] - J.shape[1])
    cov = np.linalg.pinv(J.T @ J) * (2.0 * r.cost / dof)
    sd = np.sqrt(np.clip(np.diag(cov)[n:], 0.0, None))
    return np.where(r.active_mask[n:] != 0, np.nan, sd)
