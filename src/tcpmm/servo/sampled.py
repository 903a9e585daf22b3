"""The exact sampled closed loop of one axis as a linear time-invariant system.

The multi-rate cascade (position loop every ``n_pos`` velocity-loop steps) is periodic,
so it is lifted to the position-loop period: one step of the lifted system is ``n_pos``
velocity-loop steps. The maps are built by carrying every signal as a row of
coefficients over ``[z; u]`` through the controller equations, which gives an LTI
computation of the same loop that is independent of the compiled simulator (used to
check it and as the benchmark peer). Valid while nothing saturates.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from ..mechanics.lumped import AxisMechanics
from ..mechanics.statespace import discretize_zoh, plant
from .currentfilters import biquads
from .params import ServoParams

#: Outputs of the lifted system, sampled at the start of each position-loop period.
LIFTED_OUTPUTS = ("th_m", "X_LS", "X_TCP", "w_m")
#: How far above 1 the spectral radius of a stable sampled loop may lie [-]. A mode the
#: loop cannot move and nothing damps (a structure mode of damping zero) has its
#: eigenvalue on the unit circle: marginally stable, it rings but does not diverge. The
#: rounding of the discretisation (matrix exponential, ``n_pos``-th power, eigenvalues)
#: leaves such an eigenvalue some ten machine epsilons to either side of 1, and up to
#: about ``sqrt(eps)`` where two coincide; so the tolerance is ``sqrt(eps)`` (1.5e-8), the
#: most rounding alone can do, whatever the machine. A mode growing by less per period
#: takes over 4e7 periods to double, which no run and no machine tells from a marginal
#: one; and the radius of a loop that does grow rises steeply with the gain past its
#: limit, so the tolerance moves that limit by far less than any gain step of a tuning.
RADIUS_TOLERANCE = float(np.sqrt(np.finfo(float).eps))


@lru_cache(maxsize=32)
def _plant(mech: AxisMechanics, current_bandwidth_hz):
    """The axis's plant (:func:`~tcpmm.mechanics.statespace.plant`): the same for every
    gain a tuning tries, so kept (its matrices read-only) [-]."""
    p = plant(mech, current_bandwidth_hz)
    for a in (p.A, p.B, p.C, p.D):
        a.flags.writeable = False
    return p


@lru_cache(maxsize=32)
def _discrete_plant(mech: AxisMechanics, current_bandwidth_hz, T_v: float):
    """ZOH plant from the current at ``T_v``: the same for every gain, so kept [-]."""
    p = _plant(mech, current_bandwidth_hz)
    Ad, Bd = discretize_zoh(p.A, p.B, T_v)
    Ad.flags.writeable = False
    Bd.flags.writeable = False
    return Ad, Bd[:, 0]


class _Rows:
    """Signals of the sampled loop as rows of coefficients over ``[z; u]``."""

    def __init__(self, mech: AxisMechanics, servo: ServoParams, nu: int):
        p = _plant(mech, servo.current_bandwidth_hz)
        self.p, self.servo, self.R = p, servo, mech.R_L
        n = p.A.shape[0]
        self.Ad, self.bd = _discrete_plant(mech, servo.current_bandwidth_hz, servo.T_v)
        self.sections = biquads(servo.filters, servo.T_v)
        nt, d, nf = len(servo.velocity_filter), servo.delay_samples, 2 * len(servo.filters)
        self.nz = n + 1 + nt + d + nf
        eye = np.eye(self.nz + nu)
        self.x = eye[:n]  # plant states
        self.I_w = eye[n]
        self.hist = [eye[n + 1 + j] for j in range(nt)]  # th_m(k-1), th_m(k-2), ...
        self.delay = [eye[n + 1 + nt + j] for j in range(d)]  # oldest first
        self.filt = [eye[n + 1 + nt + d + j] for j in range(nf)]
        self.u = eye[self.nz:]

    def out(self, name: str) -> np.ndarray:
        """Row of a plant output at the present step."""
        return self.p.output_row(name) @ self.x

    def feedback(self) -> np.ndarray:
        """Row of the position feedback [m]."""
        if self.servo.position_feedback == "scale":
            return self.out("X_LS")
        return self.R * self.out("th_m")

    def controller(self, w_c: np.ndarray) -> np.ndarray:
        """One velocity-controller step: its output ``i_c`` [A]; updates ``I_w``, ``hist``."""
        s = self.servo
        th_m = self.out("th_m")
        if s.velocity_feedback == "state":
            w_fb = self.out("w_m")
        else:
            th = [th_m, *self.hist]
            w_fb = sum(c * (th[i] - th[i + 1])
                       for i, c in enumerate(s.velocity_filter)) / s.T_v
        self.hist = [th_m, *self.hist[:-1]]
        e = w_c - w_fb
        self.I_w = self.I_w + e * s.T_v
        return s.K_vp * e + s.K_vi * self.I_w

    def apply(self, i_c: np.ndarray) -> None:
        """Current setpoint through the filters and the delay into the plant, one step."""
        for k, (b0, b1, b2, a1, a2) in enumerate(self.sections):
            s1, s2 = self.filt[2 * k], self.filt[2 * k + 1]
            y = b0 * i_c + s1
            self.filt[2 * k] = b1 * i_c - a1 * y + s2
            self.filt[2 * k + 1] = b2 * i_c - a2 * y
            i_c = y
        if self.delay:
            self.delay.append(i_c)
            i_c = self.delay.pop(0)
        self.x = self.Ad @ self.x + np.outer(self.bd, i_c)

    def state(self) -> np.ndarray:
        """Rows of the next state."""
        return np.vstack([self.x, self.I_w, *self.hist, *self.delay, *self.filt])


def lifted_closed_loop(mech: AxisMechanics, servo: ServoParams):
    """Lifted closed loop ``z[m+1] = Phi z[m] + Gam u[m]``, ``y[m] = C z[m] + D u[m]``.

    The input ``u = [x_cmd, v_cmd]`` is the command [m] and its velocity [m/s] at the
    position-loop instant. The state is ``[x (plant), I_w, past encoder angles, delay
    line, filter states]``.

    Returns
    -------
    Phi, Gam, C, D : ndarray
        Discrete system at the period ``T_p`` [-].
    """
    r = _Rows(mech, servo, 2)
    x_cmd, v_cmd = r.u
    w_c = (servo.K_pp * (x_cmd - r.feedback()) + servo.k_ff * v_cmd) / r.R
    y = np.vstack([r.out(o) for o in LIFTED_OUTPUTS])
    # one velocity step with the command w_c as a third input, held over the period with
    # the other two: the step's map raised to n_pos, then w_c put in as its row
    step = _Rows(mech, servo, 3)
    step.apply(step.controller(step.u[2]))
    nz = r.nz
    held = np.vstack([step.state(), np.eye(3, nz + 3, nz)])
    lifted = np.linalg.matrix_power(held, servo.n_pos)[:nz]
    return _split(lifted[:, :-1] + np.outer(lifted[:, -1], w_c), y, nz)


def _split(z_next, y, nz):
    return z_next[:, :nz], z_next[:, nz:], y[:, :nz], y[:, nz:]


def velocity_open_loop(mech: AxisMechanics, servo: ServoParams):
    """Sampled velocity loop opened at the current setpoint, at the period ``T_v``.

    The input is the current setpoint [A] entering the filters, delay, ZOH and plant;
    the output is the velocity controller's output [A] (velocity command zero). The loop
    gain is ``L(z) = -C (zI - Phi)^-1 Gam``; closing ``u = y`` gives the velocity loop.

    Returns
    -------
    Phi, Gam, C, D : ndarray
        Discrete system at the period ``T_v`` [-].
    """
    r = _Rows(mech, servo, 1)
    zero = np.zeros(r.nz + 1)
    i_out = r.controller(zero)
    r.apply(r.u[0])
    return _split(r.state(), i_out[None, :], r.nz)


def position_open_loop(mech: AxisMechanics, servo: ServoParams):
    """Sampled position loop opened at the velocity command, lifted to the period ``T_p``.

    The input is the velocity command [rad/s], held over a position-loop period with the
    velocity loop closed; the output is ``K_pp x_fb / R_L`` [rad/s], the feedback part of
    the next velocity command. The loop gain is ``L(z) = C (zI - Phi)^-1 Gam``.

    Returns
    -------
    Phi, Gam, C, D : ndarray
        Discrete system at the period ``T_p`` [-].
    """
    r = _Rows(mech, servo, 1)
    y = servo.K_pp / r.R * r.feedback()
    for _ in range(servo.n_pos):
        r.apply(r.controller(r.u[0]))
    return _split(r.state(), y[None, :], r.nz)


def sampled_spectral_radius(mech: AxisMechanics, servo: ServoParams) -> float:
    """Spectral radius of the lifted sampled loop: stable where :func:`is_stable_radius`
    says so, below 1 but for rounding [-].

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
    if servo.K_vi == 0.0:  # a P velocity loop's integrator feeds nothing back: its
        n = plant(mech, servo.current_bandwidth_hz).A.shape[0]  # 1 is no mode of the loop
        keep = np.r_[0:n, n + 1:Phi.shape[0]]
        Phi = Phi[np.ix_(keep, keep)]
    return float(np.max(np.abs(np.linalg.eigvals(Phi))))


def is_stable_radius(rho: float) -> bool:
    """Whether a sampled loop of spectral radius ``rho`` is stable: no mode grows by more
    than rounding (:data:`RADIUS_TOLERANCE`). The one verdict every judge of a sampled
    loop uses, so that a model is stable or unstable alike wherever it is judged [-].

    Parameters
    ----------
    rho : float
        Spectral radius of the sampled loop (:func:`sampled_spectral_radius`); ``nan``
        counts as unstable [-].
    """
    return bool(rho < 1.0 + RADIUS_TOLERANCE)


def radius_text(rho: float) -> str:
    """A spectral radius as text: four decimals, or within 5e-5 of 1, where those would
    read 1.0000 whether the loop grows or not, its distance from 1 (``1 + 3.1e-06``) [-]."""
    if abs(rho - 1.0) < 5e-5:
        return f"1 {'+' if rho >= 1.0 else '-'} {abs(rho - 1.0):.1e}"
    return f"{rho:.4f}"


def sampled_loop_stable(mech: AxisMechanics, servo: ServoParams) -> bool:
    """Whether the lifted sampled loop is stable (:func:`is_stable_radius`) [-].

    Parameters
    ----------
    mech : AxisMechanics
        Mechanics [SI].
    servo : ServoParams
        Servo settings [SI].
    """
    return is_stable_radius(sampled_spectral_radius(mech, servo))


def initial_state(mech: AxisMechanics, servo: ServoParams, x0: np.ndarray) -> np.ndarray:
    """Lifted state for a plant state ``x0`` at rest, integrator empty [SI]."""
    n = plant(mech, servo.current_bandwidth_hz).A.shape[0]
    nt = len(servo.velocity_filter)
    z = np.zeros(n + 1 + nt + servo.delay_samples + 2 * len(servo.filters))
    z[: x0.size] = x0
    z[n + 1 : n + 1 + nt] = x0[0]
    return z


def lifted_to_control(mech: AxisMechanics, servo: ServoParams):
    """The lifted sampled closed loop (:func:`lifted_closed_loop`) as a named discrete
    ``control.StateSpace`` at the period ``T_p``: inputs ``x_cmd`` [m], ``v_cmd`` [m/s];
    outputs :data:`LIFTED_OUTPUTS` [SI].

    Parameters
    ----------
    mech : AxisMechanics
        Mechanics [SI].
    servo : ServoParams
        Servo settings [SI].
    """
    import control

    Phi, Gam, C, D = lifted_closed_loop(mech, servo)
    return control.ss(Phi, Gam, C, D, servo.T_p, inputs=["x_cmd", "v_cmd"],
                      outputs=list(LIFTED_OUTPUTS), name="sampled_position_loop")
