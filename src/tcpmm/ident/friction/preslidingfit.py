"""Pre-sliding distance and bristle damping from the reversals of the friction runs.

Where a friction run turns round at a slow plateau speed, the motor current swings from
the friction of one direction to that of the other while the axis travels a few
micrometres: the contacts deform elastically (pre-sliding) before they slide back. The
motor encoder resolves that travel (nanometres per count) and the current gives the force,
so the reversals determine how far a contact travels while its force builds up.

The model is quasi-static and driven by the measured motion, in table units
(``R = lead / 2 pi``):

- the screw contact moves with the screw, ``s_L = R th_m - R^2 F_m / K_L`` (torsion);
- the nut force is what the motor force leaves after the screw friction and the
  inertia and damping of motor and screw, ``F_n = F_m - F_s - (J_m + J_L) a / R^2 -
  (B_m + B_L) v / R^2``, and the guideway contact moves with the table,
  ``x_t = s_L - F_n / K_t``;
- the predicted motor force is ``F_s(s_L) + F_g(x_t) + (J_m + J_L) a / R^2 +
  (B_m + B_L) v / R^2 + M_t a + C_t v``, with ``F_m = K_tc i / R`` measured.

Both contacts are LuGre contacts (:func:`tcpmm.ident.friction.presliding.with_presliding`) with the
identified levels and Stribeck curve; one pre-sliding distance ``z`` (``sigma0 = Fs / z``)
and one bristle damping ratio ``zeta`` (``sigma1 = 2 zeta sqrt(sigma0 M_t)``, fading with
speed) are fitted by bounded least squares to the motor force in a window around every
reversal (from :data:`PRE` before the turning point to :data:`POST` after it).

One distance for both contacts: the two contacts give force-travel curves of nearly the
same shape, and on records of an independent simulator a separate distance per contact
came out with screw and guideway interchanged, so the data are not taken to separate them.
The encoder position is smoothed over :data:`SMOOTH_S` and passed through a play before
it drives the contacts; the motor force is smoothed over :data:`FORCE_SMOOTH_S` before it
deflects the springs. A LuGre contact ratchets on noise: where a position loop brings the
axis to its turning point creeping at micrometres per second, every step back of a noisy
path relaxes the bristles twice as fast as a step forward loads them, the modelled force
sinks while the measured one holds, and the fit takes softer bristles (a longer
distance) for it. The play lets through every travel longer than its width (tens of
nanometres, against micrometres of pre-sliding) and none of the back-and-forth within it.

How wide the play must be is not known beforehand: the creeping turns carry real motion of
a few tens of nanometres that is not told from noise by its size, and on records of an
independent simulator the distance moved by a factor of three between no play and 50 nm.
So the width is fitted as well (:func:`_over_band`). The distance and damping are fitted
at :data:`BAND_GRID` times :data:`JITTER_SIGMAS` standard deviations of the noise left in
the smoothed path. About the width whose fit leaves the smallest force residual, the width
is refined to the vertex of a parabola and fitted once more. ``presliding_range`` spans that
fit and those at the neighbouring widths, each widened by two standard deviations of its
fit: the range over which identify says how far the predicted spikes move
(:mod:`tcpmm.ident.friction.sensitivity`).

The standard deviations come from the Jacobian, inflated by the correlation time of the
residual. The fit counts as not determined, and the caller keeps its prior, when fewer
than :data:`MIN_REVERSALS` reversals are slow enough (turning round from a plateau of
:data:`SLOW_REVERSAL_SPEED` or slower), when the encoder step at the table
is more than :data:`MAX_QUANTUM_REL` of the distance, when the nut's lost motion (left
out of the model) is more than :data:`MAX_LOST_MOTION_REL` of it, when the force residual exceeds
:data:`MAX_MISFIT` times the noise of the measured force (the reversals do not follow the
model: stick-slip, or a turn within a few samples), when the distance is uncertain by
more than :data:`MAX_LOG_STD` (in its logarithm) or when it ends on a bound.
"""

from __future__ import annotations

import itertools
import math

import numpy as np

from ... import _compiled
from ...mechanics.friction import friction_params_array
from .presliding import with_presliding
from .preslidingresult import PreslidingFit

__all__ = ["fit_presliding"]

#: Travel before the turning point that the window starts at [m].
PRE = 20e-6
#: Travel after the turning point that the window ends at [m].
POST = 40e-6
#: Speed above which the axis counts as moving, for finding the turning points [m/s].
MOVING_SPEED = 0.2e-3
#: Smoothing span of the encoder position that drives the contacts [s].
SMOOTH_S = 0.015
#: Width of the play that the smoothed encoder path passes through before it drives the
#: contacts, in standard deviations of that path's noise [-].
JITTER_SIGMAS = 6.0
#: Smoothing span of the motor force that deflects torsion and nut springs [s].
FORCE_SMOOTH_S = 0.031
#: Widths of the play tried, in :data:`JITTER_SIGMAS` noise deviations: the one whose fit
#: explains the force best is refined and kept [-].
BAND_GRID = tuple(2.0 ** k for k in range(-4, 5))
#: Bounds of the pre-sliding distance [m].
BOUNDS = (0.05e-6, 15e-6)
#: Bounds of the bristle damping ratio [-].
ZETA_BOUNDS = (0.0, 2.0)
#: Fewest reversals the fit rests on [-].
MIN_REVERSALS = 2
#: Fastest plateau a reversal turns round from that shows the pre-sliding: from the runs'
#: 0.5 and 2 mm/s plateaus the force builds over the distance; from 5 mm/s up the axis
#: brakes into the turn and the inertia and the servo shape it, and a fit to such turns
#: alone came out at 0.58 of the distance with a tenth of that as its deviation (bench
#: D, runs from 5 mm/s up) [m/s].
SLOW_REVERSAL_SPEED = 2.5e-3
#: Largest standard deviation of the logarithm of the distance for it to count [-].
MAX_LOG_STD = 0.35
#: Largest encoder step, at the table, against the fitted distance [-].
MAX_QUANTUM_REL = 0.1
#: Largest lost motion of the nut, which the reversal model leaves out, against the
#: fitted distance [-].
MAX_LOST_MOTION_REL = 0.1
#: Largest ratio of the force residual to the force noise for the model to count [-].
MAX_MISFIT = 1.5


def _odd(n: float) -> int:
    k = max(5, round(n))
    return k if k % 2 else k + 1


def _quantum(x) -> float:
    """Smallest step of a quantised signal, from its nonzero sample differences [as x]."""
    d = np.abs(np.diff(x))
    d = d[d > 0.0]
    return float(np.min(d)) if d.size else 0.0


def _smoothed_noise(raw, smooth, n: int) -> float:
    """Standard deviation of the noise left in a path smoothed over ``n`` samples: the
    robust spread of raw minus smoothed, times the noise gain of the filter [as raw]."""
    from scipy.signal import savgol_filter

    r = raw - smooth
    sigma = float(np.median(np.abs(r - np.median(r)))) / 0.6745
    impulse = np.zeros(2 * n + 1)
    impulse[n] = 1.0
    return sigma * float(np.sqrt(np.sum(savgol_filter(impulse, n, 2) ** 2)))


def _motion(record, mech):
    """Time step, smoothed table-unit motor position, velocity, acceleration, forces, and
    the play that takes the smoothed position's noise out of the contacts' paths."""
    from scipy.signal import savgol_filter

    t = np.asarray(record.time_s, float)
    h = float(np.median(np.diff(t)))
    R = mech.lead / (2.0 * math.pi)
    s_raw = np.asarray(record.motor_angle_rad, float) * R
    fm = mech.K_tc * np.asarray(record.current_cmd_A, float) / R
    n = _odd(SMOOTH_S / h)
    s = savgol_filter(s_raw, n, 2)
    return {
        "h": h, "R": R, "fm": fm, "quantum": _quantum(s_raw), "s": s,
        "band": JITTER_SIGMAS * _smoothed_noise(s_raw, s, n),
        "v": savgol_filter(s_raw, _odd(0.011 / h), 3, deriv=1, delta=h),
        "a": savgol_filter(s_raw, _odd(0.021 / h), 3, deriv=2, delta=h),
        "fms": savgol_filter(fm, _odd(FORCE_SMOOTH_S / h), 2),
    }


def _turning_points(s, v):
    """Indices where the motion turns from one direction to the other [-]."""
    moving = np.where(np.abs(v) > MOVING_SPEED, np.sign(v), 0.0)
    idx = np.flatnonzero(moving)
    out = []
    for a, b in itertools.pairwise(idx):
        if moving[a] != moving[b]:
            seg = s[a:b + 1]
            out.append(a + int(np.argmax(seg) if moving[a] > 0 else np.argmin(seg)))
    return out


def _windows(s, v, margin: int):
    """Sample ranges ``(a, b)`` from PRE before to POST after each turning point [-]."""
    out = []
    for k in _turning_points(s, v):
        a = k
        while a > margin and abs(s[a] - s[k]) < PRE:
            a -= 1
        b = k
        while b < len(s) - 1 and abs(s[b] - s[k]) < POST:
            b += 1
        if a > margin and b < len(s) - 1 and abs(s[b] - s[k]) >= POST:
            out.append((a, b))
    return out


def _plateau_speeds(v, windows) -> list:
    """The speed of the plateau each window's reversal turns round from: the largest
    between the previous window and this one; ``inf`` where the two overlap (the axis
    turned again before it travelled back ``POST``: no plateau, so no slow one) [m/s]."""
    ends = [0] + [b for _, b in windows[:-1]]
    return [float(np.max(np.abs(v[e:a + 1]))) if e <= a else math.inf
            for e, (a, _) in zip(ends, windows, strict=True)]


def _contact_force(params, path, h, band: float):
    """Force of a contact (parameter vector, ``None`` for none) along ``path`` through a
    play of width ``band`` [N]."""
    if params is None:
        return np.zeros_like(path)
    # through the module compiled ahead of time (tcpmm.sim.pathforce's functions): an
    # identification then never starts numba (its import and cache, about a second)
    moved = _compiled.call("play_operator", path, float(band))
    return _compiled.call("contact_force_along_path", moved, float(h), params)


def _window_parts(m, windows, mech, margin: int) -> list:
    """Per window what :func:`_residual` takes that no friction parameter changes: the
    screw's path and that path through the play, the motor force less the drive's
    inertia and damping, the table side's inertia and damping forces, the motor force
    measured; the fit evaluates the residual some hundred times on them [-]."""
    R = m["R"]
    drive = (mech.J_m + mech.J_L) / R**2
    drive_c = (mech.B_m + mech.B_L) / R**2
    parts = []
    for a, b in windows:
        sl = slice(a - margin, b + 1)
        fms, v, acc = m["fms"][sl], m["v"][sl], m["a"][sl]
        s_L = m["s"][sl] - R**2 / mech.K_L * fms
        parts.append((s_L, _compiled.call("play_operator", s_L, float(m["band"])),
                      fms - drive * acc - drive_c * v, (drive + mech.M_t) * acc,
                      (drive_c + mech.C_t) * v, m["fm"][sl]))
    return parts


def _residual(m, parts: list, fr, mech, margin: int) -> np.ndarray:
    """Measured minus predicted motor force over every window (:func:`_window_parts`)
    [N]."""
    h = m["h"]
    p_s, p_g = (None if c is None else friction_params_array(c)
                for c in (fr.screw, fr.guideway))
    out = []
    for s_L, moved, free, inertia, damping, fm in parts:
        f_s = (np.zeros_like(s_L) if p_s is None else
               _compiled.call("contact_force_along_path", moved, float(h), p_s))
        f_n = free - f_s
        f_g = _contact_force(p_g, s_L - f_n / mech.K_t, h, m["band"])
        pred = f_s + f_g + inertia + damping
        out.append((fm - pred)[margin:])
    return np.concatenate(out)


def _force_noise(fm, windows) -> float:
    """Noise of the motor force from its sample-to-sample differences (robust) [N]."""
    d = np.concatenate([np.diff(fm[a:b + 1]) for a, b in windows])
    return float(np.median(np.abs(d)) / (0.6745 * math.sqrt(2.0)))


def _inflation(r: np.ndarray, lags: int = 30) -> float:
    """Variance inflation of a mean over correlated residuals, ``1 + 2 sum rho_k`` [-]."""
    r = r - r.mean()
    var = float(r @ r)
    if var <= 0.0:
        return 1.0
    rho = [float(r[:-k] @ r[k:]) / var for k in range(1, min(lags, len(r) // 4) + 1)]
    return max(1.0, 1.0 + 2.0 * sum(rho))


def _not_determined(reason: str, reversals: int = 0) -> PreslidingFit:
    nan = float("nan")
    return PreslidingFit(nan, nan, nan, nan, reversals, nan, nan, False, reason)


def _solve(fun, lo, hi):
    """Bounded least squares from two starts; the lower cost wins (deterministic)."""
    from scipy.optimize import least_squares

    best = None
    for z0 in (1e-6, 5e-6):
        r = least_squares(fun, [math.log(z0), 0.3], bounds=(lo, hi), diff_step=1e-3,
                          x_scale=[1.0, 0.3])
        if best is None or r.cost < best.cost:
            best = r
    return best


def _fit_with_sd(fun, lo, hi):
    """:func:`_solve`, and the standard deviations of the log distance and the damping
    ratio from its Jacobian and the residual's correlation time [-]."""
    r = _solve(fun, lo, hi)
    dof = max(len(r.fun) - 2, 1)
    s2 = float(r.fun @ r.fun) / dof * _inflation(r.fun)
    cov = np.linalg.pinv(r.jac.T @ r.jac) * s2
    log_sd, zeta_sd = (float(math.sqrt(max(c, 0.0))) for c in np.diag(cov))
    return r, log_sd, zeta_sd


def _vertex(x, f) -> float:
    """Abscissa of the vertex of the parabola through three points [as x]."""
    (x0, x1, x2), (f0, f1, f2) = x, f
    den = (x1 - x0) * (f1 - f2) - (x1 - x2) * (f1 - f0)
    if den == 0.0:
        return x1
    return x1 - 0.5 * ((x1 - x0) ** 2 * (f1 - f2) - (x1 - x2) ** 2 * (f1 - f0)) / den


def _over_band(fit_at):
    """The fit at the play's width that explains the force best, and the range of the
    distance: ``fit_at(k)`` fits at ``k`` times :data:`JITTER_SIGMAS` noise deviations.

    The fits over :data:`BAND_GRID` are compared by their cost; about the lowest, the
    width is refined to the vertex of the parabola through it and its neighbours (in the
    logarithm of the width) and fitted once more. The range spans the chosen fit and its
    two neighbours on the grid, each widened by two standard deviations [-]."""
    grid = [fit_at(k) for k in BAND_GRID]
    cost = [g[0].cost for g in grid]
    i = int(np.argmin(cost))
    best = grid[i]
    if 0 < i < len(grid) - 1:
        x = [math.log2(BAND_GRID[j]) for j in (i - 1, i, i + 1)]
        best = fit_at(2.0 ** _vertex(x, cost[i - 1:i + 2]))
        if best[0].cost > cost[i]:  # the parabola does not describe the costs
            best = grid[i]
    ends = []
    for r, sd, _ in [best, *grid[max(i - 1, 0):i + 2]]:
        ends += [math.exp(r.x[0] - 2.0 * sd), math.exp(r.x[0] + 2.0 * sd)]
    return best, (min(ends), max(ends))


def fit_presliding(record, mechanics, friction) -> PreslidingFit:
    """Fit one pre-sliding distance and bristle damping to the friction-run reversals.

    Parameters
    ----------
    record : tcpmm.io.records.FrictionRecord
        Friction runs of the axis: time, current command, motor angle [SI].
    mechanics : tcpmm.mechanics.lumped.AxisMechanics
        Identified mechanics (inertias, damping, ``K_L``, ``K_t``, ``M_t``, ``K_tc``)
        [SI].
    friction : tcpmm.model.AxisFriction
        Identified friction: levels, Stribeck curve and share of the two contacts [SI].

    Returns
    -------
    PreslidingFit
        The distance and damping ratio with their standard deviations; ``determined``
        says whether they count [SI].
    """
    if friction is None or (friction.screw is None and friction.guideway is None):
        return _not_determined("the axis has no friction to fit")
    m = _motion(record, mechanics)
    margin = _odd(0.005 / m["h"])
    windows = _windows(m["s"], m["v"], margin)
    if len(windows) < MIN_REVERSALS:
        return _not_determined(
            f"{len(windows)} reversal(s) turn round from a plateau and travel "
            f"{POST * 1e6:g} um back; at least {MIN_REVERSALS} are needed", len(windows))
    slow = sum(v <= SLOW_REVERSAL_SPEED for v in _plateau_speeds(m["v"], windows))
    if slow < MIN_REVERSALS:
        return _not_determined(
            f"{slow} of the {len(windows)} reversals turn round from "
            f"{SLOW_REVERSAL_SPEED * 1e3:g} mm/s or slower, where the force builds over the "
            f"distance; at least {MIN_REVERSALS} are needed", len(windows))

    def model(p):
        return with_presliding(friction, mechanics, math.exp(p[0]), p[1])

    def fit_at(k):
        mk = {**m, "band": k * m["band"]}
        parts = _window_parts(mk, windows, mechanics, margin)
        return _fit_with_sd(lambda p: _residual(mk, parts, model(p), mechanics, margin),
                            lo, hi)

    lo = [math.log(BOUNDS[0]), ZETA_BOUNDS[0]]
    hi = [math.log(BOUNDS[1]), ZETA_BOUNDS[1]]
    (r, log_sd, zeta_sd), ends = _over_band(fit_at)
    z = math.exp(r.x[0])
    rms = float(np.sqrt(np.mean(r.fun**2)))
    noise = _force_noise(m["fm"], windows)
    reason = _why_not(friction.backlash, m["quantum"], z, rms, noise, log_sd,
                      min(r.x[0] - lo[0], hi[0] - r.x[0]))
    return PreslidingFit(z, z * log_sd, float(r.x[1]), zeta_sd, len(windows), rms, noise,
                         not reason, reason, ends)


def _why_not(backlash: float, quantum: float, z: float, rms: float, noise: float,
             log_sd: float, to_bound: float) -> str:
    """Why a fitted distance ``z`` [m] does not count, or ``""``: the nut's lost motion
    ``backlash`` [m] or the encoder step ``quantum`` [m] too large against it, a force
    residual ``rms`` too large against the ``noise`` [N], its log standard deviation
    ``log_sd`` [-] too large, or its logarithm within 0.01 of a bound (``to_bound``) [-]."""
    if backlash > MAX_LOST_MOTION_REL * z:
        return (f"the nut has {backlash * 1e6:.3g} um of lost motion, which the "
                f"reversal model leaves out, against a pre-sliding of {z * 1e6:.3g} um")
    if quantum > MAX_QUANTUM_REL * z:
        return (f"the encoder resolves {quantum * 1e6:.3g} um at the table, too "
                f"coarse for a pre-sliding of {z * 1e6:.3g} um")
    if rms > MAX_MISFIT * noise:
        return (f"the reversals do not follow the pre-sliding model (force residual "
                f"{rms:.3g} N against {noise:.3g} N of noise): stick-slip, or a turn "
                "too fast for the record")
    if log_sd > MAX_LOG_STD:
        return (f"the reversals leave the distance uncertain by a factor "
                f"{math.exp(log_sd):.2f}")
    if to_bound < 0.01:
        return f"the distance ends on a bound of the fit ({z * 1e6:.3g} um)"
    return ""
