"""Drive a machine model with a position command: the virtual machine tool run."""

from __future__ import annotations

import os
import warnings
from concurrent.futures import ThreadPoolExecutor
from contextlib import nullcontext
from typing import NamedTuple

import numpy as np

from ._compiled import run_axis
from ._threads import limit_blas_threads
from .analysis.runaway import say_faults
from .errors import InputError, InputWarning
from .mechanics.friction import friction_params_array
from .mechanics.statespace import (
    discretize_zoh,
    guideway_force_input,
    nut_force_input,
    plant,
    static_equilibrium,
)
from .model import Axis, Machine
from .path.command import Command
from .result import AxisRun, Run
from .servo.currentfilters import biquads
from .servo.sampled import sampled_spectral_radius
from .sim.layout import BED_VELOCITY, NX


class KernelInputs(NamedTuple):
    """Arrays for :func:`tcpmm.sim.kernel.run_axis` (see its docstring)."""

    AdT: np.ndarray
    BdT: np.ndarray
    x0: np.ndarray
    fp: np.ndarray
    ip: np.ndarray
    AdsT: np.ndarray
    BdsT: np.ndarray
    pf_s: np.ndarray
    pf_g: np.ndarray
    vtaps: np.ndarray
    AdgT: np.ndarray
    BdgT: np.ndarray
    fsec: np.ndarray


def axis_kernel_inputs(axis: Axis, x_start: float, open_loop: bool = False, rec_every: int = 1,
                       quantise_feedback: bool = True, cmd_period_s: float | None = None,
                       n_steps: int = 0):
    """Matrices, initial state and parameter vectors of :func:`tcpmm.sim.kernel.run_axis`.

    Parameters
    ----------
    axis : Axis
        The axis [SI].
    x_start : float
        Position held at the start (feedback sensor reads this) [m].
    open_loop : bool
        Torque mode: the current is the excitation alone [-].
    rec_every : int
        Record every N velocity-loop steps [-].
    quantise_feedback : bool
        Quantise encoder and scale feedback to the sensor resolution [-].
    cmd_period_s : float, optional
        Period of the command and excitation arrays, default the velocity-loop period [s].
    n_steps : int
        Velocity-loop steps to run [-].
    """
    m, s, sen, fr = axis.mechanics, axis.servo, axis.sensors, axis.friction
    play = fr.backlash if fr is not None else 0.0
    p = plant(m, s.current_bandwidth_hz)
    n = p.A.shape[0]
    relative = fr is not None and fr.guideway_velocity == "relative"
    B = np.column_stack([p.B, nut_force_input(m, n), guideway_force_input(m, n, relative)])
    Ad, Bd = discretize_zoh(p.A, B, s.T_v)
    x0_mech, i_hold = static_equilibrium(m, x_start, s.position_feedback, play)
    AdT, BdT = np.zeros((NX, NX)), np.zeros((6, NX))
    AdT[:n, :n], BdT[:, :n] = Ad.T, Bd.T
    x0 = np.zeros(NX)
    x0[:10] = x0_mech
    if s.current_bandwidth_hz is not None:
        x0[10] = i_hold
    I0 = i_hold / s.K_vi if s.K_vi > 0 and not open_loop else 0.0
    q = quantise_feedback
    fp = np.array([
        s.K_pp, s.K_vp, s.K_vi, s.k_ff, m.R_L, s.current_limit, s.T_v,
        sen.encoder_quantum if q else 0.0, sen.scale_resolution if q else 0.0,
        I0, 0.0, 0.0, m.load_force, s.T_v / (cmd_period_s or s.T_v), 0.5 * play, m.K_t,
    ])
    n_sub = fr.substeps if fr is not None else 1
    ip = np.array([s.n_pos, s.position_feedback == "scale", s.velocity_feedback == "difference",
                   s.delay_samples, not open_loop, rec_every, n_sub, n_steps,
                   s.feedforward == "segment", BED_VELOCITY if relative else -1, 1],
                  dtype=np.int64)
    AdsT, BdsT = np.zeros((NX, NX)), np.zeros((6, NX))
    AdgT, BdgT = np.zeros((NX, NX)), np.zeros((6, NX))
    if fr is not None:
        Ads, Bds = discretize_zoh(p.A, B, s.T_v / n_sub)
        AdsT[:n, :n], BdsT[:, :n] = Ads.T, Bds.T
    if play > 0.0:  # inside the play: the nut force cancelled by state feedback
        A_gap = p.A - np.outer(B[:, 4], p.output_row("F_t"))
        Adg, Bdg = discretize_zoh(A_gap, B, s.T_v / n_sub)
        AdgT[:n, :n], BdgT[:, :n] = Adg.T, Bdg.T
    pf_s = friction_params_array(fr.screw if fr is not None else None)
    pf_g = friction_params_array(fr.guideway if fr is not None else None)
    vtaps = np.asarray(s.velocity_filter, dtype=float)
    fsec = biquads(s.filters, s.T_v)
    return KernelInputs(AdT, BdT, x0, fp, ip, AdsT, BdsT, pf_s, pf_g, vtaps, AdgT, BdgT, fsec)


def command_velocity(position_m, period_s: float, kind: str = "segment") -> np.ndarray:
    """Command velocity of the feedforward at the command samples.

    Parameters
    ----------
    position_m : ndarray
        Position command, uniformly sampled [m].
    period_s : float
        Command period [s].
    kind : {"segment", "centred"}
        ``segment``: the slope of the segment that starts at each sample, held over it
        (what a drive fed interpolated commands knows); ``centred``: the centred
        difference, which looks half a period ahead [-].

    Returns
    -------
    numpy.ndarray
        Velocity per sample [m/s].
    """
    pos = np.asarray(position_m, dtype=float)
    if pos.size < 2:
        return np.zeros(pos.size)
    if kind == "centred":
        return np.gradient(pos, period_s)
    v = np.empty(pos.size)
    v[:-1] = np.diff(pos) / period_s
    v[-1] = 0.0 if pos.size < 3 else v[-2]
    return v


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
    s = axis.servo
    t = np.asarray(time_s, dtype=float)
    T_v = s.T_v
    rp = record_period_s if record_period_s is not None else float(t[1] - t[0])
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
    n = int(np.floor((t[-1] - t[0]) / T_v + 1e-9)) + 1
    T_c = float(t[1] - t[0])
    pos = np.ascontiguousarray(position_m, dtype=float)
    vel = command_velocity(pos, T_c, s.feedforward)
    if excitation_A is None:
        exc = np.zeros(t.size)
    else:
        exc = np.ascontiguousarray(excitation_A, dtype=float)
        if exc.shape != t.shape:
            raise InputError(f"{exc.size} excitation samples for {t.size} command samples; "
                             "give one excitation value per command sample")
    x_start = pos[0] if x_start is None else x_start
    k = axis_kernel_inputs(axis, x_start, open_loop, rec_every, quantise_feedback, T_c, n)
    rec = np.empty((7, (n - 1) // rec_every + 1))
    run_axis(k.AdT, k.BdT, k.x0, pos, vel, exc, k.fp, k.ip, rec, k.AdsT, k.BdsT, k.pf_s,
             k.pf_g, k.vtaps, k.AdgT, k.BdgT, k.fsec)
    if excitation_A is None:
        exc_rec = np.zeros(rec.shape[1])
    else:
        t_rec = np.arange(rec.shape[1]) * (rec_every * T_v)
        exc_rec = exc[np.minimum((t_rec / T_c + 1e-9).astype(np.int64), t.size - 1)]
    return AxisRun(
        cmd=rec[6], motor=rec[5], scale=rec[1], tcp=rec[2], current=rec[4],
        motor_angle=rec[0], motor_speed=rec[3], excitation=exc_rec,
    )


#: Speed above which a command is taken as a unit or sampling error when the model has no
#: rapid traverse of its own (300 m/min, beyond the feed axes of machine tools) [m/s].
SPEED_LIMIT_M_PER_S = 5.0


#: Position beyond which a command is taken as a unit error: the travel of the largest
#: gantry and floor-type machine tools is some tens of metres [m].
TRAVEL_LIMIT_M = 100.0


def _check_speeds(machine: Machine, command: Command) -> None:
    """Warn when the command moves an axis faster than the machine can, or to a position no
    machine tool reaches (:data:`TRAVEL_LIMIT_M`).

    The limit is 1.05 times the rapid traverse of the model's interpolation settings, or
    :data:`SPEED_LIMIT_M_PER_S` when it has none.
    """
    from .path.settings import AXES, InterpolatorSettings

    rapid = {}
    settings = InterpolatorSettings.model_validate(machine.interpolation or {})
    if "rapid_m_per_s" in settings.model_fields_set:  # not the interpolator's default
        rapid = dict(zip(AXES, settings.rapid(), strict=True))
    t = np.asarray(command.time_s, dtype=float)
    for name, pos in command.positions.items():
        far = float(np.max(np.abs(pos))) if pos.size else 0.0
        if far > TRAVEL_LIMIT_M:
            warnings.warn(
                f"axis {name}: the command goes to {far * 1e3:.4g} mm, beyond the travel of "
                f"any machine tool ({TRAVEL_LIMIT_M * 1e3:.4g} mm); check the command's units "
                "(mm)", InputWarning, stacklevel=3)
        if pos.size < 2:
            continue
        v = np.abs(np.diff(pos)) / np.diff(t)
        k = int(np.argmax(v))
        limit = rapid.get(name, max(rapid.values(), default=None))
        bound = SPEED_LIMIT_M_PER_S if limit is None else 1.05 * float(limit)
        if v[k] > bound:
            what = ("the rapid traverse of the model's interpolation settings"
                    if limit is not None else "any machine-tool feed axis")
            warnings.warn(
                f"axis {name}: the command moves at {v[k] * 60:.4g} m/min at "
                f"t = {t[k]:.6g} s, faster than {what} ({bound * 60:.4g} m/min); "
                "check the command's units (mm) and sampling", InputWarning, stacklevel=3)


def simulate(machine: Machine, command: Command, *, record_period_s=None, progress=None,
             quantise_feedback=True, threads: int | None = None) -> Run:
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

    Warns
    -----
    InputWarning
        An axis whose sampled loop is unstable, or a command faster than the machine's
        rapid traverse (see :func:`_check_speeds`).
    RunFaultWarning
        An axis that ran away from its command or saturated its current
        (:mod:`tcpmm.analysis.runaway`); the faults are also in ``run.meta["faults"]``.
    """
    unknown = [a for a in command.axes if a not in machine.axes]
    if unknown:
        raise InputError(
            f"the command drives axis {', '.join(unknown)} that the machine does not have "
            f"(machine axes: {', '.join(machine.axes)})"
        )
    rp = record_period_s if record_period_s is not None else command.period_s
    names = list(machine.axes)
    _check_speeds(machine, command)
    for name in names:
        a = machine.axes[name]
        rho = sampled_spectral_radius(a.mechanics, a.servo)
        if rho >= 1.0:
            warnings.warn(f"axis {name}: the sampled servo loop is unstable (spectral radius "
                          f"{rho:.4f}); the run is not a meaningful prediction: check the "
                          "gains (tcpmm machine show)", InputWarning, stacklevel=2)

    def one(name):
        pos = command.positions.get(name, np.zeros_like(command.time_s))
        return simulate_axis(machine.axes[name], command.time_s, pos, record_period_s=rp,
                             quantise_feedback=quantise_feedback)

    runs = {}
    # The kernel releases the GIL: axes run in parallel on the available cores.
    n_threads = min(len(names), threads or os.cpu_count() or 1)
    pool = ThreadPoolExecutor(max_workers=n_threads) if n_threads > 1 else nullcontext()
    with pool:
        done = pool.map(one, names) if n_threads > 1 else map(one, names)
        for k, (name, r) in enumerate(zip(names, done, strict=True)):
            runs[name] = r
            if progress is not None:
                progress(name, k + 1, len(names))
    n = min(r.cmd.size for r in runs.values())
    runs = {k: r.truncated(n) for k, r in runs.items()}
    time = command.time_s[0] + np.arange(n) * rp
    run = Run(time_s=time, axes=runs, meta={**command.meta, "machine": machine.name})
    say_faults(machine, run)
    return run
