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
from dataclasses import replace

import numpy as np

from ...errors import InputError
from .hysteresis import (
    PlateauDeflections,
    fit_both_free,
    fit_lost_motion_given,
    fit_share_given,
)
from .lostmotionestimate import LostMotionEstimate
from .lostmotionoptions import LostMotionOptions

__all__ = ["LostMotionEstimate", "LostMotionOptions", "estimate_lost_motion",
           "quantisation_bias_std"]

#: Highest harmonic of the quantisation saw-tooth used for the residual bias [-].
_HARMONICS = 100
#: Complex entries [-] worked on at once by :func:`quantisation_bias_std`.
_BLOCK = 1 << 18
#: Blocks a plateau is cut into for the statistical error of its mean [-].
_BLOCKS = 8


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
    # powers of the first harmonic, one exp per sample, not n, as the same products from 1;
    # the means of a block of rows at once (each the same pairwise sum as a 1-D mean) and
    # abs of each complex scalar, as numpy's vectorised abs may differ in the last bit
    zn = np.ones_like(z)
    block = np.empty((min(n.size, max(1, _BLOCK // z.size)), z.size), dtype=complex)
    c = []
    for a in range(0, n.size, block.shape[0]):
        rows = block[:min(block.shape[0], n.size - a)]
        for row in rows:
            zn = np.multiply(zn, z, out=row)
        c.extend(abs(m) ** 2 for m in rows.mean(axis=1))
    c = np.array(c)
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


def estimate_lost_motion(t, motor_angle, scale, force, R_L: float, mechanics, plateaus,
                         options: LostMotionOptions | None = None,
                         **settings) -> LostMotionEstimate:
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
    options : LostMotionOptions, optional
        Sensor steps, what is known and the thresholds of the decision [-].
    **settings
        Fields of :class:`LostMotionOptions` that replace those of ``options`` [-].

    Returns
    -------
    LostMotionEstimate
        Share, lost motion, their standard deviations and the plateau table [-].
    """
    opt = replace(options or LostMotionOptions(), **settings)
    t = np.asarray(t, dtype=float)
    th = np.asarray(motor_angle, dtype=float)
    xs = np.asarray(scale, dtype=float)
    f = np.asarray(force, dtype=float)
    if not (t.size == th.size == xs.size == f.size):
        raise InputError("time, motor angle, scale and force must have the same length",
                         column="scale")
    opt.check()
    v, d, d_sd, fm = _plateau_table(t, th, xs, f, R_L, plateaus, opt)
    fric, y = _friction_side(v, d, fm, R_L, mechanics, opt)
    p = PlateauDeflections.build(v, d, d_sd, fric, y, mechanics, opt)
    n_pos, n_neg = int(np.sum(p.use & (p.v > 0))), int(np.sum(p.use & (p.v < 0)))
    if n_pos < 2 or n_neg < 2 or p.use.sum() < p.k + 2:
        nan = float("nan")
        return p.result(nan, nan, 0.0, nan, None, False,
                        f"need at least 2 plateaus in each direction "
                        f"{'at speeds run both ways ' if opt.offset == 'per_speed' else ''}"
                        f"(have {n_pos} forward, {n_neg} back)", "none", nan)
    if opt.share is not None:
        return fit_share_given(p, float(opt.share))
    if opt.backlash is not None:
        return fit_lost_motion_given(p)
    return fit_both_free(p)


def _plateau_table(t, th, xs, f, R_L: float, plateaus, opt: LostMotionOptions):
    """Per plateau: mean velocity [m/s], mean deflection ``R_L th - X_LS`` [m], its
    standard deviation (statistics and quantisation, at least a nanometre) [m] and the
    mean force [N]."""
    d_all = R_L * th - xs
    q_enc = R_L * opt.encoder_quantum
    rows = []
    for p in plateaus:
        a, b = int(p.start), int(p.stop)
        if b - a < 3:
            continue
        tt = t[a:b]
        vel = float((xs[b - 1] - xs[a]) / (tt[-1] - tt[0]))
        dm, sd_stat = _plateau_mean(d_all, a, b)
        sd_q = math.hypot(quantisation_bias_std(tt, R_L * th[a:b], q_enc),
                          quantisation_bias_std(tt, xs[a:b], opt.scale_resolution))
        rows.append((vel, dm, math.hypot(sd_stat, sd_q), float(f[a:b].mean())))
    if not rows:
        raise InputError("no plateau long enough to average the deflection", column="scale")
    v, d, d_sd, fm = (np.array(c) for c in zip(*rows, strict=True))
    # no plateau mean is known better than a nanometre (numerical floor of the weights)
    return v, d, np.maximum(d_sd, 1e-9), fm


def _friction_side(v, d, fm, R_L: float, m, opt: LostMotionOptions):
    """The friction force of each plateau [N] and the left side ``y`` of the fit: the
    nut deflection plus offset (plus ``beta v`` with ``viscous="fit"``) [m]."""
    K_L, K_t = float(m.K_L), float(m.K_t)
    load = float(getattr(m, "load_force", 0.0))
    if opt.viscous == "known":
        linear = (m.B_m + m.B_L) / R_L**2 + m.C_t
        fric = fm - linear * v + load
        y = d - R_L**2 / K_L * (fm - m.B_m * v / R_L**2) - (m.C_t * v - load) / K_t
    else:
        if opt.total_viscous is not None:
            slope = float(opt.total_viscous)
        else:
            pos, neg = (v > 0).astype(float), (v < 0).astype(float)
            (_, _, slope), *_ = np.linalg.lstsq(np.column_stack([pos, neg, v]), fm, rcond=None)
        fric = fm - slope * v + load
        y = d - R_L**2 / K_L * fm
    return fric, y


