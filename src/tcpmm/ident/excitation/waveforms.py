"""Excitation signals for servo identification (input of ``tcpmm excite``).

The signal is a current [A] to inject into the current command of a drive (paper
section 3.2: a swept sine fed into the driver's current command). Each designer returns
an :class:`Excitation` whose :meth:`Excitation.write_csv` gives ``time_s,excitation_A``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from tcpmm.errors import InputError
from tcpmm.io.csvutil import atomic_write_columns

#: PRBS power is down 3 dB at this fraction of the clock frequency [-].
PRBS_3DB_FRACTION = 0.443
#: Kinds accepted by :func:`design_excitation` and their aliases.
KINDS = {
    "linear": "linear_sweep",
    "linear_sweep": "linear_sweep",
    "log": "log_sweep",
    "log_sweep": "log_sweep",
    "multisine": "multisine",
    "prbs": "prbs",
}


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


def _positive(name: str, value, unit: str) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number, got {value!r}", column=name) from None
    if not (math.isfinite(v) and v > 0):
        raise InputError(f"{name} must be positive and finite, got {value!r} {unit}", column=name)
    return v


def _count(name: str, value, lo: int, hi: int | None) -> int:
    ok = isinstance(value, int | np.integer) and not isinstance(value, bool)
    if not (ok and value >= lo and (hi is None or value <= hi)):
        rng = f">= {lo}" if hi is None else f"{lo}..{hi}"
        raise InputError(f"{name} must be an integer {rng}, got {value!r}", column=name)
    return int(value)


def _band(f0_hz, f1_hz, fs_hz, *, log: bool) -> tuple[float, float, float]:
    fs = _positive("fs_hz", fs_hz, "Hz")
    f1 = _positive("f1_hz", f1_hz, "Hz")
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


def _n_samples(duration_s, fs: float) -> int:
    dur = _positive("duration_s", duration_s, "s")
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
    f0, f1, fs = _band(f0_hz, f1_hz, fs_hz, log=kind == "log_sweep")
    amp = _positive("amplitude_A", amplitude_A, "A")
    n = _n_samples(duration_s, fs)
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


def schroeder_phases(amplitudes) -> np.ndarray:
    """Schroeder phases for lines of given amplitudes (low crest factor).

    ``phi_k = -2 pi sum_{l<k} (k - l) p_l`` with ``p_l`` the power fraction of line l;
    for equal amplitudes ``phi_k = -pi k (k - 1) / K``.

    Parameters
    ----------
    amplitudes : array_like
        Line amplitudes, any scale [-].

    Returns
    -------
    ndarray
        Phases [rad].
    """
    a = np.asarray(amplitudes, dtype=float)
    p = a**2 / np.sum(a**2)
    s = np.concatenate(([0.0], np.cumsum(np.cumsum(p))[:-1]))
    return -2 * np.pi * s


def _line_amplitudes(spectrum, f: np.ndarray) -> np.ndarray:
    if isinstance(spectrum, str):
        if spectrum == "flat":
            return np.ones_like(f)
        if spectrum == "pink":
            return 1 / np.sqrt(f)
        raise InputError(
            f"spectrum '{spectrum}' unknown; use 'flat', 'pink', a function of f [Hz] or one "
            "amplitude per line",
            column="spectrum",
        )
    a = spectrum(f) if callable(spectrum) else spectrum
    a = np.broadcast_to(np.asarray(a, dtype=float), f.shape).copy()
    if not (np.all(np.isfinite(a)) and np.all(a >= 0) and np.any(a > 0)):
        raise InputError("spectrum amplitudes must be finite, >= 0, not all 0", column="spectrum")
    return a


def multisine(
    f0_hz,
    f1_hz,
    amplitude_A,
    duration_s,
    fs_hz,
    *,
    n_periods: int = 1,
    spectrum: str | Callable | np.ndarray = "flat",
    phases: str = "schroeder",
    seed: int | None = None,
) -> Excitation:
    """Periodic multisine with lines on the period's frequency grid inside [f0, f1].

    Parameters
    ----------
    f0_hz : float
        Lowest line wanted [Hz].
    f1_hz : float
        Highest line wanted, at most fs/2 [Hz].
    amplitude_A : float
        Peak current of the signal [A].
    duration_s : float
        Total length, ``n_periods`` periods; one period is rounded to whole samples [s].
    fs_hz : float
        Sample rate [Hz].
    n_periods : int
        Number of identical periods (the first may be dropped as transient) [-].
    spectrum : {"flat", "pink"}, callable or array_like
        Line amplitude shape: flat, 1/sqrt(f), a function of f [Hz], or one value per
        line [-].
    phases : {"schroeder", "random"}
        Schroeder phases (low crest factor) or uniform random phases [-].
    seed : int, optional
        Seed of the random phases [-].

    Returns
    -------
    Excitation
        The multisine; ``params`` holds ``lines_hz``, ``period_s`` and ``crest_factor``.
    """
    f0, f1, fs = _band(f0_hz, f1_hz, fs_hz, log=False)
    amp = _positive("amplitude_A", amplitude_A, "A")
    n_periods = _count("n_periods", n_periods, 1, None)
    n_total = _n_samples(duration_s, fs)
    n_per = n_total // n_periods
    df = fs / max(n_per, 1)
    k = np.arange(max(1, math.ceil(f0 / df - 1e-9)), math.floor(f1 / df + 1e-9) + 1)
    k = k[k < n_per / 2]
    if k.size == 0:
        raise InputError(
            f"no frequency line in {f0:g}-{f1:g} Hz: one period is {n_per / fs:g} s, so lines "
            f"are {df:g} Hz apart. Lengthen the period (duration_s / n_periods)",
            column="duration_s",
        )
    f = k * df
    a = _line_amplitudes(spectrum, f)
    if phases == "schroeder":
        phi = schroeder_phases(a)
    elif phases == "random":
        phi = np.random.default_rng(seed).uniform(0, 2 * np.pi, k.size)
    else:
        raise InputError(f"phases '{phases}' unknown; use 'schroeder' or 'random'", column="phases")
    spec = np.zeros(n_per // 2 + 1, dtype=complex)
    spec[k] = a * np.exp(1j * phi)
    one = np.fft.irfft(spec, n_per)
    one *= amp / np.max(np.abs(one))
    x = np.tile(one, n_periods)
    t = np.arange(x.size) / fs
    cf = float(np.max(np.abs(one)) / np.sqrt(np.mean(one**2)))
    params = {
        "f0_hz": f0,
        "f1_hz": f1,
        "amplitude_A": amp,
        "n_periods": int(n_periods),
        "period_s": n_per / fs,
        "lines_hz": f,
        "n_lines": int(k.size),
        "phases": phases,
        "crest_factor": cf,
    }
    return Excitation(t, x, fs, "multisine", (float(f[0]), float(f[-1])), params)


def prbs(order, clock_hz, amplitude_A, fs_hz, *, n_periods: int = 1) -> Excitation:
    """Maximum-length binary sequence (PRBS) held for ``fs/clock`` samples per bit.

    One period has ``2**order - 1`` bits; its lines are ``clock/(2**order - 1)`` apart and
    its power is 3 dB down at 0.443 clock, zero at the clock frequency.

    Parameters
    ----------
    order : int
        Shift-register length, 2..32 [-].
    clock_hz : float
        Bit rate; fs_hz / clock_hz must be a whole number [Hz].
    amplitude_A : float
        Level of the two states, +/- amplitude [A].
    fs_hz : float
        Sample rate [Hz].
    n_periods : int
        Number of sequence periods [-].

    Returns
    -------
    Excitation
        The sequence; ``band_hz`` is (first line, -3 dB frequency).
    """
    from scipy.signal import max_len_seq

    order = _count("order", order, 2, 32)
    n_periods = _count("n_periods", n_periods, 1, None)
    fs = _positive("fs_hz", fs_hz, "Hz")
    clock = _positive("clock_hz", clock_hz, "Hz")
    amp = _positive("amplitude_A", amplitude_A, "A")
    ratio = fs / clock
    m = round(ratio)
    if m < 1 or abs(ratio - m) > 1e-9 * ratio:
        hint = f"; e.g. clock_hz = {fs / max(1, math.floor(ratio)):g}" if ratio >= 1 else ""
        raise InputError(
            f"fs_hz / clock_hz = {ratio:g} must be a whole number >= 1{hint}", column="clock_hz"
        )
    length = 2**order - 1
    bits = max_len_seq(order)[0].astype(float) * 2 - 1
    one = np.repeat(bits * amp, m)
    x = np.tile(one, n_periods)
    t = np.arange(x.size) / fs
    band = (clock / length, PRBS_3DB_FRACTION * clock)
    params = {
        "order": int(order),
        "clock_hz": clock,
        "amplitude_A": amp,
        "n_periods": int(n_periods),
        "period_s": length * m / fs,
        "samples_per_bit": m,
    }
    return Excitation(t, x, fs, "prbs", band, params)


def prbs_for_band(f0_hz, f1_hz, amplitude_A, duration_s, fs_hz) -> Excitation:
    """PRBS whose clock keeps f1 within the -3 dB band and whose lines reach down to f0.

    Parameters
    ----------
    f0_hz : float
        Lowest frequency wanted; sets the order [Hz].
    f1_hz : float
        Highest frequency wanted; sets the clock [Hz].
    amplitude_A : float
        Level [A].
    duration_s : float
        Length available; as many whole periods as fit [s].
    fs_hz : float
        Sample rate [Hz].

    Returns
    -------
    Excitation
        The sequence.
    """
    f0, f1, fs = _band(f0_hz, f1_hz, fs_hz, log=True)
    dur = _positive("duration_s", duration_s, "s")
    m = max(1, math.floor(fs * PRBS_3DB_FRACTION / f1))
    clock = fs / m
    if PRBS_3DB_FRACTION * clock < f1:
        raise InputError(
            f"f1_hz={f1:g} is above the PRBS -3 dB limit {PRBS_3DB_FRACTION * fs:g} Hz at "
            f"fs_hz={fs:g}; lower f1 or sample faster",
            column="f1_hz",
        )
    order = max(2, math.ceil(math.log2(clock / f0 + 1)))
    if order > 32:
        raise InputError(f"f0_hz={f0:g} needs a PRBS longer than order 32", column="f0_hz")
    period = (2**order - 1) / clock
    n_periods = math.floor(dur / period + 1e-9)
    if n_periods < 1:
        raise InputError(
            f"one PRBS period reaching down to {f0:g} Hz lasts {period:.4g} s, longer than "
            f"duration_s={dur:g} s; record longer or raise f0",
            column="duration_s",
        )
    return prbs(order, clock, amplitude_A, fs, n_periods=n_periods)


def design_excitation(kind, f0_hz, f1_hz, amplitude_A, duration_s, fs_hz, **options):
    """Dispatch for ``tcpmm excite KIND --band F0,F1 --amplitude-A --duration-s --fs-hz``.

    Parameters
    ----------
    kind : str
        ``linear``, ``log``, ``multisine`` or ``prbs`` (or the function names) [-].
    f0_hz : float
        Band start [Hz].
    f1_hz : float
        Band end [Hz].
    amplitude_A : float
        Peak current [A].
    duration_s : float
        Length [s].
    fs_hz : float
        Sample rate [Hz].
    **options
        Keyword options of the chosen designer (``taper_s``, ``n_periods``, ``phases``,
        ``spectrum``, ``seed``); options set to None are dropped, so a CLI can pass all
        of its flags unconditionally [-].

    Returns
    -------
    Excitation
        The signal.
    """
    name = KINDS.get(str(kind).lower().replace("-", "_"))
    if name is None:
        raise InputError(
            f"excitation kind '{kind}' unknown; use linear, log, multisine or prbs",
            column="kind",
        )
    options = {k: v for k, v in options.items() if v is not None}
    n = _positive("duration_s", duration_s, "s") * _positive("fs_hz", fs_hz, "Hz")
    if n > MAX_SAMPLES:
        raise InputError(f"{duration_s:g} s at {fs_hz:g} Hz is {n:.3g} samples; at most "
                         f"{MAX_SAMPLES:.0e} are designed at once: shorten the signal or "
                         "lower the sample rate", column="duration_s")
    if name == "prbs":
        if options:
            raise InputError(f"prbs from a band takes no options, got {sorted(options)}")
        return prbs_for_band(f0_hz, f1_hz, amplitude_A, duration_s, fs_hz)
    fn = {"linear_sweep": linear_sweep, "log_sweep": log_sweep, "multisine": multisine}[name]
    try:
        return fn(f0_hz, f1_hz, amplitude_A, duration_s, fs_hz, **options)
    except TypeError as exc:
        raise InputError(f"{name}: {exc}") from None
