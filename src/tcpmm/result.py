"""Results of a run: per-axis signals in SI, the run-file table, plots."""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields, replace

import numpy as np

from .io import runwrite
from .io.bytenames import readable

#: Run-file column suffix -> AxisRun field (docs/formats.md section 3), values in mm or A.
RUN_COLUMNS = {"cmd_mm": "cmd", "motor_mm": "motor", "scale_mm": "scale", "tcp_mm": "tcp",
               "current_A": "current"}
#: Run-file columns of the block each sample's command is in, and their types [-].
BLOCK_COLUMNS = {"nc_line": np.int32, "rapid": np.int8}
#: The shares of the path at which the two are compared [-].
_PROGRESS = (0.1, 0.25, 0.5, 0.75, 0.9)
#: A step shorter than this share of a path's median step is rest [-].
_CREEP = 0.05
#: The most the median distance between the run's own command and a command given for
#: it, at the run's times, may be of the largest travel of an axis: a compensated
#: command lies off its program by the error it corrects, a few per cent of the path at
#: most; another program lies off it by the path's own size [-].
_OFF_PATH = 0.1


@dataclass
class AxisRun:
    """Signals of one axis, sampled at the run's times.

    Parameters
    ----------
    cmd : ndarray
        Position command [m].
    motor : ndarray or None
        Motor encoder position expressed at the table, ``th_m * lead / 2pi`` [m].
    scale : ndarray or None
        Linear scale X_LS [m].
    tcp : ndarray or None
        TCP position X_TCP [m].
    current : ndarray or None
        Current command [A].
    motor_angle, motor_speed, excitation : ndarray or None
        Motor angle [rad], motor speed [rad/s], injected excitation [A].
    current_peak : ndarray or None
        Largest size of the current over the velocity-loop steps since the sample
        before, where the run was simulated (a sample every millisecond misses the
        velocity loop's peaks between); not in run files [A].
    """

    cmd: np.ndarray | None
    motor: np.ndarray | None = None
    scale: np.ndarray | None = None
    tcp: np.ndarray | None = None
    current: np.ndarray | None = None
    motor_angle: np.ndarray | None = None
    motor_speed: np.ndarray | None = None
    excitation: np.ndarray | None = None
    current_peak: np.ndarray | None = None

    def truncated(self, n: int) -> AxisRun:
        """The first ``n`` samples."""
        return AxisRun(**{f.name: None if getattr(self, f.name) is None
                          else getattr(self, f.name)[:n] for f in fields(self)})

    def peak_current(self) -> np.ndarray | None:
        """Size of the current per sample: the largest over the steps since the sample
        before where the run has it (a simulated run), else the sampled one's [A]."""
        if self.current_peak is not None:
            return self.current_peak
        return None if self.current is None else np.abs(self.current)

    def sensor(self, name: str) -> np.ndarray | None:
        """Position by sensor name ``cmd``, ``motor``, ``scale`` or ``tcp`` [m]."""
        return getattr(self, name)


def json_ready(data):
    """``data`` with every float that is not finite replaced by ``None``, tuples as lists:
    what ``json.dumps(..., allow_nan=False)`` writes, a missing figure as ``null``, the
    form every result's ``to_dict`` and the command line's ``--json`` share; the
    undecoded bytes of a name in a text decoded (:func:`~tcpmm.io.bytenames.readable`),
    as JSON holds no lone surrogate [-]."""
    if isinstance(data, float):
        return data if math.isfinite(data) else None
    if isinstance(data, str):
        return readable(data)
    if isinstance(data, dict):
        return {json_ready(k): json_ready(v) for k, v in data.items()}
    if isinstance(data, list | tuple):
        return [json_ready(v) for v in data]
    return data


def scalar_meta(meta: dict) -> dict:
    """The entries of a run's or command's meta data that JSON holds as they are (text,
    numbers, none): its arrays and tuples left out [-]."""
    return {k: v for k, v in meta.items() if isinstance(v, (str, int, float, bool, type(None)))}


@dataclass
class Run:
    """A simulated or measured run of several axes.

    Parameters
    ----------
    time_s : ndarray
        Sample times [s].
    axes : dict of str to AxisRun
        Signals per axis [SI].
    meta : dict
        Description (command geometry, machine name, source file) [-].
    nc_line : ndarray of int, optional
        Per sample, the NC program's line of the block its command is in, 0 where none;
        a run made from a program has it (:mod:`tcpmm.path.blocktrack`) [-].
    rapid : ndarray of int, optional
        Per sample, 1 where its command is in a G0 rapid (or a dwell after one), else 0
        [-].
    """

    time_s: np.ndarray
    axes: dict[str, AxisRun]
    meta: dict = field(default_factory=dict)
    nc_line: np.ndarray | None = None
    rapid: np.ndarray | None = None

    def with_command(self, command, window_s: float = 0.2) -> Run:
        """The run with its command signals replaced by ``command`` at the run's times,
        held before its first sample and after its last: a run measured against the
        program it was to follow, where it ran a command compensated for its error. An
        axis the command does not drive keeps the run's own.

        Parameters
        ----------
        command : Command
            The program's command, on the run's time line (``time_s``, ``positions``
            per axis) [s], [m].
        window_s : float
            The time around a sample in which the contour seeks its command: the command
            must reach each share of its path within half of it of the run's own (a
            command planned otherwise is refused) [s].
        """
        from .errors import InputError

        given = command.positions
        if not any(a in given for a in self.axes):
            raise InputError(f"the command drives none of the run's axes "
                             f"({', '.join(self.axes)})")
        _same_timeline(self, command, window_s / 2)
        axes = {a: replace(r, cmd=np.interp(self.time_s, command.time_s, given[a]))
                if a in given else r for a, r in self.axes.items()}
        blocks = (self.nc_line, self.rapid)
        if command.blocks() is not None:
            k = np.clip(np.searchsorted(command.time_s, self.time_s, side="right") - 1, 0,
                        command.time_s.size - 1)
            blocks = tuple(v[k] for v in command.blocks())
        return Run(self.time_s, axes, {**self.meta, "command": "given"}, *blocks)

    def columns(self) -> dict[str, np.ndarray]:
        """The run-file columns (docs/formats.md section 3): ``time_s``, then mm and A, then
        ``nc_line`` and ``rapid`` where the run has them (integers)."""
        data = {"time_s": self.time_s}
        for name, a in self.axes.items():
            for suffix, attr in RUN_COLUMNS.items():
                v = getattr(a, attr)
                if v is not None:
                    data[f"{name.lower()}_{suffix}"] = v * (1.0 if attr == "current" else 1e3)
        for name, dtype in BLOCK_COLUMNS.items():
            v = getattr(self, name)
            if v is not None:
                data[name] = np.asarray(v, dtype)
        return data

    def to_pandas(self):
        """The run-file table (docs/formats.md section 3): mm and A."""
        import pandas as pd

        return pd.DataFrame(self.columns())

    def write_csv(self, path) -> None:
        """Write the run file as CSV, atomically."""
        runwrite.write_run_csv(self, path)

    def write(self, path) -> None:
        """Write the run file, atomically: Parquet for ``.parquet``, else CSV."""
        runwrite.write_run(self, path)

    def to_dict(self) -> dict:
        """JSON-ready summary: samples, duration, axes and the sensors recorded, and the
        axes that ran away or saturated (:mod:`tcpmm.analysis.runaway`) [-]."""
        t = self.time_s
        return {"samples": int(t.size), "duration_s": float(t[-1] - t[0]) if t.size else 0.0,
                "axes": {n: [s for s, attr in RUN_COLUMNS.items() if getattr(a, attr) is not None]
                         for n, a in self.axes.items()},
                "meta": scalar_meta(self.meta),
                "faults": list(self.meta.get("faults", []))}

    def plot(self, ax=None, path=None, axes=None):
        """Time plots of command, motor, scale and TCP following errors per axis; the
        figure.

        Parameters
        ----------
        ax : array-like of matplotlib Axes, optional
            Two per machine axis shown; a new figure when omitted [-].
        path : str or Path, optional
            Also save it there (PNG/PDF/SVG) [-].
        axes : list of str, optional
            Machine axes to show, default all [-].
        """
        from .plot.time import plot_run

        return plot_run(self, path=path, axes=axes, ax=ax)


def _steps(positions: list) -> np.ndarray:
    """Length of each step of a path given by its axes' ``positions`` [m]."""
    return np.sqrt(sum(np.diff(np.asarray(x, float)) ** 2 for x in positions))


def _moving(step) -> np.ndarray:
    """Per step, whether the path moves: steps shorter than :data:`_CREEP` of its median
    one are rest [-]."""
    return step > _CREEP * np.median(step[step > 0])


def _progress_times(time_s, step, moving):
    """When a path of steps ``step`` has covered each share of :data:`_PROGRESS` of its
    length, in its time of motion (the steps not ``moving`` count as rest, neither length
    nor time); and the time it starts to move [s]."""
    length = np.concatenate([[0.0], np.cumsum(np.where(moving, step, 0.0))])
    return (np.interp(np.asarray(_PROGRESS) * length[-1], length,
                      motion_time(time_s, moving)[0]),
            float(time_s[int(np.argmax(moving))]))


def motion_time(time_s, moves):
    """Time at each sample of a command less the time it has rested before it (``moves``:
    per step between samples, whether it moves), never decreasing; and that rest [s]."""
    rest = np.concatenate([[0.0], np.cumsum(np.where(moves, 0.0, np.diff(time_s)))])
    return np.maximum.accumulate(time_s - rest), rest


def _same_timeline(run, command, tol_s: float) -> None:
    """Refuse a command that runs on another time line than the run's own (a program
    planned at other limits, or not the run's program at all): the run's samples would be
    paired with points of the path seconds away; ``tol_s`` half the contour's window [s]."""
    from .errors import InputError

    axes = [a for a, r in run.axes.items() if a in command.positions and r.cmd is not None]
    if not axes:
        return
    own_step = _steps([run.axes[a].cmd for a in axes])
    step = _steps([command.positions[a] for a in axes])
    if not (np.any(own_step > 0) and np.any(step > 0)):
        return
    moving = _moving(step)
    # the given command's rests are the run's too: a compensated command still corrects
    # the tool while the program dwells
    at = np.clip(np.searchsorted(command.time_s, run.time_s[1:], side="left") - 1, 0,
                 moving.size - 1)
    both = _moving(own_step) & moving[at]
    own, own_start = _progress_times(run.time_s, own_step, both)
    theirs, start = _progress_times(command.time_s, step, moving)
    if abs(own_start - start) > tol_s:  # taken at the run's clock, it must start with it
        raise InputError(
            f"the command file is on another time line than the run's own command: it "
            f"starts to move at {start:.3f} s, the run's own at {own_start:.3f} s, and the "
            "contour takes it at the run's times; measure the run against the command it "
            "was planned with (for a compensated command, tcpmm compensate --reference-out "
            "REF.csv writes it)")
    k = int(np.argmax(np.abs(own - theirs)))
    if abs(own[k] - theirs[k]) > tol_s:
        raise InputError(
            f"the command file is on another time line than the run's own command: it has "
            f"covered {_PROGRESS[k]:.0%} of its path after {theirs[k]:.3f} s of motion, the "
            f"run's own after {own[k]:.3f} s, and the contour pairs a sample with the "
            f"command within {2 * tol_s:g} s of it; measure the run against the command it "
            "was planned with (for a compensated command, tcpmm compensate --reference-out "
            "REF.csv writes it), or widen --window-s where the path does not come back near "
            "itself")
    _same_path(run, command, axes, both)


def _same_path(run, command, axes: list, both) -> None:
    """Refuse a command that is not the run's path: at the run's times, where both move
    (``both``, per step), it lies a median distance from the run's own command of more
    than :data:`_OFF_PATH` of the run's largest axis travel."""
    from .errors import InputError

    if not np.any(both):
        return
    t = run.time_s[1:][both]
    own = [run.axes[a].cmd[1:][both] for a in axes]
    given = [np.interp(t, command.time_s, command.positions[a]) for a in axes]
    off = float(np.median(np.sqrt(sum((g - o) ** 2 for g, o in zip(given, own, strict=True)))))
    span = max(float(np.ptp(run.axes[a].cmd)) for a in axes)
    if off > _OFF_PATH * span:
        raise InputError(
            f"the command file is not the run's path: at the run's times it lies "
            f"{off * 1e3:.3g} mm from the run's own command (median), whose largest axis "
            f"travel is {span * 1e3:.3g} mm; measure the run against the program it ran (for "
            "a compensated command, tcpmm compensate --reference-out REF.csv writes it)")
