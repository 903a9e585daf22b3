"""Identification of friction and of rigid-axis dynamics from measured runs.

Two methods:

- **Stribeck curve from constant-velocity runs** (``identify_stribeck_run``): the axis is
  moved back and forth at several constant speeds (``friction.csv``); the plateaus of
  constant velocity are detected in both directions, the force (or current) is averaged
  on each, and the curve
  ``F(v) = sign(v) (Fc_d + (Fs_d - Fc_d) exp(-|v/vs|**delta)) + Fv v`` is fitted by
  nonlinear least squares (``fit_stribeck``).
- **IDIM-LS** (``idim_ls``): inverse dynamic identification model with least squares
  for a rigid axis, ``tau = M q'' + F_friction(q') + offset``, from position and force
  records: zero-phase Butterworth low-pass of the position, central differences for
  ``q'`` and ``q''``, optional parallel decimation of regressors and force, linear least
  squares with standard deviations ``sigma^2 (W^T W)^-1``, ``sigma^2 = ||y - W theta||^2
  / (N - p)``. The default settings reproduce the EMPS benchmark's published script.

Conventions follow MATLAB's ``filtfilt`` (edge padding of ``3 (n - 1)`` samples) and
``decimate`` (8th-order Chebyshev I, 0.05 dB ripple, cutoff ``0.8 / r`` of Nyquist,
zero-phase, samples kept so that the last one is included), so published IDIM-LS
results are reproduced to their printed digits.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field

import numpy as np
from scipy import optimize, signal

from tcpmm.errors import InputError
from tcpmm.mechanics.friction import StribeckFriction

__all__ = [
    "ParameterEstimate",
    "Plateau",
    "central_difference",
    "decimate",
    "find_plateaus",
    "fit_stribeck",
    "friction_from_idim",
    "identify_stribeck_run",
    "idim_ls",
    "lowpass_filtfilt",
    "read_friction_csv",
]


@dataclass(frozen=True)
class ParameterEstimate:
    """Least-squares parameter estimates with their standard deviations.

    Parameters
    ----------
    names : tuple of str
        Parameter names [-].
    values : numpy.ndarray
        Estimates, in the units of each parameter (kg, N s/m, N, m/s) [-].
    std : numpy.ndarray
        Standard deviations, same units; ``nan`` where not estimated [-].
    relative_error : float
        ``100 ||y - y_hat|| / ||y||`` on the data used for the fit [%].
    residual_std : float
        ``sigma = ||y - y_hat|| / sqrt(N - p)`` [N].
    condition : float
        Condition number of the regressor matrix (linear fits) or of the Jacobian [-].
    n_samples : int
        Number of equations used [-].
    extra : dict
        Other settings or results (e.g. a fitted Stribeck velocity) [-].
    """

    names: tuple[str, ...]
    values: np.ndarray
    std: np.ndarray
    relative_error: float
    residual_std: float
    condition: float
    n_samples: int
    extra: dict = field(default_factory=dict)

    def __getitem__(self, name: str) -> float:
        try:
            return float(self.values[self.names.index(name)])
        except ValueError:
            raise KeyError(f"no parameter {name!r}; have {self.names}") from None

    def std_of(self, name: str) -> float:
        """Standard deviation of one parameter.

        Parameters
        ----------
        name : str
            Parameter name [-].

        Returns
        -------
        float
            Its standard deviation, in the parameter's unit [-].
        """
        return float(self.std[self.names.index(name)])

    def to_dict(self) -> dict:
        """Plain dictionary for JSON output.

        Returns
        -------
        dict
            ``{"parameters": {name: {"value", "std", "std_percent"}}, ...}`` [-].
        """
        params = {}
        for n, v, s in zip(self.names, self.values, self.std, strict=True):
            params[n] = {
                "value": float(v),
                "std": None if not np.isfinite(s) else float(s),
                "std_percent": None if not np.isfinite(s) or v == 0 else float(100.0 * s / abs(v)),
            }
        out = {
            "parameters": params,
            "relative_error_percent": float(self.relative_error),
            "residual_std": float(self.residual_std),
            "condition_number": float(self.condition),
            "n_samples": int(self.n_samples),
        }
        out.update({k: v for k, v in self.extra.items()})
        return out


def _as_1d(x, name: str) -> np.ndarray:
    a = np.asarray(x, dtype=float).ravel()
    if a.size == 0 or not np.all(np.isfinite(a)):
        raise InputError(f"{name} must be a non-empty array of finite numbers", column=name)
    return a


def lowpass_filtfilt(x, dt: float, cutoff: float, order: int = 4) -> np.ndarray:
    """Zero-phase Butterworth low-pass (forward-backward), MATLAB ``filtfilt`` padding.

    Parameters
    ----------
    x : array_like
        Signal, uniformly sampled [any].
    dt : float
        Sample time [s].
    cutoff : float
        Cut-off frequency of the single-pass filter [Hz].
    order : int
        Butterworth order of the single-pass filter [-].

    Returns
    -------
    numpy.ndarray
        Filtered signal, same length and unit as ``x`` [any].
    """
    x = _as_1d(x, "x")
    nyq = 0.5 / dt
    if not 0.0 < cutoff < nyq:
        raise InputError(
            f"cut-off {cutoff} Hz must lie between 0 and the Nyquist frequency {nyq} Hz",
            column="cutoff",
        )
    b, a = signal.butter(order, cutoff / nyq)
    pad = 3 * (max(len(a), len(b)) - 1)
    if x.size <= pad:
        raise InputError(f"need more than {pad} samples to filter, got {x.size}", column="x")
    return signal.filtfilt(b, a, x, padlen=pad)


def central_difference(x, dt: float) -> np.ndarray:
    """Derivative by central differences, one-sided at both ends.

    Parameters
    ----------
    x : array_like
        Signal, uniformly sampled [any].
    dt : float
        Sample time [s].

    Returns
    -------
    numpy.ndarray
        ``dx/dt``, same length as ``x`` [unit of x per s].
    """
    x = _as_1d(x, "x")
    if x.size < 2:
        raise InputError("need at least 2 samples to differentiate", column="x")
    dx = np.empty_like(x)
    dx[1:-1] = (x[2:] - x[:-2]) / (2.0 * dt)
    dx[0] = (x[1] - x[0]) / dt
    dx[-1] = (x[-1] - x[-2]) / dt
    return dx


def decimate(x, factor: int) -> np.ndarray:
    """Zero-phase low-pass and down-sampling, MATLAB ``decimate`` conventions.

    Parameters
    ----------
    x : array_like
        Signal, or a 2-D array whose columns are decimated in parallel [any].
    factor : int
        Keep one sample in ``factor`` (1 returns the input) [-].

    Returns
    -------
    numpy.ndarray
        Decimated signal; the last input sample is always kept [any].
    """
    x = np.asarray(x, dtype=float)
    r = int(factor)
    if r < 1:
        raise InputError("decimation factor must be >= 1", column="decimation")
    if r == 1:
        return x.copy()
    b, a = signal.cheby1(8, 0.05, 0.8 / r)
    pad = 3 * (max(len(a), len(b)) - 1)
    n = x.shape[0]
    if n <= pad:
        raise InputError(f"need more than {pad} samples to decimate, got {n}", column="x")
    y = signal.filtfilt(b, a, x, axis=0, padlen=pad)
    nout = -(-n // r)
    start = r - (r * nout - n) - 1
    return y[start::r]


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
    q = _as_1d(q, "q")
    force = _as_1d(force, "force")
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
        vs = 10.0 ** float(res.x)
        extra["stribeck_velocity"] = vs
    elif stribeck_velocity is None:
        vs = None
    else:
        vs = float(stribeck_velocity)
        if vs <= 0.0:
            raise InputError("stribeck_velocity must be > 0", column="stribeck_velocity")
        extra["stribeck_velocity"] = vs
    if vs is not None:
        extra["stribeck_delta"] = float(stribeck_delta)
    Wd, yd, names = build(vs)
    est = _lstsq(Wd, yd, names)
    return ParameterEstimate(
        est.names,
        est.values,
        est.std,
        est.relative_error,
        est.residual_std,
        est.condition,
        est.n_samples,
        extra,
    )


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


@dataclass(frozen=True)
class Plateau:
    """A stretch of (nearly) constant velocity.

    Parameters
    ----------
    start : int
        First sample index (after trimming) [-].
    stop : int
        One past the last sample index [-].
    velocity : float
        Mean velocity [m/s].
    force : float
        Mean force or current on the plateau [N or A].
    force_std : float
        Sample standard deviation of the force on the plateau [N or A].
    """

    start: int
    stop: int
    velocity: float
    force: float
    force_std: float


def find_plateaus(
    t,
    v,
    effort,
    *,
    v_min: float | None = None,
    rel_tol: float = 0.05,
    min_duration: float = 0.2,
    trim: float = 0.1,
) -> list[Plateau]:
    """Detect constant-velocity plateaus in both directions.

    A sample is steady when the velocity stays within ``rel_tol`` of its value over a
    window of ``min_duration / 4``; consecutive steady samples of one sign form a
    plateau, split wherever the velocity drifts by more than ``rel_tol``; plateaus are
    trimmed by ``trim`` of their length at each end and kept if they last at least
    ``min_duration``.

    Parameters
    ----------
    t : array_like
        Time [s].
    v : array_like
        Velocity (e.g. filtered central difference of the position) [m/s].
    effort : array_like
        Force or current to average on each plateau [N or A].
    v_min : float, optional
        Slowest speed treated as motion; default 0.2 % of the largest speed [m/s].
    rel_tol : float
        Relative velocity tolerance [-].
    min_duration : float
        Shortest plateau kept [s].
    trim : float
        Fraction cut at each end of a plateau [-].

    Returns
    -------
    list of Plateau
        Plateaus in time order [-].
    """
    from scipy.ndimage import maximum_filter1d, minimum_filter1d

    t = _as_1d(t, "t")
    v = _as_1d(v, "v")
    effort = _as_1d(effort, "effort")
    if not (t.size == v.size == effort.size):
        raise InputError("t, v and effort must have the same length", column="effort")
    dt = float(np.median(np.diff(t)))
    vmax = float(np.max(np.abs(v)))
    if v_min is None:
        v_min = 2e-3 * vmax
    w = max(round(0.25 * min_duration / dt), 3)
    vhi = maximum_filter1d(v, w)
    vlo = minimum_filter1d(v, w)
    steady = (np.abs(v) > v_min) & ((vhi - vlo) <= rel_tol * np.abs(v))
    sgn = np.sign(v) * steady
    out = []
    edges = np.flatnonzero(np.diff(np.r_[0.0, sgn, 0.0]) != 0)
    for i0, i1 in itertools.pairwise(edges):
        if sgn[i0] == 0:
            continue
        i = i0
        while i < i1:
            ref = v[i]
            drift = np.flatnonzero(np.abs(v[i:i1] - ref) > rel_tol * abs(ref))
            j = i1 if drift.size == 0 else i + int(drift[0])
            n = j - i
            cut = int(trim * n)
            a, b = i + cut, j - cut
            if b > a + 1 and (t[b - 1] - t[a]) >= min_duration:
                seg = effort[a:b]
                out.append(
                    Plateau(
                        int(a),
                        int(b),
                        float(np.mean(v[a:b])),
                        float(np.mean(seg)),
                        float(np.std(seg, ddof=1)),
                    )
                )
            i = j
    return out


def _stribeck_curve(p, v, delta, tie):
    fcp, fcn, fsp, fsn, logvs, fv = p
    if tie:
        fsn = fsp
    vs = 10.0**logvs
    e = np.exp(-(np.abs(v / vs) ** delta))
    return np.where(v > 0, fcp + (fsp - fcp) * e, -(fcn + (fsn - fcn) * e)) + fv * v


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
    v = _as_1d(velocity, "velocity")
    f = _as_1d(force, "force")
    if v.size != f.size:
        raise InputError("velocity and force must have the same length", column="force")
    npos, nneg = int(np.sum(v > 0)), int(np.sum(v < 0))
    npar = 5 if tie_static else 6
    if npos < 2 or nneg < 2 or v.size <= npar:
        raise InputError(
            f"need plateaus in both directions (>= 2 each) and more than {npar} in all; got "
            f"{npos} positive and {nneg} negative; run more constant-speed passes",
            column="velocity",
        )
    vs_init = float(np.min(np.abs(v))) if vs0 is None else float(vs0)
    # linear start: Coulomb + viscous from the faster half of each side
    fast = np.abs(v) >= np.median(np.abs(v))
    pos = ((v > 0) & fast).astype(float)
    neg = ((v < 0) & fast).astype(float)
    A = np.column_stack([pos, -neg, v * fast])
    c0, *_ = np.linalg.lstsq(A, f * fast, rcond=None)
    fcp0, fcn0, fv0 = max(c0[0], 0.0), max(c0[1], 0.0), max(c0[2], 0.0)
    slow_p = f[v > 0][np.argmin(v[v > 0])]
    slow_n = -f[v < 0][np.argmax(v[v < 0])]
    p0 = np.array([fcp0, fcn0, max(slow_p, fcp0), max(slow_n, fcn0), math.log10(vs_init), fv0])
    free = np.ones(6, dtype=bool)
    if tie_static:
        free[3] = False

    def resid(x):
        p = p0.copy()
        p[free] = x
        return _stribeck_curve(p, v, delta, tie_static) - f

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


def identify_stribeck_run(
    t,
    position,
    effort,
    *,
    cutoff: float = 20.0,
    delta: float = 2.0,
    tie_static: bool = False,
    v_min: float | None = None,
    rel_tol: float = 0.05,
    min_duration: float = 0.2,
    trim: float = 0.1,
):
    """Stribeck curve from a record of back-and-forth runs at constant speeds.

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
        Plateau detection settings, see ``find_plateaus`` ([m/s], [-], [s], [-]).

    Returns
    -------
    tuple
        ``(ParameterEstimate, list of Plateau)`` [-].
    """
    t = _as_1d(t, "t")
    x = _as_1d(position, "position")
    u = _as_1d(effort, "effort")
    if not (t.size == x.size == u.size):
        raise InputError("time, position and effort must have the same length", column="effort")
    dts = np.diff(t)
    dt = float(np.median(dts))
    if dt <= 0 or np.max(np.abs(dts - dt)) > 0.01 * dt:
        raise InputError("time must increase with a uniform step (1 % tolerance)", column="time_s")
    v = central_difference(lowpass_filtfilt(x, dt, cutoff), dt)
    plateaus = find_plateaus(
        t, v, u, v_min=v_min, rel_tol=rel_tol, min_duration=min_duration, trim=trim
    )
    if not plateaus:
        raise InputError(
            f"no constant-velocity plateau of at least {min_duration} s found; record "
            "longer constant-speed passes or lower min_duration",
            column="position",
        )
    est = fit_stribeck(
        [p.velocity for p in plateaus],
        [p.force for p in plateaus],
        delta=delta,
        tie_static=tie_static,
    )
    return est, plateaus


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
    from ..io.bundle import read_friction_csv as read_record

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
