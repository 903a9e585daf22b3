"""Nut stiffness, guideway share and lost motion from a whole friction record.

On the plateaus of constant speed the nut carries only the guideway friction, and the
plateau deflections give the share over the nut stiffness, ``s/K_t``
(:mod:`tcpmm.ident.friction.lostmotion`). The sweep cannot give ``K_t`` when the nut has free play:
its dynamic force is many times the friction that holds the nut on one flank, the nut
crosses the play every cycle and the FRFs see a soft nut. Between the plateaus, though,
the table accelerates and the nut carries ``M_t a`` as well, firmly on one flank. The
equations of motion (physics.md section 1) hold at every instant:

    d   = R_L th_m - X_LS = R_L T_s/K_L + F_t/K_t + sign(F_t) g/2 + c
    T_s = J_L th_L'' + B_L th_L' + R_L (F_t + F_s)     (screw, torsion spring)
    F_t = M_t a + C_t v + s F_f(v)                     (table; guideway friction s F_f)

where ``F_s`` is the screw's share of the friction. The torque through the coupling is
taken from the load side, which the steady runs measure (``F_f`` and the viscous force
``V v`` of everything but the motor bearing), not from the logged current: a trace
sampled in step with the interpolator reads the velocity-loop ripple of every command
step at the same phase, which looks like inertia and in the torsion term like a stiffer
nut. With ``th_L'' = a/R_L`` and ``y = d - (R_L^2/K_L) ((J_L/R_L^2 + M_t) a + F_f + V v)``,

    y = c + beta v + (s/K_t) F_f(v) + (M_t/K_t) a + sign(F_t) g/2,
    beta = C_t/K_t,

linear in ``(c, beta, s/K_t, M_t/K_t, g)``. With ``M_t`` from the FRF fit (the sweep
determines the masses well even with free play) the acceleration term gives ``K_t`` and
the friction term the share. ``F_f`` is the Coulomb and Stribeck part of the steady
friction curve; the viscous part through the nut is in ``beta``.

The signals are low-passed without phase shift before differencing, as for the rigid
inverse dynamics. Samples near a reversal of the nut force (where the filter smears the
jump across the play) or of the velocity (stiction) are left out. The filtered residuals
are correlated over about ``1/(2 cutoff)``, which the standard deviations account for.

On the plateaus the guideway friction and the play both shift ``y`` with the sign of the
velocity; only the ramps between them tell the two apart, because there the nut force has
the sign of the acceleration, and while braking that is against the velocity. The
guideway's part of the nut deflection, ``s F_f/K_t``, is often a tenth of a micrometre,
and the ramps are short: a low cut-off smears each change of acceleration over so many
samples that few ramp samples are left, a high one lets the noise of the twice
differentiated scale in. So several cut-offs are tried and the estimate that determines
the share best is kept.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ...errors import InputError
from ..frf.signals import central_difference, lowpass_filtfilt
from .nutrounding import quantisation_cov

__all__ = ["CUTOFFS_HZ", "LOST_MOTION_Z", "RESOLUTION_STEPS", "NutEstimate", "estimate_nut"]

#: Cut-offs tried for the low-pass before differencing [Hz]. A low one smears every change
#: of acceleration over many samples, which are then left out; a high one lets more noise,
#: and from 60 Hz the servo's transients, into the acceleration. The estimate that
#: determines the share best is kept, and a cut-off above :data:`TRANSIENT_FREE_HZ` counts
#: only where the next lower one agrees with it (docs/validation/identification_findings.md).
CUTOFFS_HZ = (20.0, 40.0, 60.0)
#: Standard deviations (the two cut-offs' combined) within which the stiffness at a
#: cut-off must agree with that at the next lower one for the higher to count [-].
CUTOFF_AGREEMENT = 3.0
#: Highest cut-off that the servo's transients do not reach into [Hz].
TRANSIENT_FREE_HZ = 40.0

#: Standard deviations by which the lost motion must exceed zero to be modelled: axes
#: without play reach a few of them, and a real play dropped leaves its hysteresis to be
#: taken for guideway friction (docs/validation/identification_findings.md) [-].
LOST_MOTION_Z = 3.0
#: Lost motion within this many scale steps may be the scale's rounding as well as the
#: nut's play, whatever its standard deviation [-].
RESOLUTION_STEPS = 2.0


@dataclass(frozen=True)
class NutEstimate:
    """Nut stiffness, guideway share and lost motion from a friction record.

    Parameters
    ----------
    stiffness : float
        Axial stiffness of the screw-nut in contact, ``K_t`` [N/m].
    stiffness_std : float
        Its standard deviation (the data alone, ``M_t`` taken as known) [N/m].
    guideway_share : float
        Share of the Coulomb and Stribeck friction on the guideway [-].
    guideway_share_std : float
        Its standard deviation [-].
    backlash : float
        Total lost motion of the screw-nut [m].
    backlash_std : float
        Its standard deviation [m].
    table_viscous : float
        Viscous force per speed that passes through the nut [N s/m].
    table_viscous_std : float
        Its standard deviation [N s/m].
    offset : float
        Zero offset between encoder (at the table) and scale [m].
    determined : bool
        The record determines stiffness and share [-].
    reason : str
        Why not, or what was found [-].
    samples : int
        Samples in the fit [-].
    rms : float
        Root mean square of the residual deflection [m].
    cutoff : float
        Low-pass cut-off of the signals the estimate was taken from [Hz].
    scale_resolution : float
        Resolution of the scale the deflection was read with [m].
    """

    stiffness: float
    stiffness_std: float
    guideway_share: float
    guideway_share_std: float
    backlash: float
    backlash_std: float
    table_viscous: float
    table_viscous_std: float
    offset: float
    determined: bool
    reason: str
    samples: int
    rms: float
    cutoff: float = float("nan")
    scale_resolution: float = 0.0

    def lost_motion_found(self, z: float = LOST_MOTION_Z) -> bool:
        """Whether the lost motion is significant: more than ``z`` standard deviations.

        Parameters
        ----------
        z : float
            Significance in standard deviations [-].

        Returns
        -------
        bool
            Determined and ``backlash > z * backlash_std`` [-].
        """
        return bool(self.determined and self.backlash > z * self.backlash_std)

    def at_resolution(self, z: float = LOST_MOTION_Z) -> bool:
        """Whether a significant lost motion lies within :data:`RESOLUTION_STEPS` scale
        steps, so that the record cannot tell it from the scale's rounding [-].

        Parameters
        ----------
        z : float
            Significance in standard deviations [-].
        """
        return bool(self.lost_motion_found(z)
                    and self.backlash < RESOLUTION_STEPS * self.scale_resolution)

    def to_dict(self) -> dict:
        """Plain dictionary for a JSON report (SI units) [-]."""

        def num(x):
            return float(x) if np.isfinite(x) else None

        return {
            "stiffness_N_per_m": {"value": num(self.stiffness), "std": num(self.stiffness_std)},
            "guideway_share": {"value": num(self.guideway_share),
                               "std": num(self.guideway_share_std)},
            "backlash_m": {"value": num(self.backlash), "std": num(self.backlash_std)},
            "table_viscous_N_s_per_m": {"value": num(self.table_viscous),
                                        "std": num(self.table_viscous_std)},
            "offset_m": num(self.offset),
            "determined": bool(self.determined),
            "reason": self.reason,
            "samples": int(self.samples),
            "rms_m": num(self.rms),
            "cutoff_hz": num(self.cutoff),
        }


def estimate_nut(t, motor_angle, scale, R_L: float, mechanics, friction_curve,
                 total_viscous: float, *, share: float = 0.5, cutoff=CUTOFFS_HZ,
                 min_speed: float = 2e-4, margin: float = 1.5,
                 max_rel_std: float = 0.3, scale_resolution: float = 0.0) -> NutEstimate:
    """Nut stiffness, guideway share and lost motion from a record with accelerations.

    Samples enter the fit where the sign of the nut force is sure (:func:`_sure_signs`),
    decided twice at each cut-off (:func:`_estimate_at`); of the cut-offs, the one that
    determines the share best is kept (:func:`_best_cutoff`).

    Parameters
    ----------
    t : array_like
        Time, uniformly sampled [s].
    motor_angle : array_like
        Motor encoder angle [rad].
    scale : array_like
        Linear scale ``X_LS`` [m].
    R_L : float
        Screw ratio ``lead / 2 pi`` [m/rad].
    mechanics : AxisMechanics
        Identified mechanics; ``J_L``, ``K_L``, ``B_m`` and ``M_t`` are used, ``C_t``
        only to decide the nut-force signs of the first fit [SI].
    friction_curve : callable
        Coulomb and Stribeck part of the steady friction at a velocity array, with the
        sign of the velocity, table units [N].
    total_viscous : float
        Slope of the steady motor force over the speed, at the table; the motor
        bearing's ``B_m/R_L^2`` of it does not twist the shaft [N s/m].
    share : float
        Guideway share assumed to decide the nut-force signs of nearly steady samples [-].
    cutoff : float or sequence of float
        Zero-phase low-pass before differencing (see :data:`CUTOFFS_HZ`); cut-offs at or
        above 0.8 times the Nyquist frequency are skipped [Hz].
    min_speed : float
        Samples slower than this are left out (stiction) [m/s].
    margin : float
        Factor on the largest friction force a deceleration must exceed to set the sign [-].
    max_rel_std : float
        Largest relative standard deviation of ``M_t/K_t`` for which the record counts
        as determining the stiffness [-].
    scale_resolution : float
        Resolution of the scale; its rounding, which does not average out on speeds locked
        to the sensor steps, enters the standard deviations [m].

    Returns
    -------
    NutEstimate
        The estimate; ``determined`` says whether to use it [-].
    """
    t = np.asarray(t, dtype=float)
    if not (t.size == np.size(motor_angle) == np.size(scale)):
        raise InputError("time, motor angle and scale must have the same length", column="scale")
    dt = float(np.median(np.diff(t)))
    cutoffs = [float(c) for c in np.atleast_1d(cutoff)]
    usable = sorted(c for c in cutoffs if c < 0.4 / dt) or cutoffs[:1]
    found = [_estimate_at(t, dt, motor_angle, scale, R_L, mechanics, friction_curve,
                          total_viscous, share, c, min_speed, margin, max_rel_std,
                          scale_resolution) for c in usable]
    return replace(_best_cutoff(found, usable), scale_resolution=float(scale_resolution))


def _best_cutoff(found: list, cutoffs: list) -> NutEstimate:
    """Of the estimates ``found`` at the ``cutoffs`` [Hz], the determined one with the
    smallest standard deviation of the share; one above :data:`TRANSIENT_FREE_HZ` counts
    only where the next lower cut-off agrees (:func:`_same_nut`). Without any, the
    first [-]."""
    determined = [e for k, e in enumerate(found)
                  if e.determined and np.isfinite(e.guideway_share_std)
                  and (cutoffs[k] <= TRANSIENT_FREE_HZ
                       or (k > 0 and _same_nut(e, found[k - 1])))]
    return min(determined, key=lambda e: e.guideway_share_std) if determined else found[0]


def _same_nut(e: NutEstimate, lower: NutEstimate) -> bool:
    """Whether ``lower``, at the next lower cut-off, determines the stiffness of ``e``
    within :data:`CUTOFF_AGREEMENT` combined standard deviations and finds lost motion
    where ``e`` does [-]."""
    return bool(lower.determined and lower.lost_motion_found() == e.lost_motion_found()
                and abs(e.stiffness - lower.stiffness)
                <= CUTOFF_AGREEMENT * math.hypot(e.stiffness_std, lower.stiffness_std))


def _estimate_at(t, dt, motor_angle, scale, R_L, mechanics, friction_curve, total_viscous,
                 share, cutoff, min_speed, margin, max_rel_std,
                 scale_resolution=0.0) -> NutEstimate:
    """:func:`estimate_nut` at one cut-off [Hz]; the other arguments as there [SI].

    The sweep rarely determines ``C_t`` (it can come out several times too large, and then
    the braking samples that separate play from share are lost), so the nut-force signs
    are decided a second time with the viscous force through the nut and the share of the
    first fit; the second fit is kept unless only the first is determined.
    """
    m = mechanics
    th = lowpass_filtfilt(motor_angle, dt, cutoff)
    x = lowpass_filtfilt(scale, dt, cutoff)
    v = central_difference(x, dt)
    a = central_difference(v, dt)
    ff = np.asarray(friction_curve(v), dtype=float)
    load_viscous = max(float(total_viscous) - m.B_m / R_L**2, 0.0)
    y = R_L * th - x - R_L**2 / m.K_L * (
        (m.J_L / R_L**2 + m.M_t) * a + ff + load_viscous * v)
    guard = max(1, round(1.0 / (cutoff * dt)))  # the filter's smear of a jump

    def fit(C_t, s):
        return _fit_nut(t, v, a, y, ff, guard, m, C_t, min(max(float(s), 0.0), 1.0),
                        min_speed, margin, max_rel_std, (scale, scale_resolution))

    kept = fit(m.C_t, share)
    c_tab = kept.table_viscous
    if np.isfinite(c_tab) and c_tab >= 0.0:
        again = fit(c_tab, kept.guideway_share if np.isfinite(kept.guideway_share) else share)
        if again.determined or not kept.determined:
            kept = again
    return replace(kept, cutoff=cutoff)


def _sure_signs(v, a, ff, guard: int, M_t: float, C_t: float, share: float,
                min_speed: float, margin: float):
    """The sign of the nut force ``F_t = M_t a + C_t v + s F_f(v)`` and where it is sure.

    It is that of ``v`` where the table does not decelerate (all terms agree for any share
    ``s`` in ``[0, 1]``) or decelerates only a little (``M_t |a|`` below a quarter of
    ``share |F_f| + C_t |v|``), and that of ``a`` where the deceleration force exceeds
    ``margin`` times ``|F_f| + C_t |v|``; the samples in between, those slower than
    ``min_speed`` [m/s], and those within the filter's smear (``guard`` samples) of a
    change, are left out. ``v``, ``a`` and ``ff`` are the filtered speed, acceleration and
    friction [m/s, m/s^2, N], ``M_t`` [kg], ``C_t`` [N s/m], ``share`` and ``margin`` [-].

    Returns
    -------
    tuple of numpy.ndarray
        The sign of the nut force, and whether each sample enters the fit [-].
    """
    from scipy.ndimage import binary_dilation

    inertia = M_t * np.abs(a)
    largest = np.abs(ff) + C_t * np.abs(v)
    along = a * v >= 0.0
    steady = inertia < 0.25 * (share * np.abs(ff) + C_t * np.abs(v))
    braking = ~along & (inertia > margin * largest)
    sgn = np.where(braking, np.sign(a), np.sign(v))
    sure = (along | steady | braking) & (np.abs(v) >= min_speed)
    jump = np.zeros(v.size, dtype=bool)
    jump[1:] = (sgn[1:] != sgn[:-1]) | (sure[1:] != sure[:-1])
    use = sure & ~binary_dilation(jump | ~sure, np.ones(2 * guard + 1, dtype=bool))
    use[:3 * guard] = use[-3 * guard:] = False  # filter start-up
    return sgn, use


def _fit_nut(t, v, a, y, ff, guard: int, m, C_t: float, share: float, min_speed: float,
             margin: float, max_rel_std: float, scale_q=(None, 0.0)) -> NutEstimate:
    """The least-squares fit of :func:`estimate_nut` on the filtered signals, with the
    nut-force signs decided by ``C_t`` [N s/m] and ``share`` [-]; ``scale_q`` is the
    recorded scale and its resolution ([m], [m]), whose rounding enters the covariance."""
    sgn, use = _sure_signs(v, a, ff, guard, m.M_t, C_t, share, min_speed, margin)
    n = int(use.sum())
    nan = float("nan")
    if n < 20 * guard:
        return NutEstimate(nan, nan, nan, nan, 0.0, nan, nan, nan, nan, False,
                           f"only {n} samples of a sure nut-force sign away from stiction",
                           n, nan)
    A = np.column_stack([np.ones(n), v[use], ff[use], a[use], 0.5 * sgn[use]])
    theta, *_ = np.linalg.lstsq(A, y[use], rcond=None)
    r = y[use] - A @ theta
    s2 = float(r @ r) / max(n - A.shape[1], 1) * guard  # correlated over ~guard samples
    try:
        inv = np.linalg.inv(A.T @ A)
        cov = inv * s2
        if scale_q[0] is not None:
            cov = cov + quantisation_cov(t, use, inv @ A.T, np.asarray(scale_q[0]),
                                          scale_q[1], v)
    except np.linalg.LinAlgError:
        cov = np.full((5, 5), np.inf)
    c, beta, p_s, p_a, g = (float(q) for q in theta)
    sd = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    rms = float(np.sqrt(np.mean(r**2)))
    if not (p_a > 0 and sd[3] <= max_rel_std * p_a):
        return NutEstimate(nan, nan, nan, nan, 0.0, nan, nan, nan, c, False,
                           f"the accelerations of the record do not determine the nut "
                           f"stiffness (M_t/K_t = {p_a:.3g} +- {sd[3]:.2g} kg m/N)",
                           n, rms)
    K_t = m.M_t / p_a
    s = p_s * K_t  # (s/K_t) K_t
    # delta method for s = M_t p_s/p_a
    jac = m.M_t * np.array([1.0 / p_a, -p_s / p_a**2])
    s_sd = float(math.sqrt(max(jac @ cov[np.ix_([2, 3], [2, 3])] @ jac, 0.0)))
    c_tab = K_t * beta
    return NutEstimate(
        stiffness=K_t, stiffness_std=K_t * sd[3] / p_a, guideway_share=s,
        guideway_share_std=s_sd, backlash=max(g, 0.0), backlash_std=float(sd[4]),
        table_viscous=c_tab, table_viscous_std=K_t * float(sd[1]), offset=c,
        determined=bool(0.0 <= s <= 1.0 and g >= -4.0 * sd[4]),
        reason=("stiffness, share and lost motion from the accelerations and plateaus"
                if 0.0 <= s <= 1.0 else f"share {s:.2f} outside [0, 1]"),
        samples=n, rms=rms)
