"""Continuous-time closed loops of one axis: velocity loop G_v, position loop G_p and
command -> X_TCP (paper Fig. 4), as state spaces derived from the plant.

The controller is taken continuous here (sampling and delay neglected), as in the paper's
eqs. (7)-(8); :mod:`tcpmm.servo.sampled` gives the exact sampled loop.
"""

from __future__ import annotations

import numpy as np

from ..mechanics.params import AxisMechanics
from ..mechanics.statespace import StateSpace, plant
from ..mechanics.transfer import freqresp_ss
from .params import ServoParams

CLOSED_LOOP_TFS = ("G_v", "G_p", "cmd_to_tcp", "cmd_to_motor", "cmd_to_current")


def position_closed_loop(mech: AxisMechanics, servo: ServoParams) -> StateSpace:
    """Closed position loop with inputs ``x_cmd`` [m], ``v_cmd`` [m/s].

    States are the plant states plus the velocity-loop integral. Outputs are the plant
    outputs plus ``i_c`` [A].
    """
    p = plant(mech, servo.current_bandwidth_hz)
    n = p.A.shape[0]
    R = mech.R_L
    c_fb = p.output_row("X_LS") if servo.position_feedback == "scale" else R * p.output_row("th_m")
    c_w = p.output_row("w_m")
    b = p.B[:, 0]
    # w_c = (K_pp (x_cmd - c_fb x) + k_ff v_cmd)/R ; e = w_c - c_w x ; i = K_vp e + K_vi I
    e_x = -servo.K_pp / R * c_fb - c_w
    e_u = np.array([servo.K_pp / R, servo.k_ff / R])
    A = np.zeros((n + 1, n + 1))
    A[:n, :n] = p.A + np.outer(b, servo.K_vp * e_x)
    A[:n, n] = b * servo.K_vi
    A[n, :n] = e_x
    B = np.zeros((n + 1, 2))
    B[:n] = np.outer(b, servo.K_vp * e_u)
    B[n] = e_u
    C = np.vstack([np.hstack([p.C, np.zeros((p.C.shape[0], 1))]),
                   np.hstack([servo.K_vp * e_x, [servo.K_vi]])])
    D = np.vstack([np.zeros((p.C.shape[0], 2)), servo.K_vp * e_u])
    return StateSpace(A, B, C, D, (*p.states, "I_w"), ("x_cmd", "v_cmd"), (*p.outputs, "i_c"))


def velocity_closed_loop(mech: AxisMechanics, servo: ServoParams) -> StateSpace:
    """Closed velocity loop with input ``w_c`` [rad/s]; outputs the plant's and ``i_c``."""
    p = plant(mech, servo.current_bandwidth_hz)
    n = p.A.shape[0]
    c_w = p.output_row("w_m")
    b = p.B[:, 0]
    A = np.zeros((n + 1, n + 1))
    A[:n, :n] = p.A - servo.K_vp * np.outer(b, c_w)
    A[:n, n] = servo.K_vi * b
    A[n, :n] = -c_w
    B = np.zeros((n + 1, 1))
    B[:n, 0] = servo.K_vp * b
    B[n, 0] = 1.0
    C = np.vstack([np.hstack([p.C, np.zeros((p.C.shape[0], 1))]),
                   np.hstack([-servo.K_vp * c_w, [servo.K_vi]])])
    D = np.vstack([np.zeros((p.C.shape[0], 1)), [[servo.K_vp]]])
    return StateSpace(A, B, C, D, (*p.states, "I_w"), ("w_c",), (*p.outputs, "i_c"))


def closed_loop_freqresp(mech: AxisMechanics, servo: ServoParams, name: str, f_hz):
    """Frequency response of a closed loop.

    Parameters
    ----------
    mech, servo : AxisMechanics, ServoParams
        The axis [SI].
    name : {"G_v", "G_p", "cmd_to_tcp", "cmd_to_motor", "cmd_to_current"}
        ``G_v = w_m/w_c`` [-]; ``G_p`` = feedback position / command [-]; ``cmd_to_tcp``
        = X_TCP / command [-]; ``cmd_to_motor`` = R_L th_m / command [-];
        ``cmd_to_current`` = i_c / command [A/m]. Velocity feedforward is included.
    f_hz : array_like
        Frequencies [Hz].
    """
    f = np.atleast_1d(np.asarray(f_hz, dtype=float))
    if name == "G_v":
        return freqresp_ss(velocity_closed_loop(mech, servo), f, "w_m", "w_c")
    cl = position_closed_loop(mech, servo)
    s = 2j * np.pi * f
    out = {
        "G_p": "X_LS" if servo.position_feedback == "scale" else "th_m",
        "cmd_to_tcp": "X_TCP",
        "cmd_to_motor": "th_m",
        "cmd_to_current": "i_c",
    }
    if name not in out:
        raise KeyError(f"unknown closed loop {name!r}; known: {', '.join(CLOSED_LOOP_TFS)}")
    o = out[name]
    h = freqresp_ss(cl, f, o, "x_cmd") + s * freqresp_ss(cl, f, o, "v_cmd")
    if o == "th_m":
        h = h * mech.R_L
    return h


def is_stable(mech: AxisMechanics, servo: ServoParams) -> bool:
    """True when every pole of the continuous position loop is in the open left half-plane
    (the position loop closes the rigid-body integrator, so none may sit at zero)."""
    return bool(np.all(np.linalg.eigvals(position_closed_loop(mech, servo).A).real < 0))
