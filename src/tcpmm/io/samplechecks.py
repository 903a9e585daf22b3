"""Checks of a record's samples: every value finite, the time strictly increasing and,
where asked, uniform; each message names the file and the line or sample."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from tcpmm.errors import InputError

#: Fewest samples accepted in a sweep record [-].
MIN_SWEEP_SAMPLES = 64
#: Largest accepted deviation of one sample interval from the nominal one [-].
UNIFORM_TIME_TOL = 0.05

LineOf = Callable[[int], int | None]


def _where(i: int, line_of: LineOf | None) -> tuple[int | None, str]:
    """Line number (CSV) or a sample-index phrase (other sources) for sample ``i``."""
    if line_of is not None:
        return line_of(i), ""
    return None, f" at sample {i} (0-based)"


def check_finite(values: np.ndarray, name: str, source=None, line_of: LineOf | None = None):
    """Raise :class:`InputError` at the first NaN or infinite value.

    Parameters
    ----------
    values : ndarray
        Samples [-].
    name : str
        Column or channel name used in the message [-].
    source : str, optional
        File the values come from [-].
    line_of : callable, optional
        Maps a 0-based sample index to a 1-based file line [-].
    """
    finite = np.isfinite(values)
    if not finite.all():
        i = int(np.flatnonzero(~finite)[0])
        line, at = _where(i, line_of)
        kind = "NaN" if np.isnan(values[i]) else "infinite"
        raise InputError(
            f"value is {kind}{at}; every sample must be a finite number. Repair or cut the record",
            file=source,
            line=line,
            column=name,
        )


def _check_steps(t: np.ndarray, uniform: bool, source, line_of: LineOf | None,
                 name: str) -> None:
    """Refuse a step back in time, and, where asked, a step off the median interval.

    Parameters
    ----------
    t : ndarray
        Sample times, finite [s].
    uniform : bool
        Require a constant sample interval [-].
    source : str or None
        File the times come from [-].
    line_of : callable or None
        Maps a 0-based sample index to a 1-based file line [-].
    name : str
        Column name used in messages [-].
    """
    n = t.size
    dt = np.diff(t)
    bad = np.flatnonzero(dt <= 0)
    first_bad = int(bad[0]) if bad.size else n
    nominal = float(np.median(dt)) if uniform else float("nan")
    if uniform and nominal > 0:
        # a jump straight before a step back is an ordering problem, reported as such
        stop = max(first_bad - 1, 0) if bad.size else n
        off = np.flatnonzero(np.abs(dt[:stop] - nominal) > UNIFORM_TIME_TOL * nominal)
    else:
        off = np.empty(0, dtype=int)
    if off.size:
        i = int(off[0]) + 1
        line, at = _where(i, line_of)
        ratio = dt[i - 1] / nominal
        hint = f" ({ratio - 1:.0f} sample(s) lost?)" if ratio > 1.5 else ""
        raise InputError(
            f"non-uniform sampling{at}: interval {dt[i - 1]:.6g} s before this sample, "
            f"{nominal:.6g} s elsewhere{hint}. The record must be uniformly sampled: "
            "re-export it without gaps or cut it here",
            file=source,
            line=line,
            column=name,
        )
    if bad.size:
        i = first_bad + 1
        line, at = _where(i, line_of)
        raise InputError(
            f"time does not increase{at}: {t[i]:.9g} s follows {t[i - 1]:.9g} s. Sort the "
            "rows by time and remove repeated samples",
            file=source,
            line=line,
            column=name,
        )


def check_time(
    time_s: np.ndarray,
    *,
    source=None,
    line_of: LineOf | None = None,
    uniform: bool = True,
    min_samples: int = MIN_SWEEP_SAMPLES,
    name: str = "time_s",
) -> float:
    """Check a time vector: enough samples, strictly increasing and (optionally) uniform.

    Parameters
    ----------
    time_s : ndarray
        Sample times [s].
    source : str, optional
        File the times come from [-].
    line_of : callable, optional
        Maps a 0-based sample index to a 1-based file line [-].
    uniform : bool
        Require a constant sample interval [-].
    min_samples : int
        Fewest samples accepted [-].
    name : str
        Column name used in messages [-].

    Returns
    -------
    float
        Sample rate from the first and last sample (NaN when not uniform) [Hz].
    """
    t = np.asarray(time_s, dtype=float)
    n = t.size
    if n < min_samples:
        raise InputError(
            f"only {n} samples; at least {min_samples} are needed. Record longer",
            file=source,
            column=name,
        )
    check_finite(t, name, source, line_of)
    _check_steps(t, uniform, source, line_of, name)
    if not uniform:
        return float("nan")
    return float((n - 1) / (t[-1] - t[0]))
