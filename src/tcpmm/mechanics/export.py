"""Minimal, named python-control models of an axis, from its state space.

The 10-state plant carries two parts that no transfer function of the drive sees: the
rigid-body position (a pure integrator that only the position of the table reveals)
and the TCP structure ``X_h``, which the nut force drives one way. In relative
coordinates (shaft twist ``th_m - th_L``, nut deflection ``R th_L - X_LS``, bed ``X_b``,
structure ``X_h`` and the motor angle ``th_m``) these parts decouple exactly, and a
transfer function keeps only the states its output sees and its input drives
(:func:`structural_minimal`): no pole-zero pair is cancelled numerically.

``G_T = X_LS/th_m`` is the load chain driven by a prescribed motor angle (the motor
torque, where the current enters, is the force that prescribes it); ``G_tcp =
X_TCP/X_LS`` is the bed and the structure under a prescribed table-bed motion,
``1 - P_t/(P_t + Q_b) (1 + Q_b/Q_h)`` with ``P_t = M_t s^2 + C_t s``, ``Q_x = M_x s^2 +
C_x s + K_x``, realised as two scaled second-order sections.
"""

from __future__ import annotations

import numpy as np

from .lumped import AxisMechanics
from .statespace import StateSpace, plant

#: Names of the plant states in relative coordinates.
RELATIVE_STATES = ("twist", "nut", "X_b", "X_h", "th_m",
                   "w_twist", "v_nut", "v_b", "v_h", "w_m")
#: Entries below this fraction of their row's largest are rounding, not coupling [-].
_ZERO = 1e-12


def relative_coordinates(ss: StateSpace, mech: AxisMechanics) -> StateSpace:
    """The same system with its first 10 (plant) states in relative coordinates.

    Parameters
    ----------
    ss : StateSpace
        A system whose first 10 states are the plant's (plant or a closed loop) [-].
    mech : AxisMechanics
        Axis parameters [SI].
    """
    R = mech.R_L
    Tq = np.array([[1.0, -1.0, 0, 0, 0],  # twist = th_m - th_L
                   [0, R, -1.0, 1.0, 0],  # nut = R th_L - (X_t - X_b)
                   [0, 0, 0, 1.0, 0],  # X_b
                   [0, 0, 0, 0, 1.0],  # X_h
                   [1.0, 0, 0, 0, 0]])  # th_m
    n = ss.A.shape[0]
    T = np.eye(n)
    T[:5, :5] = Tq
    T[5:10, 5:10] = Tq
    Ti = np.linalg.inv(T)
    A = T @ ss.A @ Ti
    A[np.abs(A) < _ZERO * np.max(np.abs(A), axis=1, keepdims=True)] = 0.0
    return StateSpace(A, T @ ss.B, ss.C @ Ti, ss.D, (*RELATIVE_STATES, *ss.states[10:]),
                      ss.inputs, ss.outputs)


def structural_minimal(ss: StateSpace, inputs, outputs) -> StateSpace:
    """Keep the states that the ``inputs`` reach and the ``outputs`` see.

    Reachability and observability are read from the nonzero pattern of the matrices,
    so a decoupled part is removed exactly, with no rank decision.

    Parameters
    ----------
    ss : StateSpace
        The system [-].
    inputs, outputs : sequence of str
        Signals kept [-].
    """
    iu = [ss.inputs.index(u) for u in inputs]
    iy = [ss.outputs.index(y) for y in outputs]
    B, C = ss.B[:, iu], ss.C[iy]
    link = ss.A != 0.0  # link[i, j]: state j drives state i
    reach = _closure(np.any(B != 0.0, axis=1), link)
    seen = _closure(np.any(C != 0.0, axis=0), link.T)
    k = np.flatnonzero(reach & seen)
    return StateSpace(ss.A[np.ix_(k, k)], B[k], C[:, k], ss.D[np.ix_(iy, iu)],
                      tuple(ss.states[i] for i in k), tuple(inputs), tuple(outputs))


def _closure(start: np.ndarray, link: np.ndarray) -> np.ndarray:
    """States reached from ``start`` along ``link[i, j]`` (j -> i)."""
    s = start.copy()
    while True:
        nxt = s | np.any(link[:, s], axis=1)
        if np.array_equal(nxt, s):
            return s
        s = nxt


def biquad(num, den) -> StateSpace:
    """``(n0 s^2 + n1 s + n2)/(d0 s^2 + d1 s + d2)`` as a state space scaled by its
    natural frequency (states of equal magnitude: a well-conditioned realisation)."""
    num = np.asarray(num, dtype=float) / den[0]
    a1, a2 = den[1] / den[0], den[2] / den[0]
    w = np.sqrt(a2)
    A = np.array([[0.0, w], [-w, -a1]])
    B = np.array([[0.0], [1.0]])
    C = np.array([[(num[2] - num[0] * a2) / w, num[1] - num[0] * a1]])
    return StateSpace(A, B, C, np.array([[num[0]]]), ("q", "v"), ("u",), ("y",))


def series(first: StateSpace, second: StateSpace) -> StateSpace:
    """SISO ``second(first(u))`` [-]."""
    n1 = first.A.shape[0]
    A = np.block([[first.A, np.zeros((n1, second.A.shape[0]))],
                  [second.B @ first.C, second.A]])
    B = np.vstack([first.B, second.B @ first.D])
    C = np.hstack([second.D @ first.C, second.C])
    return StateSpace(A, B, C, second.D @ first.D, (*first.states, *second.states),
                      first.inputs, second.outputs)


def reduced_ss(mech: AxisMechanics, name: str, current_bandwidth_hz=None) -> StateSpace:
    """Minimal state space of G_M [rad/s/A], G_T [m/rad] or G_tcp [-].

    Parameters
    ----------
    mech : AxisMechanics
        Axis parameters [SI].
    name : {"G_M", "G_T", "G_tcp"}
        Which reduced model [-].
    current_bandwidth_hz : float, optional
        First-order current loop bandwidth (G_M only) [Hz].
    """
    p = plant(mech, current_bandwidth_hz)
    if name == "G_M":
        return structural_minimal(relative_coordinates(p, mech), ["i_c"], ["w_m"])
    if name == "G_T":  # in absolute coordinates: th_m prescribed, the rest free
        keep = [i for i, s in enumerate(p.states) if s not in ("th_m", "w_m", "i_act")]
        th, w = p.states.index("th_m"), p.states.index("w_m")
        A = p.A[np.ix_(keep, keep)]
        b_q, b_w = p.A[keep, th], p.A[keep, w]  # th_m and its rate drive the load
        c = p.output_row("X_LS")
        # x' = A x + b_q th + b_w th'  ->  xi = x - b_w th:  xi' = A xi + (A b_w + b_q) th
        sys = StateSpace(A, (A @ b_w + b_q)[:, None], c[keep][None, :],
                         np.array([[c[keep] @ b_w + c[th]]]),
                         tuple(p.states[i] for i in keep), ("th_m",), ("X_LS",))
        return structural_minimal(sys, ["th_m"], ["X_LS"])
    if name == "G_tcp":
        m = mech
        h1 = biquad([m.M_t, m.C_t, 0.0], [m.M_t + m.M_b, m.C_t + m.C_b, m.K_b])
        h2 = biquad([m.M_h + m.M_b, m.C_h + m.C_b, m.K_h + m.K_b], [m.M_h, m.C_h, m.K_h])
        s = series(h1, h2)
        states = ("bed_1", "bed_2", "structure_1", "structure_2")
        return StateSpace(s.A, s.B, -s.C, 1.0 - s.D, states, ("X_LS",), ("X_TCP",))
    raise KeyError(f"unknown transfer function {name!r}; known: G_M, G_T, G_tcp")
