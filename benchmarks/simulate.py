"""Simulator speed, side by side with its peers in one run, on one core.

1. The paper's circle (R35 mm, F5000, CCW then CW, 8.1 s) on the built-in machine, 3 axes
   with friction on screw and guideway, at the servo's own rates (8 kHz velocity loop,
   2 kHz position loop): the compiled kernel's real-time factor (the axes one after the
   other on one thread), and the same without friction.
2. One axis (X), 60 s, at the servo's own rates, against python-control
   ``forced_response`` and scipy ``dlsim`` on their best formulation: the exact lifted
   loop at the 2 kHz position rate (``tcpmm.servo.sampled.lifted_closed_loop``), a linear
   time-invariant system they step once per position-loop period. tcpmm steps the
   velocity loop (4 steps per position step) through ``simulate_axis`` (discretisation
   included), with friction (the headline) and without (the like-for-like check: its
   output is compared with dlsim's).
3. The compute floor: the bare state update ``x' = Ad x + Bd u`` of the kernel's states
   (:data:`tcpmm.sim.layout.NX`), unrolled and carried in registers, compiled by numba as
   the kernel is (LLVM's SLP vectoriser on, no reference counting), with each axis's
   matrices of the circle for the same number of steps, the current command from an
   array. The kernel's time on the circle, with friction and without, is given as a ratio
   to it (``floor_ratio_friction``, ``floor_ratio_linear``): what the servo, the friction
   and the record cost over the arithmetic no simulation of the model can skip.

Every tool is timed the same way: rounds in which each of the six runs once in turn (the
circle's among the peers', interleaved, so that a change of machine load hits all alike
and a slow second of the machine not all the rounds of one tool), min and median over the
rounds. BLAS is limited to one thread. Not a test:
``python benchmarks/simulate.py [--rounds N] [--json] [--clock wall|cpu]``.
"""

from __future__ import annotations

import argparse
import json
import time

import numba
import numpy as np
from numba import njit
from threadpoolctl import threadpool_limits

from tcpmm._compiled import run_axis, status
from tcpmm._pycc import vectorised
from tcpmm.demo import paper_circle_command
from tcpmm.machines.builtin import builtin_machine
from tcpmm.servo.sampled import initial_state, lifted_closed_loop
from tcpmm.sim.inputs import command_velocity, kernel_inputs
from tcpmm.sim.layout import NX
from tcpmm.sim.simulate import simulate_axis

DURATION_S = 60.0


#: The clock the tools are timed with: the wall clock, or this thread's CPU time (on a
#: loaded machine the wall clock also counts the time spent waiting for a core).
CLOCKS = {"wall": time.perf_counter, "cpu": time.thread_time}


def interleaved(tools: dict, rounds: int, clock=time.perf_counter) -> dict:
    """``{name: (min, median, last output)}`` of the tools run in turn, ``rounds`` times."""
    times = {k: [] for k in tools}
    outs = {}
    for _ in range(rounds):
        for name, f in tools.items():
            t0 = clock()
            outs[name] = f()
            times[name].append(clock() - t0)
    return {k: (min(v), float(np.median(v)), outs[k]) for k, v in times.items()}


def circle_inputs(machine):
    """Per axis of ``machine`` for the paper's circle: the axis, its command, the steps the
    kernel takes and the kernel's inputs; and the command's time [s]."""
    cmd = paper_circle_command(machine)
    t = cmd.time_s
    T_c = float(t[1] - t[0])
    axes = []
    for name, ax in machine.axes.items():
        pos = np.ascontiguousarray(cmd.positions.get(name, np.zeros_like(t)))
        n = int(np.floor((t[-1] - t[0]) / ax.servo.T_v + 1e-9)) + 1
        every = round(T_c / ax.servo.T_v)
        axes.append((ax, pos, n, kernel_inputs(ax, pos, np.zeros(t.size), T_c, n,
                                               rec_every=every)))
    return axes, t


def circle_kernel(machine):
    """A function running the kernel on every axis of ``machine`` for the paper's circle,
    one axis after the other; and the circle's duration [s]."""
    axes, t = circle_inputs(machine)
    jobs = [k.as_args(k.empty_record()) for _, _, _, k in axes]

    def run():
        for args in jobs:
            run_axis(*args)

    return run, float(t[-1] - t[0])


@njit(cache=True, nogil=True, _nrt=False)
def _floor_steps(AdT, BdT, x, u):
    """``x' = Ad x + Bd[:, 0] u[k]`` for every ``k``, in place in ``x``: the sums in a
    tuple (registers), each state's column in turn, as the kernel's free step does."""
    for k in range(u.size):
        uk = u[k]
        y = (BdT[0, 0] * uk, BdT[0, 1] * uk, BdT[0, 2] * uk, BdT[0, 3] * uk,
             BdT[0, 4] * uk, BdT[0, 5] * uk, BdT[0, 6] * uk, BdT[0, 7] * uk,
             BdT[0, 8] * uk, BdT[0, 9] * uk, BdT[0, 10] * uk)
        for j in range(NX):
            xj = x[j]
            y = (y[0] + AdT[j, 0] * xj, y[1] + AdT[j, 1] * xj, y[2] + AdT[j, 2] * xj,
                 y[3] + AdT[j, 3] * xj, y[4] + AdT[j, 4] * xj, y[5] + AdT[j, 5] * xj,
                 y[6] + AdT[j, 6] * xj, y[7] + AdT[j, 7] * xj, y[8] + AdT[j, 8] * xj,
                 y[9] + AdT[j, 9] * xj, y[10] + AdT[j, 10] * xj)
        for i in range(NX):
            x[i] = y[i]


def compute_floor(machine):
    """A function running the bare state update on every axis of ``machine`` for as many
    steps as the kernel takes on the paper's circle, with that axis's matrices and a
    current that follows the command; and the number of steps [-]."""
    axes, t = circle_inputs(machine)
    jobs = []
    for ax, pos, n, k in axes:
        AdT, BdT, x0 = k.as_args(k.empty_record())[:3]
        # a current of the order of the kernel's, changing every step: nothing to hoist
        u = np.interp(np.arange(n) * ax.servo.T_v, t - t[0], pos) * 100.0
        jobs.append((AdT, BdT, x0, u))
    with vectorised():
        _floor_steps.compile(tuple(numba.typeof(a) for a in jobs[0]))

    def run():
        for AdT, BdT, x0, u in jobs:
            _floor_steps(AdT, BdT, x0.copy(), u)

    return run, sum(j[3].size for j in jobs)


def peers() -> tuple:
    """One axis at the servo's own rates, tcpmm and the lifted loop in the peers: the
    tools, the number of position steps, and the relative difference of tcpmm's linear
    run from dlsim's given the tools' outputs."""
    import control
    from scipy.signal import dlsim

    lin = builtin_machine(friction=False).axes["X"]
    fric = builtin_machine().axes["X"]
    T_p = lin.servo.T_p
    t = np.arange(0.0, DURATION_S, T_p)
    w = 2 * np.pi * 0.4
    x = 0.035 * (1 - np.cos(w * t))  # starts at rest: stays linear (no saturation)
    v = command_velocity(x, T_p, lin.servo.feedforward)
    Phi, Gam, C, D = lifted_closed_loop(lin.mechanics, lin.servo)
    z0 = initial_state(lin.mechanics, lin.servo, np.zeros(10))
    u = np.column_stack([x, v])
    sys_d = control.ss(Phi, Gam, C, D, T_p)
    kw = dict(record_period_s=T_p, quantise_feedback=False)
    tools = {
        "tcpmm, with friction": lambda: simulate_axis(fric, t, x, **kw),
        "tcpmm, linear": lambda: simulate_axis(lin, t, x, **kw),
        "scipy dlsim": lambda: dlsim((Phi, Gam, C, D, T_p), u, x0=z0)[1],
        "control.forced_response": lambda: control.forced_response(sys_d, T=t, U=u.T, X0=z0),
    }

    def rel_diff(res):
        y_dl = res["scipy dlsim"][2]
        return float(np.max(np.abs(res["tcpmm, linear"][2].scale - y_dl[:, 1]))
                     / np.max(np.abs(y_dl[:, 1])))

    return tools, t.size, rel_diff


def print_figures(out: dict, circ: dict, res: dict, steps: int, n_steps: int) -> None:
    """The figures as text: the circle's kernel and floor, then the one axis's peers."""
    T, rounds = out["circle_duration_s"], out["rounds"]
    diff = out["max_relative_difference_to_dlsim"]
    t_fr, t_lin = res["tcpmm, with friction"][0], res["tcpmm, linear"][0]
    print(f"Kernel: {out['kernel']}")
    print(f"The paper's circle, 3 axes, {T:.2f} s, kernel on one thread, {rounds} rounds "
          f"(min / median, {out['clock']} clock):")
    for name, (lo, med, _) in circ.items():
        print(f"  {name:18s} {lo * 1e3:7.1f} / {med * 1e3:7.1f} ms   real-time factor "
              f"{T / lo:6.0f} / {T / med:6.0f}")
    print(f"  per axis-step {circ['with friction'][0] / n_steps * 1e9:.1f} ns with friction, "
          f"{circ['without friction'][0] / n_steps * 1e9:.1f} ns without, compute floor "
          f"{out['floor_ns_per_step']:.1f} ns: ratio {out['floor_ratio_friction']:.2f}x / "
          f"{out['floor_ratio_friction_median']:.2f}x with friction, "
          f"{out['floor_ratio_linear']:.2f}x / {out['floor_ratio_linear_median']:.2f}x "
          "without (min / median)")
    print(f"One axis, {DURATION_S:.0f} s at the servo's own rates ({steps} position "
          f"steps), min / median of {rounds}; ratio = peer min / tcpmm-with-friction min "
          "(tcpmm-linear min):")
    for name, (lo, med, _) in res.items():
        ratio = "" if name.startswith("tcpmm") else \
            f"   ratio {lo / t_fr:5.1f}x ({lo / t_lin:5.1f}x)"
        print(f"  {name:24s} {lo * 1e3:8.1f} / {med * 1e3:8.1f} ms{ratio}")
    print(f"  tcpmm linear vs dlsim, max relative difference of the scale: {diff:.1e}")


def main(argv=None) -> dict:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--rounds", type=int, default=7, help="timed rounds (>= 5)")
    p.add_argument("--json", action="store_true", help="print the figures as JSON only")
    p.add_argument("--clock", choices=list(CLOCKS), default="wall",
                   help="wall clock (default) or the thread's CPU time")
    args = p.parse_args(argv)
    rounds = max(5, args.rounds)
    threadpool_limits(1)
    fric, T = circle_kernel(builtin_machine())
    lin, _ = circle_kernel(builtin_machine(friction=False))
    floor, n_steps = compute_floor(builtin_machine())
    fric(), lin(), floor()  # compile or load the cache
    axis_tools, steps, rel_diff = peers()
    # every tool once per round, the circle's among the peers' (a round is some seconds):
    # a change of the machine's load hits all alike, and a slow second not all of a tool
    both = interleaved({"with friction": fric, "without friction": lin,
                        "compute floor": floor} | axis_tools, rounds, CLOCKS[args.clock])
    circ = {k: both[k] for k in ("with friction", "without friction", "compute floor")}
    res = {k: both[k] for k in axis_tools}
    diff = rel_diff(res)
    t_fr, t_lin = res["tcpmm, with friction"][0], res["tcpmm, linear"][0]
    t_ctrl, t_dl = res["control.forced_response"][0], res["scipy dlsim"][0]
    out = {
        "rounds": rounds,
        "clock": args.clock,
        "circle_duration_s": T,
        "circle_realtime_factor": T / circ["with friction"][0],
        "circle_realtime_factor_median": T / circ["with friction"][1],
        "circle_realtime_factor_linear": T / circ["without friction"][0],
        "forced_response_ratio_own_rates": t_ctrl / t_fr,
        "forced_response_ratio_own_rates_linear": t_ctrl / t_lin,
        "dlsim_ratio_own_rates": t_dl / t_fr,
        "dlsim_ratio_own_rates_linear": t_dl / t_lin,
        "max_relative_difference_to_dlsim": diff,
        "floor_steps": n_steps,
        "floor_ns_per_step": circ["compute floor"][0] / n_steps * 1e9,
        "floor_ratio_friction": circ["with friction"][0] / circ["compute floor"][0],
        "floor_ratio_friction_median": circ["with friction"][1] / circ["compute floor"][1],
        "floor_ratio_linear": circ["without friction"][0] / circ["compute floor"][0],
        "floor_ratio_linear_median": circ["without friction"][1] / circ["compute floor"][1],
        "kernel": status(),
    }
    if args.json:
        print(json.dumps(out, indent=1))
        return out
    print_figures(out, circ, res, steps, n_steps)
    return out


if __name__ == "__main__":
    main()
