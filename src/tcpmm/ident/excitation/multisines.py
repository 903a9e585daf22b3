"""Periodic multisines: lines on the period's frequency grid with Schroeder or random
phases."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from tcpmm.errors import InputError

from .waveforms import Excitation, checked_band, n_samples, positive, whole_number

__all__ = ["multisine", "schroeder_phases"]


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


def multisine(f0_hz, f1_hz, amplitude_A, duration_s, fs_hz, *, n_periods: int = 1,
              spectrum: str | Callable | np.ndarray = "flat", phases: str = "schroeder",
              seed: int | None = None) -> Excitation:
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
    f0, f1, fs = checked_band(f0_hz, f1_hz, fs_hz, log=False)
    amp = positive("amplitude_A", amplitude_A, "A")
    n_periods = whole_number("n_periods", n_periods, 1, None)
    n_total = n_samples(duration_s, fs)
    n_per = n_total // n_periods
    k, df = _line_numbers(f0, f1, fs, n_per)
    f = k * df
    a = _line_amplitudes(spectrum, f)
    one = _one_period(k, a, _line_phases(phases, a, seed), n_per, amp)
    x = np.tile(one, n_periods)
    t = np.arange(x.size) / fs
    cf = float(np.max(np.abs(one)) / np.sqrt(np.mean(one**2)))
    params = {"f0_hz": f0, "f1_hz": f1, "amplitude_A": amp, "n_periods": int(n_periods),
              "period_s": n_per / fs, "lines_hz": f, "n_lines": int(k.size), "phases": phases,
              "crest_factor": cf}
    return Excitation(t, x, fs, "multisine", (float(f[0]), float(f[-1])), params)


def _line_numbers(f0: float, f1: float, fs: float, n_per: int) -> tuple:
    """The lines of a period of ``n_per`` samples inside [f0, f1] and below Nyquist, as
    multiples of the line spacing [-], and that spacing [Hz]; raises if there are none."""
    df = fs / max(n_per, 1)
    k = np.arange(max(1, math.ceil(f0 / df - 1e-9)), math.floor(f1 / df + 1e-9) + 1)
    k = k[k < n_per / 2]
    if k.size == 0:
        raise InputError(
            f"no frequency line in {f0:g}-{f1:g} Hz: one period is {n_per / fs:g} s, so lines "
            f"are {df:g} Hz apart. Lengthen the period (duration_s / n_periods)",
            column="duration_s",
        )
    return k, df


def _line_phases(phases: str, a: np.ndarray, seed) -> np.ndarray:
    """Schroeder phases for the line amplitudes ``a``, or uniform random ones [rad]."""
    if phases == "schroeder":
        return schroeder_phases(a)
    if phases == "random":
        return np.random.default_rng(seed).uniform(0, 2 * np.pi, a.size)
    raise InputError(f"phases '{phases}' unknown; use 'schroeder' or 'random'", column="phases")


def _one_period(k: np.ndarray, a: np.ndarray, phi: np.ndarray, n_per: int,
                amp: float) -> np.ndarray:
    """One period of ``n_per`` samples with lines ``k`` of amplitudes ``a`` and phases
    ``phi``, scaled to the peak ``amp`` [A]."""
    spec = np.zeros(n_per // 2 + 1, dtype=complex)
    spec[k] = a * np.exp(1j * phi)
    one = np.fft.irfft(spec, n_per)
    one *= amp / np.max(np.abs(one))
    return one
