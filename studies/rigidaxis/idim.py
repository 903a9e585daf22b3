"""Inverse dynamic identification of a rigid axis by least squares (IDIM-LS).

``idim_ls`` fits ``tau = M q'' + F_friction(q') + offset`` to position and force
records: zero-phase Butterworth low-pass of the position, central differences for
``q'`` and ``q''``, optional parallel decimation of regressors and force, linear least
squares with standard deviations ``sigma^2 (W^T W)^-1``, ``sigma^2 = ||y - W theta||^2
/ (N - p)``. The default settings reproduce the EMPS benchmark's published script.
``friction_from_idim`` turns the estimate into a friction model and a force offset.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
from scipy import optimize

from tcpmm.errors import InputError
from tcpmm.ident.frf.signals import as_1d, central_difference, decimate, lowpass_filtfilt
from tcpmm.ident.friction.estimate import ParameterEstimate
from tcpmm.mechanics.friction import StribeckFriction

__all__ = ["friction_from_idim", "idim_ls"]


def _shift(y: np.ndarray, s: float) -> np.ndarray:
    if s == 0.0:
        return y
    idx = np.arange(y.size, dtype=float)
    return np.interp(idx - s, idx, y)


def _lstsq(W: np.ndarray, y: np.ndarray, names) -> ParameterEstimate:
    theta, *_ = np.linalg.lstsq(W, y, rcond=None)
    e = y - W @ theta
    n, p = W.shape
    dof = max(n - p, 1)
    sigma2 = float(e @ e) / dof
    try:
        cov = sigma2 * np.linalg.inv(W.T @ W)
        std = np.sqrt(np.abs(np.diag(cov)))
    except np.linalg.LinAlgError:
        std = np.full(p, np.nan)
    return ParameterEstimate(
        names=tuple(names),
        values=theta,
        std=std,
        relative_error=float(100.0 * np.linalg.norm(e) / np.linalg.norm(y)),
        residual_std=math.sqrt(sigma2),
        condition=float(np.linalg.cond(W)),
        n_samples=n,
    )


def _regressor(ddq, dq, friction, offset, vs, delta):
    pos = (dq > 0.0).astype(float)
    neg = (dq < 0.0).astype(float)
    cols = [ddq]
    names = ["M"]
    if friction == "symmetric":
        cols += [dq, np.sign(dq)]
        names += ["Fv", "Fc"]
        if vs is not None:
            cols.append(np.sign(dq) * np.exp(-(np.abs(dq / vs) ** delta)))
            names.append("dFs")
        if offset:
            cols.append(np.ones_like(dq))
            names.append("offset")
    else:
        cols += [dq * pos, pos, dq * neg, -neg]
        names += ["Fv+", "Fc+", "Fv-", "Fc-"]
        if vs is not None:
            e = np.exp(-(np.abs(dq / vs) ** delta))
            cols += [pos * e, -neg * e]
            names += ["dFs+", "dFs-"]
    return np.column_stack(cols), names


def idim_ls(
    q,
    force,
    dt: float,
    *,
    cutoff: float = 100.0,
    order: int = 4,
    decimation: int = 1,
    friction: str = "symmetric",
    offset: bool = True,
    stribeck_velocity=None,
    stribeck_delta: float = 2.0,
    force_shift: float = 0.0,
    skip: int = 49,
    v_min: float = 0.0,
) -> ParameterEstimate:
    """Inverse dynamic identification of a rigid axis by least squares (IDIM-LS).

    Model: ``force = M q'' + F_friction(q') [+ offset]`` with

    - ``friction="symmetric"``: ``Fv q' + Fc sign(q') [+ dFs sign(q') exp(-|q'/vs|^d)]``,
      parameters ``M, Fv, Fc, [dFs], [offset]``;
    - ``friction="asymmetric"``: ``Fv+ q'+ + Fc+ [q'>0] + Fv- q'- - Fc- [q'<0]`` (plus
      ``dFs+``/``dFs-`` Stribeck terms), parameters ``M, Fv+, Fc+, Fv-, Fc-, ...``. A
      constant offset is not separable from ``Fc+``/``Fc-`` here (it is absorbed as
      ``Fc+ + offset`` and ``Fc- - offset``), so ``offset`` is ignored.

    ``dFs = Fs - Fc`` is the Stribeck excess at zero speed.

    Parameters
    ----------
    q : array_like
        Measured position [m].
    force : array_like
        Measured actuator force (e.g. ``gtau * vir``) [N].
    dt : float
        Sample time [s].
    cutoff : float
        Cut-off of the zero-phase Butterworth position filter [Hz].
    order : int
        Order of that filter [-].
    decimation : int
        Parallel decimation factor of regressors and force (1: none) [-].
    friction : {"symmetric", "asymmetric"}
        Friction model [-].
    offset : bool
        Include a constant force offset (symmetric model only) [-].
    stribeck_velocity : float or "fit" or None
        Stribeck velocity; ``"fit"`` searches it (1-D, minimum residual); ``None`` omits
        the Stribeck term [m/s].
    stribeck_delta : float
        Stribeck exponent [-].
    force_shift : float
        Delay of the force relative to the motion, applied to the force before the fit
        (fractional, linear interpolation) [samples].
    skip : int
        Samples dropped at the start (edge effects of filter and differences) [-].
    v_min : float
        Equations (after decimation) with ``|q'| <= v_min`` are dropped; stick phases
        carry any force inside the static band, which the model cannot explain [m/s].

    Returns
    -------
    ParameterEstimate
        Estimates, standard deviations, relative force error and condition number [-].
    """
    q, force = _checked(q, force, friction, skip)
    qf = lowpass_filtfilt(q, dt, cutoff, order)
    dq = central_difference(qf, dt)
    ddq = central_difference(dq, dt)
    y_full = _shift(force, float(force_shift))
    sl = slice(int(skip), None)
    ddq, dq, y_full = ddq[sl], dq[sl], y_full[sl]

    keep = np.abs(decimate(dq, decimation)) > v_min
    if np.count_nonzero(keep) < 10:
        raise InputError(f"fewer than 10 equations with |q'| > v_min={v_min}", column="v_min")

    def build(vs):
        W, names = _regressor(ddq, dq, friction, offset, vs, stribeck_delta)
        Wd = decimate(W, decimation)[keep]
        yd = decimate(y_full, decimation)[keep]
        return Wd, yd, names

    extra = {
        "cutoff_hz": cutoff,
        "decimation": int(decimation),
        "friction": friction,
        "force_shift_samples": float(force_shift),
        "v_min": float(v_min),
    }
    vs = _stribeck_velocity(stribeck_velocity, dq, build)
    if vs is not None:
        extra["stribeck_velocity"] = vs
        extra["stribeck_delta"] = float(stribeck_delta)
    Wd, yd, names = build(vs)
    return replace(_lstsq(Wd, yd, names), extra=extra)


def _checked(q, force, friction: str, skip: int):
    """Position [m] and force [N] as 1-D arrays of one length, the friction model and the
    samples skipped checked [-]."""
    q = as_1d(q, "q")
    force = as_1d(force, "force")
    if q.size != force.size:
        raise InputError(
            f"q and force must have the same length, got {q.size} and {force.size}",
            column="force",
        )
    if friction not in ("symmetric", "asymmetric"):
        raise InputError(
            f"friction must be 'symmetric' or 'asymmetric', got {friction!r}",
            column="friction",
        )
    if not (0 <= skip < q.size - 10):
        raise InputError(f"skip={skip} leaves too few samples", column="skip")
    return q, force


def _stribeck_velocity(stribeck_velocity, dq, build) -> float | None:
    """The Stribeck velocity as given, ``None`` (no Stribeck term), or with ``"fit"`` the
    one of least squared residual of the fit ``build(vs)`` gives, over four decades below
    the largest speed [m/s]."""
    if isinstance(stribeck_velocity, str):
        if stribeck_velocity != "fit":
            raise InputError(
                "stribeck_velocity must be a number, 'fit' or None", column="stribeck_velocity"
            )
        vmax = float(np.max(np.abs(dq)))

        def cost(logvs):
            Wd, yd, _ = build(10.0**logvs)
            th, *_ = np.linalg.lstsq(Wd, yd, rcond=None)
            r = yd - Wd @ th
            return float(r @ r)

        res = optimize.minimize_scalar(
            cost,
            bounds=(math.log10(vmax) - 4.0, math.log10(vmax)),
            method="bounded",
            options={"xatol": 1e-3},
        )
        return 10.0 ** float(res.x)
    if stribeck_velocity is None:
        return None
    vs = float(stribeck_velocity)
    if vs <= 0.0:
        raise InputError("stribeck_velocity must be > 0", column="stribeck_velocity")
    return vs


def friction_from_idim(est: ParameterEstimate, v_stick: float = 0.0):
    """Friction model and force offset from an ``idim_ls`` result.

    Parameters
    ----------
    est : ParameterEstimate
        Result of ``idim_ls`` [-].
    v_stick : float
        Karnopp band for the returned model [m/s].

    Returns
    -------
    tuple
        ``(StribeckFriction, offset)``; negative identified levels are clipped to 0
        [-, N].
    """
    names = est.names
    vs = est.extra.get("stribeck_velocity", 1e-3)
    delta = est.extra.get("stribeck_delta", 2.0)
    clip = lambda x: max(float(x), 0.0)  # noqa: E731
    if "Fc" in names:
        fc = clip(est["Fc"])
        fs = clip(fc + est["dFs"]) if "dFs" in names else None
        fv = clip(est["Fv"])
        model = StribeckFriction.symmetric(fc=fc, fv=fv, fs=fs, vs=vs, delta=delta, v_stick=v_stick)
        off = est["offset"] if "offset" in names else 0.0
        return model, float(off)
    fcp, fcn = clip(est["Fc+"]), clip(est["Fc-"])
    model = StribeckFriction(
        fc_pos=fcp,
        fc_neg=fcn,
        fs_pos=clip(fcp + est["dFs+"]) if "dFs+" in names else fcp,
        fs_neg=clip(fcn + est["dFs-"]) if "dFs-" in names else fcn,
        vs=vs,
        delta=delta,
        fv_pos=clip(est["Fv+"]),
        fv_neg=clip(est["Fv-"]),
        v_stick=v_stick,
    )
    return model, 0.0
