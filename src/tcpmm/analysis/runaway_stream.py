"""The faults of a run that comes in pieces, as :func:`tcpmm.analysis.runaway.run_faults`
finds them on the whole run, in bounded memory.

Per axis it keeps the command's largest step between samples (which sets the runaway
tolerance), the largest deviation so far, the times at which the deviation set a new
largest while above the tolerance the steps so far give (the first sample beyond the final
tolerance is one of them: the tolerance only grows), and the run of samples at the current
limit still open at the end of a piece.
"""

from __future__ import annotations

import numpy as np

from .runaway import SATURATED_SAMPLES, AxisFault, tolerance_at_step


class _AxisWatch:
    """One axis's figures so far [SI]."""

    def __init__(self, name: str, axis):
        self.name, self.axis = name, axis
        self.last_cmd = None
        self.step = 0.0
        self.dev = -np.inf
        self.peaks: list = []  # (time, deviation) of each new largest above the tolerance
        self.open_len, self.open_t = 0, None  # the run at the limit the last piece ended in
        self.sat_len, self.sat_first = 0, None

    def add(self, t, run, period_s: float) -> None:
        s = self.axis.servo
        cmd = np.asarray(run.cmd, dtype=float)
        if cmd.size:
            joined = cmd if self.last_cmd is None else np.concatenate([[self.last_cmd], cmd])
            if joined.size > 1:
                self.step = max(self.step, float(np.max(np.abs(np.diff(joined)))))
            self.last_cmd = cmd[-1]
        fb = run.motor if s.position_feedback == "encoder" else run.scale
        fb = run.tcp if fb is None else fb
        dev = np.abs(np.asarray(fb, dtype=float) - cmd) if fb is not None else np.zeros(t.size)
        dev = np.where(np.isfinite(dev), dev, np.inf)
        if dev.size:
            tol = tolerance_at_step(s, self.step, period_s)
            self.peaks = [p for p in self.peaks if p[1] > tol]
            most = float(np.max(dev))
            # a piece that sets no new largest above the tolerance adds no peak: its
            # running largest is not needed (most pieces of a long run)
            if most > max(self.dev, tol):
                top = np.maximum.accumulate(dev)
                new = np.flatnonzero(top > np.concatenate([[self.dev], top[:-1]]))
                self.peaks += [(float(t[k]), float(dev[k])) for k in new if dev[k] > tol]
            self.dev = max(self.dev, most)
        if run.current is not None:
            self._saturation(t, np.abs(np.asarray(run.current, dtype=float))
                             >= s.current_limit * (1 - 1e-9))

    def _saturation(self, t, at_limit) -> None:
        """Runs of samples at the current limit, the one open at a piece's end carried."""
        if not at_limit.size:
            return
        if self.open_len and not at_limit[0]:
            self._close(self.open_len, self.open_t)
            self.open_len = 0
        edges = np.flatnonzero(np.diff(np.concatenate([[False], at_limit, [False]])
                                       .astype(np.int8)))
        for a, b in zip(edges[::2].tolist(), edges[1::2].tolist(), strict=True):
            n, t0 = b - a, float(t[a])
            if a == 0 and self.open_len:
                n, t0 = n + self.open_len, self.open_t
                self.open_len = 0
            if b == at_limit.size:
                self.open_len, self.open_t = n, t0
            else:
                self._close(n, t0)

    def _close(self, n: int, t0: float) -> None:
        if n > SATURATED_SAMPLES:
            self.sat_len += n
            self.sat_first = float(t0) if self.sat_first is None else self.sat_first

    def fault(self, period_s: float) -> AxisFault | None:
        if self.open_len:
            self._close(self.open_len, self.open_t)
            self.open_len = 0
        tol = tolerance_at_step(self.axis.servo, self.step, period_s)
        away = next((p[0] for p in self.peaks if p[1] > tol), None)
        if away is None and self.sat_first is None:
            return None
        return AxisFault(self.name, self.dev, away, tol, float(self.sat_len * period_s),
                         self.sat_first, float(self.axis.servo.current_limit))


class FaultWatch:
    """The faults of a machine's run given piece by piece.

    Parameters
    ----------
    machine : Machine
        The model simulated [SI].
    """

    def __init__(self, machine):
        self.machine = machine
        self.axes: dict = {}
        self.period_s = None

    def add(self, run) -> None:
        """Take the next piece of the run (:class:`~tcpmm.result.Run`) [SI]."""
        t = np.asarray(run.time_s, dtype=float)
        if self.period_s is None and t.size >= 2:
            self.period_s = float(t[1] - t[0])
        for name, a in run.axes.items():
            if name in self.machine.axes and a.cmd is not None:
                w = self.axes.setdefault(name, _AxisWatch(name, self.machine.axes[name]))
                w.add(t, a, self.period_s or 1.0)

    def faults(self) -> list[AxisFault]:
        """The faults, one per axis that has any, once the whole run was taken [-]."""
        if self.period_s is None:
            return []
        return [f for w in self.axes.values() if (f := w.fault(self.period_s)) is not None]
