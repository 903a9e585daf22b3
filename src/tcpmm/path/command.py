"""The interpolated position command: what the CNC sends to the drives."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError

#: Largest departure of a command's sample interval from their mean, relative to it, that
#: is taken as uniform sampling: a clock time's rounding in a text file, not a gap [-].
UNIFORM_TOL = 1e-6


@dataclass(frozen=True)
class Command:
    """Position command per axis, sampled uniformly at the interpolation period.

    Parameters
    ----------
    time_s : ndarray
        Sample times, uniform, starting anywhere [s].
    positions : dict of str to ndarray
        Commanded position per axis name (upper case, e.g. ``"X"``), same length as
        ``time_s`` [m].
    meta : dict
        Free-form description of how the command was made (e.g. circle radius [m],
        centre [m], direction) used by analysis and reports [-].
    """

    time_s: np.ndarray
    positions: dict[str, np.ndarray]
    meta: dict = field(default_factory=dict)

    def __post_init__(self):
        t = np.asarray(self.time_s, dtype=float)
        if t.ndim != 1 or t.size < 2:
            raise InputError("a command needs at least two samples in time")
        dt = np.diff(t)
        if not np.all(np.isfinite(t)) or np.any(dt <= 0):
            raise InputError("command time must be finite and strictly increasing")
        if np.max(np.abs(dt - dt.mean())) > UNIFORM_TOL * dt.mean() + 1e-12:
            raise InputError("command time must be uniformly sampled")
        pos = {}
        for name, p in self.positions.items():
            p = np.asarray(p, dtype=float)
            if p.shape != t.shape:
                raise InputError(
                    f"axis {name}: {p.size} positions for {t.size} time samples", column=name
                )
            if not np.all(np.isfinite(p)):
                raise InputError(f"axis {name}: positions must be finite", column=name)
            pos[name.upper()] = p
        object.__setattr__(self, "time_s", t)
        object.__setattr__(self, "positions", pos)

    @property
    def period_s(self) -> float:
        """Interpolation period [s]."""
        return float((self.time_s[-1] - self.time_s[0]) / (self.time_s.size - 1))

    @property
    def axes(self) -> list[str]:
        """Axis names in order [-]."""
        return list(self.positions)

    def blocks(self) -> tuple | None:
        """A program's command: the NC line and the rapid flag of each sample
        (``meta["nc_line"]``, ``meta["rapid"]``, :mod:`tcpmm.path.blocktrack`); ``None``
        where it has them not for every sample (a command made from another of other
        samples keeps that one's meta, not its blocks) [-]."""
        got = [self.meta.get(c) for c in ("nc_line", "rapid")]
        if any(v is None or np.shape(v) != self.time_s.shape for v in got):
            return None
        return tuple(np.asarray(v) for v in got)

    def velocity(self, axis: str) -> np.ndarray:
        """Commanded axis velocity by central differences [m/s]."""
        return np.gradient(self.positions[axis.upper()], self.time_s)

    def to_pandas(self):
        """Table with ``time_s`` and one column per axis in mm (command file layout)."""
        import pandas as pd

        data = {"time_s": self.time_s}
        for name, p in self.positions.items():
            data[f"{name.lower()}_mm"] = p * 1e3
        return pd.DataFrame(data)

    def to_dict(self) -> dict:
        """JSON-ready summary: samples, period, duration and the axes' ranges in mm [-]."""
        return {"samples": int(self.time_s.size), "period_s": self.period_s,
                "duration_s": float(self.time_s[-1] - self.time_s[0]),
                "axes": {n: {"min_mm": float(p.min() * 1e3), "max_mm": float(p.max() * 1e3)}
                         for n, p in self.positions.items()}}

    def plot(self, ax=None, path=None):
        """The path in its plane, per-axis position and velocity against time, and the feed
        along the path; the figure.

        Parameters
        ----------
        ax : array-like of matplotlib Axes, optional
            Four in row order (path, position, velocity, feed); a new figure when
            omitted [-].
        path : str or Path, optional
            Also save it there (PNG/PDF/SVG) [-].
        """
        from ..plot.path import plot_command

        return plot_command(self, path, ax=ax)


def concatenate(commands: list[Command]) -> Command:
    """Commands one after another on one time line (same period and axes) [-].

    The second starts one period after the last sample of the first; ``meta`` keeps the
    list of the parts' meta under ``"parts"`` with their sample offsets.
    """
    if not commands:
        raise InputError("nothing to concatenate")
    T = commands[0].period_s
    axes = commands[0].axes
    parts, times, pos, offset = [], [], {a: [] for a in axes}, 0
    t0 = commands[0].time_s[0]
    for c in commands:
        if abs(c.period_s - T) > 1e-9 * T or c.axes != axes:
            raise InputError("commands to join need the same period and axes")
        times.append(t0 + (offset + np.arange(c.time_s.size)) * T)
        for a in axes:
            pos[a].append(c.positions[a])
        parts.append({**c.meta, "sample_offset": offset})
        offset += c.time_s.size
    return Command(
        np.concatenate(times), {a: np.concatenate(v) for a, v in pos.items()}, {"parts": parts}
    )
