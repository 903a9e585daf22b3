"""A simulated axis that runs away from its command or holds its current at the drive's
limit: no prediction of a machine's accuracy, but a result to say (a load the drive cannot
hold, a gain of the wrong sign, a current limit far too low), never a run file left to
speak for itself.

An axis *runs away* when its position feedback leaves the command by more than
:func:`runaway_tolerance`: 1 mm, or a hundred times the steady following error its
feed and gains give, whichever is larger (a following error of a well-tuned axis is tens
of micrometres, of one without feedforward a few millimetres at a fast feed). Its current
*saturates* when the current command sits at the limit for more than
:data:`SATURATED_SAMPLES` samples in a row.
"""

from __future__ import annotations

import warnings
from dataclasses import asdict, dataclass

import numpy as np

from ..errors import RunFaultWarning
from ..model import drive_force_limit

#: Samples in a row at the current limit beyond which an axis counts as saturated: a
#: sample or two at a sharp corner's acceleration are the drive's ordinary work [-].
SATURATED_SAMPLES = 5
#: Smallest deviation from the command counted as running away [m].
RUNAWAY_FLOOR_M = 1e-3
#: Multiple of the steady following error counted as running away [-].
RUNAWAY_FACTOR = 100.0


@dataclass(frozen=True)
class AxisFault:
    """What went wrong on one axis of a run.

    Parameters
    ----------
    axis : str
        Axis name [-].
    deviation_m : float
        Largest distance of the position feedback from the command; ``inf`` where the
        run left the finite numbers [m].
    runaway_from_s : float or None
        Time it first left the command by more than ``tolerance_m``, or ``None`` [s].
    tolerance_m : float
        Deviation counted as running away (:func:`runaway_tolerance`) [m].
    saturated_s : float
        Time the current command spent at the limit in runs of more than
        :data:`SATURATED_SAMPLES` samples [s].
    saturated_from_s : float or None
        Start of the first such run, or ``None`` [s].
    current_limit_A : float
        The drive's current limit [A].
    """

    axis: str
    deviation_m: float
    runaway_from_s: float | None
    tolerance_m: float
    saturated_s: float
    saturated_from_s: float | None
    current_limit_A: float

    def text(self) -> str:
        """One line naming the axis, the time and the size [-]."""
        parts = []
        if self.runaway_from_s is not None:
            size = ("to non-finite numbers" if not np.isfinite(self.deviation_m)
                    else f"by up to {_length(self.deviation_m)}")
            parts.append(f"leaves the command from t = {self.runaway_from_s:.4g} s, {size} "
                         f"(tolerance {_length(self.tolerance_m)})")
        if self.saturated_from_s is not None:
            parts.append(f"holds its current at the limit of {self.current_limit_A:g} A from "
                         f"t = {self.saturated_from_s:.4g} s, for {self.saturated_s:.4g} s in "
                         "all")
        return (f"axis {self.axis}: " + " and ".join(parts) + "; the run is no prediction "
                "of the machine: check the load force, the gains and the current limit")

    def to_dict(self) -> dict:
        """JSON-ready fields (``inf`` as ``None``), with :meth:`text` [-]."""
        d = asdict(self)
        d["deviation_m"] = d["deviation_m"] if np.isfinite(d["deviation_m"]) else None
        return {**d, "text": self.text()}


def _length(x_m: float) -> str:
    return f"{x_m:.3g} m" if x_m >= 1.0 else f"{x_m * 1e3:.3g} mm"


def runaway_tolerance(servo, command_m, period_s: float) -> float:
    """Deviation from the command beyond which an axis counts as running away.

    Parameters
    ----------
    servo : ServoParams
        The axis's servo (``K_pp``, ``k_ff``) [SI].
    command_m : ndarray
        Position command [m].
    period_s : float
        Its sample period [s].

    Returns
    -------
    float
        The larger of :data:`RUNAWAY_FLOOR_M` and :data:`RUNAWAY_FACTOR` times the steady
        following error at the command's top speed, ``v (1 - k_ff) / K_pp`` [m].
    """
    cmd = np.asarray(command_m, dtype=float)
    step = float(np.max(np.abs(np.diff(cmd)))) if cmd.size > 1 else 0.0
    return tolerance_at_step(servo, step, period_s)


def tolerance_at_step(servo, step_m: float, period_s: float) -> float:
    """:func:`runaway_tolerance` of a command whose largest step between two samples is
    ``step_m`` [m], sampled every ``period_s`` [s]; the tolerance [m]."""
    v = step_m / period_s
    lag = v * abs(1.0 - servo.k_ff) / servo.K_pp if servo.K_pp > 0 else np.inf
    return max(RUNAWAY_FLOOR_M, RUNAWAY_FACTOR * lag if np.isfinite(lag) else 0.0)


def _longest_runs(mask, min_len: int):
    """Start indices and lengths of the runs of ``True`` longer than ``min_len`` [-]."""
    m = np.concatenate([[False], np.asarray(mask, dtype=bool), [False]])
    edges = np.flatnonzero(np.diff(m.astype(np.int8)))
    starts, ends = edges[::2], edges[1::2]
    keep = ends - starts > min_len
    return starts[keep], (ends - starts)[keep]


def axis_fault(name: str, axis, time_s, run) -> AxisFault | None:
    """The fault of one simulated axis, or ``None`` where it followed its command.

    Parameters
    ----------
    name : str
        Axis name [-].
    axis : Axis
        The axis simulated [SI].
    time_s : ndarray
        The run's sample times [s].
    run : AxisRun
        Its signals [SI].
    """
    t = np.asarray(time_s, dtype=float)
    if t.size < 2 or run.cmd is None:
        return None
    s = axis.servo
    fb = run.motor if s.position_feedback == "encoder" else run.scale
    fb = run.tcp if fb is None else fb
    tol = runaway_tolerance(s, run.cmd, float(t[1] - t[0]))
    dev = np.abs(np.asarray(fb, dtype=float) - run.cmd) if fb is not None else np.zeros(t.size)
    dev = np.where(np.isfinite(dev), dev, np.inf)
    away = np.flatnonzero(dev > tol)
    sat_starts, sat_lens = np.array([], int), np.array([], int)
    if run.current is not None:
        cur = np.abs(np.asarray(run.current, dtype=float))
        sat_starts, sat_lens = _longest_runs(cur >= s.current_limit * (1 - 1e-9),
                                             SATURATED_SAMPLES)
    if not away.size and not sat_starts.size:
        return None
    dt = float(t[1] - t[0])
    return AxisFault(name, float(np.max(dev)), float(t[away[0]]) if away.size else None, tol,
                     float(np.sum(sat_lens) * dt),
                     float(t[sat_starts[0]]) if sat_starts.size else None,
                     float(s.current_limit))


def run_faults(machine, run) -> list[AxisFault]:
    """The faults of a simulated run, one per axis that has any (:func:`axis_fault`).

    Parameters
    ----------
    machine : Machine
        The model simulated [SI].
    run : Run
        Its run [SI].
    """
    faults = []
    for name, a in run.axes.items():
        if name in machine.axes:
            f = axis_fault(name, machine.axes[name], run.time_s, a)
            if f is not None:
                faults.append(f)
    return faults


def say_faults(machine, run) -> list[AxisFault]:
    """Find the faults of a simulated run, keep them in ``run.meta["faults"]`` and warn
    once per axis (:class:`tcpmm.errors.RunFaultWarning`); returns them.

    Parameters
    ----------
    machine : Machine
        The model simulated [SI].
    run : Run
        Its run, whose ``meta`` is updated [SI].
    """
    faults = run_faults(machine, run)
    run.meta["faults"] = [f.to_dict() for f in faults]
    warn_faults(faults, stacklevel=4)
    return faults


def warn_faults(faults, stacklevel: int = 3) -> None:
    """Warn once per fault (:class:`tcpmm.errors.RunFaultWarning`), at the caller's
    caller by default [-]."""
    for f in faults:
        warnings.warn(f.text(), RunFaultWarning, stacklevel=stacklevel)


def unheld_loads(machine) -> dict:
    """The axes whose load force alone takes more current standing still than the drive
    gives, the load force above :func:`tcpmm.model.drive_force_limit`: no gain or feed
    brings their current within its limit; per such axis ``(load force [N], that current [A], the
    limit [A])``.

    Parameters
    ----------
    machine : Machine
        The model [SI].
    """
    out = {}
    for name, axis in machine.axes.items():
        force, limit = abs(axis.mechanics.load_force), drive_force_limit(axis)
        if force > limit:
            amps = axis.servo.current_limit
            out[name] = (float(axis.mechanics.load_force), amps * force / limit, float(amps))
    return out


def unheld_words(unheld: dict) -> list[str]:
    """A sentence per axis of :func:`unheld_loads` [-]."""
    return [f"axis {n} cannot hold its load standing still: its load force of {f:.4g} N "
            f"takes {a:.3g} A, above its current limit of {lim:g} A, whatever its gains and "
            "feed; check current_limit and load_force" for n, (f, a, lim) in unheld.items()]

