"""In-memory measurement records (SI units), shared by the CSV, TDMS and MAT readers."""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np
import pandas as pd

from tcpmm.errors import InputError
from tcpmm.io.samplechecks import LineOf, check_finite, check_time

#: Fewest samples accepted in a friction record [-].
MIN_FRICTION_SAMPLES = 16
#: The signal a record's field is read from, as the user names it (a map's key, a
#: CSV's column): a message naming the field in metres named no column of any file [-].
SIGNAL = {"scale_m": "scale_mm", "tcp_m": "tcp_mm"}


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
                check_finite(v, SIGNAL.get(name, name), rec.source, line_of)
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
            check_finite(getattr(rec, name), SIGNAL.get(name, name), rec.source, line_of)
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
