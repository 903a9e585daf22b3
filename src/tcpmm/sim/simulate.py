"""Drive a machine model with a position command: the virtual machine tool run."""

from __future__ import annotations

import warnings
from concurrent.futures import ThreadPoolExecutor
from contextlib import nullcontext

import numpy as np

from .._threads import limit_blas_threads, usable_cores
from ..analysis.runaway import say_faults
from ..errors import InputError, UnstableLoopWarning
from ..model import Axis, Machine
from ..path.blocktrack import at_times
from ..path.command import UNIFORM_TOL, Command
from ..result import AxisRun, Run
from ..servo.sampled import is_stable_radius, sampled_spectral_radius
from .commandcheck import CommandCheck
from .inputs import kernel_inputs, run_kernel, sensor_datums


def record_every(record_period_s: float | None, cmd_period_s: float, T_v: float) -> int:
    """Velocity-loop steps per record [-]: the record period [s] (default the command
    period [s]) over the velocity-loop period ``T_v`` [s], refused unless a whole number."""
    rp = record_period_s if record_period_s is not None else cmd_period_s
    what = ("the record period" if record_period_s is not None
            else "the record period (by default the command's sample period)")
    if not (np.isfinite(rp) and rp > 0):
        raise InputError(f"{what} must be a positive number of seconds, got {rp}")
    rec_every = round(rp / T_v)
    if rec_every < 1 or abs(rec_every * T_v - rp) > 1e-9 * rp + 1e-12:
        near = max(1, rec_every) * T_v
        raise InputError(
            f"{what}, {rp:g} s, is not a multiple of the velocity-loop period {T_v:g} s; "
            f"give a record period that is, e.g. {near:g} s"
        )
    return rec_every


def command_steps(time_s: np.ndarray, T_v: float) -> tuple[float, int]:
    """The command's sample period and the velocity-loop steps its samples span.

    A period a whole number of steps long, to within what a command takes as uniform
    (:data:`~tcpmm.path.command.UNIFORM_TOL`), is taken as exactly that many steps. The
    difference of two clock times (5.001 - 5.0 s) rounds a hair off the period; the step
    that maps to a sample's index then falls a hair short of it and takes the sample
    before, and with a segment feed-forward the velocity of the segment before for half
    of every sample: the same command would simulate differently by where its time
    starts.

    Parameters
    ----------
    time_s : ndarray
        Command sample times, uniform [s].
    T_v : float
        Velocity-loop period [s].

    Returns
    -------
    tuple of (float, int)
        Period [s] and number of steps [-].
    """
    T_c = float(time_s[1] - time_s[0])
    mean = float(time_s[-1] - time_s[0]) / (time_s.size - 1)
    per = round(mean / T_v)
    if per >= 1 and abs(per * T_v - mean) <= UNIFORM_TOL * mean:
        return per * T_v, (time_s.size - 1) * per + 1
    return T_c, int(np.floor((time_s[-1] - time_s[0]) / T_v + 1e-9)) + 1


def simulate_axis(axis: Axis, time_s, position_m, *, excitation_A=None, open_loop=False,
                  record_period_s=None, quantise_feedback=True, x_start=None) -> AxisRun:
    """Simulate one axis driven by a position command.

    Parameters
    ----------
    axis : Axis
        The axis [SI].
    time_s : ndarray
        Command sample times, uniform [s].
    position_m : ndarray
        Position command [m]; fine-interpolated linearly to the velocity-loop rate.
    excitation_A : ndarray, optional
        Current injected into the current command, sampled at ``time_s`` and held [A].
    open_loop : bool
        Torque mode (loops open): the current command is the excitation alone [-].
    record_period_s : float, optional
        Output period, a multiple of the velocity-loop period; default the command
        period [s].
    quantise_feedback : bool
        Quantise the feedback sensors to their resolution [-].
    x_start : float, optional
        Initial position, default the first command sample [m].
    """
    limit_blas_threads()
    t = np.asarray(time_s, dtype=float)
    T_v = axis.servo.T_v
    T_c, n = command_steps(t, T_v)
    rec_every = record_every(record_period_s, T_c, T_v)
    pos = np.ascontiguousarray(position_m, dtype=float)
    if excitation_A is None:
        exc = np.zeros(t.size)
    else:
        exc = np.ascontiguousarray(excitation_A, dtype=float)
        if exc.shape != t.shape:
            raise InputError(f"{exc.size} excitation samples for {t.size} command samples; "
                             "give one excitation value per command sample")
    rec, _ = run_kernel(kernel_inputs(axis, pos, exc, T_c, n, x_start=x_start,
                                      open_loop=open_loop, rec_every=rec_every,
                                      quantise_feedback=quantise_feedback))
    if excitation_A is None:
        exc_rec = np.zeros(rec.shape[1])
    else:
        t_rec = np.arange(rec.shape[1]) * (rec_every * T_v)
        exc_rec = exc[np.minimum((t_rec / T_c + 1e-9).astype(np.int64), t.size - 1)]
    return records_run(rec, sensor_datums(axis), exc_rec)


def records_run(rec, datums: tuple, excitation) -> AxisRun:
    """The kernel's record as the signals of a run, the sensors read from their ``datums``
    (:func:`~tcpmm.sim.inputs.sensor_datums`), with the ``excitation`` recorded [SI]."""
    d_motor, d_scale, d_tcp = datums
    return AxisRun(
        cmd=rec[6], motor=rec[5] - d_motor, scale=rec[1] - d_scale, tcp=rec[2] - d_tcp,
        current=rec[4], motor_angle=rec[0], motor_speed=rec[3], excitation=excitation,
        current_peak=rec[7],
    )


def _unstable_radii(machine: Machine, names=None) -> dict:
    """Of the axes ``names`` (all when omitted), the spectral radius of each whose sampled
    position loop is unstable [-]."""
    radii = {}
    for name in machine.axes if names is None else names:
        a = machine.axes[name]
        rho = sampled_spectral_radius(a.mechanics, a.servo)
        if not is_stable_radius(rho):
            radii[name] = rho
    return radii


def unstable_loops(machine: Machine, names=None) -> list[str]:
    """Of the axes ``names`` (all when omitted), each whose sampled position loop is
    unstable, in words: a run of it diverges, so its figures are no prediction [-].

    Parameters
    ----------
    machine : Machine
        The model [SI].
    names : iterable of str, optional
        The axes judged [-].
    """
    return [f"axis {name}: its sampled position loop is unstable (spectral radius "
            f"{rho:.4g})" for name, rho in _unstable_radii(machine, names).items()]


def check_stability(machine: Machine) -> None:
    """Warn of each axis whose sampled servo loop is unstable (from :func:`simulate`)."""
    for name, rho in _unstable_radii(machine).items():
        warnings.warn(f"axis {name}: the sampled servo loop is unstable (spectral radius "
                      f"{rho:.4f}); the run is not a meaningful prediction: check the "
                      "gains (tcpmm machine show)", UnstableLoopWarning, stacklevel=3)


def _run_axes(one, names: list, threads: int | None, progress) -> dict:
    """``{name: one(name)}`` for the axes ``names``, in ``threads`` threads (default one
    per axis up to the cores), calling ``progress(name, done, total)`` after each [-]."""
    runs = {}
    # The kernel releases the GIL: axes run in parallel on the available cores.
    n_threads = min(len(names), threads or usable_cores())
    pool = ThreadPoolExecutor(max_workers=n_threads) if n_threads > 1 else nullcontext()
    with pool:
        done = pool.map(one, names) if n_threads > 1 else map(one, names)
        for k, (name, r) in enumerate(zip(names, done, strict=True)):
            runs[name] = r
            if progress is not None:
                progress(name, k + 1, len(names))
    return runs


def _axis_runner(machine, command, rp, quantise_feedback, feed: dict, axis_runs):
    """``one(name)``: the run of axis ``name`` of :func:`simulate`, taken from
    ``axis_runs`` where it keeps it, else run (and kept there) [-]."""

    def one(name):
        axis = machine.axes[name]
        key = (axis, command, feed.get(name), rp, quantise_feedback)
        kept = _kept_run(axis_runs, name, key)
        if kept is not None:
            return kept
        pos = command.positions.get(name, np.zeros_like(command.time_s))
        run = simulate_axis(axis, command.time_s, pos, record_period_s=rp,
                            quantise_feedback=quantise_feedback, excitation_A=feed.get(name))
        if axis_runs is not None:
            axis_runs[name] = (key, run)
        return run

    return one


def _kept_run(axis_runs: dict | None, name: str, key: tuple):
    """The run of axis ``name`` that ``axis_runs`` keeps for ``key`` (axis, command and
    feed-forward: the same objects; record period and quantisation: equal), else None."""
    kept = axis_runs.get(name) if axis_runs is not None else None
    if kept is None:
        return None
    was, run = kept
    same = all(a is b for a, b in zip(was[:3], key[:3], strict=True)) and was[3:] == key[3:]
    return run if same else None


def refuse_one_record(record_period_s: float, duration_s: float | None = None) -> None:
    """Refuse a record period longer than the run (of ``duration_s``; None: a stream that
    recorded one sample): its file would hold the first sample alone, which every reader
    of a run refuses [-].

    Parameters
    ----------
    record_period_s : float
        The record period asked for [s].
    duration_s : float, optional
        The run's duration; None where a stream recorded one sample [s].
    """
    if duration_s is not None and not record_period_s > duration_s:
        return
    how_long = f" ({duration_s:.6g} s)" if duration_s is not None else ""
    raise InputError(f"the record period, {record_period_s:g} s, is longer than the run"
                     f"{how_long}: it would record the first sample alone, and a run needs "
                     "two or more; give a shorter record period")


def simulate(machine: Machine, command: Command, *, record_period_s=None, progress=None,
             quantise_feedback=True, threads: int | None = None,
             current_feedforward_A: dict | None = None, axis_runs: dict | None = None) -> Run:
    """Run the machine model on a position command, every axis of the model.

    Axes of the model that the command does not name hold position 0.

    Parameters
    ----------
    machine : Machine
        The machine model [SI].
    command : Command
        Interpolated position command [m].
    record_period_s : float, optional
        Output period, default the interpolation period [s].
    progress : callable, optional
        Called with ``(axis_name, done, total)`` after each axis [-].
    quantise_feedback : bool
        Quantise the feedback sensors to their resolution [-].
    threads : int, optional
        Axes run at once, in threads; default one per axis up to the cores. A process
        that is one of several on the same cores (a sweep's worker) runs them in turn [-].
    current_feedforward_A : dict of str to ndarray, optional
        Per axis a current added to its current command, one value per command sample and
        held, as a drive adds a friction compensation's feed-forward [A].
    axis_runs : dict, optional
        Where the axes' runs are kept, by name, with what they were run on: an axis
        found there run on this very command and axis (the same objects) with these
        settings is taken as it is, not run again; the others are run and kept. Give the
        same dict to the runs of machines that share axes (variants of one axis) [-].

    Warns
    -----
    InputWarning
        A command beyond any machine's travel or rapid traverse (:mod:`.commandcheck`).
    RunFaultWarning
        An axis whose sampled loop is unstable (:class:`UnstableLoopWarning`), or
        that ran away from its command or saturated its current
        (:mod:`tcpmm.analysis.runaway`); the faults are also in ``run.meta["faults"]``.
    """
    check = CommandCheck(machine)
    check.add(command.time_s, command.positions)
    rp = record_period_s if record_period_s is not None else command.period_s
    refuse_one_record(rp, float(command.time_s[-1] - command.time_s[0]))
    check.warn()
    check_stability(machine)

    one = _axis_runner(machine, command, rp, quantise_feedback, current_feedforward_A or {},
                       axis_runs)
    runs = _run_axes(one, list(machine.axes), threads, progress)
    n = min(r.cmd.size for r in runs.values())
    runs = {k: r.truncated(n) for k, r in runs.items()}
    time = command.time_s[0] + np.arange(n) * rp
    meta = {k: v for k, v in command.meta.items() if k not in ("nc_line", "rapid")}
    blocks = command.blocks()
    if blocks is not None:  # a program's: the block of each record's command
        blocks = at_times(time, float(command.time_s[0]), command.period_s, blocks)
    run = Run(time, runs, {**meta, "machine": machine.name}, *(blocks or ()))
    say_faults(machine, run)
    return run
