"""Continuous-time closed loops of one axis: velocity loop G_v, position loop G_p and
command -> X_TCP (paper Fig. 4), as state spaces derived from the plant.

The controller is taken continuous here (sampling and delay neglected), as in the paper's
eqs. (7)-(8); :mod:`tcpmm.servo.sampled` gives the exact sampled loop.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..mechanics.export import relative_coordinates, structural_minimal
from ..mechanics.lumped import AxisMechanics
from ..mechanics.statespace import StateSpace, plant, to_control
from ..mechanics.transfer import freqresp_ss
from .currentfilters import continuous_ss
from .params import ServoParams
from .sampled import RADIUS_TOLERANCE

CLOSED_LOOP_TFS = ("G_v", "G_p", "cmd_to_tcp", "cmd_to_motor", "cmd_to_current")

#: Each transfer function of an axis that ``tcpmm bode`` gives: what it relates and its
#: unit (the reduced plant's, the closed loops' and the open sampled loops') [-].
TF_MEANING = {
    "G_M": ("motor speed per current command", "rad/s/A"),
    "G_T": ("scale position per motor angle", "m/rad"),
    "G_tcp": ("TCP position per scale position", "m/m"),
    "G_v": ("motor speed per speed command, velocity loop closed", "-"),
    "G_p": ("fed-back position per position command, position loop closed", "m/m"),
    "cmd_to_tcp": ("TCP position per position command", "m/m"),
    "cmd_to_motor": ("motor position (its angle times the screw's travel per radian) per "
                     "position command", "m/m"),
    "cmd_to_current": ("current command per position command", "A/m"),
    "L_v": ("open velocity loop, sampled", "-"),
    "L_p": ("open position loop, sampled", "-"),
}


def _close(p: StateSpace, servo: ServoParams, e_x, e_u, inputs) -> StateSpace:
    """Close the PI velocity controller (and its current-setpoint filters) around the
    plant ``p``: velocity error ``e = e_x x + e_u u``; ``i_c = K_vp e + K_vi int(e)``
    through the filters into the plant. States: plant, ``I_w``, filter states."""
    n = p.A.shape[0]
    Af, bf, cf, df = continuous_ss(servo.filters)
    nf = Af.shape[0]
    b = p.B[:, 0]
    ic_x, ic_u = servo.K_vp * e_x, servo.K_vp * e_u  # i_c over x and u (and K_vi I_w)
    A = np.zeros((n + 1 + nf, n + 1 + nf))
    A[:n, :n] = p.A + np.outer(b, df * ic_x)
    A[:n, n] = b * (df * servo.K_vi)
    A[:n, n + 1:] = np.outer(b, cf)
    A[n, :n] = e_x
    A[n + 1:, :n] = np.outer(bf, ic_x)
    A[n + 1:, n] = bf * servo.K_vi
    A[n + 1:, n + 1:] = Af
    B = np.vstack([np.outer(b, df * ic_u), e_u, np.outer(bf, ic_u)])
    C = np.vstack([np.hstack([p.C, np.zeros((p.C.shape[0], 1 + nf))]),
                   np.hstack([df * ic_x, [df * servo.K_vi], cf])])
    D = np.vstack([np.zeros((p.C.shape[0], len(inputs))), df * ic_u])
    states = (*p.states, "I_w", *(f"filter_{i}" for i in range(nf)))
    return StateSpace(A, B, C, D, states, inputs, (*p.outputs, "i_c"))


def position_closed_loop(mech: AxisMechanics, servo: ServoParams) -> StateSpace:
    """Closed position loop with inputs ``x_cmd`` [m], ``v_cmd`` [m/s].

    States are the plant states, the velocity-loop integral and the filter states.
    Outputs are the plant outputs plus ``i_c`` [A], the current setpoint after the
    filters.
    """
    p = plant(mech, servo.current_bandwidth_hz)
    R = mech.R_L
    c_fb = p.output_row("X_LS") if servo.position_feedback == "scale" else R * p.output_row("th_m")
    c_w = p.output_row("w_m")
    # w_c = (K_pp (x_cmd - c_fb x) + k_ff v_cmd)/R ; e = w_c - c_w x
    e_x = -servo.K_pp / R * c_fb - c_w
    e_u = np.array([servo.K_pp / R, servo.k_ff / R])
    return _close(p, servo, e_x, e_u, ("x_cmd", "v_cmd"))


def velocity_closed_loop(mech: AxisMechanics, servo: ServoParams) -> StateSpace:
    """Closed velocity loop with input ``w_c`` [rad/s]; outputs the plant's and ``i_c``."""
    p = plant(mech, servo.current_bandwidth_hz)
    return _close(p, servo, -p.output_row("w_m"), np.array([1.0]), ("w_c",))


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
    """True when no pole of the continuous position loop lies right of the imaginary axis
    by more than rounding: damping ratio above ``-RADIUS_TOLERANCE``, the sampled loop's
    tolerance (:func:`~tcpmm.servo.sampled.is_stable_radius`), so that an undamped mode
    the loop cannot move is marginally stable here as there. None may sit at zero: the
    position loop closes the rigid-body integrator [-]."""
    ev = np.linalg.eigvals(position_closed_loop(mech, servo).A)
    if servo.K_vi == 0.0:  # a P velocity loop's integrator feeds nothing back: its column
        ev = np.delete(ev, np.argmin(np.abs(ev)))  # is zero, its 0 no mode of the loop
    return bool(np.all(ev.real < RADIUS_TOLERANCE * np.abs(ev)))


def closed_loop_ss(mech: AxisMechanics, servo: ServoParams, name: str) -> StateSpace:
    """Minimal SISO state space of a closed loop, from the command [m] (feedforward of
    its derivative included) or, for ``G_v``, from the velocity command [rad/s].

    Parameters
    ----------
    mech, servo : AxisMechanics, ServoParams
        The axis [SI].
    name : str
        One of :data:`CLOSED_LOOP_TFS` [-].
    """
    if name == "G_v":
        cl = velocity_closed_loop(mech, servo)
        return structural_minimal(relative_coordinates(cl, mech), ["w_c"], ["w_m"])
    out = _OUTPUT.get(name)
    if out is None:
        raise KeyError(f"unknown closed loop {name!r}; known: {', '.join(CLOSED_LOOP_TFS)}")
    o = out(servo) if callable(out) else out
    cl = position_closed_loop(mech, servo)
    k = cl.outputs.index(o)
    if cl.D[k, 1] != 0.0:
        raise InputError(f"{name} with velocity feedforward (k_ff = {servo.k_ff}) is "
                         "improper (the command's derivative reaches the current "
                         "directly); export the two-input loop (name=None) instead")
    # v_cmd = s x_cmd: s C (sI - A)^-1 b_v = C b_v + C A (sI - A)^-1 b_v
    b = cl.B[:, 0] + cl.A @ cl.B[:, 1]
    d = cl.D[:, 0] + cl.C @ cl.B[:, 1]
    gain = mech.R_L if o == "th_m" else 1.0
    siso = StateSpace(cl.A, b[:, None], gain * cl.C, gain * d[:, None], cl.states,
                      ("x_cmd",), cl.outputs)
    red = structural_minimal(relative_coordinates(siso, mech), ["x_cmd"], [o])
    label = {"G_p": "x_fb", "cmd_to_motor": "x_motor"}.get(name, o)
    return StateSpace(red.A, red.B, red.C, red.D, red.states, red.inputs, (label,))


_OUTPUT = {
    "G_p": lambda s: "X_LS" if s.position_feedback == "scale" else "th_m",
    "cmd_to_tcp": "X_TCP",
    "cmd_to_motor": "th_m",
    "cmd_to_current": "i_c",
}


def closed_loop_to_control(mech: AxisMechanics, servo: ServoParams, name: str | None = None):
    """A closed loop as a named ``control.StateSpace``.

    Parameters
    ----------
    mech, servo : AxisMechanics, ServoParams
        The axis [SI].
    name : str, optional
        A SISO loop of :data:`CLOSED_LOOP_TFS` (:func:`closed_loop_ss`); ``None`` for
        the continuous position loop with inputs ``x_cmd, v_cmd`` and every output [-].
    """
    if name is None:
        return to_control(position_closed_loop(mech, servo), name="position_loop")
    return to_control(closed_loop_ss(mech, servo, name), name=name)
