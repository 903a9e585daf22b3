"""The 10-state linear model of one axis (docs/model.md section 1).

State ``x = [th_m, th_L, X_t, X_b, X_h, w_m, w_L, v_t, v_b, v_h]`` (positions [rad, m],
then velocities [rad/s, m/s]). Inputs ``u = [i_c, T_m, T_L, F_t_ext]``: current command
[A], external torque on the motor shaft [N m], external torque on the screw [N m] and
external force on the carriage [N]. The external inputs are where friction, lost motion
and loads enter. With an optional first-order current loop the current becomes an
eleventh state driven by ``i_c``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._compiled import expm
from .lumped import AxisMechanics

STATES = ("th_m", "th_L", "X_t", "X_b", "X_h", "w_m", "w_L", "v_t", "v_b", "v_h")
INPUTS = ("i_c", "T_m", "T_L", "F_t")
#: Output names and the rows of C that form them.
OUTPUTS = ("w_m", "th_m", "X_LS", "X_TCP", "X_t", "F_t")
N_POS = 5


@dataclass(frozen=True)
class StateSpace:
    """Continuous-time ``x' = A x + B u``, ``y = C x`` with named signals.

    Parameters
    ----------
    A, B, C, D : ndarray
        System matrices in SI units [-].
    states, inputs, outputs : tuple of str
        Names of the signals [-].
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    states: tuple
    inputs: tuple
    outputs: tuple

    def output_row(self, name: str) -> np.ndarray:
        """Row of C for a named output [-]."""
        return self.C[self.outputs.index(name)]

    def to_control(self, name: str | None = None):
        """The same system as a ``control.StateSpace`` with its signal names."""
        return to_control(self, name)


def plant(mech: AxisMechanics, current_bandwidth_hz: float | None = None) -> StateSpace:
    """State space of the axis mechanics, from the equations of motion.

    Parameters
    ----------
    mech : AxisMechanics
        Axis parameters [SI].
    current_bandwidth_hz : float, optional
        Bandwidth of a first-order current loop; ``None`` for the ideal loop (gain 1)
        [Hz].

    Returns
    -------
    StateSpace
        Inputs ``i_c, T_m, T_L, F_t``; outputs ``w_m, th_m, X_LS, X_TCP, X_t, F_t``.
    """
    m = mech
    R = m.R_L
    n = 10
    A = np.zeros((n, n))
    A[:N_POS, N_POS:] = np.eye(N_POS)
    # Spring forces as rows over the position states.
    T_shaft = np.array([m.K_L, -m.K_L, 0, 0, 0])  # K_L (th_m - th_L)
    F_nut = m.K_t * np.array([0, R, -1, 1, 0])  # K_t (R th_L - (X_t - X_b))
    inertia = np.array([m.J_m, m.J_L, m.M_t, m.M_b, m.M_h])
    damping = np.array([m.B_m, m.B_L, m.C_t, m.C_b, m.C_h])
    K = np.zeros((N_POS, N_POS))  # generalised restoring forces: M q'' = -K q - C q' + ...
    K[0] -= -T_shaft
    K[1] -= T_shaft - R * F_nut
    K[2] -= F_nut
    K[3] -= -F_nut - np.array([0, 0, 0, m.K_b, 0])
    K[4] -= F_nut - np.array([0, 0, 0, 0, m.K_h])
    A[N_POS:, :N_POS] = -K / inertia[:, None]
    A[N_POS:, N_POS:] = -np.diag(damping / inertia)
    B = np.zeros((n, 4))
    B[5, 0] = m.K_tc / m.J_m
    B[5, 1] = 1.0 / m.J_m
    B[6, 2] = 1.0 / m.J_L
    B[7, 3] = 1.0 / m.M_t
    C = np.zeros((6, n))
    C[0, 5] = 1.0  # w_m
    C[1, 0] = 1.0  # th_m
    C[2, 2], C[2, 3] = 1.0, -1.0  # X_LS = X_t - X_b
    C[3, 2], C[3, 4] = 1.0, -1.0  # X_TCP = X_t - X_h
    C[4, 2] = 1.0  # X_t
    C[5, :N_POS] = F_nut  # F_t
    states = STATES
    if current_bandwidth_hz is not None:
        wc = 2.0 * np.pi * current_bandwidth_hz
        A = np.block([[A, B[:, :1]], [np.zeros((1, n)), np.array([[-wc]])]])
        B = np.vstack([np.hstack([np.zeros((n, 1)), B[:, 1:]]), [[wc, 0, 0, 0]]])
        C = np.hstack([C, np.zeros((C.shape[0], 1))])
        states = (*STATES, "i_act")
    return StateSpace(A, B, C, np.zeros((C.shape[0], B.shape[1])), states, INPUTS, OUTPUTS)


def oscillating_modes(mech: AxisMechanics) -> np.ndarray:
    """The eigenvalues of the mechanics' oscillating modes, one of each pair (positive
    imaginary part), by increasing modulus. Not the rigid body's double 0, which rounding
    splits into a pair of up to sqrt(eps) of the largest (an undamped model's read as a
    mode of 0.0 Hz) [rad/s].

    Parameters
    ----------
    mech : AxisMechanics
        The axis' mechanics [SI].
    """
    ev = np.linalg.eigvals(plant(mech).A)
    osc = ev[(ev.imag > 1e-9 * np.maximum(np.abs(ev), 1.0))
             & (np.abs(ev) > 1e-6 * np.abs(ev).max())]
    return osc[np.argsort(np.abs(osc))]


def nut_force_input(mech: AxisMechanics, n_states: int = 10) -> np.ndarray:
    """Input column of a force added to the screw-nut force ``F_t``.

    The force acts as the nut does: on the table, against the screw (``R_L`` times it as
    a torque on ``th_L``), against the bed and on the TCP structure. Nonlinear nut
    elements (lost motion) enter the linear plant through it.

    Parameters
    ----------
    mech : AxisMechanics
        Axis parameters [SI].
    n_states : int
        State size of the plant (10, or 11 with the current-loop state) [-].

    Returns
    -------
    numpy.ndarray
        ``dx/dt`` per newton [SI].
    """
    b = np.zeros(n_states)
    b[6] = -mech.R_L / mech.J_L
    b[7] = 1.0 / mech.M_t
    b[8] = -1.0 / mech.M_b
    b[9] = 1.0 / mech.M_h
    return b


def guideway_force_input(mech: AxisMechanics, n_states: int = 10,
                         relative: bool = False) -> np.ndarray:
    """Input column of the guideway's friction force.

    Parameters
    ----------
    mech : AxisMechanics
        Axis parameters [SI].
    n_states : int
        State size of the plant (10, or 11 with the current-loop state) [-].
    relative : bool
        The guide acts between table and bed: its force on the table has its reaction on
        the bed; otherwise it acts on the table alone [-].

    Returns
    -------
    numpy.ndarray
        ``dx/dt`` per newton pushing the table [SI].
    """
    b = np.zeros(n_states)
    b[7] = 1.0 / mech.M_t
    if relative:
        b[8] = -1.0 / mech.M_b
    return b


def discretize_zoh(A: np.ndarray, B: np.ndarray, dt: float):
    """Exact zero-order-hold discretisation through one matrix exponential.

    Parameters
    ----------
    A, B : ndarray
        Continuous-time matrices [-].
    dt : float
        Sample period [s].

    Returns
    -------
    Ad, Bd : ndarray
        ``x[k+1] = Ad x[k] + Bd u[k]`` [-].
    """
    n, m = B.shape
    M = np.zeros((n + m, n + m))
    M[:n, :n] = A * dt
    M[:n, n:] = B * dt
    E = expm(M)
    return E[:n, :n], E[:n, n:]


def static_equilibrium(mech: AxisMechanics, x_fb: float, feedback: str = "scale",
                       backlash: float = 0.0):
    """Rest state holding the axis at a feedback position against the load force.

    Parameters
    ----------
    mech : AxisMechanics
        Axis parameters [SI].
    x_fb : float
        Position the position loop holds (scale or encoder at the table) [m].
    feedback : {"scale", "encoder"}
        Which sensor closes the position loop [-].
    backlash : float
        Total free play of the screw-nut; a carried load closes it on one side [m].

    Returns
    -------
    x0 : ndarray
        Mechanical state (10) at rest [SI].
    i_hold : float
        Current that holds the load [A].
    """
    m = mech
    R = m.R_L
    F_t = -m.load_force  # the nut carries the load
    X_b = -F_t / m.K_b
    X_h = F_t / m.K_h
    torque = R * F_t  # at the motor, through the rigid chain
    i_hold = torque / m.K_tc
    twist = torque / m.K_L  # th_m - th_L
    # nut deflection R th_L - X_LS, with the free play closed on the loaded side
    nut = F_t / m.K_t + 0.5 * backlash * float(np.sign(F_t))
    if feedback == "scale":
        x_ls = x_fb
        th_L = (x_ls + nut) / R
        th_m = th_L + twist
    else:
        th_m = x_fb / R
        th_L = th_m - twist
        x_ls = R * th_L - nut
    x0 = np.zeros(10)
    x0[:5] = [th_m, th_L, x_ls + X_b, X_b, X_h]
    return x0, i_hold


def to_control(ss: StateSpace, name: str | None = None, dt=None):
    """A :class:`StateSpace` as a named ``control.StateSpace`` (``dt`` for a discrete one)."""
    import control  # python-control is slow to import and needed only here

    kw = {} if dt is None else {"dt": dt}
    return control.ss(ss.A, ss.B, ss.C, ss.D, states=list(ss.states), inputs=list(ss.inputs),
                      outputs=list(ss.outputs), name=name, **kw)
