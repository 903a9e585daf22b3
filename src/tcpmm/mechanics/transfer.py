"""Transfer functions of one axis, derived from its state space.

The reduced models of the paper (Fig. 6) are ratios of plant responses to the current
command: ``G_M = w_m/i_c``, ``G_T = X_LS/th_m``, ``G_tcp = X_TCP/X_LS``. The block
transfer functions of eqs. (1)-(4), (9) are given in closed form as well, for checks and
for export; the printed eqs. (5), (6) and (8) are not used (docs/model.md section 2).
"""

from __future__ import annotations

import numpy as np

from .export import reduced_ss
from .lumped import AxisMechanics
from .statespace import StateSpace, plant, to_control

#: Reduced transfer functions: name -> (numerator output, denominator output).
REDUCED = {
    "G_M": ("w_m", None),
    "G_T": ("X_LS", "th_m"),
    "G_tcp": ("X_TCP", "X_LS"),
}
BLOCKS = ("G_m", "G_L", "G_t", "G_b", "G_h")


def freqresp_ss(ss: StateSpace, f_hz, output: str, input: str = "i_c") -> np.ndarray:
    """Frequency response ``C_out (j w I - A)^-1 B_in`` of a state space.

    Parameters
    ----------
    ss : StateSpace
        The system [-].
    f_hz : array_like
        Frequencies [Hz].
    output, input : str
        Signal names [-].

    Returns
    -------
    ndarray of complex
        Response at each frequency [output unit / input unit].
    """
    f = np.atleast_1d(np.asarray(f_hz, dtype=float))
    s = 2j * np.pi * f
    n = ss.A.shape[0]
    M = s[:, None, None] * np.eye(n)[None] - ss.A[None]
    b = np.broadcast_to(ss.B[:, ss.inputs.index(input)], (f.size, n))[..., None]
    x = np.linalg.solve(M, b)[..., 0]
    c = ss.output_row(output)
    return x @ c + ss.D[ss.outputs.index(output), ss.inputs.index(input)]


def reduced_freqresp(mech: AxisMechanics, name: str, f_hz, current_bandwidth_hz=None):
    """Frequency response of G_M [rad/s/A], G_T [m/rad] or G_tcp [-].

    Parameters
    ----------
    mech : AxisMechanics
        Axis parameters [SI].
    name : {"G_M", "G_T", "G_tcp"}
        Which reduced model [-].
    f_hz : array_like
        Frequencies [Hz].
    current_bandwidth_hz : float, optional
        First-order current loop bandwidth, ``None`` for the ideal loop [Hz].
    """
    if name not in REDUCED:
        raise KeyError(f"unknown transfer function {name!r}; known: {', '.join(REDUCED)}")
    ss = plant(mech, current_bandwidth_hz)
    num, den = REDUCED[name]
    h = freqresp_ss(ss, f_hz, num)
    if den is not None:
        h = h / freqresp_ss(ss, f_hz, den)
    return h


def block_freqresp(mech: AxisMechanics, name: str, f_hz) -> np.ndarray:
    """Closed-form block transfer functions G_m, G_L, G_t, G_b, G_h (eqs. 1-4, 9).

    Parameters
    ----------
    mech : AxisMechanics
        Axis parameters [SI].
    name : str
        One of ``G_m, G_L, G_t, G_b, G_h`` [-].
    f_hz : array_like
        Frequencies [Hz].
    """
    s = 2j * np.pi * np.atleast_1d(np.asarray(f_hz, dtype=float))
    m = mech
    table = {
        "G_m": lambda: 1 / (m.J_m * s + m.B_m),
        "G_L": lambda: 1 / (m.J_L * s**2 + m.B_L * s),
        "G_t": lambda: 1 / (m.M_t * s**2 + m.C_t * s),
        "G_b": lambda: -1 / (m.M_b * s**2 + m.C_b * s + m.K_b),
        "G_h": lambda: 1 / (m.M_h * s**2 + m.C_h * s + m.K_h),
    }
    if name not in table:
        raise KeyError(f"unknown block {name!r}; known: {', '.join(table)}")
    return table[name]()


def g_t_closed_form(mech: AxisMechanics, f_hz) -> np.ndarray:
    """The corrected eq. (6): G_T from the block transfer functions [m/rad]."""
    GL = block_freqresp(mech, "G_L", f_hz)
    D = block_freqresp(mech, "G_t", f_hz) - block_freqresp(mech, "G_b", f_hz)
    m = mech
    num = GL * m.K_L * m.K_t * m.R_L * D
    den = (1 + GL * m.K_L) * (1 + m.K_t * D) + GL * m.K_t * m.R_L**2
    return num / den


def g_tcp_closed_form(mech: AxisMechanics, f_hz) -> np.ndarray:
    """Eq. (10): G_tcp = (G_t - G_h)/(G_t - G_b) [-]."""
    Gt = block_freqresp(mech, "G_t", f_hz)
    return (Gt - block_freqresp(mech, "G_h", f_hz)) / (Gt - block_freqresp(mech, "G_b", f_hz))


def to_control_tf(mech: AxisMechanics, name: str, current_bandwidth_hz=None):
    """A reduced or block transfer function for python-control.

    Reduced models (G_M, G_T, G_tcp) are minimal named state spaces from the plant
    (:func:`tcpmm.mechanics.export.reduced_ss`), returned as ``control.StateSpace``:
    a polynomial of their order would lose the poles to rounding. Blocks come from their
    closed forms as ``control.TransferFunction``.
    """
    import control  # python-control is slow to import and needed only here

    m = mech
    blocks = {
        "G_m": ([1.0], [m.J_m, m.B_m]),
        "G_L": ([1.0], [m.J_L, m.B_L, 0.0]),
        "G_t": ([1.0], [m.M_t, m.C_t, 0.0]),
        "G_b": ([-1.0], [m.M_b, m.C_b, m.K_b]),
        "G_h": ([1.0], [m.M_h, m.C_h, m.K_h]),
    }
    if name in blocks:
        return control.tf(*blocks[name])
    if name not in REDUCED:
        raise KeyError(f"unknown transfer function {name!r}; known: "
                       f"{', '.join([*REDUCED, *blocks])}")
    return to_control(reduced_ss(mech, name, current_bandwidth_hz), name=name)
