"""Simulator speed: 60 s of machine time, 3 axes, velocity loop 8 kHz.

Prints the real-time factor of the compiled simulator on the built-in machine (linear, as
the paper models it, and with friction), and, on
the same linear closed loop (position loop at the velocity-loop rate so that the loop is
time-invariant at 8 kHz), the ratio against python-control ``forced_response`` and scipy
``dlsim`` measured in the same run. Not a test: run ``python benchmarks/simulate.py``.
"""

from __future__ import annotations

import time

import numpy as np
from threadpoolctl import threadpool_limits

from tcpmm.builtin import builtin_machine
from tcpmm.path.command import Command
from tcpmm.servo.sampled import initial_state, lifted_closed_loop
from tcpmm.simulate import simulate, simulate_axis

DURATION_S = 60.0
T_V = 1.25e-4


def best(f, repeat=3):
    ts = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = f()
        ts.append(time.perf_counter() - t0)
    return min(ts), out


def main():
    threadpool_limits(1)
    m = builtin_machine(friction=False, k_ff=0.0)  # the linear TCP-MM of the paper
    t = np.arange(0, DURATION_S, 1e-3)
    w = 2 * np.pi * 0.4
    cmd = Command(
        t,
        {
            "X": 0.035 * np.sin(w * t),
            "Y": 0.035 * (1 - np.cos(w * t)),
            "Z": 0.01 * np.sin(0.5 * w * t),
        },
    )
    simulate(m, Command(t[:100], {k: v[:100] for k, v in cmd.positions.items()}))  # compile
    t_sim, _ = best(lambda: simulate(m, cmd, record_period_s=1e-3))
    print(
        f"tcpmm simulate, 3 axes, {DURATION_S:.0f} s at 8 kHz: {t_sim * 1e3:.1f} ms "
        f"-> real-time factor {DURATION_S / t_sim:.0f}"
    )

    mf = builtin_machine()
    simulate(mf, Command(t[:100], {k: v[:100] for k, v in cmd.positions.items()}))
    t_fr, _ = best(lambda: simulate(mf, cmd, record_period_s=1e-3), repeat=1)
    print(f"  with guideway and screw friction: {t_fr * 1e3:.1f} ms "
          f"-> real-time factor {DURATION_S / t_fr:.0f}")

    # Same linear closed loop at 8 kHz for all three tools (one axis, X).
    ax = m.axes["X"]
    ax = ax.replace(
        servo=ax.servo.model_copy(update={"T_p": T_V}),
        sensors=ax.sensors.model_copy(
            update={"encoder_counts_per_rev": 0, "scale_resolution": 0.0}
        ),
    )
    tv = np.arange(0, DURATION_S, T_V)
    xc = 0.035 * (1 - np.cos(w * tv))  # starts at rest: stays linear (no saturation)
    t_ours, r = best(lambda: simulate_axis(ax, tv, xc, record_period_s=T_V))
    Phi, Gam, C, D = lifted_closed_loop(ax.mechanics, ax.servo)
    z0 = initial_state(ax.mechanics, ax.servo, np.zeros(10))
    u = np.column_stack([xc, np.gradient(xc, tv)])

    from scipy.signal import dlsim

    t_dlsim, (_, y_dl, _) = best(lambda: dlsim((Phi, Gam, C, D, T_V), u, x0=z0), repeat=1)
    import control

    sys_d = control.ss(Phi, Gam, C, D, T_V)
    t_ctrl, _ = best(lambda: control.forced_response(sys_d, T=tv, U=u.T, X0=z0), repeat=1)
    err = np.max(np.abs(r.scale - y_dl[:, 1])) / np.max(np.abs(y_dl[:, 1]))
    print(f"one axis, linear closed loop at 8 kHz, {tv.size} steps:")
    print(f"  tcpmm kernel            {t_ours * 1e3:9.1f} ms")
    print(f"  scipy dlsim             {t_dlsim * 1e3:9.1f} ms   ratio {t_dlsim / t_ours:6.1f}x")
    print(f"  control.forced_response {t_ctrl * 1e3:9.1f} ms   ratio {t_ctrl / t_ours:6.1f}x")
    print(f"  max relative difference to dlsim: {err:.2e}")


if __name__ == "__main__":
    main()
