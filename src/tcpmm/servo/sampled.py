"""The exact sampled closed loop of one axis as a linear time-invariant system.

The multi-rate cascade (position loop every ``n_pos`` velocity-loop steps) is periodic,
so it is lifted to the position-loop period: one step of the lifted system is ``n_pos``
velocity-loop steps. The maps are built by carrying every signal as a row of
coefficients over ``[z; u]`` through the controller equations, which gives an LTI
computation of the same loop that is independent of the compiled simulator (used to
check it and as the benchmark peer). Valid while nothing saturates.
"""

from __future__ import annotations

import numpy as np

from ..mechanics.params import AxisMechanics
from ..mechanics.statespace import discretize_zoh, plant
from .params import ServoParams

#: Outputs of the lifted system, sampled at the start of each position-loop period.
LIFTED_OUTPUTS = ("th_m", "X_LS", "X_TCP", "w_m")


def lifted_closed_loop(mech: AxisMechanics, servo: ServoParams):
    """Lifted closed loop ``z[m+1] = Phi z[m] + Gam u[m]``, ``y[m] = C z[m] + D u[m]``.

    The input ``u = [x_cmd, v_cmd]`` is the command [m] and its velocity [m/s] at the
    position-loop instant. The state is ``[x (plant), I_w, past encoder angles, delay line]``.

    Returns
    -------
    Phi, Gam, C, D : ndarray
        Discrete system at the period ``T_p`` [-].
    """
    p = plant(mech, servo.current_bandwidth_hz)
    n = p.A.shape[0]
    Ad, Bd = discretize_zoh(p.A, p.B, servo.T_v)
    bd = Bd[:, 0]
    d = servo.delay_samples
    taps = servo.velocity_filter
    nt = len(taps)  # past encoder angles kept, newest first
    nz = n + 1 + nt + d
    nu = 2
    eye = np.eye(nz + nu)
    x = eye[:n]  # rows: plant states as functions of [z; u]
    I_w = eye[n]
    hist = [eye[n + 1 + j] for j in range(nt)]  # th_m(k-1), th_m(k-2), ...
    delay = [eye[n + 1 + nt + j] for j in range(d)]  # oldest first
    x_cmd, v_cmd = eye[nz], eye[nz + 1]
    R = mech.R_L
    th_m = p.output_row("th_m") @ x
    x_fb = p.output_row("X_LS") @ x if servo.position_feedback == "scale" else R * th_m
    w_c = (servo.K_pp * (x_cmd - x_fb) + servo.k_ff * v_cmd) / R
    y = np.vstack([th_m, p.output_row("X_LS") @ x, p.output_row("X_TCP") @ x,
                   p.output_row("w_m") @ x])
    for _ in range(servo.n_pos):
        th_m = p.output_row("th_m") @ x
        if servo.velocity_feedback == "state":
            w_fb = p.output_row("w_m") @ x
        else:
            th = [th_m, *hist]
            w_fb = sum(c * (th[i] - th[i + 1]) for i, c in enumerate(taps)) / servo.T_v
        hist = [th_m, *hist[:-1]]
        e = w_c - w_fb
        I_w = I_w + e * servo.T_v
        i_c = servo.K_vp * e + servo.K_vi * I_w
        if d:
            delay.append(i_c)
            i_c = delay.pop(0)
        x = Ad @ x + np.outer(bd, i_c)
    z_next = np.vstack([x, I_w, *hist, *delay])
    Phi, Gam = z_next[:, :nz], z_next[:, nz:]
    return Phi, Gam, y[:, :nz], y[:, nz:]


def sampled_spectral_radius(mech: AxisMechanics, servo: ServoParams) -> float:
    """Spectral radius of the lifted sampled loop: below 1 it is stable [-].

    Parameters
    ----------
    mech : AxisMechanics
        Mechanics [SI].
    servo : ServoParams
        Servo settings [SI].

    Returns
    -------
    float
        Largest modulus of the eigenvalues of ``Phi`` (:func:`lifted_closed_loop`) [-].
    """
    Phi = lifted_closed_loop(mech, servo)[0]
    return float(np.max(np.abs(np.linalg.eigvals(Phi))))


def initial_state(mech: AxisMechanics, servo: ServoParams, x0: np.ndarray) -> np.ndarray:
    """Lifted state for a plant state ``x0`` at rest, integrator empty [SI]."""
    n = plant(mech, servo.current_bandwidth_hz).A.shape[0]
    nt = len(servo.velocity_filter)
    z = np.zeros(n + 1 + nt + servo.delay_samples)
    z[: x0.size] = x0
    z[n + 1 : n + 1 + nt] = x0[0]
    return z
