"""Excitation signals for servo identification (input of ``tcpmm excite``).

The signal is a current [A] to inject into the current command of a drive (paper
section 3.2: a swept sine fed into the driver's current command). Each designer returns
an :class:`Excitation` whose :meth:`Excitation.write_csv` gives ``time_s,excitation_A``.
This module holds the signal type, the checks of the designers' arguments and the swept
sines; multisines are in :mod:`~tcpmm.ident.excitation.multisines`, PRBS in
:mod:`~tcpmm.ident.excitation.prbsignal`, the choice by kind in
:mod:`~tcpmm.ident.excitation.kinds`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from tcpmm.errors import InputError
from tcpmm.io.csvutil import atomic_write_columns

__all__ = ["MAX_SAMPLES", "Excitation", "checked_band", "linear_sweep", "log_sweep",
           "n_samples", "positive", "whole_number"]


@dataclass(frozen=True, eq=False)
class Excitation:
    """A designed excitation signal.

    Parameters
    ----------
    time_s : ndarray
        Sample times from 0 [s].
    signal_A : ndarray
        Excitation current [A].
    fs_hz : float
        Sample rate [Hz].
    kind : str
        ``linear_sweep``, ``log_sweep``, ``multisine`` or ``prbs`` [-].
    band_hz : tuple of float
        Frequency band the signal covers [Hz].
    params : dict
        Design parameters and derived figures (e.g. crest factor, lines) [-].
    """

    time_s: np.ndarray
    signal_A: np.ndarray
    fs_hz: float
    kind: str
    band_hz: tuple[float, float]
    params: dict = field(default_factory=dict)

    @property
    def n_samples(self) -> int:
        """Number of samples [-]."""
        return int(self.signal_A.size)

    @property
    def duration_s(self) -> float:
        """Length n / fs [s]."""
        return self.n_samples / self.fs_hz

    @property
    def peak_A(self) -> float:
        """Largest absolute value [A]."""
        return float(np.max(np.abs(self.signal_A)))

    @property
    def rms_A(self) -> float:
        """Root mean square [A]."""
        return float(np.sqrt(np.mean(self.signal_A**2)))

    @property
    def crest_factor(self) -> float:
        """Peak over RMS [-]."""
        return self.peak_A / self.rms_A

    def to_pandas(self) -> pd.DataFrame:
        """The signal as columns ``time_s, excitation_A``."""
        return pd.DataFrame({"time_s": self.time_s, "excitation_A": self.signal_A})

    def write_csv(self, path: str | Path) -> Path:
        """Write ``time_s,excitation_A`` atomically, ready for a drive or DAQ program.

        Parameters
        ----------
        path : str or Path
            Target CSV file [-].

        Returns
        -------
        Path
            The file written.
        """
        return atomic_write_columns(
            path, {"time_s": self.time_s, "excitation_A": self.signal_A}, "%.12g"
        )


#: Most samples a designed signal may have (10^8: 1000 s at 100 kHz, 2.4 GB as CSV) [-].
MAX_SAMPLES = 10**8


def positive(name: str, value, unit: str) -> float:
    """``value`` as a float; raises unless a positive finite number [unit]."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number, got {value!r}", column=name) from None
    if not (math.isfinite(v) and v > 0):
        raise InputError(f"{name} must be positive and finite, got {value!r} {unit}", column=name)
    return v


def whole_number(name: str, value, lo: int, hi: int | None) -> int:
    """``value`` as an int; raises unless an integer in ``lo..hi`` (no upper bound for
    ``hi=None``) [-]."""
    ok = isinstance(value, int | np.integer) and not isinstance(value, bool)
    if not (ok and value >= lo and (hi is None or value <= hi)):
        rng = f">= {lo}" if hi is None else f"{lo}..{hi}"
        raise InputError(f"{name} must be an integer {rng}, got {value!r}", column=name)
    return int(value)


def checked_band(f0_hz, f1_hz, fs_hz, *, log: bool) -> tuple[float, float, float]:
    """``(f0, f1, fs)`` of a band below Nyquist, ``f0 > 0`` for a logarithmic one; raises
    otherwise [Hz]."""
    fs = positive("fs_hz", fs_hz, "Hz")
    f1 = positive("f1_hz", f1_hz, "Hz")
    try:
        f0 = float(f0_hz)
    except (TypeError, ValueError):
        raise InputError(f"f0_hz must be a number, got {f0_hz!r}", column="f0_hz") from None
    if log and not f0 > 0:
        raise InputError(
            f"f0_hz must be > 0 for a logarithmic sweep, got {f0_hz!r} Hz", column="f0_hz"
        )
    if not (math.isfinite(f0) and f0 >= 0):
        raise InputError(f"f0_hz must be >= 0, got {f0_hz!r} Hz", column="f0_hz")
    if not f0 < f1:
        raise InputError(f"band start f0_hz={f0:g} must be below f1_hz={f1:g}", column="f0_hz")
    if f1 > fs / 2:
        raise InputError(
            f"f1_hz={f1:g} is above the Nyquist frequency {fs / 2:g} Hz of fs_hz={fs:g}; "
            "lower f1 or raise the sample rate (2.5 x f1 or more is advisable)",
            column="f1_hz",
        )
    return f0, f1, fs


def n_samples(duration_s, fs: float) -> int:
    """Samples of ``duration_s`` at ``fs``; raises for fewer than 2 [-]."""
    dur = positive("duration_s", duration_s, "s")
    n = round(dur * fs)
    if n < 2:
        raise InputError(
            f"duration_s={dur:g} s at fs_hz={fs:g} gives {n} samples; need at least 2",
            column="duration_s",
        )
    return n


def _taper(n: int, fs: float, taper_s: float) -> np.ndarray:
    if not (math.isfinite(taper_s) and taper_s >= 0):
        raise InputError(f"taper_s must be >= 0, got {taper_s!r} s", column="taper_s")
    m = round(taper_s * fs)
    w = np.ones(n)
    if m == 0:
        return w
    if 2 * m > n:
        raise InputError(
            f"taper_s={taper_s:g} s twice is longer than the signal ({n / fs:g} s)",
            column="taper_s",
        )
    ramp = 0.5 - 0.5 * np.cos(np.pi * np.arange(m) / m)
    w[:m] = ramp
    w[n - m :] = ramp[::-1]
    return w


def _sweep(kind, f0_hz, f1_hz, amplitude_A, duration_s, fs_hz, taper_s):
    f0, f1, fs = checked_band(f0_hz, f1_hz, fs_hz, log=kind == "log_sweep")
    amp = positive("amplitude_A", amplitude_A, "A")
    n = n_samples(duration_s, fs)
    T = n / fs
    t = np.arange(n) / fs
    if kind == "log_sweep":
        k = math.log(f1 / f0)
        phase = 2 * np.pi * f0 * T / k * np.expm1(t * k / T)
    else:
        phase = 2 * np.pi * (f0 * t + 0.5 * (f1 - f0) * t**2 / T)
    x = amp * np.sin(phase) * _taper(n, fs, float(taper_s))
    params = {"f0_hz": f0, "f1_hz": f1, "amplitude_A": amp, "duration_s": T, "taper_s": taper_s}
    return Excitation(t, x, fs, kind, (f0, f1), params)


def linear_sweep(f0_hz, f1_hz, amplitude_A, duration_s, fs_hz, *, taper_s=0.0) -> Excitation:
    """Swept sine whose frequency rises linearly from f0 to f1.

    Parameters
    ----------
    f0_hz : float
        Start frequency, >= 0 [Hz].
    f1_hz : float
        End frequency, at most fs/2 [Hz].
    amplitude_A : float
        Peak current [A].
    duration_s : float
        Length; rounded to whole samples [s].
    fs_hz : float
        Sample rate [Hz].
    taper_s : float
        Raised-cosine fade-in and fade-out length at each end [s].

    Returns
    -------
    Excitation
        The sweep.
    """
    return _sweep("linear_sweep", f0_hz, f1_hz, amplitude_A, duration_s, fs_hz, taper_s)


def log_sweep(f0_hz, f1_hz, amplitude_A, duration_s, fs_hz, *, taper_s=0.0) -> Excitation:
    """Swept sine whose frequency rises exponentially (equal time per octave).

    Parameters
    ----------
    f0_hz : float
        Start frequency, > 0 [Hz].
    f1_hz : float
        End frequency, at most fs/2 [Hz].
    amplitude_A : float
        Peak current [A].
    duration_s : float
        Length; rounded to whole samples [s].
    fs_hz : float
        Sample rate [Hz].
    taper_s : float
        Raised-cosine fade-in and fade-out length at each end [s].

    Returns
    -------
    Excitation
        The sweep.
    """
    return _sweep("log_sweep", f0_hz, f1_hz, amplitude_A, duration_s, fs_hz, taper_s)
