"""The weighted fits of the plateau hysteresis behind
:func:`~tcpmm.ident.friction.lostmotion.estimate_lost_motion`; their result is a
:class:`~tcpmm.ident.friction.lostmotionestimate.LostMotionEstimate`.

The plateau deflections are set up once (:class:`PlateauDeflections`); which unknowns
are fitted depends on what is given: the share (:func:`fit_share_given`), the lost motion
(:func:`fit_lost_motion_given`) or neither (:func:`fit_both_free`, which keeps share and
lost motion together only when the lost motion is significant). The model and the decision are
described in :mod:`tcpmm.ident.friction.lostmotion`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from .lostmotionestimate import LostMotionEstimate
from .lostmotionoptions import LostMotionOptions

__all__ = ["PlateauDeflections", "fit_both_free", "fit_lost_motion_given", "fit_share_given"]


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


@dataclass(frozen=True)
class PlateauDeflections:
    """The plateau deflections set up for the weighted fits of offsets, share and lost
    motion, with the fits and the result built from them.

    ``base`` holds the offset columns (and the speed column with ``viscous="fit"``), ``k``
    their number, ``use`` the plateaus of speeds run both ways; ``Bu, yu, au, sdu`` are
    those rows of ``base``, ``y``, ``a_col = F_fric/K_t`` and the deflection std [SI].
    """

    opt: LostMotionOptions
    m: object
    v: np.ndarray
    d: np.ndarray
    d_sd: np.ndarray
    fric: np.ndarray
    y: np.ndarray
    a_col: np.ndarray
    base: np.ndarray
    use: np.ndarray
    n_off: int

    @classmethod
    def build(cls, v, d, d_sd, fric, y, m, opt: LostMotionOptions) -> PlateauDeflections:
        """From the plateau table (velocity [m/s], deflection and its std [m]), the
        friction force [N] and the left side of the fit [m]."""
        # offsets (common or per speed) and, when fitted, the speed-proportional part
        group = (np.zeros(v.size, dtype=int) if opt.offset == "common"
                 else _speed_groups(v, opt.rel_tol))
        both = np.array([np.any(v[group == j] > 0) and np.any(v[group == j] < 0)
                         for j in range(group.max() + 1)])
        base = (group[:, None] == np.flatnonzero(both)[None, :]).astype(float)
        if opt.viscous == "fit":
            base = np.column_stack([base, v])
        return cls(opt, m, v, d, d_sd, fric, y, fric / float(m.K_t), base, both[group],
                   int(both.sum()))

    @property
    def k(self) -> int:
        return self.base.shape[1]

    @property
    def Bu(self):
        return self.base[self.use]

    @property
    def yu(self):
        return self.y[self.use]

    @property
    def au(self):
        return self.a_col[self.use]

    @property
    def sdu(self):
        return self.d_sd[self.use]

    @property
    def n_eff(self) -> float:
        """Plateaus that carry the fit, counted by weight [-]."""
        w = 1.0 / self.sdu**2
        return float(w.sum() ** 2 / (w @ w))

    def nut_sign(self, s):
        load = float(getattr(self.m, "load_force", 0.0))
        return np.sign(self.m.C_t * self.v - load + s * self.fric)

    def reverses(self, s) -> bool:
        sgn = self.nut_sign(s)[self.use]
        return bool(np.any(sgn > 0) and np.any(sgn < 0))

    def fit_free(self, with_g, s_sign):
        """Base, s [and g]: full vector (base, s, g), stds, chi2, unscaled stds."""
        k, nan = self.k, float("nan")
        cols = [self.Bu, self.au] + ([0.5 * self.nut_sign(s_sign)[self.use]] if with_g else [])
        th_, sd, chi2, meas = _wls(np.column_stack(cols), self.yu, self.sdu)
        if not with_g:
            th_, sd, meas = np.r_[th_, 0.0], np.r_[sd, nan], np.r_[meas, nan]
        sd[k] = math.hypot(sd[k], abs(th_[k]) * self.opt.stiffness_rel_std)
        return th_, sd, chi2, meas

    def fit_fixed(self, s, with_g):
        """Base [and g >= 0] with the share held at ``s``."""
        k, nan = self.k, float("nan")
        if with_g and self.reverses(s):
            A = np.column_stack([self.Bu, 0.5 * self.nut_sign(s)[self.use]])
            th_, sd, chi2, _ = _wls(A, self.yu - s * self.au, self.sdu)
            if th_[-1] >= 0.0:
                return np.r_[th_[:k], s, th_[-1]], np.r_[sd[:k], nan, sd[-1]], chi2
        th_, sd, chi2, _ = _wls(self.Bu, self.yu - s * self.au, self.sdu)
        return np.r_[th_, s, 0.0], np.r_[sd, nan, nan], chi2

    def fit_given(self, g_, s_sign):
        """Base and s with the lost motion held at ``g_``."""
        return _wls(np.column_stack([self.Bu, self.au]),
                    self.yu - 0.5 * g_ * self.nut_sign(s_sign)[self.use], self.sdu)

    def result(self, s, s_sd, g, g_sd, theta, determined, reason, model, chi2,
               sd_theta=None) -> LostMotionEstimate:
        k, m, nan = self.k, self.m, float("nan")
        c_tab = c_tab_sd = nan
        if theta is None:
            off, mod, c = np.zeros_like(self.y), np.zeros_like(self.y), nan
        else:
            off = self.base @ theta[:k]
            mod = theta[k] * self.a_col + 0.5 * theta[k + 1] * self.nut_sign(theta[k])
            c = float(np.mean(theta[:self.n_off]))
            if self.opt.viscous == "fit":  # beta = C_table/K_t - B_m/K_L
                K_t, K_L = float(m.K_t), float(m.K_L)
                c_tab = float(K_t * (theta[k - 1] + m.B_m / K_L))
                if sd_theta is not None:
                    c_tab_sd = float(K_t * sd_theta[k - 1])
        return LostMotionEstimate(
            guideway_share=float(s), guideway_share_std=float(s_sd), backlash=float(g),
            backlash_std=float(g_sd), offset=c, determined=bool(determined), reason=reason,
            model=model, chi2=float(chi2), velocity=self.v, deflection=self.d,
            deflection_std=self.d_sd, friction_force=self.fric, nut_deflection=self.y - off,
            fitted=mod, table_viscous=c_tab, table_viscous_std=c_tab_sd)

    def checked(self, est: LostMotionEstimate) -> LostMotionEstimate:
        """``est``, or marked not determined when its fit does not follow the model or its
        share is not resolved."""
        max_chi2, max_share_std = self.opt.max_chi2, self.opt.max_share_std
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


def _share_to(sd: float) -> str:
    """How closely the plateau deflections fix a guideway share of standard deviation
    ``sd``: a share lies in 0 to 1, so an estimate with ``sd`` beyond it says nothing and
    is not given [-]."""
    if not np.isfinite(sd):
        return "do not fix the guideway share"
    return f"fix the guideway share only to +- {sd:.2g}"


def fit_share_given(p: PlateauDeflections, s: float) -> LostMotionEstimate:
    """The share given: offsets and lost motion from the remaining hysteresis."""
    k = p.k
    theta, sd, chi2 = p.fit_fixed(s, True)
    ok = p.n_eff >= p.opt.min_plateaus and p.reverses(s)
    why = (f"share given ({s:.2f}); lost motion from the remaining hysteresis" if ok else
           "share given; lost motion not observable (the nut force does not reverse or "
           "too few plateaus resolve the deflection), taken as 0")
    return p.result(s, 0.0, theta[k + 1] if ok else 0.0, sd[k + 1] if ok else float("nan"),
                    theta, ok, why, "lost-motion", chi2, sd)


def fit_lost_motion_given(p: PlateauDeflections) -> LostMotionEstimate:
    """The lost motion given: offsets, speed-proportional part and share; the share's
    std includes what the lost motion's moves it by."""
    k, opt, nan = p.k, p.opt, float("nan")
    g, s_ref = max(float(opt.backlash), 0.0), 0.5
    for _ in range(5):
        th_, sd, chi2, meas = p.fit_given(g, s_ref)
        s_new = min(max(float(th_[k]), 0.0), 1.0)
        if np.array_equal(p.nut_sign(s_new), p.nut_sign(s_ref)):
            break
        s_ref = s_new
    # the share moves with the lost motion: ds/dg from the same fit with g + dg
    dg = max(float(opt.backlash_std), 1e-12)
    th_dg = p.fit_given(g + dg, s_ref)[0]
    sd[k] = math.hypot(sd[k], abs(th_[k]) * opt.stiffness_rel_std,
                       (th_dg[k] - th_[k]) * float(opt.backlash_std) / dg)
    theta, sd_t = np.r_[th_, g], np.r_[sd, nan]
    s = float(th_[k])
    n_eff = p.n_eff
    if not (np.isfinite(meas[k]) and meas[k] <= opt.max_share_std
            and n_eff >= opt.min_plateaus):
        return p.result(s, sd[k], g, nan, theta, False,
                        f"with the lost motion given, the plateau deflections do not "
                        f"resolve the share ({s:.2f} +- {meas[k]:.2f} on {n_eff:.1f} "
                        f"plateaus)", "share", chi2, sd_t)
    return p.checked(p.result(s, sd[k], g, nan, theta, 0.0 <= s <= 1.0,
                              "lost motion given; share from the plateau hysteresis"
                              if 0.0 <= s <= 1.0 else f"share {s:.2f} outside [0, 1]",
                              "lost-motion given", chi2, sd_t))


def fit_both_free(p: PlateauDeflections) -> LostMotionEstimate:
    """Share without lost motion first; its unscaled std tells whether the plateau
    deflections resolve the nut deflection at all. Then share and lost motion together
    (:func:`_share_and_lost_motion`), kept only if the lost motion is significant; else
    the share alone, or share 1 with the rest of the hysteresis as lost motion."""
    k, opt, nan = p.k, p.opt, float("nan")
    th_a, sd_a, chi_a, meas_a = p.fit_free(False, 0.0)
    s_a, s_a_sd, resolution = float(th_a[k]), float(sd_a[k]), float(meas_a[k])
    n_eff = p.n_eff
    if not np.isfinite(resolution) or resolution > opt.max_share_std:
        return p.result(s_a, s_a_sd, 0.0, nan, th_a, False,
                        f"the plateau deflections {_share_to(resolution)}: they do not "
                        f"resolve the nut deflection of the friction "
                        f"({np.median(np.abs(p.a_col)) * 1e6:.2g} um; their std "
                        f"{np.median(p.d_sd) * 1e6:.2g} um)", "share", chi_a, sd_a)
    if n_eff < opt.min_plateaus:
        return p.result(s_a, s_a_sd, 0.0, nan, th_a, False,
                        f"only {n_eff:.1f} plateaus (by weight) resolve the deflection: on "
                        f"the others the sensor quantisation does not average out (the speeds "
                        f"advance a whole number of sensor steps per sample); run speeds "
                        f"that do not", "share", chi_a, sd_a)
    if s_a < -opt.z_lost_motion * s_a_sd:
        return p.result(s_a, s_a_sd, 0.0, nan, th_a, False,
                        f"the encoder-minus-scale hysteresis has the wrong sign (share "
                        f"{s_a:.2f} +- {s_a_sd:.2f}); check the signs of motor angle, scale "
                        f"and current", "share", chi_a, sd_a)
    both = _share_and_lost_motion(p, min(max(s_a, 0.0), 1.0))
    if both is not None:
        return both
    if s_a <= 1.0 or not p.reverses(1.0):
        s = min(max(s_a, 0.0), 1.0)
        theta, sd_t, chi2 = (th_a, sd_a, chi_a) if s == s_a else p.fit_fixed(s, False)
        why = ("no lost motion needed: the hysteresis is explained by guideway friction"
               if p.reverses(s) else
               "the nut force does not reverse (the load is carried on one flank): lost "
               "motion is not observable, taken as 0")
        return p.checked(p.result(s, s_a_sd, 0.0, nan, theta, True, why, "share", chi2, sd_t))
    # more hysteresis than all the friction on the guideway explains: s = 1, the rest is g
    th_c, sd_c, chi_c = p.fit_fixed(1.0, True)
    return p.checked(p.result(1.0, s_a_sd, th_c[k + 1], sd_c[k + 1], th_c, True,
                              f"the hysteresis exceeds all friction on the guideway (share "
                              f"{s_a:.2f} without lost motion): share 1, the rest is lost "
                              f"motion", "lost-motion", chi_c, sd_c))


def _share_and_lost_motion(p: PlateauDeflections, s_ref: float) -> LostMotionEstimate | None:
    """Share and lost motion both from the speed dependence of the friction, from the
    share ``s_ref`` of the fit without lost motion; ``None`` unless the nut force reverses
    and the lost motion is significant with the share in [0, 1] and resolved."""
    if not p.reverses(s_ref):
        return None
    k, opt = p.k, p.opt
    th_b, sd_b, chi_b, _ = p.fit_free(True, s_ref)
    for _ in range(5):
        s_new = min(max(float(th_b[k]), 0.0), 1.0)
        if np.array_equal(p.nut_sign(s_new), p.nut_sign(s_ref)):
            break
        s_ref = s_new
        th_b, sd_b, chi_b, _ = p.fit_free(True, s_ref)
    s_b, g_b = float(th_b[k]), float(th_b[k + 1])
    if (0.0 <= s_b <= 1.0 and g_b > opt.z_lost_motion * sd_b[k + 1]
            and sd_b[k] <= opt.max_share_std):
        return p.checked(p.result(s_b, sd_b[k], g_b, sd_b[k + 1], th_b, True,
                                  "share and lost motion both from the speed dependence "
                                  "of the friction", "share+lost-motion", chi_b, sd_b))
    return None
