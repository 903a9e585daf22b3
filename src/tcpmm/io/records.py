"""In-memory measurement records (SI units), shared by the CSV, TDMS and MAT readers."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, fields

import numpy as np
import pandas as pd

from tcpmm.errors import InputError

#: Fewest samples accepted in a sweep record [-].
MIN_SWEEP_SAMPLES = 64
#: Fewest samples accepted in a friction record [-].
MIN_FRICTION_SAMPLES = 16
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
    if not uniform:
        return float("nan")
    return float((n - 1) / (t[-1] - t[0]))


def _as_1d(name: str, values, n: int | None, source) -> np.ndarray:
    a = np.asarray(values, dtype=float)
    if a.ndim != 1:
        a = np.squeeze(a)
    if a.ndim != 1:
        raise InputError(f"expected a 1-D signal, got shape {a.shape}", file=source, column=name)
    if n is not None and a.size != n:
        raise InputError(
            f"has {a.size} samples but time_s has {n}; all signals of a record must have "
            "the same length",
            file=source,
            column=name,
        )
    return a


@dataclass(frozen=True, eq=False)
class SweepRecord:
    """One servo-excitation record of one axis, in SI units.

    Parameters
    ----------
    time_s : ndarray
        Sample times, uniform [s].
    fs_hz : float
        Sample rate [Hz].
    excitation_A : ndarray
        Injected excitation r [A].
    current_cmd_A : ndarray
        Total current command i_c [A].
    motor_angle_rad : ndarray
        Motor encoder angle theta_m [rad].
    scale_m : ndarray
        Linear scale X_LS [m].
    tcp_m : ndarray or None
        TCP position X_TCP; None when no TCP device was fitted [m].
    source : str or None
        File the record was read from [-].
    axis : str or None
        Axis name [-].
    """

    time_s: np.ndarray
    fs_hz: float
    excitation_A: np.ndarray
    current_cmd_A: np.ndarray
    motor_angle_rad: np.ndarray
    scale_m: np.ndarray
    tcp_m: np.ndarray | None = None
    source: str | None = None
    axis: str | None = None

    def __post_init__(self):
        t = _as_1d("time_s", self.time_s, None, self.source)
        object.__setattr__(self, "time_s", t)
        for f in ("excitation_A", "current_cmd_A", "motor_angle_rad", "scale_m", "tcp_m"):
            v = getattr(self, f)
            if v is not None:
                object.__setattr__(self, f, _as_1d(f, v, t.size, self.source))
        object.__setattr__(self, "fs_hz", float(self.fs_hz))

    @classmethod
    def from_arrays(
        cls,
        time_s,
        excitation_A,
        current_cmd_A,
        motor_angle_rad,
        scale_m,
        tcp_m=None,
        *,
        source=None,
        axis=None,
        line_of: LineOf | None = None,
    ) -> SweepRecord:
        """Build a record from SI arrays, checking time and values; ``fs_hz`` from time.

        Parameters
        ----------
        time_s : array_like
            Sample times [s].
        excitation_A : array_like
            Excitation r [A].
        current_cmd_A : array_like
            Current command i_c [A].
        motor_angle_rad : array_like
            Motor angle [rad].
        scale_m : array_like
            Linear scale [m].
        tcp_m : array_like, optional
            TCP position [m].
        source : str, optional
            Originating file, for messages [-].
        axis : str, optional
            Axis name [-].
        line_of : callable, optional
            Maps a 0-based sample index to a file line, for messages [-].
        """
        rec = cls(
            time_s,
            np.nan,
            excitation_A,
            current_cmd_A,
            motor_angle_rad,
            scale_m,
            tcp_m,
            None if source is None else str(source),
            axis,
        )
        fs = check_time(rec.time_s, source=rec.source, line_of=line_of)
        for name in ("excitation_A", "current_cmd_A", "motor_angle_rad", "scale_m", "tcp_m"):
            v = getattr(rec, name)
            if v is not None:
                check_finite(v, name, rec.source, line_of)
        object.__setattr__(rec, "fs_hz", fs)
        return rec

    @property
    def n_samples(self) -> int:
        """Number of samples [-]."""
        return int(self.time_s.size)

    @property
    def duration_s(self) -> float:
        """Record length n / fs [s]."""
        return self.n_samples / self.fs_hz

    @property
    def has_tcp(self) -> bool:
        """True when the record holds a TCP signal [-]."""
        return self.tcp_m is not None

    def to_pandas(self) -> pd.DataFrame:
        """Signals as a DataFrame with SI column names."""
        cols = {f.name: getattr(self, f.name) for f in fields(self)}
        return pd.DataFrame({k: v for k, v in cols.items() if isinstance(v, np.ndarray)})


@dataclass(frozen=True, eq=False)
class FrictionRecord:
    """Slow bidirectional constant-velocity runs of one axis, in SI units.

    Parameters
    ----------
    time_s : ndarray
        Sample times, strictly increasing [s].
    current_cmd_A : ndarray
        Current command i_c [A].
    motor_angle_rad : ndarray
        Motor encoder angle [rad].
    scale_m : ndarray
        Linear scale [m].
    source : str or None
        File the record was read from [-].
    axis : str or None
        Axis name [-].
    """

    time_s: np.ndarray
    current_cmd_A: np.ndarray
    motor_angle_rad: np.ndarray
    scale_m: np.ndarray
    source: str | None = None
    axis: str | None = None

    def __post_init__(self):
        t = _as_1d("time_s", self.time_s, None, self.source)
        object.__setattr__(self, "time_s", t)
        for f in ("current_cmd_A", "motor_angle_rad", "scale_m"):
            object.__setattr__(self, f, _as_1d(f, getattr(self, f), t.size, self.source))

    @classmethod
    def from_arrays(
        cls,
        time_s,
        current_cmd_A,
        motor_angle_rad,
        scale_m,
        *,
        source=None,
        axis=None,
        line_of: LineOf | None = None,
    ) -> FrictionRecord:
        """Build a record from SI arrays, checking time and values.

        Parameters
        ----------
        time_s : array_like
            Sample times [s].
        current_cmd_A : array_like
            Current command [A].
        motor_angle_rad : array_like
            Motor angle [rad].
        scale_m : array_like
            Linear scale [m].
        source : str, optional
            Originating file [-].
        axis : str, optional
            Axis name [-].
        line_of : callable, optional
            Maps a 0-based sample index to a file line [-].
        """
        rec = cls(
            time_s,
            current_cmd_A,
            motor_angle_rad,
            scale_m,
            None if source is None else str(source),
            axis,
        )
        check_time(
            rec.time_s,
            source=rec.source,
            line_of=line_of,
            uniform=False,
            min_samples=MIN_FRICTION_SAMPLES,
        )
        for name in ("current_cmd_A", "motor_angle_rad", "scale_m"):
            check_finite(getattr(rec, name), name, rec.source, line_of)
        return rec

    @property
    def n_samples(self) -> int:
        """Number of samples [-]."""
        return int(self.time_s.size)

    def to_pandas(self) -> pd.DataFrame:
        """Signals as a DataFrame with SI column names."""
        return pd.DataFrame(
            {
                "time_s": self.time_s,
                "current_cmd_A": self.current_cmd_A,
                "motor_angle_rad": self.motor_angle_rad,
                "scale_m": self.scale_m,
            }
        )


@dataclass(frozen=True, eq=False)
class AxisRecords:
    """The records of one axis of a bundle.

    Parameters
    ----------
    name : str
        Axis name [-].
    sweep : SweepRecord
        Servo-excitation record [-].
    friction : FrictionRecord or None
        Constant-velocity runs, when measured [-].
    """

    name: str
    sweep: SweepRecord
    friction: FrictionRecord | None = None
