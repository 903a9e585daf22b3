"""Analytic sensitivities of the physical model's FRFs to its log-parameters.

The chain rule through the block algebra of :func:`tcpmm.ident.physical.axisfrfs.model_frfs`:
``d log G / d log p`` for every parameter at once, one row per parameter. The least-squares
fit of the log-parameters gets its Jacobian from these in a few array operations per FRF,
where a finite-difference Jacobian costs one model evaluation per parameter.
"""

from __future__ import annotations

import numpy as np

from ...mechanics.lumped import AxisMechanics

#: Rows of :func:`log_sensitivities`: the mechanics parameters the fit may take, then the
#: current-loop bandwidth ``f_i``.
PARAMS = ("J_m", "B_m", "J_L", "B_L", "K_L", "M_t", "C_t", "K_t", "M_b", "C_b", "K_b",
          "M_h", "C_h", "K_h", "f_i")


def _kept(row: dict, n: int, **terms) -> dict:
    """Those ``terms`` that have a row in ``row``, each as a complex row of ``n`` bins [-]."""
    out = {}
    for p, v in terms.items():
        if p in row:
            out[p] = np.empty(n, dtype=complex)
            out[p][:] = v
    return out


def _nut_side(m: AxisMechanics, s, row: dict):
    """Table and bed admittances and their log-parameter derivatives, the latter by
    parameter [m/N]."""
    n = s.size
    den_t = m.M_t * s**2 + m.C_t * s
    den_b = m.M_b * s**2 + m.C_b * s + m.K_b
    d_den_t = _kept(row, n, M_t=m.M_t * s**2, C_t=m.C_t * s)
    d_den_b = _kept(row, n, M_b=m.M_b * s**2, C_b=m.C_b * s, K_b=np.full(n, m.K_b))
    D = 1 / den_t + 1 / den_b
    t2, b2 = den_t**2, den_b**2
    dD = {p: -v / t2 for p, v in d_den_t.items()}
    dD.update({p: -(v / b2) for p, v in d_den_b.items()})
    return den_t, d_den_t, D, dD


def log_sensitivities(mech: AxisMechanics, name: str, f_hz, current_bandwidth_hz=None,
                      nut_gain=None, params=PARAMS) -> np.ndarray:
    """``d log G / d log p`` of one FRF of :func:`~tcpmm.ident.physical.axisfrfs.model_frfs`.

    The zero-order hold does not depend on any parameter and drops out. Each row is the
    chain rule's sum over the terms that depend on its parameter: the terms that do not
    are zero and are left out of it.

    Parameters
    ----------
    mech : AxisMechanics
        Parameters [SI].
    name : str
        ``"G_M"``, ``"G_T"`` or ``"G_tcp"`` [-].
    f_hz : numpy.ndarray
        Frequencies [Hz].
    current_bandwidth_hz : float, optional
        First-order current loop in G_M [Hz].
    nut_gain : callable, optional
        Factor on ``K_t`` per frequency, as in ``model_frfs`` [-].
    params : sequence of str, optional
        The rows wanted, each in :data:`PARAMS`: every value is computed by the same
        operations whichever rows are left out [-].

    Returns
    -------
    numpy.ndarray
        Complex sensitivities, one row per entry of ``params``, one column per
        frequency [-].
    """
    m = mech
    f = np.asarray(f_hz, dtype=float)
    s = 2j * np.pi * f
    row = {p: i for i, p in enumerate(params)}
    den_t, d_den_t, D, dD = _nut_side(m, s, row)
    if name == "G_tcp":
        rows = _tcp_rows(m, s, row, den_t, d_den_t, D, dD)
    else:
        K_t = m.K_t if nut_gain is None else m.K_t * nut_gain(f)
        rows = _screw_rows(m, s, row, name, K_t, D, dD)
    out = np.zeros((len(row), s.size), dtype=complex)
    for p, v in rows.items():
        out[row[p]] = v
    if name not in ("G_tcp", "G_T") and current_bandwidth_hz is not None and "f_i" in row:
        x = s / (2 * np.pi * current_bandwidth_hz)
        out[row["f_i"]] = x / (1 + x)
    return out


def _tcp_rows(m, s, row, den_t, d_den_t, D, dD) -> dict:
    """The rows of ``G_tcp``: the table's and the headstock's admittances over ``D``."""
    den_h = m.M_h * s**2 + m.C_h * s + m.K_h
    d_den_h = _kept(row, s.size, M_h=m.M_h * s**2, C_h=m.C_h * s, K_h=np.full(s.size, m.K_h))
    A = 1 / den_t - 1 / den_h
    t2, h2 = den_t**2, den_h**2
    rows = {p: -(dD[p] / D) for p in dD}
    rows.update({p: -v / t2 / A - dD[p] / D for p, v in d_den_t.items()})
    rows.update({p: v / h2 / A for p, v in d_den_h.items()})
    return rows


def _screw_rows(m, s, row, name, K_t, D, dD) -> dict:
    """The rows of ``G_T`` or ``G_M``: the screw's load through the nut, and the motor."""
    n = s.size
    R2 = m.R_L**2
    KtD = K_t * D
    dKt = _kept(row, n, K_t=np.broadcast_to(K_t, s.shape))
    dKtD = {p: v * D for p, v in dKt.items()}
    dKtD.update({p: K_t * v for p, v in dD.items()})
    q = 1 + KtD
    q2 = q**2
    ZL = m.J_L * s**2 + m.B_L * s + K_t * R2 / q
    dZL = {p: R2 * -(K_t * v / q2) for p, v in dKtD.items()}
    dZL.update({p: R2 * (v / q - K_t * dKtD[p] / q2) for p, v in dKt.items()})
    dZL.update(_kept(row, n, J_L=m.J_L * s**2, B_L=m.B_L * s))
    dKL = _kept(row, n, K_L=np.full(n, m.K_L))
    if name == "G_T":
        ZK, KKD = ZL + m.K_L, KtD * q
        rows = {p: -(v / ZK) for p, v in dZL.items()}
        rows.update({p: rows[p] + v / KKD for p, v in dKtD.items()})
        rows.update({p: v / m.K_L - v / ZK for p, v in dKL.items()})
        return rows
    Zm = m.K_L * ZL / (ZL + m.K_L)
    Zm2, ZL2 = Zm**2, ZL**2
    dZm = {p: Zm2 * (v / ZL2) for p, v in dZL.items()}
    dZm.update({p: Zm2 * (v / m.K_L**2) for p, v in dKL.items()})
    den_m = m.J_m * s**2 + m.B_m * s + Zm
    rows = {p: -v / den_m for p, v in dZm.items()}
    rows.update({p: -v / den_m for p, v in _kept(row, n, J_m=m.J_m * s**2,
                                                    B_m=m.B_m * s).items()})
    return rows


def residual_jacobian(mech: AxisMechanics, freqs: dict, weights: dict, residual,
                      names, tied: dict, current_bandwidth_hz=None,
                      nut_gain=None, pairs: dict | None = None) -> np.ndarray:
    """Jacobian of the stacked log residuals of :func:`~tcpmm.ident.physical.fitdata.log_residual`
    with respect to the fitted log-parameters.

    Parameters
    ----------
    mech : AxisMechanics
        Parameters at which to differentiate [SI].
    freqs, weights : dict
        Frequencies [Hz] and weights [-] per FRF, in the order of the residual.
    residual : numpy.ndarray
        The residual at ``mech``; where it is not finite-valued (the fallback 1e3) its
        rows are zero [-].
    names : sequence of str
        Fitted parameters, the columns [-].
    tied : dict
        Parameters held in proportion to ``M_t``; they move with its column [-].
    current_bandwidth_hz : float, optional
        Current-loop bandwidth [Hz].
    nut_gain : callable, optional
        Factor on ``K_t`` per frequency [-].
    pairs : dict, optional
        Model values at ``freqs`` where these are the two points per bin of
        :meth:`~tcpmm.ident.physical.fitdata.FRFData.band_points` and the residual
        compares the mean of each pair: the sensitivity of that mean [SI].

    Returns
    -------
    numpy.ndarray
        Real Jacobian, residuals by parameters [-].
    """
    # only the rows that reach the Jacobian: the others cost most of the arithmetic
    used = tuple(p for p in PARAMS if p in names or p in tied or (tied and p == "M_t"))
    row = {p: i for i, p in enumerate(used)}
    blocks = []
    for k, f in freqs.items():
        d = log_sensitivities(mech, k, f, current_bandwidth_hz, nut_gain, used)
        if pairs is not None:
            g, n = pairs[k], f.size // 2
            d = (g[:n] * d[:, :n] + g[n:] * d[:, n:]) / (g[:n] + g[n:])
        d = d * weights[k]
        blocks += [d.real, d.imag]
    S = np.concatenate(blocks, axis=1)
    if tied:
        S[row["M_t"]] += sum(S[row[p]] for p in tied)
    J = S[[row[p] for p in names]].T
    J[~np.isfinite(J).all(axis=1) | (residual == 1e3)] = 0.0
    return np.ascontiguousarray(J)
