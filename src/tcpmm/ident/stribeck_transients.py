"""Stribeck curve from the whole friction record, accelerations included.

The plateaus of constant speed give a handful of points of the steady friction curve, and
the slowest of them sits at or above the Stribeck speed of many guides: fitted to the
plateaus alone, static level and Stribeck speed are then an extrapolation that only fixes
a combination of the two (a static level a hundred times the Coulomb level with a Stribeck
speed far below the slowest run fits as well as the truth). Between the plateaus the axis
accelerates from rest and brakes to rest, passing through every speed below the slowest
plateau; there the motor force is ``M a + F(v)``.

:func:`fit_stribeck_transients` fits that rigid-body inverse model to every moving sample
(IDIM): zero-phase low-pass of position and force alike (below the drive's first mode),
central differences for velocity and acceleration, and for a given Stribeck speed a
bounded linear least-squares fit of ``M``, the Coulomb levels, the static excess over them
and the viscous slope. The Stribeck speed minimises the profiled cost over a logarithmic
grid, refined by a bounded scalar search. ``M`` is fitted, not taken from the FRFs: a
current logged in step with the interpolator carries a ripple proportional to the
acceleration, which a free ``M`` absorbs and a fixed one would put into the friction.
Samples slower than ``v_min`` are left out: at rest the friction is anything up to the
static level, which the steady curve does not describe.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import lsq_linear, minimize_scalar

from tcpmm.errors import InputError

from .estimate import ParameterEstimate
from .signals import _as_1d, central_difference, lowpass_filtfilt

__all__ = ["fit_stribeck_transients"]

#: Slowest speed used in the fit: below it the axis is taken as at rest [m/s].
V_MIN = 1e-4
#: Range searched for the Stribeck speed [m/s].
VS_RANGE = (2e-5, 5e-2)
#: Moving samples slower than the slowest plateau needed per direction [-].
MIN_SLOW_SAMPLES = 20
_NAMES = ("M", "Fc+", "Fc-", "dFs+", "dFs-", "Fv")


def _columns(a, v, vs, delta):
    pos = (v > 0.0).astype(float)
    neg = -(v < 0.0).astype(float)
    e = np.exp(-(np.abs(v) / vs) ** delta)
    return np.column_stack([a, pos, neg, pos * e, neg * e, v])


def _solve(a, v, f, vs, delta):
    """Bounded linear fit at one Stribeck speed: ``(theta, cost, A)``."""
    A = _columns(a, v, vs, delta)
    scale = np.maximum(np.sqrt(np.sum(A * A, axis=0)), 1e-300)
    r = lsq_linear(A / scale, f, bounds=(0.0, np.inf), method="bvls")
    theta = r.x / scale
    e = f - A @ theta
    return theta, float(e @ e), A


def _profile_min(a, v, f, delta):
    """Stribeck speed minimising the profiled cost: grid, then a bounded refinement."""
    grid = np.logspace(math.log10(VS_RANGE[0]), math.log10(VS_RANGE[1]), 49)
    costs = np.array([_solve(a, v, f, vs, delta)[1] for vs in grid])
    k = int(np.argmin(costs))
    lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)]
    res = minimize_scalar(lambda lv: _solve(a, v, f, 10.0**lv, delta)[1],
                          bounds=(math.log10(lo), math.log10(hi)), method="bounded",
                          options={"xatol": 1e-4})
    return float(10.0 ** res.x) if res.fun <= costs[k] else float(grid[k])


def _log_vs_std(a, v, f, vs, delta, sigma2):
    """Standard deviation of ``ln vs`` from the curvature of the profiled cost."""
    h = 0.05
    c = [_solve(a, v, f, vs * math.exp(s * h), delta)[1] for s in (-1, 0, 1)]
    curv = (c[0] - 2.0 * c[1] + c[2]) / h**2
    return math.sqrt(2.0 * sigma2 / curv) if curv > 0 else float("inf")


def _moving_samples(t, x, force, cutoff_hz, v_min):
    dt = float(np.median(np.diff(t)))
    if dt <= 0 or np.max(np.abs(np.diff(t) - dt)) > 0.01 * dt:
        raise InputError("time must increase with a uniform step (1 % tolerance)",
                         column="time_s")
    xf = lowpass_filtfilt(x, dt, cutoff_hz)
    v = central_difference(xf, dt)
    a = central_difference(v, dt)
    f = lowpass_filtfilt(force, dt, cutoff_hz)
    edge = min(max(round(0.1 / dt), 2), t.size // 4)
    use = np.abs(v) > v_min
    use[:edge] = False
    use[-edge:] = False
    return a[use], v[use], f[use], dt


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
        ``Fc+, Fc-, Fs+, Fs-, vs, Fv`` as :func:`tcpmm.ident.friction.fit_stribeck` names
        them ([N], [N], [N], [N], [m/s], [N s/m]); ``extra`` holds the fitted mass ``M``
        [kg] with its std and the settings. Standard deviations count the samples the
        low-pass leaves independent (``2 cutoff dt`` of them) [-].

    Raises
    ------
    InputError
        When the record has too little motion below the slowest plateau in a direction.
    """
    t, x, u = _as_1d(t, "t"), _as_1d(position, "position"), _as_1d(force, "force")
    a, v, f, dt = _moving_samples(t, x, u, cutoff_hz, v_min)
    slow = np.abs(v) < slowest_plateau
    n_pos, n_neg = int(np.sum(slow & (v > 0))), int(np.sum(slow & (v < 0)))
    if min(n_pos, n_neg) < MIN_SLOW_SAMPLES:
        raise InputError(f"the friction runs move below their slowest pass in too few samples "
                         f"({n_pos} positive, {n_neg} negative; at least {MIN_SLOW_SAMPLES} "
                         "each): the accelerations do not show the Stribeck hump")
    vs = _profile_min(a, v, f, delta)
    theta, cost, A = _solve(a, v, f, vs, delta)
    n_eff = max(f.size * min(2.0 * cutoff_hz * dt, 1.0), len(_NAMES) + 1.0)
    sigma2 = cost / max(f.size - len(_NAMES), 1)
    inflate = f.size / n_eff  # residuals are correlated over 1 / (2 cutoff)
    try:
        cov = inflate * sigma2 * np.linalg.inv(A.T @ A)
    except np.linalg.LinAlgError:
        cov = np.full((len(_NAMES), len(_NAMES)), np.nan)
    sd_lnvs = math.sqrt(inflate) * _log_vs_std(a, v, f, vs, delta, sigma2)
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


#: Range searched for the pre-sliding displacement [m].
PRESLIDING_RANGE = (5e-8, 3e-5)


def lugre_contact(curve: dict, presliding: float, mass: float, damping_ratio: float):
    """LuGre contact with the levels of a steady curve and the bristles of a pre-sliding
    displacement: ``sigma0 = Fs / presliding``, micro-damping ``2 zeta sqrt(sigma0 m)``
    fading with speed as the Stribeck hump does.

    Parameters
    ----------
    curve : dict
        ``Fc+, Fc-, Fs+, Fs-, vs`` [N, N, N, N, m/s].
    presliding : float
        Pre-sliding displacement at the static level [m].
    mass : float
        Mass the bristles damp [kg].
    damping_ratio : float
        Bristle damping ratio [-].

    Returns
    -------
    LuGreFriction
        Without viscous part [-].
    """
    from ..mechanics.friction import LuGreFriction

    fs = max(curve["Fs+"], curve["Fs-"], curve["Fc+"], curve["Fc-"])
    sigma0 = fs / presliding
    return LuGreFriction(fc_pos=curve["Fc+"], fc_neg=curve["Fc-"], fs_pos=curve["Fs+"],
                         fs_neg=curve["Fs-"], vs=curve["vs"], sigma0=sigma0,
                         sigma1=2.0 * damping_ratio * math.sqrt(sigma0 * mass),
                         sigma1_fades=True)


def _presliding_cost(d, path, curve, dt, cutoff_hz, a, v, f, use, mass, zeta):
    from ..mechanics.friction import friction_params_array
    from ..sim.lugre_path import lugre_path_force

    p = friction_params_array(lugre_contact(curve, d, mass, zeta))
    fl = lowpass_filtfilt(lugre_path_force(path, dt, p, 0.0), dt, cutoff_hz)
    A = np.column_stack([a, v])[use]
    y = (f - fl)[use]
    theta, *_ = np.linalg.lstsq(A, y, rcond=None)
    e = y - A @ theta
    return float(e @ e)


def fit_presliding(t, position, force, curve: dict, *, mass: float, cutoff_hz: float = 30.0,
                   damping_ratio: float = 0.5):
    """Pre-sliding displacement from the force at the reversals of a friction record.

    After a reversal a contact builds its friction up over the pre-sliding displacement;
    the motor force there, low-passed as in :func:`fit_stribeck_transients`, follows a
    LuGre contact with the fitted steady curve driven by the recorded displacement of each
    sample. The displacement minimises the misfit of the whole record (rest included),
    with ``M`` and the viscous slope fitted again for each; profiled over a logarithmic
    grid and refined.

    Parameters
    ----------
    t : array_like
        Time, uniformly sampled [s].
    position : array_like
        Axis position (the motor angle times ``R_L``) [m].
    force : array_like
        Motor force at the table [N].
    curve : dict
        The steady curve, ``Fc+, Fc-, Fs+, Fs-, vs`` [N, N, N, N, m/s].
    mass : float
        Mass the bristles damp (the axis's rigid-body mass at the table) [kg].
    cutoff_hz : float
        Low-pass cut-off [Hz].
    damping_ratio : float
        Bristle damping ratio [-].

    Returns
    -------
    tuple of float
        ``(presliding, std)``: the displacement and one standard deviation; the std is
        ``inf`` when the cost has no minimum inside the searched range [m].
    """
    t, x, u = _as_1d(t, "t"), _as_1d(position, "position"), _as_1d(force, "force")
    dt = float(np.median(np.diff(t)))
    xf = lowpass_filtfilt(x, dt, cutoff_hz)
    v = central_difference(xf, dt)
    a = central_difference(v, dt)
    f = lowpass_filtfilt(u, dt, cutoff_hz)
    path = np.r_[np.diff(x), 0.0] / dt  # each sample's own displacement, held
    edge = min(max(round(0.1 / dt), 2), t.size // 4)
    use = np.ones(t.size, dtype=bool)
    use[:edge] = False
    use[-edge:] = False
    args = (path, curve, dt, cutoff_hz, a, v, f, use, mass, damping_ratio)
    grid = np.logspace(math.log10(PRESLIDING_RANGE[0]), math.log10(PRESLIDING_RANGE[1]), 29)
    costs = np.array([_presliding_cost(d, *args) for d in grid])
    k = int(np.argmin(costs))
    if k in (0, grid.size - 1):
        return float(grid[k]), float("inf")
    res = minimize_scalar(lambda ld: _presliding_cost(10.0**ld, *args),
                          bounds=(math.log10(grid[k - 1]), math.log10(grid[k + 1])),
                          method="bounded", options={"xatol": 1e-3})
    d = float(10.0**res.x) if res.fun <= costs[k] else float(grid[k])
    n = int(use.sum())
    sigma2 = _presliding_cost(d, *args) / max(n - 3, 1)
    inflate = 1.0 / min(2.0 * cutoff_hz * dt, 1.0)
    h = 0.05
    c = [_presliding_cost(d * math.exp(s * h), *args) for s in (-1, 0, 1)]
    curv = (c[0] - 2.0 * c[1] + c[2]) / h**2
    sd_ln = math.sqrt(inflate * 2.0 * sigma2 / curv) if curv > 0 else float("inf")
    return d, d * sd_ln
