"""G_M, G_T and G_tcp of the five-inertia axis by the block algebra of its equations of
motion (physics.md section 1): cheap enough to be evaluated at every step of a least-squares
fit."""

from __future__ import annotations

import numpy as np

from ...mechanics.lumped import AxisMechanics

__all__ = ["model_frfs", "nut_path", "zoh"]


def nut_path(mech: AxisMechanics, s, K_t=None):
    """Block algebra of the table side at Laplace points ``s``.

    Parameters
    ----------
    mech : AxisMechanics
        Parameters [SI].
    s : numpy.ndarray
        Laplace points ``j 2 pi f`` [rad/s].
    K_t : float or numpy.ndarray, optional
        Nut stiffness, per point if it varies; default ``mech.K_t`` [N/m].

    Returns
    -------
    tuple of numpy.ndarray
        The table's impedance ``M_t s^2 + C_t s`` [N/m], the compliance between table and
        bed under the nut force ``D = G_t - G_b`` [m/N], and the screw's load-side
        impedance ``Z_L`` seen through the nut [N m/rad].
    """
    m = mech
    K_t = m.K_t if K_t is None else K_t
    den_t = m.M_t * s**2 + m.C_t * s
    D = 1 / den_t + 1 / (m.M_b * s**2 + m.C_b * s + m.K_b)
    ZL = m.J_L * s**2 + m.B_L * s + K_t * m.R_L**2 / (1 + K_t * D)
    return den_t, D, ZL


def model_frfs(mech: AxisMechanics, freqs: dict, current_bandwidth_hz=None,
               hold_period_s: float = 0.0, nut_gain=None) -> dict:
    """G_M, G_T, G_tcp of a mechanics at the frequencies of each FRF.

    Uses the block algebra of the equations of motion (equal to the state-space
    responses, see the tests); vectorised, so cheap enough for least squares.

    Parameters
    ----------
    mech : AxisMechanics
        Parameters [SI].
    freqs : dict
        Frequencies per transfer-function name [Hz].
    current_bandwidth_hz : float, optional
        First-order current loop in G_M [Hz].
    hold_period_s : float
        The drive holds the current command over its velocity-loop period; seen from
        the sampled command this is a zero-order hold in G_M [s].
    nut_gain : callable, optional
        ``nut_gain(f)``: factor on ``K_t`` per frequency, the nut's lost motion as the
        excitation sees it (:func:`tcpmm.ident.friction.playdf.play_gain`) [-].
    """
    out = {}
    m = mech
    R = m.R_L
    for name, f in freqs.items():
        s = 2j * np.pi * np.asarray(f, dtype=float)
        K_t = m.K_t if nut_gain is None or name == "G_tcp" else m.K_t * nut_gain(f)
        den_t, D, ZL = nut_path(m, s, K_t)
        if name == "G_tcp":
            den_h = m.M_h * s**2 + m.C_h * s + m.K_h
            out[name] = (1 / den_t - 1 / den_h) / D
            continue
        KtD = K_t * D
        if name == "G_T":
            out[name] = (m.K_L / (ZL + m.K_L)) * R * KtD / (1 + KtD)
            continue
        Zm = m.K_L * ZL / (ZL + m.K_L)
        G_M = m.K_tc * s / (m.J_m * s**2 + m.B_m * s + Zm)
        if current_bandwidth_hz is not None:
            G_M = G_M / (1 + s / (2 * np.pi * current_bandwidth_hz))
        if hold_period_s > 0:
            G_M = G_M * zoh(s, hold_period_s)
        out[name] = G_M
    return out


def zoh(s, T):
    """Zero-order hold (1 - exp(-sT))/(sT) [-]."""
    x = s * T
    return np.where(np.abs(x) < 1e-8, 1.0 - x / 2, -np.expm1(-x) / np.where(x == 0, 1, x))

