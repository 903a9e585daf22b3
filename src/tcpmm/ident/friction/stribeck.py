"""Stribeck friction curve from constant-velocity runs.

The axis is moved back and forth at several constant speeds (``friction.csv``); the
plateaus of constant velocity are detected in both directions
(:func:`~tcpmm.ident.friction.plateaus.find_plateaus`), the force (or current) is averaged
on each, and the curve
``F(v) = sign(v) (Fc_d + (Fs_d - Fc_d) exp(-|v/vs|**delta)) + Fv v`` is fitted by
nonlinear least squares (``fit_stribeck``). ``identify_stribeck_run`` does both on a
record of time, position and effort; ``read_friction_csv`` and
``friction_record_arrays`` give that record from a ``friction.csv`` file.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import optimize

from tcpmm.errors import InputError

from ...io.bundle import read_friction_csv as read_record
from ..frf.signals import as_1d, central_difference, lowpass_filtfilt
from .estimate import ParameterEstimate
from .hump import HUMP_KEEP_REL_STD, without_undetermined_hump
from .plateaus import Plateau, find_plateaus

__all__ = [
    "HUMP_KEEP_REL_STD",
    "PLATEAU_DURATIONS_S",
    "NoPlateauError",
    "coulomb_stribeck",
    "fit_stribeck",
    "identify_stribeck_run",
    "read_friction_csv",
    "stribeck_curve",
    "without_undetermined_hump",
]


#: Shortest plateau durations tried in turn by :func:`identify_stribeck_run`, longest
#: first [s].
PLATEAU_DURATIONS_S = (0.2, 0.1, 0.05)


class NoPlateauError(InputError):
    """A record without constant-velocity passes long enough for a friction fit."""


def stribeck_curve(p, v, delta: float, tie: bool):
    """The Stribeck curve at velocities ``v`` [m/s] from the parameter vector ``p`` =
    ``(Fc+, Fc-, Fs+, Fs-, log10 vs, Fv)`` [N or A, log10 m/s, N s/m or A s/m], with the
    exponent ``delta`` [-]; ``tie`` takes ``Fs-`` as ``Fs+`` [-]. Returns the force with
    the sign of the velocity [N or A]."""
    fcp, fcn, fsp, fsn, logvs, fv = p
    if tie:
        fsn = fsp
    vs = 10.0**logvs
    e = np.exp(-(np.abs(v / vs) ** delta))
    return np.where(v > 0, fcp + (fsp - fcp) * e, -(fcn + (fsn - fcn) * e)) + fv * v


def _too_few_plateaus(velocity: np.ndarray, tie_static: bool) -> str | None:
    """What plateaus at these velocities [m/s] lack for the Stribeck fit, or ``None``
    when they determine it: two per direction and more than its parameters (5 with the
    static levels tied, else 6)."""
    npar = 5 if tie_static else 6
    npos, nneg = int((velocity > 0).sum()), int((velocity < 0).sum())
    if min(npos, nneg) >= 2 and velocity.size > npar:
        return None
    return (f"need plateaus in both directions (>= 2 each) and more than {npar} in all; got "
            f"{npos} positive and {nneg} negative; run more constant-speed passes")


def fit_stribeck(
    velocity, force, *, delta: float = 2.0, tie_static: bool = False, vs0=None
) -> ParameterEstimate:
    """Fit the asymmetric Stribeck curve to steady (velocity, force) pairs.

    ``F(v) = sign(v) (Fc_d + (Fs_d - Fc_d) exp(-|v/vs|**delta)) + Fv v``, with
    ``d = +`` for ``v > 0`` and ``-`` for ``v < 0``; both directions must be present.

    Parameters
    ----------
    velocity : array_like
        Plateau velocities, both signs [m/s].
    force : array_like
        Mean force (or current) on each plateau [N or A].
    delta : float
        Stribeck exponent, held fixed [-].
    tie_static : bool
        Fit one static level ``Fs`` for both directions [-].
    vs0 : float, optional
        Start value of the Stribeck velocity; default the smallest |velocity| [m/s].

    Returns
    -------
    ParameterEstimate
        Parameters ``Fc+, Fc-, Fs+, Fs-, vs, Fv`` (``Fs-`` equals ``Fs+`` and carries
        no separate std when tied) with standard deviations from the Jacobian
        (``sigma^2 (J^T J)^-1``) [-].
    """
    v = as_1d(velocity, "velocity")
    f = as_1d(force, "force")
    if v.size != f.size:
        raise InputError("velocity and force must have the same length", column="force")
    lacking = _too_few_plateaus(v, tie_static)
    if lacking is not None:
        raise InputError(lacking, column="velocity")
    vs_init = float(np.min(np.abs(v))) if vs0 is None else float(vs0)
    p0 = _start(v, f, vs_init)
    free = np.ones(6, dtype=bool)
    if tie_static:
        free[3] = False

    def resid(x):
        p = p0.copy()
        p[free] = x
        return stribeck_curve(p, v, delta, tie_static) - f

    lo = np.array([0.0, 0.0, 0.0, 0.0, math.log10(vs_init) - 3.0, 0.0])[free]
    hi = np.array([np.inf, np.inf, np.inf, np.inf, math.log10(np.max(np.abs(v))) + 1.0, np.inf])[
        free
    ]
    x0 = np.clip(p0[free], lo + 1e-12, hi - 1e-12)
    sol = optimize.least_squares(resid, x0, bounds=(lo, hi), x_scale="jac")
    p = p0.copy()
    p[free] = sol.x
    if tie_static:
        p[3] = p[2]
    return _estimate(p, free, sol, v, f, delta, tie_static)


def _start(v, f, vs_init: float) -> np.ndarray:
    """Start of the Stribeck fit to plateau velocities ``v`` [m/s] and forces ``f`` [N]:
    Coulomb and viscous levels by linear least squares on the faster half of each side,
    the static levels at the slowest plateau's force, the Stribeck speed ``vs_init``
    [m/s]; in the order of :func:`stribeck_curve` [-]."""
    fast = np.abs(v) >= np.median(np.abs(v))
    pos = ((v > 0) & fast).astype(float)
    neg = ((v < 0) & fast).astype(float)
    A = np.column_stack([pos, -neg, v * fast])
    c0, *_ = np.linalg.lstsq(A, f * fast, rcond=None)
    fcp0, fcn0, fv0 = max(c0[0], 0.0), max(c0[1], 0.0), max(c0[2], 0.0)
    slow_p = f[v > 0][np.argmin(v[v > 0])]
    slow_n = -f[v < 0][np.argmax(v[v < 0])]
    return np.array([fcp0, fcn0, max(slow_p, fcp0), max(slow_n, fcn0), math.log10(vs_init),
                     fv0])


def _estimate(p, free, sol, v, f, delta: float, tie_static: bool) -> ParameterEstimate:
    """The fitted parameters ``p`` (order of :func:`stribeck_curve`) with standard
    deviations from the Jacobian of the least-squares solution ``sol`` over the ``free``
    ones, as :func:`fit_stribeck` returns them [-]."""
    r = sol.fun
    dof = max(v.size - int(free.sum()), 1)
    sigma2 = float(r @ r) / dof
    J = sol.jac
    try:
        cov = sigma2 * np.linalg.inv(J.T @ J)
        sd_free = np.sqrt(np.abs(np.diag(cov)))
    except np.linalg.LinAlgError:
        sd_free = np.full(int(free.sum()), np.nan)
    sd = np.full(6, np.nan)
    sd[free] = sd_free
    vs = 10.0 ** p[4]
    sd_vs = vs * math.log(10.0) * sd[4]
    values = np.array([p[0], p[1], p[2], p[3], vs, p[5]])
    std = np.array([sd[0], sd[1], sd[2], sd[3] if not tie_static else sd[2], sd_vs, sd[5]])
    return ParameterEstimate(
        names=("Fc+", "Fc-", "Fs+", "Fs-", "vs", "Fv"),
        values=values,
        std=std,
        relative_error=float(100.0 * np.linalg.norm(r) / np.linalg.norm(f)),
        residual_std=math.sqrt(sigma2),
        condition=float(np.linalg.cond(J)) if J.size else float("nan"),
        n_samples=int(v.size),
        extra={"stribeck_delta": float(delta), "tie_static": bool(tie_static)},
    )


def coulomb_stribeck(curve: dict):
    """The Coulomb and Stribeck part (no viscous slope) of a fitted steady friction curve.

    Parameters
    ----------
    curve : dict
        Fitted values by name (``Fc+``, ``Fc-``, ``Fs+``, ``Fs-``, ``vs``), table units
        [N, m/s].

    Returns
    -------
    callable
        Friction at a velocity array, with the sign of the velocity [N].
    """
    p = (curve["Fc+"], curve["Fc-"], curve["Fs+"], curve["Fs-"],
         np.log10(max(float(curve["vs"]), 1e-6)), 0.0)

    def part(vel):
        return stribeck_curve(p, vel, 2.0, False)

    return part


def identify_stribeck_run(t, position, effort, *, cutoff: float = 20.0, delta: float = 2.0,
                          tie_static: bool = False, v_min: float | None = None,
                          rel_tol: float = 0.05, min_duration: float | None = None,
                          trim: float = 0.1):
    """Stribeck curve from a record of back-and-forth runs at constant speeds.

    Plateaus are looked for with the shortest duration ``min_duration``; by default with
    each of :data:`PLATEAU_DURATIONS_S` in turn, down to the first that finds enough for the
    fit (two per direction and more than the fitted parameters), so that passes of 0.3 s
    or less are used too and records of longer passes keep the longest duration.

    Parameters
    ----------
    t : array_like
        Time, uniformly sampled [s].
    position : array_like
        Axis position [m].
    effort : array_like
        Force or current command [N or A]; the fitted levels are in this unit.
    cutoff : float
        Low-pass cut-off applied to the position before differentiation [Hz].
    delta : float
        Stribeck exponent [-].
    tie_static : bool
        One static level for both directions [-].
    v_min, rel_tol, min_duration, trim
        Plateau detection settings, see ``find_plateaus`` ([m/s], [-], [s], [-]);
        ``min_duration=None`` tries :data:`PLATEAU_DURATIONS_S`.

    Returns
    -------
    tuple
        ``(ParameterEstimate, list of Plateau)`` [-].
    """
    t = as_1d(t, "t")
    x = as_1d(position, "position")
    u = as_1d(effort, "effort")
    if not (t.size == x.size == u.size):
        raise InputError("time, position and effort must have the same length", column="effort")
    dts = np.diff(t)
    dt = float(np.median(dts))
    if dt <= 0 or np.max(np.abs(dts - dt)) > 0.01 * dt:
        raise InputError("time must increase with a uniform step (1 % tolerance)", column="time_s")
    v = central_difference(lowpass_filtfilt(x, dt, cutoff), dt)
    plateaus = _plateaus_for_fit(t, v, u, tie_static, min_duration, v_min=v_min,
                                 rel_tol=rel_tol, trim=trim)
    est = fit_stribeck(
        [p.velocity for p in plateaus],
        [p.force for p in plateaus],
        delta=delta,
        tie_static=tie_static,
    )
    return est, plateaus


def _plateaus_for_fit(t, v, u, tie_static: bool, min_duration, **detect) -> list[Plateau]:
    """The plateaus of velocity ``v`` [m/s] and effort ``u`` [N or A] found with the
    shortest duration ``min_duration`` [s], or with the first of :data:`PLATEAU_DURATIONS_S`
    that finds enough for the fit; ``detect`` the other settings of
    :func:`~tcpmm.ident.friction.plateaus.find_plateaus` [-].

    Raises
    ------
    NoPlateauError
        When no plateau is found at all.
    """
    durations = PLATEAU_DURATIONS_S if min_duration is None else (min_duration,)
    for d in durations:
        plateaus = find_plateaus(t, v, u, min_duration=d, **detect)
        if _too_few_plateaus(np.array([p.velocity for p in plateaus]), tie_static) is None:
            break
    if not plateaus:
        raise NoPlateauError(
            f"no constant-velocity plateau of at least {durations[-1]} s found; record "
            "longer constant-speed passes or lower min_duration",
            column="position",
        )
    return plateaus


def read_friction_csv(path, lead: float, torque_constant: float, position: str = "scale"):
    """Read a ``friction.csv`` record (formats.md section 1) as time, position and force.

    Parameters
    ----------
    path : str or Path
        The CSV file with columns ``time_s, current_cmd_A, motor_angle_rad, scale_mm`` [-].
    lead : float
        Ball-screw lead per motor revolution [m].
    torque_constant : float
        Motor torque constant ``K_tc`` [N m/A].
    position : {"scale", "motor"}
        Position source: the linear scale, or the motor angle times ``lead / 2 pi`` [-].

    Returns
    -------
    tuple of numpy.ndarray
        ``(t, x, force)``: time [s], position [m] and the motor force at the table
        ``K_tc i 2 pi / lead`` (losses of the screw not included) [N].
    """
    return friction_record_arrays(read_record(path), lead, torque_constant, position)


def friction_record_arrays(record, lead: float, torque_constant: float, position: str = "scale"):
    """Time [s], position [m] and motor force at the table [N] of a ``FrictionRecord``.

    Parameters
    ----------
    record : FrictionRecord
        The record, SI [-].
    lead : float
        Ball-screw lead [m].
    torque_constant : float
        Motor torque constant [N m/A].
    position : {"scale", "motor"}
        Position source [-].
    """
    if position not in ("scale", "motor"):
        raise InputError(
            f"position must be 'scale' or 'motor', got {position!r}", column="position"
        )
    ratio = lead / (2 * np.pi)
    x = record.scale_m if position == "scale" else record.motor_angle_rad * ratio
    force = torque_constant * record.current_cmd_A / ratio
    return record.time_s, x, force
