"""Sampling, trend removal, segmenting and band checks behind the FRF estimators."""

from __future__ import annotations

import warnings

import numpy as np

from ...errors import InputError, InputWarning

#: The lowest frequency asked for must lie at least this many bins above 0 Hz.
MIN_BINS_BELOW_FMIN = 4
#: Fewer segments than this make coherence meaningless.
MIN_SEGMENTS = 4
#: Excitation power below this fraction of its in-band maximum counts as "no excitation".
NO_POWER_FRACTION = 1e-6
#: The band a sweep sweeps reaches from its lowest to its highest bin of at least this
#: fraction of the maximum power: beyond them lie the roll-off at its ends and the
#: leakage, a hundredth of it, which dips below :data:`NO_POWER_FRACTION` here and there
#: (a logarithmic sweep's power at its top end lies some 1e-3 below its peak) [-].
SWEPT_FRACTION = 1e-4


def sample_rate_hz(time_s, file=None, column: str = "time_s", rtol: float = 0.1) -> float:
    """Sample rate of a uniformly sampled time vector.

    Parameters
    ----------
    time_s : array_like
        Sample times [s].
    file : str or Path, optional
        File the times come from, for error messages [-].
    column : str
        Column name for error messages [-].
    rtol : float
        Largest allowed deviation of one step from the median step, relative [-].

    Returns
    -------
    float
        Sample rate [Hz].
    """
    t = np.asarray(time_s, dtype=float)
    if t.ndim != 1 or t.size < 3:
        raise InputError("need at least three time samples", file=file, column=column)
    bad = np.flatnonzero(~np.isfinite(t))
    if bad.size:
        raise InputError(f"time is not a number at sample {bad[0]}", file=file, column=column)
    dt = np.diff(t)
    step = float(np.median(dt))
    if step <= 0:
        raise InputError("time must increase", file=file, column=column)
    off = np.flatnonzero(np.abs(dt - step) > rtol * step)
    if off.size:
        i = int(off[0])
        raise InputError(
            f"time is not uniformly sampled: step {dt[i]:.6g} s between samples {i} and {i + 1} "
            f"against a median step of {step:.6g} s (missing or repeated samples?); resample "
            "the record onto a uniform grid first",
            file=file,
            column=column,
        )
    return float((t.size - 1) / (t[-1] - t[0]))


def remove_trend(x, order: int | None = 1) -> np.ndarray:
    """Subtract a polynomial trend fitted over the whole record.

    Parameters
    ----------
    x : array_like
        Samples, uniformly spaced [-].
    order : int or None
        Polynomial order (0 mean, 1 line, ...); None leaves the data as they are [-].

    Returns
    -------
    ndarray
        Detrended copy [-].
    """
    x = np.asarray(x, dtype=float)
    if order is None:
        return x.copy()
    tau = np.linspace(-1.0, 1.0, x.size)
    coef = np.polynomial.legendre.legfit(tau, x, order)
    return x - np.polynomial.legendre.legval(tau, coef)


def detrend_order(detrend) -> int | None:
    names = {"none": None, "constant": 0, "linear": 1, "quadratic": 2, "cubic": 3}
    if detrend is None or detrend is False:
        return None
    if isinstance(detrend, str):
        key = detrend.lower()
        if key not in names:
            raise InputError(f"detrend must be one of {sorted(names)} or an integer order")
        return names[key]
    order = int(detrend)
    if order < 0 or order > 5:
        raise InputError(f"detrend polynomial order must be 0..5, got {detrend}")
    return order


def checked_signal(x, name: str, n: int | None, file=None) -> np.ndarray:
    a = np.asarray(x, dtype=float)
    if a.ndim != 1:
        raise InputError(f"signal {name} must be one-dimensional", file=file, column=name)
    if n is not None and a.size != n:
        raise InputError(
            f"signal {name} has {a.size} samples, the excitation {n}", file=file, column=name
        )
    bad = np.flatnonzero(~np.isfinite(a))
    if bad.size:
        raise InputError(
            f"signal {name} holds {bad.size} non-finite values (first at sample {bad[0]}); "
            "remove or interpolate them before estimating FRFs",
            file=file,
            column=name,
        )
    return a


def effective_averages(win: np.ndarray, step: int, n_seg: int) -> float:
    """Welch's number of independent averages for overlapping windowed segments."""
    m = win.size
    w2 = float(np.dot(win, win))
    total = 0.0
    j = 1
    while j < n_seg and j * step < m:
        rho = float(np.dot(win[: m - j * step], win[j * step :])) / w2
        total += (1.0 - j / n_seg) * rho**2
        j += 1
    return n_seg / (1.0 + 2.0 * total)


def segmenting(n: int, fs_hz: float, nperseg, fmin_hz, overlap: float, file=None):
    """Choose and check the segment length."""
    if not 0.0 <= overlap < 1.0:
        raise InputError(f"overlap must be in [0, 1), got {overlap}")
    duration = n / fs_hz
    need = None
    if fmin_hz is not None:
        if fmin_hz <= 0:
            raise InputError(f"fmin_hz must be > 0, got {fmin_hz}")
        need = int(np.ceil(MIN_BINS_BELOW_FMIN * fs_hz / fmin_hz))

    def n_segments(m):
        step = max(1, round(m * (1.0 - overlap)))
        return 0 if m > n else (n - m) // step + 1

    if nperseg is None:
        m = 2 ** int(np.floor(np.log2(max(n / 4.0, 2.0))))
        while m > 16 and n_segments(m) < 8:
            m //= 2
        if need is not None and m < need:
            m = 2 ** int(np.ceil(np.log2(need)))
            if n_segments(m) < MIN_SEGMENTS:
                m = need
    else:
        m = int(nperseg)
        if m < 8:
            raise InputError(f"nperseg must be >= 8, got {nperseg}")
        if need is not None and m < need:
            raise InputError(
                f"segments of {m} samples ({m / fs_hz:.4g} s) resolve {fs_hz / m:.4g} Hz: too "
                f"coarse for fmin_hz = {fmin_hz:g} Hz, which needs nperseg >= {need}"
            )
    k = n_segments(m)
    step = max(1, round(m * (1.0 - overlap)))
    if k >= 1 and n - m > (k - 1) * step:
        # scipy drops a partial last segment: add one and overlap a little more instead
        k += 1
        step = (n - m) // (k - 1)
    if k < MIN_SEGMENTS:
        seg_s = m / fs_hz
        need_s = seg_s * (1.0 + (MIN_SEGMENTS - 1) * (1.0 - overlap))
        low = f" for the lowest frequency {fmin_hz:g} Hz" if fmin_hz is not None else ""
        raise InputError(
            f"record too short{low}: it lasts {duration:.4g} s, but {MIN_SEGMENTS} averaged "
            f"segments of {seg_s:.4g} s need {need_s:.4g} s; record longer or raise the "
            "lowest frequency",
            file=file,
        )
    return m, m - step, k


def _power_gaps(freq_hz: np.ndarray, p_uu: np.ndarray, name: str, file=None):
    """Warn about contiguous bands without excitation power within the band the
    excitation sweeps (:data:`SWEPT_FRACTION`), naming ``file`` where given; return the
    excited mask.

    A signal without any power leaves no frequency response to estimate: that is an error.
    """
    top = float(np.max(p_uu)) if p_uu.size else 0.0
    excited = p_uu > NO_POWER_FRACTION * top
    if top <= 0:
        raise InputError(f"{name} carries no power in the band: there is no frequency "
                         "response to estimate; record the sweep with a non-zero excitation",
                         file=file, column=name)
    swept = np.flatnonzero(p_uu >= SWEPT_FRACTION * top)
    idx = np.flatnonzero(~excited)
    idx = idx[(idx > swept[0]) & (idx < swept[-1])]
    if idx.size:
        splits = np.flatnonzero(np.diff(idx) > 1) + 1
        bands = [f"{freq_hz[g[0]]:.4g}-{freq_hz[g[-1]]:.4g} Hz" for g in np.split(idx, splits)]
        said = InputError(
            f"no excitation power in {', '.join(bands)}, within the band it sweeps "
            f"({freq_hz[swept[0]]:.4g}-{freq_hz[swept[-1]]:.4g} Hz; power of {name} below "
            f"{NO_POWER_FRACTION:g} of its maximum): the FRF there is noise", file=file)
        warnings.warn(said.format(), InputWarning, stacklevel=3)
    return excited


def band_bins(freq, p_uu, fmin_hz, fmax_hz, name, file=None):
    """Bins to keep: the band asked for, or (if not asked) the excited span without DC."""
    keep = freq > 0
    if fmin_hz is not None:
        keep &= freq >= fmin_hz
    if fmax_hz is not None:
        keep &= freq <= fmax_hz
    if not np.any(keep):
        raise InputError(f"no frequency bins between {fmin_hz} Hz and {fmax_hz} Hz")
    if fmin_hz is None or fmax_hz is None:
        top = float(np.max(p_uu[keep]))
        exc = np.flatnonzero(keep & (p_uu > NO_POWER_FRACTION * top))
        if exc.size:
            if fmin_hz is None:
                keep &= np.arange(freq.size) >= exc[0]
            if fmax_hz is None:
                keep &= np.arange(freq.size) <= exc[-1]
    _power_gaps(freq[keep], p_uu[keep], name, file)
    return keep
