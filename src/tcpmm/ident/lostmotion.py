"""Guideway share of the friction and lost motion of the screw-nut from constant-speed runs.

At a constant table speed ``v`` all accelerations vanish and the difference between the
motor encoder at the table and the linear scale, ``d = R_L th_m - X_LS``, is a static
deflection of the drive train (physics.md section 1):

    d(v) = c + R_L^2/K_L (F_motor - B_m v/R_L^2) + F_nut/K_t + sign(F_nut) g/2

with ``c`` the unknown zero offset between encoder and scale, ``F_motor = K_tc i/R_L`` the
motor force at the table, ``F_nut = C_t v + F_guideway - F_load`` the force through the
nut and ``g`` the total lost motion of the screw-nut. The torsion spring ``K_L`` carries
screw and guideway friction, the nut spring ``K_t`` only the guideway part; so the
hysteresis of ``d`` between the two directions tells how much of the friction acts on
the guideway. With ``F_guideway = s F_fric`` (``F_fric`` the measured friction force of a
plateau, the viscous part of the linear mechanics taken off), the mean deflection of each
plateau is linear in ``(c, s, g)``.

When the damping of the mechanics is not known (FRF fits rarely determine ``B_m``,
``B_L``, ``C_t``), the part of the deflection proportional to the speed is fitted as well
(``viscous="fit"``); ``s`` is then the share of the Coulomb and Stribeck friction, the part
that shapes the reversal spikes.

``s`` and ``g`` are told apart only by the speed dependence of the friction (viscous and
Stribeck parts): a Coulomb force and a free play both give a constant step between the
directions. The data decide for both only when the lost motion is significant in the
full fit; otherwise the explanation without lost motion is kept (``g = 0``,
``0 <= s <= 1``), and only the hysteresis that ``s = 1`` cannot explain becomes ``g``.

Encoder and scale are quantised; on a plateau the quantisation averages out only if the
position sweeps through the quantisation steps (the advance per sample is not a whole
number of steps). The standard deviation of each plateau mean includes the part of the
quantisation error that this sweep leaves, so locked records give large uncertainties
instead of a wrong answer.

The split counts as not determined (the caller falls back to a prior) when the plateau
deflections do not resolve the nut deflection, when too few plateaus carry the fit, when
the hysteresis has the wrong sign, or when the deflections do not follow the model (large
reduced chi-square: wrong damping or stiffness, or an encoder-to-scale offset that changes
along the travel, e.g. the lead error of the screw; one offset per speed removes the
latter).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ..errors import InputError

__all__ = ["LostMotionEstimate", "estimate_lost_motion", "quantisation_bias_std"]

#: Highest harmonic of the quantisation saw-tooth used for the residual bias [-].
_HARMONICS = 100
#: Blocks a plateau is cut into for the statistical error of its mean [-].
_BLOCKS = 8


@dataclass(frozen=True)
class LostMotionEstimate:
    """Guideway share and lost motion from the encoder-minus-scale deflection.

    Parameters
    ----------
    guideway_share : float
        Share of the friction acting on the guideway, the rest on the screw [-].
    guideway_share_std : float
        Its standard deviation [-].
    backlash : float
        Total lost motion of the screw-nut [m].
    backlash_std : float
        Its standard deviation; ``nan`` when it was not fitted [m].
    offset : float
        Zero offset ``c`` between encoder (at the table) and scale; the mean of the
        offsets of the speeds with ``offset="per_speed"`` [m].
    determined : bool
        The data determine the split; when ``False`` use a prior and see ``reason`` [-].
    reason : str
        Which explanation was kept, or why the split is not determined [-].
    model : str
        ``"share"`` (``g = 0``), ``"share+lost-motion"`` (both from the speed
        dependence), ``"lost-motion"`` (``s = 1``, the rest is ``g``) or
        ``"lost-motion given"`` (``g`` given, ``s`` fitted) [-].
    chi2 : float
        Reduced chi-square of the kept fit with the plateau standard deviations [-].
    velocity : numpy.ndarray
        Mean velocity of each plateau [m/s].
    deflection : numpy.ndarray
        Mean ``R_L th_m - X_LS`` of each plateau [m].
    deflection_std : numpy.ndarray
        Standard deviation of that mean (statistics and quantisation) [m].
    friction_force : numpy.ndarray
        Friction force of each plateau: motor force minus the viscous forces of the
        linear mechanics, plus the load force [N].
    nut_deflection : numpy.ndarray
        Deflection minus offset, screw torsion and the viscous part of the nut force:
        the measured ``s F_fric/K_t + sign(F_nut) g/2`` [m].
    fitted : numpy.ndarray
        The kept model's value of ``nut_deflection`` [m].
    table_viscous : float
        With ``viscous="fit"``: the viscous force per speed that passes through the nut
        (table damping and viscous guideway friction), from the speed-proportional part
        of the deflection; ``nan`` otherwise [N s/m].
    table_viscous_std : float
        Its standard deviation [N s/m].
    """

    guideway_share: float
    guideway_share_std: float
    backlash: float
    backlash_std: float
    offset: float
    determined: bool
    reason: str
    model: str
    chi2: float
    velocity: np.ndarray
    deflection: np.ndarray
    deflection_std: np.ndarray
    friction_force: np.ndarray
    nut_deflection: np.ndarray
    fitted: np.ndarray
    table_viscous: float = float("nan")
    table_viscous_std: float = float("nan")

    def to_dict(self) -> dict:
        """Plain dictionary for a JSON report.

        Returns
        -------
        dict
            Share, lost motion and offset with standard deviations, the decision, and
            the plateau table (SI: m/s, m, N) [-].
        """

        def num(x):
            return float(x) if np.isfinite(x) else None

        return {
            "guideway_share": {"value": num(self.guideway_share),
                               "std": num(self.guideway_share_std)},
            "backlash_m": {"value": num(self.backlash), "std": num(self.backlash_std)},
            "offset_m": num(self.offset),
            "determined": bool(self.determined),
            "model": self.model,
            "reason": self.reason,
            "chi2_reduced": num(self.chi2),
            "table_viscous_N_s_per_m": {"value": num(self.table_viscous),
                                        "std": num(self.table_viscous_std)},
            "plateaus": [
                {"velocity_m_per_s": float(v), "deflection_m": float(d),
                 "deflection_std_m": float(sd), "friction_force_N": float(f),
                 "nut_deflection_m": float(n), "fitted_m": float(y)}
                for v, d, sd, f, n, y in zip(
                    self.velocity, self.deflection, self.deflection_std,
                    self.friction_force, self.nut_deflection, self.fitted, strict=True)
            ],
        }


def quantisation_bias_std(t, x, quantum: float) -> float:
    """Standard deviation of the quantisation error left in the mean of a steady ramp.

    The samples of a steady motion ``x ~ a + b t`` hit the quantisation steps at phases
    ``phi_k = (a + b t_k)/q``. The mean quantisation error, averaged over the unknown
    phase ``a/q``, has variance ``q^2 sum_n |mean_k exp(2 pi i n phi_k)|^2 / (2 pi^2 n^2)``:
    ``q^2/12`` when every sample has the same phase (the advance per sample is a whole
    number of steps), near 0 when the phases fill the step evenly. Vibration about the
    ramp is not counted as dither (a wobble of about one step can visit the phases as
    unevenly as it fills them), and the result is not taken below the error of ``N``
    independent, uniformly distributed rounding errors, ``q / sqrt(12 N)``.

    Parameters
    ----------
    t : array_like
        Sample times on the plateau [s].
    x : array_like
        Quantised position on the plateau [m].
    quantum : float
        Quantisation step; 0 for an ideal sensor [m].

    Returns
    -------
    float
        Standard deviation of the quantisation error of ``mean(x)`` [m].
    """
    if quantum <= 0.0:
        return 0.0
    t = np.asarray(t, dtype=float)
    x = np.asarray(x, dtype=float)
    if x.size < 3:
        return quantum / math.sqrt(12.0)
    tc = t - t.mean()
    slope = float(tc @ (x - x.mean()) / (tc @ tc)) if tc @ tc > 0 else 0.0
    line = x.mean() + slope * tc
    phase = (line - line[0]) / quantum
    n = np.arange(1, _HARMONICS + 1)
    z = np.exp(2j * np.pi * phase)
    zn = np.ones_like(z)
    c = np.empty(n.size)
    for i in range(n.size):  # powers of the first harmonic: one exp per sample, not n
        zn *= z
        c[i] = abs(zn.mean()) ** 2
    var_phase = float(np.sum(c / (2.0 * np.pi**2 * n**2)))
    # the few highest harmonics stand for the rest of the series (sum of 1/n^2 beyond)
    var_phase += float(np.mean(c[-10:])) / (2.0 * np.pi**2 * _HARMONICS)
    return quantum * math.sqrt(min(max(var_phase, 1.0 / (12.0 * x.size)), 1.0 / 12.0))


def _plateau_mean(d, start, stop):
    seg = d[start:stop]
    m = float(seg.mean())
    nb = min(_BLOCKS, seg.size // 4)
    if nb < 2:
        return m, float(np.std(seg, ddof=1) / math.sqrt(seg.size)) if seg.size > 1 else 0.0
    blocks = np.array([b.mean() for b in np.array_split(seg, nb)])
    return m, float(np.std(blocks, ddof=1) / math.sqrt(nb))


def _wls(A, y, sd):
    """Weighted least squares.

    Returns the estimates, their standard deviations scaled by the reduced chi-square
    where it exceeds 1, the reduced chi-square, and the unscaled standard deviations
    (from the plateau standard deviations alone).
    """
    w = 1.0 / sd
    Aw, yw = A * w[:, None], y * w
    theta, *_ = np.linalg.lstsq(Aw, yw, rcond=None)
    r = yw - Aw @ theta
    n, p = A.shape
    dof = n - p
    chi2 = float(r @ r) / dof if dof > 0 else float("nan")
    try:
        meas = np.sqrt(np.abs(np.diag(np.linalg.inv(Aw.T @ Aw))))
    except np.linalg.LinAlgError:
        meas = np.full(p, np.inf)
    if dof <= 0:
        return theta, np.full(p, np.inf), chi2, meas
    return theta, meas * math.sqrt(max(chi2, 1.0)), chi2, meas


def _speed_groups(v, rel_tol):
    speed = np.abs(v)
    order = np.argsort(speed)
    group = np.empty(v.size, dtype=int)
    g, ref = 0, speed[order[0]]
    for i in order:
        if speed[i] > ref * (1.0 + 2.0 * rel_tol):
            g, ref = g + 1, speed[i]
        group[i] = g
    return group


def estimate_lost_motion(
    t,
    motor_angle,
    scale,
    force,
    R_L: float,
    mechanics,
    plateaus,
    *,
    encoder_quantum: float = 0.0,
    scale_resolution: float = 0.0,
    stiffness_rel_std: float = 0.0,
    viscous: str = "known",
    offset: str = "common",
    share: float | None = None,
    backlash: float | None = None,
    backlash_std: float = 0.0,
    max_share_std: float = 0.1,
    z_lost_motion: float = 4.0,
    min_plateaus: float = 4.0,
    max_chi2: float = 25.0,
    rel_tol: float = 0.05,
    total_viscous: float | None = None,
) -> LostMotionEstimate:
    """Guideway share of the friction and lost motion from the plateau deflections.

    Parameters
    ----------
    t : array_like
        Time of the friction record [s].
    motor_angle : array_like
        Motor encoder angle [rad].
    scale : array_like
        Linear scale ``X_LS`` [m].
    force : array_like
        Motor force at the table, ``K_tc i / R_L`` [N].
    R_L : float
        Screw ratio ``lead / 2 pi`` [m/rad].
    mechanics : AxisMechanics
        Axis parameters; ``K_L``, ``K_t``, ``C_t``, ``load_force`` and, with
        ``viscous="known"``, ``B_m`` and ``B_L`` are used [SI].
    plateaus : sequence of Plateau
        Constant-speed plateaus of this record (``find_plateaus``), indices into the
        arrays above [-].
    encoder_quantum : float
        Encoder step at the motor; 0 for ideal [rad].
    scale_resolution : float
        Scale step; 0 for ideal [m].
    stiffness_rel_std : float
        Relative standard deviation of ``K_t``; the share scales with it [-].
    viscous : {"known", "fit"}
        ``"known"``: the viscous forces of the mechanics (``B_m``, ``B_L``, ``C_t``) are
        taken as known, ``F_fric`` is the plateau force minus them and ``s`` applies to
        all of it. ``"fit"``: the part of the deflection proportional to the speed is a
        free parameter (it takes up ``C_t``, ``B_m`` and the viscous friction, which FRF
        fits rarely determine), ``F_fric`` is the plateau force minus its viscous part
        (``total_viscous`` times the speed), and ``s`` is the share of the Coulomb and
        Stribeck friction only [-].
    offset : {"common", "per_speed"}
        One encoder-to-scale offset for the whole record, or one per speed (forward and
        back plateaus of a speed cover the same travel, so lead errors of the screw and
        slow thermal drift cancel) [-].
    share : float, optional
        Guideway share given by the user: only offset and lost motion are fitted [-].
    backlash : float, optional
        Lost motion known from elsewhere (e.g. :func:`tcpmm.ident.nutstiffness.estimate_nut`):
        only offsets, the speed-proportional part and the share are fitted [m].
    backlash_std : float
        Standard deviation of that lost motion; it enters the share's [m].
    max_share_std : float
        Largest standard deviation of the share for which the split counts as
        determined [-].
    z_lost_motion : float
        Lost motion and share are both fitted only when the lost motion exceeds this many
        of its standard deviations [-].
    min_plateaus : float
        Fewest plateaus that must carry the fit, counted by weight
        ``(sum w)^2 / sum w^2`` with ``w = 1/std^2``; fewer means that the quantisation
        averages out on too few plateaus to trust the split [-].
    max_chi2 : float
        Largest reduced chi-square of the kept fit; above it the deflections do not
        follow the model (wrong damping or stiffness, position-dependent errors) and the
        split counts as not determined [-].
    rel_tol : float
        Relative speed tolerance that groups plateaus of one speed [-].
    total_viscous : float, optional
        Viscous slope of the plateau forces, all contacts and damping together, from a
        friction curve that models the Stribeck hump; ``viscous="fit"`` only. Default: a
        line through the plateau forces, which the hump at the slow plateaus tilts: its
        slope comes out low, and what the speed-proportional deflection then gives for
        the table's viscous force as well, by the share times that error (measured: 4 %
        low on the built-in axes, 14 % on axis Y of machine 1 of
        ``docs/validation/unseen_machines.py --seed 0 --backlash``) [N s/m].

    Returns
    -------
    LostMotionEstimate
        Share, lost motion, their standard deviations and the plateau table [-].
    """
    t = np.asarray(t, dtype=float)
    th = np.asarray(motor_angle, dtype=float)
    xs = np.asarray(scale, dtype=float)
    f = np.asarray(force, dtype=float)
    if not (t.size == th.size == xs.size == f.size):
        raise InputError("time, motor angle, scale and force must have the same length",
                         column="scale")
    if offset not in ("common", "per_speed"):
        raise InputError(f"offset must be 'common' or 'per_speed', got {offset!r}",
                         column="offset")
    if viscous not in ("known", "fit"):
        raise InputError(f"viscous must be 'known' or 'fit', got {viscous!r}", column="viscous")
    m = mechanics
    K_L, K_t = float(m.K_L), float(m.K_t)
    load = float(getattr(m, "load_force", 0.0))

    # plateau means of deflection and force
    d_all = R_L * th - xs
    q_enc = R_L * encoder_quantum
    rows = []
    for p in plateaus:
        a, b = int(p.start), int(p.stop)
        if b - a < 3:
            continue
        tt = t[a:b]
        vel = float((xs[b - 1] - xs[a]) / (tt[-1] - tt[0]))
        dm, sd_stat = _plateau_mean(d_all, a, b)
        sd_q = math.hypot(quantisation_bias_std(tt, R_L * th[a:b], q_enc),
                          quantisation_bias_std(tt, xs[a:b], scale_resolution))
        rows.append((vel, dm, math.hypot(sd_stat, sd_q), float(f[a:b].mean())))
    if not rows:
        raise InputError("no plateau long enough to average the deflection", column="scale")
    v, d, d_sd, fm = (np.array(c) for c in zip(*rows, strict=True))
    # no plateau mean is known better than a nanometre (numerical floor of the weights)
    d_sd = np.maximum(d_sd, 1e-9)

    # left side y = nut deflection + offset (+ beta v), friction regressor a_col
    if viscous == "known":
        linear = (m.B_m + m.B_L) / R_L**2 + m.C_t
        fric = fm - linear * v + load
        y = d - R_L**2 / K_L * (fm - m.B_m * v / R_L**2) - (m.C_t * v - load) / K_t
    else:
        if total_viscous is not None:
            slope = float(total_viscous)
        else:
            pos, neg = (v > 0).astype(float), (v < 0).astype(float)
            (_, _, slope), *_ = np.linalg.lstsq(np.column_stack([pos, neg, v]), fm, rcond=None)
        fric = fm - slope * v + load
        y = d - R_L**2 / K_L * fm
    a_col = fric / K_t

    # offsets (common or per speed) and, when fitted, the speed-proportional part
    group = np.zeros(v.size, dtype=int) if offset == "common" else _speed_groups(v, rel_tol)
    both = np.array([np.any(v[group == j] > 0) and np.any(v[group == j] < 0)
                     for j in range(group.max() + 1)])
    use = both[group]
    n_off = int(both.sum())
    base = (group[:, None] == np.flatnonzero(both)[None, :]).astype(float)
    if viscous == "fit":
        base = np.column_stack([base, v])
    k = base.shape[1]
    nan = float("nan")

    def nut_sign(s):
        return np.sign(m.C_t * v - load + s * fric)

    def result(s, s_sd, g, g_sd, theta, determined, reason, model, chi2, sd_theta=None):
        c_tab = c_tab_sd = nan
        if theta is None:
            off, mod, c = np.zeros_like(y), np.zeros_like(y), nan
        else:
            off = base @ theta[:k]
            mod = theta[k] * a_col + 0.5 * theta[k + 1] * nut_sign(theta[k])
            c = float(np.mean(theta[:n_off]))
            if viscous == "fit":  # beta = C_table/K_t - B_m/K_L
                c_tab = float(K_t * (theta[k - 1] + m.B_m / K_L))
                if sd_theta is not None:
                    c_tab_sd = float(K_t * sd_theta[k - 1])
        return LostMotionEstimate(
            guideway_share=float(s), guideway_share_std=float(s_sd), backlash=float(g),
            backlash_std=float(g_sd), offset=c, determined=bool(determined), reason=reason,
            model=model, chi2=float(chi2), velocity=v, deflection=d, deflection_std=d_sd,
            friction_force=fric, nut_deflection=y - off, fitted=mod, table_viscous=c_tab,
            table_viscous_std=c_tab_sd)

    n_pos, n_neg = int(np.sum(use & (v > 0))), int(np.sum(use & (v < 0)))
    if n_pos < 2 or n_neg < 2 or use.sum() < k + 2:
        return result(nan, nan, 0.0, nan, None, False,
                      f"need at least 2 plateaus in each direction "
                      f"{'at speeds run both ways ' if offset == 'per_speed' else ''}"
                      f"(have {n_pos} forward, {n_neg} back)", "none", nan)
    Bu, yu, au, sdu = base[use], y[use], a_col[use], d_sd[use]
    w = 1.0 / sdu**2
    n_eff = float(w.sum() ** 2 / (w @ w))

    def reverses(s):
        sgn = nut_sign(s)[use]
        return bool(np.any(sgn > 0) and np.any(sgn < 0))

    def fit_free(with_g, s_sign):
        """Base, s [and g]: full vector (base, s, g), stds, chi2, unscaled stds."""
        cols = [Bu, au] + ([0.5 * nut_sign(s_sign)[use]] if with_g else [])
        th_, sd, chi2, meas = _wls(np.column_stack(cols), yu, sdu)
        if not with_g:
            th_, sd, meas = np.r_[th_, 0.0], np.r_[sd, nan], np.r_[meas, nan]
        sd[k] = math.hypot(sd[k], abs(th_[k]) * stiffness_rel_std)
        return th_, sd, chi2, meas

    def fit_fixed(s, with_g):
        """Base [and g >= 0] with the share held at ``s``."""
        if with_g and reverses(s):
            A = np.column_stack([Bu, 0.5 * nut_sign(s)[use]])
            th_, sd, chi2, _ = _wls(A, yu - s * au, sdu)
            if th_[-1] >= 0.0:
                return np.r_[th_[:k], s, th_[-1]], np.r_[sd[:k], nan, sd[-1]], chi2
        th_, sd, chi2, _ = _wls(Bu, yu - s * au, sdu)
        return np.r_[th_, s, 0.0], np.r_[sd, nan, nan], chi2

    if share is not None:
        s = float(share)
        theta, sd, chi2 = fit_fixed(s, True)
        ok = n_eff >= min_plateaus and reverses(s)
        why = (f"share given ({s:.2f}); lost motion from the remaining hysteresis" if ok else
               "share given; lost motion not observable (the nut force does not reverse or "
               "too few plateaus resolve the deflection), taken as 0")
        return result(s, 0.0, theta[k + 1] if ok else 0.0, sd[k + 1] if ok else nan, theta,
                      ok, why, "lost-motion", chi2)

    def checked(est):
        if est.chi2 > max_chi2:
            return replace(est, determined=False, reason=(
                f"the plateau deflections do not follow the model (reduced chi-square "
                f"{est.chi2:.3g} > {max_chi2:g}; {est.reason}): damping or stiffness of the "
                f"mechanics may be wrong, or the encoder-to-scale offset changes along the "
                f"travel"))
        if est.model == "share" and est.guideway_share_std > max_share_std:
            return replace(est, determined=False, reason=(
                f"guideway share {est.guideway_share:.2f} +- {est.guideway_share_std:.2f} "
                f"is not determined (std above {max_share_std:g})"))
        return est

    if backlash is not None:
        def fit_given(g_, s_sign):
            """Base and s with the lost motion held at ``g_``."""
            return _wls(np.column_stack([Bu, au]), yu - 0.5 * g_ * nut_sign(s_sign)[use], sdu)

        g, s_ref = max(float(backlash), 0.0), 0.5
        for _ in range(5):
            th_, sd, chi2, meas = fit_given(g, s_ref)
            s_new = min(max(float(th_[k]), 0.0), 1.0)
            if np.array_equal(nut_sign(s_new), nut_sign(s_ref)):
                break
            s_ref = s_new
        # the share moves with the lost motion: ds/dg from the same fit with g + dg
        dg = max(float(backlash_std), 1e-12)
        th_dg = fit_given(g + dg, s_ref)[0]
        sd[k] = math.hypot(sd[k], abs(th_[k]) * stiffness_rel_std,
                           (th_dg[k] - th_[k]) * float(backlash_std) / dg)
        theta, sd_t = np.r_[th_, g], np.r_[sd, nan]
        s = float(th_[k])
        if not (np.isfinite(meas[k]) and meas[k] <= max_share_std and n_eff >= min_plateaus):
            return result(s, sd[k], g, nan, theta, False,
                          f"with the lost motion given, the plateau deflections do not "
                          f"resolve the share ({s:.2f} +- {meas[k]:.2f} on {n_eff:.1f} "
                          f"plateaus)", "share", chi2, sd_t)
        return checked(result(s, sd[k], g, nan, theta, 0.0 <= s <= 1.0,
                              "lost motion given; share from the plateau hysteresis"
                              if 0.0 <= s <= 1.0 else f"share {s:.2f} outside [0, 1]",
                              "lost-motion given", chi2, sd_t))

    # g = 0, s free; its unscaled std tells whether the plateau deflections resolve the
    # nut deflection at all
    th_a, sd_a, chi_a, meas_a = fit_free(False, 0.0)
    s_a, s_a_sd, resolution = float(th_a[k]), float(sd_a[k]), float(meas_a[k])
    if not np.isfinite(resolution) or resolution > max_share_std:
        return result(s_a, s_a_sd, 0.0, nan, th_a, False,
                      f"guideway share {s_a:.2f} +- {resolution:.2f} is not determined: the "
                      f"nut deflection of the friction ({np.median(np.abs(a_col)) * 1e6:.2g} "
                      f"um) is not resolved by the plateau deflections (std "
                      f"{np.median(d_sd) * 1e6:.2g} um)", "share", chi_a)
    if n_eff < min_plateaus:
        return result(s_a, s_a_sd, 0.0, nan, th_a, False,
                      f"only {n_eff:.1f} plateaus (by weight) resolve the deflection: on the "
                      f"others the sensor quantisation does not average out (the speeds "
                      f"advance a whole number of sensor steps per sample); run speeds "
                      f"that do not", "share", chi_a)
    if s_a < -z_lost_motion * s_a_sd:
        return result(s_a, s_a_sd, 0.0, nan, th_a, False,
                      f"the encoder-minus-scale hysteresis has the wrong sign (share "
                      f"{s_a:.2f} +- {s_a_sd:.2f}); check the signs of motor angle, scale "
                      f"and current", "share", chi_a)
    s_ref = min(max(s_a, 0.0), 1.0)
    if reverses(s_ref):
        # share and lost motion together, kept only if the lost motion is significant
        th_b, sd_b, chi_b, _ = fit_free(True, s_ref)
        for _ in range(5):
            s_new = min(max(float(th_b[k]), 0.0), 1.0)
            if np.array_equal(nut_sign(s_new), nut_sign(s_ref)):
                break
            s_ref = s_new
            th_b, sd_b, chi_b, _ = fit_free(True, s_ref)
        s_b, g_b = float(th_b[k]), float(th_b[k + 1])
        if (0.0 <= s_b <= 1.0 and g_b > z_lost_motion * sd_b[k + 1]
                and sd_b[k] <= max_share_std):
            return checked(result(s_b, sd_b[k], g_b, sd_b[k + 1], th_b, True,
                                  "share and lost motion both from the speed dependence "
                                  "of the friction", "share+lost-motion", chi_b, sd_b))
    if s_a <= 1.0 or not reverses(1.0):
        s = min(max(s_a, 0.0), 1.0)
        theta, sd_t, chi2 = (th_a, sd_a, chi_a) if s == s_a else fit_fixed(s, False)
        why = ("no lost motion needed: the hysteresis is explained by guideway friction"
               if reverses(s) else
               "the nut force does not reverse (the load is carried on one flank): lost "
               "motion is not observable, taken as 0")
        return checked(result(s, s_a_sd, 0.0, nan, theta, True, why, "share", chi2, sd_t))
    # more hysteresis than all the friction on the guideway explains: s = 1, the rest is g
    th_c, sd_c, chi_c = fit_fixed(1.0, True)
    return checked(result(1.0, s_a_sd, th_c[k + 1], sd_c[k + 1], th_c, True,
                          f"the hysteresis exceeds all friction on the guideway (share "
                          f"{s_a:.2f} without lost motion): share 1, the rest is lost motion",
                          "lost-motion", chi_c, sd_c))
