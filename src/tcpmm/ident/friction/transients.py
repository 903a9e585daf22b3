"""Stribeck curve from the whole friction record, accelerations included.

The plateaus of constant speed give a handful of points of the steady friction curve, and
the slowest of them sits at or above the Stribeck speed of many guides: fitted to the
plateaus alone, static level and Stribeck speed are then an extrapolation that only fixes
a combination of the two (a static level a hundred times the Coulomb level with a Stribeck
speed far below the slowest run fits as well as the truth). Between the plateaus the axis
accelerates from rest and brakes to rest, passing through every speed below the slowest
plateau; there the motor force is ``M a + F(v)``.

:func:`fit_stribeck_transients` fits that rigid-body inverse model to the whole record
(IDIM with parallel filtering): the regressors are formed on the lightly smoothed motion and
low-passed like the force (below the drive's first mode), and for a given Stribeck speed a
bounded linear least-squares fit gives ``M``, the Coulomb levels, the static excess over
them and the viscous slope. While the axis rests the friction holds whatever force the
loop applies, up to the static level, which the steady curve does not describe: each rest
gets a force of its own, fitted with the rest, so that the low-pass smears the same force
into the samples around it in model and measurement. The Stribeck speed minimises the
profiled cost over a logarithmic grid, refined by a bounded scalar search. ``M`` is fitted,
not taken from the FRFs: a current logged in step with the interpolator carries a ripple
proportional to the acceleration, which a free ``M`` absorbs and a fixed one would put into
the friction.
"""

from __future__ import annotations

import math
from functools import partial

import numpy as np
from scipy.linalg import solve_triangular
from scipy.optimize import lsq_linear, minimize_scalar, nnls

from tcpmm.errors import InputError

from ..frf.signals import as_1d, central_difference, lowpass_filtfilt
from .estimate import ParameterEstimate

__all__ = ["fit_stribeck_transients"]

#: Slowest speed used in the fit: below it the axis is taken as at rest [m/s].
V_MIN = 1e-4
#: Range searched for the Stribeck speed [m/s].
VS_RANGE = (2e-5, 5e-2)
#: Cut-off of the light smoothing of the position before differencing [Hz].
LIGHT_CUTOFF_HZ = 150.0
#: Moving samples slower than the slowest plateau needed per direction [-].
MIN_SLOW_SAMPLES = 20
_NAMES = ("M", "Fc+", "Fc-", "dFs+", "dFs-", "Fv")


def _prepare(t, x, force, cutoff_hz, v_min):
    """Signals of the fit: the raw regressors (lightly smoothed motion), the low-passed force,
    the low-passed indicator of every rest, and the samples used."""
    dt = float(np.median(np.diff(t)))
    if dt <= 0 or np.max(np.abs(np.diff(t) - dt)) > 0.01 * dt:
        raise InputError("time must increase with a uniform step (1 % tolerance)",
                         column="time_s")
    light = min(LIGHT_CUTOFF_HZ, 0.4 / dt)
    v = central_difference(lowpass_filtfilt(x, dt, light), dt)
    a = central_difference(v, dt)
    moving = np.abs(v) > v_min
    edges = np.flatnonzero(np.diff(np.r_[0, (~moving).astype(int), 0]))
    rests = [(i0, i1) for i0, i1 in zip(edges[::2], edges[1::2], strict=True)]
    low = partial(lowpass_filtfilt, dt=dt, cutoff=cutoff_hz)
    rest_cols = np.zeros((t.size, len(rests)))
    for k, (i0, i1) in enumerate(rests):
        ind = np.zeros(t.size)
        ind[i0:i1] = 1.0
        rest_cols[:, k] = low(ind)
    pos = np.where(v > v_min, 1.0, 0.0)
    neg = np.where(v < -v_min, -1.0, 0.0)
    fixed = np.column_stack([low(a), low(pos), low(neg), low(v)])
    edge = min(max(round(0.1 / dt), 2), t.size // 4)
    use = np.ones(t.size, dtype=bool)
    use[:edge] = use[-edge:] = False
    return {"dt": dt, "v": v, "pos": pos, "neg": neg, "fixed": fixed, "rests": rest_cols,
            "f": low(force), "use": use, "low": low, "moving": moving}


def _stribeck_regressors(p, vs, delta):
    """The two regressors that depend on the Stribeck speed ``vs`` [m/s], low-passed, on
    every sample."""
    e = np.exp(-(np.abs(p["v"]) / vs) ** delta)
    return p["low"](p["pos"] * e), p["low"](p["neg"] * e)


def _matrix(p, vs, delta):
    """Low-passed regressors ``[M, Fc+, Fc-, dFs+, dFs-, Fv, rest forces...]`` at ``vs``."""
    fx = p["fixed"]
    cols = [fx[:, 0], fx[:, 1], fx[:, 2], *_stribeck_regressors(p, vs, delta), fx[:, 3]]
    return np.column_stack([*cols, p["rests"]])[p["use"]]


def _column_norms(A):
    """Euclidean norm of each column of ``A``, at least 1e-300: the scaling of the least
    squares [units of A]."""
    return np.maximum(np.sqrt(np.sum(A * A, axis=0)), 1e-300)


def _solve(p, vs, delta):
    """Bounded linear fit at one Stribeck speed: ``(theta, cost, A)``; the friction
    parameters are not negative, the forces held at rest are free."""
    A = _matrix(p, vs, delta)
    f = p["f"][p["use"]]
    scale = _column_norms(A)
    theta = np.linalg.lstsq(A / scale, f, rcond=None)[0]
    if np.any(theta[:len(_NAMES)] < 0.0):  # a bound is active: the bounded solution
        lo = np.r_[np.zeros(len(_NAMES)), np.full(A.shape[1] - len(_NAMES), -np.inf)]
        theta = lsq_linear(A / scale, f, bounds=(lo, np.inf), method="bvls").x
    theta = theta / scale
    e = f - A @ theta
    return theta, float(e @ e), A


def _profiled_cost(p, delta):
    """The fit's cost as a function of the Stribeck speed [m/s] -> [N^2].

    Only two regressors change with the speed: the others (mass, Coulomb levels, viscous
    slope and the forces at rest) are projected out once by a QR factorisation, and each
    speed solves for the two Stribeck excesses alone, not negative. Where that solution puts
    another friction parameter below zero, or the fixed regressors are near rank deficient,
    the cost is the bounded fit's, :func:`_solve`.
    """
    F = np.column_stack([p["fixed"], p["rests"]])[p["use"]]
    f = p["f"][p["use"]]
    scale = _column_norms(F)
    Q, R = np.linalg.qr(F / scale)
    d = np.abs(np.diag(R))
    if d.min() <= 1e-10 * d.max():
        return lambda vs: _solve(p, vs, delta)[1]
    qf = Q.T @ f
    fr = f - Q @ qf
    n_friction = p["fixed"].shape[1]  # mass, Coulomb levels, viscous slope: not negative

    def cost(vs):
        G = np.column_stack(_stribeck_regressors(p, vs, delta))[p["use"]]
        qg = Q.T @ G
        Gr = G - Q @ qg
        beta = np.linalg.lstsq(Gr, fr, rcond=None)[0]
        if np.any(beta < 0.0):
            beta = nnls(Gr, fr)[0]
        held = solve_triangular(R, qf - qg @ beta)[:n_friction] / scale[:n_friction]
        if np.any(held < 0.0):
            return _solve(p, vs, delta)[1]
        e = fr - Gr @ beta
        return float(e @ e)
    return cost


def _profile_min(p, delta):
    """Stribeck speed minimising the profiled cost: grid, then a bounded refinement.

    The grid only picks the bracket, so it takes the projected cost of
    :func:`_profiled_cost`; the refinement and the comparison with the grid's best point
    take the bounded fit's own cost, whose rounding the search's steps follow."""
    fast = _profiled_cost(p, delta)
    grid = np.logspace(math.log10(VS_RANGE[0]), math.log10(VS_RANGE[1]), 25)
    k = int(np.argmin([fast(vs) for vs in grid]))
    lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)]
    res = minimize_scalar(lambda lv: _solve(p, 10.0**lv, delta)[1],
                          bounds=(math.log10(lo), math.log10(hi)), method="bounded",
                          options={"xatol": 1e-4})
    return float(10.0 ** res.x) if res.fun <= _solve(p, grid[k], delta)[1] else float(grid[k])


def _log_vs_std(p, vs, delta, sigma2):
    """Standard deviation of ``ln vs`` from the curvature of the profiled cost."""
    h = 0.05
    c = [_solve(p, vs * math.exp(s * h), delta)[1] for s in (-1, 0, 1)]
    curv = (c[0] - 2.0 * c[1] + c[2]) / h**2
    return math.sqrt(2.0 * sigma2 / curv) if curv > 0 else float("inf")


def fit_stribeck_transients(t, position, force, *, slowest_plateau: float,
                            cutoff_hz: float = 30.0, v_min: float = V_MIN,
                            delta: float = 2.0) -> ParameterEstimate:
    """Steady friction curve and rigid-body mass from every moving sample of a record.

    Parameters
    ----------
    t : array_like
        Time, uniformly sampled [s].
    position : array_like
        Axis position, best the motor angle times ``R_L`` (finer than most scales) [m].
    force : array_like
        Motor force at the table [N].
    slowest_plateau : float
        Speed of the slowest constant-speed pass; the fit needs motion below it in both
        directions, where the accelerations show the Stribeck hump [m/s].
    cutoff_hz : float
        Low-pass cut-off of position and force, below the drive's first mode [Hz].
    v_min : float
        Slowest speed used [m/s].
    delta : float
        Stribeck exponent [-].

    Returns
    -------
    ParameterEstimate
        ``Fc+, Fc-, Fs+, Fs-, vs, Fv`` as :func:`tcpmm.ident.friction.stribeck.fit_stribeck` names
        them ([N], [N], [N], [N], [m/s], [N s/m]); ``extra`` holds the fitted mass ``M``
        [kg] with its std and the settings. Standard deviations count the samples the
        low-pass leaves independent (``2 cutoff dt`` of them) [-].

    Raises
    ------
    InputError
        When the record has too little motion below the slowest plateau in a direction.
    """
    t, x, u = as_1d(t, "t"), as_1d(position, "position"), as_1d(force, "force")
    p = _prepare(t, x, u, cutoff_hz, v_min)
    _require_slow_motion(p["v"][p["moving"]], slowest_plateau)
    vs = _profile_min(p, delta)
    return _estimate(p, vs, delta, cutoff_hz, v_min)


def _require_slow_motion(v, slowest_plateau: float) -> None:
    """Refuse a record whose moving samples ``v`` [m/s] pass below the slowest plateau
    [m/s] in fewer than :data:`MIN_SLOW_SAMPLES` in either direction: there the
    accelerations do not show the Stribeck hump."""
    slow = np.abs(v) < slowest_plateau
    n_pos, n_neg = int(np.sum(slow & (v > 0))), int(np.sum(slow & (v < 0)))
    if min(n_pos, n_neg) < MIN_SLOW_SAMPLES:
        raise InputError(f"the friction runs move below their slowest pass in too few samples "
                         f"({n_pos} positive, {n_neg} negative; at least {MIN_SLOW_SAMPLES} "
                         "each): the accelerations do not show the Stribeck hump")


def _estimate(p, vs: float, delta: float, cutoff_hz: float, v_min: float) -> ParameterEstimate:
    """The fit at the Stribeck speed ``vs`` [m/s] as :func:`fit_stribeck_transients`
    returns it, the covariance inflated by the residuals' correlation over
    ``1 / (2 cutoff_hz)`` [s]; ``delta`` [-] and ``v_min`` [m/s] as there [-]."""
    theta, cost, A = _solve(p, vs, delta)
    n = A.shape[0]
    n_eff = max(n * min(2.0 * cutoff_hz * p["dt"], 1.0), A.shape[1] + 1.0)
    sigma2 = cost / max(n - A.shape[1], 1)
    inflate = n / n_eff  # residuals are correlated over 1 / (2 cutoff)
    try:
        cov = inflate * sigma2 * np.linalg.inv(A.T @ A)
    except np.linalg.LinAlgError:
        cov = np.full((A.shape[1], A.shape[1]), np.nan)
    sd_lnvs = math.sqrt(inflate) * _log_vs_std(p, vs, delta, sigma2)
    theta = theta[:len(_NAMES)]
    f = p["f"][p["use"]]
    M, fcp, fcn, dsp, dsn, fv = theta
    sd = np.sqrt(np.abs(np.diag(cov)))
    sd_fsp = math.sqrt(abs(cov[1, 1] + cov[3, 3] + 2 * cov[1, 3]))
    sd_fsn = math.sqrt(abs(cov[2, 2] + cov[4, 4] + 2 * cov[2, 4]))
    return ParameterEstimate(
        names=("Fc+", "Fc-", "Fs+", "Fs-", "vs", "Fv"),
        values=np.array([fcp, fcn, fcp + dsp, fcn + dsn, vs, fv]),
        std=np.array([sd[1], sd[2], sd_fsp, sd_fsn, vs * sd_lnvs, sd[5]]),
        relative_error=float(100.0 * math.sqrt(cost) / np.linalg.norm(f)),
        residual_std=math.sqrt(sigma2),
        condition=float(np.linalg.cond(A / np.sqrt(np.sum(A * A, axis=0)))),
        n_samples=int(f.size),
        extra={"source": "transients", "M": float(M), "M_std": float(sd[0]),
               "cutoff_hz": float(cutoff_hz), "v_min": float(v_min),
               "stribeck_delta": float(delta)},
    )
