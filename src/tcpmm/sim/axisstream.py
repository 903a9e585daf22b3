"""The machine model driven by a position command that comes in pieces.

Each axis keeps its kernel's state from one piece to the next (the plant, the loops'
integrator, speed command and counters, the delay line, the encoder history, the
current filters and the friction contacts: ``state``, :mod:`tcpmm.sim.layout`) and the
command samples its fine interpolation and feedforward still need. A piece runs the
velocity-loop steps whose command samples (and the one after, for the feedforward's
slope) are all there; the rest wait for the next piece. The records are those of
:func:`tcpmm.sim.simulate.simulate` on the whole command, to the bit.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .._compiled import run_axis
from ..model import Axis
from ..result import AxisRun
from . import layout as L
from .axishold import HeldCommand, held
from .inputs import kernel_inputs, sensor_datums
from .simulate import record_every, records_run


class AxisStream:
    """One axis of a model run on a command given in pieces.

    Parameters
    ----------
    axis : Axis
        The axis [SI].
    cmd_period_s : float
        Period of the command samples [s].
    record_period_s : float, optional
        Output period, a multiple of the velocity-loop period; default the command
        period [s].
    quantise_feedback : bool
        Quantise the feedback sensors to their resolution [-].
    """

    def __init__(self, axis: Axis, cmd_period_s: float, record_period_s=None,
                 quantise_feedback: bool = True):
        self.axis = axis
        self.T_c = float(cmd_period_s)
        self.rec_every = record_every(record_period_s, self.T_c, axis.servo.T_v)
        self.quantise = quantise_feedback
        self.datums = sensor_datums(axis)
        self.buf = np.zeros(0)  # command samples from index j0 of the whole command on
        self.j0 = 0
        self.step = 0  # next velocity-loop step
        self.inputs = None
        self.x = None
        #: most command samples held at once [-]
        self.most_held = 0
        self.hold = HeldCommand(self.rec_every)

    def push(self, position_m, final: bool = False, last_time_s: float | None = None):
        """Run the steps the command so far allows; their records.

        Parameters
        ----------
        position_m : ndarray
            The next command samples [m].
        final : bool
            The command ends with them [-].
        last_time_s : float, optional
            With ``final``: the time of the last sample less that of the first, which
            sets the number of steps as :func:`~tcpmm.sim.simulate.simulate_axis` does [s].

        Returns
        -------
        AxisRun
            The records of the steps run (none where no step could run) [SI].
        """
        self.buf = np.concatenate([self.buf, np.asarray(position_m, dtype=float)])
        self.most_held = max(self.most_held, self.buf.size)
        n_cmd = self.j0 + self.buf.size
        ratio = self.axis.servo.T_v / self.T_c
        if final:
            stop = int(np.floor(last_time_s / self.axis.servo.T_v + 1e-9)) + 1
        else:
            stop = _steps_until(self.step, ratio, n_cmd - 3)
        if stop <= self.step:
            return self._signals(np.empty((len(L.REC_COLUMNS), 0)))
        rec = self._run(self.step, stop, ratio, n_cmd, final)
        self.step = stop
        # the first sample the next step needs, and the one before for a centred slope
        keep = int(stop * ratio) - 1 - self.j0
        if not final and keep > 0:
            self.buf = self.buf[keep:].copy()
            self.j0 += keep
        return self._signals(rec)

    def _signals(self, rec) -> AxisRun:
        """The records as the signals of a run, no excitation [SI]."""
        return records_run(rec, self.datums, np.zeros(rec.shape[1]))

    def _run(self, first: int, stop: int, ratio: float, n_cmd: int, final: bool):
        """The kernel over steps ``first`` to ``stop - 1`` [SI]."""
        j_first = min(int(first * ratio), n_cmd - 1)
        j_last = n_cmd - 1 if final else int((stop - 1) * ratio) + 1
        lo, hi = j_first - self.j0, j_last - self.j0 + 1
        cmd = np.ascontiguousarray(self.buf[lo:hi])
        vcmd = window_velocity(self.buf, lo, hi, self.j0 + lo == 0, final, n_cmd, self.T_c,
                               self.axis.servo.feedforward)
        if self.inputs is None:
            k = kernel_inputs(self.axis, cmd, np.zeros(cmd.size), self.T_c, 1,
                              rec_every=self.rec_every, quantise_feedback=self.quantise)
            size = L.state_size(k.delay, k.vtaps.size, k.fsec.shape[0])
            self.inputs, self.x = k, k.x0
            self.state = np.zeros(size)
        self.state[L.S_CMD0] = j_first
        k = dataclasses.replace(self.inputs, x0=self.x, cmd=cmd, vcmd=vcmd,
                                excitation=np.zeros(cmd.size), n_steps=stop - first,
                                state=self.state)
        bits = held(cmd, vcmd)
        if bits is None:
            self.hold.reset(None)
            return self._steps(k.as_args(None), first, stop)
        args = k.as_args(None)
        return self.hold.run(bits, lambda a, b: self._steps(args, a, b), first, stop,
                             self._plant, self.state)

    def _plant(self, x=None):
        """The plant state; set to ``x`` where given [SI]."""
        if x is not None:
            self.x = x
        return self.x

    def _steps(self, args: tuple, a: int, b: int) -> np.ndarray:
        """The kernel's records of steps ``a`` to ``b - 1`` on the arguments ``args``
        (:meth:`~tcpmm.sim.inputs.KernelInputs.as_args`) from the present state, which
        it advances [SI]."""
        re = self.rec_every
        rec = np.empty((len(L.REC_COLUMNS), (b + re - 1) // re - (a + re - 1) // re))
        ip = args[7].copy()
        ip[L.IP_N_STEPS] = b - a
        self.x = run_axis(*args[:2], self.x, *args[3:7], ip, rec, *args[9:])
        return rec


def _steps_until(first: int, ratio: float, j_max: int) -> int:
    """The first step from ``first`` on whose command sample ``int(k * ratio)`` is past
    ``j_max`` [-]."""
    if j_max < 0:
        return first
    k = max(first, int(j_max / ratio) - 1)
    while int(k * ratio) <= j_max:
        k += 1
    while k > first and int((k - 1) * ratio) > j_max:
        k -= 1
    return k


def window_velocity(buf, lo: int, hi: int, at_start: bool, final: bool, n_cmd: int,
                    period_s: float, kind: str) -> np.ndarray:
    """Command velocity of the feedforward at samples ``buf[lo:hi]``, as
    :func:`~tcpmm.sim.inputs.command_velocity` gives it on the whole command of ``n_cmd``
    samples: ``buf`` holds the sample after ``hi`` unless ``final`` (``hi`` is the end),
    and the one before ``lo`` unless ``at_start`` (``lo`` is the command's first) [m/s]."""
    v = np.empty(hi - lo)
    inner = hi - 1 if final else hi  # the samples with one after them
    if kind == "centred":
        a = lo + 1 if at_start else lo
        v[a - lo:inner - lo] = (buf[a + 1:inner + 1] - buf[a - 1:inner - 1]) / (2.0 * period_s)
        if at_start:
            v[0] = (buf[lo + 1] - buf[lo]) / period_s
        if final:
            v[-1] = (buf[hi - 1] - buf[hi - 2]) / period_s
        return v
    v[:inner - lo] = np.diff(buf[lo:inner + 1]) / period_s
    if final:
        v[-1] = 0.0 if n_cmd < 3 else (buf[hi - 1] - buf[hi - 2]) / period_s
    return v
