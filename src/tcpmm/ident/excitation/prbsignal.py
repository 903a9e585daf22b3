"""Maximum-length binary sequences (PRBS), of a given order and clock or chosen for a band."""

from __future__ import annotations

import math

import numpy as np

from tcpmm.errors import InputError

from .waveforms import Excitation, checked_band, positive, whole_number

__all__ = ["PRBS_3DB_FRACTION", "prbs", "prbs_for_band"]

#: PRBS power is down 3 dB at this fraction of the clock frequency [-].
PRBS_3DB_FRACTION = 0.443


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

    order = whole_number("order", order, 2, 32)
    n_periods = whole_number("n_periods", n_periods, 1, None)
    fs = positive("fs_hz", fs_hz, "Hz")
    clock = positive("clock_hz", clock_hz, "Hz")
    amp = positive("amplitude_A", amplitude_A, "A")
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
    f0, f1, fs = checked_band(f0_hz, f1_hz, fs_hz, log=True)
    dur = positive("duration_s", duration_s, "s")
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
            f"duration_s={dur:g} s; make it at least {math.ceil(period * 1e3) / 1e3:g} s "
            "long, or raise f0",
            column="duration_s",
        )
    return prbs(order, clock, amplitude_A, fs, n_periods=n_periods)
