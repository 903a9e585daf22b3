"""Virtual measurements: what the sensors of a machine model would record.

Used by the demo (the paper end to end without a machine) and by the known-answer tests
(simulate, identify, recover the parameters).
"""

from __future__ import annotations

import numpy as np

from .._validate import count, nonnegative_number
from ..errors import InputError
from ..ident.excitation import log_sweep
from ..io.bundle import write_bundle
from ..io.bundle_schema import MachineConfig
from ..io.records import FrictionRecord, SweepRecord
from ..model import Axis, Machine
from ..result import Run
from ..sim.simulate import simulate, simulate_axis


def quantise(x, q):
    """Round to the sensor resolution ``q`` (0: ideal) [same unit as x]."""
    return np.round(x / q) * q if q > 0 else np.asarray(x, dtype=float)


def virtual_sweep(axis: Axis, duration_s: float = 12.0, band_hz=(5.0, 1500.0),
                  amplitude_A: float = 2.0, travel_speed_m_per_s: float = 0.02,
                  noise_m: float = 2e-8, seed: int = 0, name: str = "X",
                  open_loop: bool = False) -> SweepRecord:
    """Servo excitation of one axis: a log sweep injected into the current command while
    the axis travels slowly under its own loops, recorded by quantised sensors.

    Parameters
    ----------
    axis : Axis
        The (true) axis [SI].
    duration_s : float
        Record length [s].
    band_hz : tuple
        Sweep band [Hz].
    amplitude_A : float
        Sweep amplitude [A].
    travel_speed_m_per_s : float
        Constant travel speed during the sweep, keeps friction out of stiction [m/s].
    noise_m : float
        RMS white noise added to the TCP device [m].
    seed : int
        Random seed [-].
    name : str
        Axis name [-].
    open_loop : bool
        Torque mode instead of closed loops [-].
    """
    T_v = axis.servo.T_v
    fs = 1.0 / T_v
    exc = log_sweep(band_hz[0], band_hz[1], amplitude_A, duration_s, fs, taper_s=0.05)
    t = exc.time_s
    cmd = travel_speed_m_per_s * t
    r = simulate_axis(axis, t, cmd, excitation_A=exc.signal_A, open_loop=open_loop,
                      record_period_s=T_v)
    rng = np.random.default_rng(seed)
    s = axis.sensors
    return SweepRecord.from_arrays(
        t, exc.signal_A, r.current, quantise(r.motor_angle, s.encoder_quantum),
        quantise(r.scale, s.scale_resolution),
        quantise(r.tcp + noise_m * rng.standard_normal(t.size), s.tcp_resolution),
        source=f"virtual sweep of axis {name}", axis=name)


def virtual_run(machine: Machine, command, noise_m: float = 2e-8, seed: int = 1) -> Run:
    """A measured run of the (true) machine: sensors quantised, TCP device noisy.

    Parameters
    ----------
    machine : Machine
        The machine measured [SI].
    command : Command
        Position command of the run [m].
    noise_m : float
        Standard deviation of the TCP device's noise, before its quantisation, 0 or more
        [m].
    seed : int
        Seed of the noise, 0 or more [-].

    Returns
    -------
    Run
        Encoder, scale and TCP as the sensors read them [SI].
    """
    noise_m = nonnegative_number("noise_m", noise_m, "m")
    rng = np.random.default_rng(count("seed", seed))
    run = simulate(machine, command)
    for name, a in run.axes.items():
        s = machine.axes[name].sensors
        a.motor = quantise(a.motor_angle, s.encoder_quantum) * machine.axes[name].mechanics.R_L
        a.scale = quantise(a.scale, s.scale_resolution)
        a.tcp = quantise(a.tcp + noise_m * rng.standard_normal(a.tcp.size), s.tcp_resolution)
    run.meta["virtual"] = True
    return run


#: Plateau speeds of the virtual friction runs [m/s]: from a quarter of the Stribeck
#: velocity of the built-in machine up, so that the Stribeck curve is determined, and round
#: speeds times 1.0618, so that the advance per 1 ms sample is not a whole number of 1 um
#: sensor steps and the quantisation of encoder and scale averages out on each plateau (at
#: whole numbers every sample rounds alike and the sub-micrometre nut deflection is lost).
FRICTION_SPEEDS = tuple(round(v * 1.0618, 7)
                        for v in (0.0005, 0.001, 0.002, 0.005, 0.01, 0.02, 0.05, 0.1))


def virtual_friction(axis: Axis, speeds_m_per_s=FRICTION_SPEEDS,
                     plateau_s: float = 0.6, accel_m_per_s2: float = 1.0,
                     name: str = "X") -> FrictionRecord:
    """Slow back-and-forth runs at constant speeds under the axis's own loops
    (``friction.csv``), recorded by quantised sensors.

    Parameters
    ----------
    axis : Axis
        The (true) axis [SI].
    speeds_m_per_s : tuple
        Plateau speeds, each run forward then back [m/s].
    plateau_s : float
        Duration of each constant-speed plateau [s].
    accel_m_per_s2 : float
        Acceleration between plateaus [m/s^2].
    name : str
        Axis name [-].
    """
    T = 1e-3
    v_prof = [0.0]
    for v in speeds_m_per_s:
        for target in (v, -v):
            ramp = int(np.ceil(abs(target - v_prof[-1]) / accel_m_per_s2 / T))
            v_prof += list(np.linspace(v_prof[-1], target, ramp + 1)[1:])
            v_prof += [target] * int(plateau_s / T)
    v_prof += list(np.linspace(v_prof[-1], 0.0, 50)[1:]) + [0.0] * 100
    v_prof = np.asarray(v_prof)
    t = np.arange(v_prof.size) * T
    x = np.concatenate([[0.0], np.cumsum(0.5 * (v_prof[1:] + v_prof[:-1])) * T])
    r = simulate_axis(axis, t, x)
    s = axis.sensors
    return FrictionRecord.from_arrays(t, r.current, quantise(r.motor_angle, s.encoder_quantum),
                                      quantise(r.scale, s.scale_resolution),
                                      source=f"virtual friction runs of axis {name}", axis=name)


def bundle_machine_yaml(machine: Machine, axes) -> dict:
    """The ``machine.yaml`` a user would write for these axes of a machine model."""
    out = {"format": "tcpmm-bundle/1", "name": machine.name, "axes": {}}
    for name in axes:
        a = machine.axes[name]
        s, sen = a.servo, a.sensors
        out["axes"][name] = {
            "lead_mm": a.mechanics.lead * 1e3,
            "torque_constant_Nm_per_A": a.mechanics.K_tc,
            "servo": {
                "position_feedback": s.position_feedback,
                "position_gain_1_per_s": s.K_pp,
                "velocity_gain_A_s_per_rad": s.K_vp,
                "velocity_integral_gain_A_per_rad": s.K_vi,
                "velocity_feedforward": s.k_ff,
                "position_loop_period_s": s.T_p,
                "velocity_loop_period_s": s.T_v,
                "current_limit_A": s.current_limit,
            },
            "sensors": {
                "encoder_counts_per_rev": sen.encoder_counts_per_rev,
                "scale_resolution_um": sen.scale_resolution * 1e6,
                "tcp_resolution_um": sen.tcp_resolution * 1e6,
            },
        }
        if s.filters:
            out["axes"][name]["servo"]["current_setpoint_filters"] = [
                f.model_dump() for f in s.filters]
    return out


def axis_config(machine: Machine, name: str):
    """The validated configuration of one axis a user would write (``machine.yaml``),
    which identification is given [-]."""
    return MachineConfig.model_validate(bundle_machine_yaml(machine, [name])).axes[name]


def virtual_bundle(machine: Machine, path, axes=("X", "Y"), seed: int = 0):
    """Write the measurement bundle a user would record on this machine: per axis a
    servo-excitation sweep while the axis travels and, with friction, the constant-speed
    friction runs (docs/measure.md).

    Parameters
    ----------
    machine : Machine
        The machine measured [SI].
    path : str or Path
        Bundle folder, created [-].
    axes : tuple of str
        Axes recorded, of the machine's; ``"XY"`` is ``("X", "Y")`` [-].
    seed : int
        Seed of the first axis's excitation, 0 or more; the next axes count on from it [-].

    Returns
    -------
    Path
        The bundle folder [-].
    """
    seed, recs = count("seed", seed), {}
    axes = tuple(axes) if not isinstance(axes, str) else tuple(axes.upper())
    if not axes or (lacks := [a for a in axes if a not in machine.axes]):
        raise InputError(f"axes={axes!r}: the machine has no axis {', '.join(lacks)} (it has "
                         f"{', '.join(machine.axes)}); name some of those" if axes else
                         f"axes: none named; name some of {', '.join(machine.axes)}")
    for k, name in enumerate(axes):
        a = machine.axes[name]
        recs[name] = {"sweep": virtual_sweep(a, name=name, seed=seed + k)}
        if a.friction is not None:
            recs[name]["friction"] = virtual_friction(a, name=name)
    return write_bundle({"machine": bundle_machine_yaml(machine, axes), "axes": recs}, path)
