"""The guideway share of the friction from the column's deflection during a travelling sweep.

A sweep that travels at a steady speed ``v`` keeps the friction sliding. Over the record
the accelerations average out and the nut pushes the table with the force that holds it
against its guideway friction, its viscous damping and a load ``F_load`` (the weight on a
vertical axis), ``F_t = F_g(v) + C_t v - F_load``. The nut's reaction bends the TCP
structure (``K_h X_h = F_t``) and the bed (``K_b X_b = -F_t + F_g``, the guideway's
reaction on the bed), so the mean of scale minus TCP over the record is

    <X_LS - X_TCP> = <X_h - X_b> = F_t / K_h + (C_t v - F_load) / K_b.

With ``K_h`` and ``K_b`` from the sweep's FRFs this gives the force on the table side of
the nut, and with the steady friction curve of the friction runs, the part of its Coulomb
and Stribeck level that acts on the guideway. The TCP device resolves the deflection
(micrometres for a few hundred newtons on a column of 10-30 N/um) far better than a
linear scale resolves the nut's deflection, and what it measures is what the TCP does at
a reversal: the column springs back by twice ``F_g / K_h``.

The share is the one for which the identified model reproduces the measured mean
deflection; its standard deviation counts the scatter of the deflection over the record,
the uncertainty of ``K_h`` and of the table's viscous force. That force has two measures,
the friction runs' plateaus and the FRFs' ``C_t``, which :func:`table_viscous_estimate`
weighs together. :func:`sweep_share` gives the share on the friction runs' steady curve, and
:func:`settle_sweep_share` works it and the plateaus' table damping out on each other.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from ...errors import InputWarning
from .stribeck import coulomb_stribeck

__all__ = ["SweepDeflection", "settle_sweep_share", "share_from_sweep", "sweep_deflection",
           "sweep_share", "table_viscous_estimate", "travel_speed", "travel_velocity"]

#: Blocks the record is cut into to see the scatter of its mean deflection [-].
N_BLOCKS = 16
#: Standard errors and least change over the record at which the deflection drifts
#: (:func:`deflection_drift`) [-], [m].
DRIFT_T, DRIFT_MIN_M = 5.0, 0.5e-6
#: Largest relative standard deviation of the FRFs' ``C_t`` that counts as a measure of
#: the table damping: above it the FRFs do not determine it (the physical fit's own test),
#: and a spread that wide in the fit's log-parameters is too skewed to weigh [-].
FRF_C_T_REL_STD = 0.5
#: Largest share outside [0, 1], in standard deviations, still taken as [0, 1]; beyond
#: it the data contradict the model of where the friction acts [-].
OUTSIDE_Z = 3.0
#: Largest standard deviation of the sweep's share that determines it: beyond, its
#: interval of one standard deviation is wider than [0, 1] and says nothing of where the
#: friction acts (a sweep cut short, whose FRFs leave ``K_h`` a guess, gives thousands) [-].
SHARE_STD_MAX = 0.5
#: Travel over a sweep record below which it counts as standing still: the guideway
#: friction then holds the nut on no particular flank [m].
MIN_SWEEP_TRAVEL_M = 1e-3
#: Largest difference of the Coulomb levels of the two directions, relative to their mean,
#: for which a sweep travelling one way gives the share [-].
SWEEP_ASYMMETRY = 0.2
#: Rounds of plateau damping and sweep share, each resting on the other, and the change of
#: the share that ends them [-].
SWEEP_ITERATIONS, SWEEP_SHARE_TOL = 5, 1e-4


@dataclass(frozen=True)
class SweepDeflection:
    """Mean deflection of the TCP structure relative to the bed during a travelling sweep.

    Parameters
    ----------
    velocity : float
        Mean travel speed, signed [m/s].
    deflection : float
        Mean of scale minus TCP over the record [m].
    deflection_std : float
        Its standard deviation, from the scatter of the means of :data:`N_BLOCKS` blocks
        of the record, and half the drift where there is one [m].
    drift : float
        Change of the deflection over the record where it drifts (:func:`deflection_drift`),
        else 0 [m].
    cover : BandCover, optional
        What the FRFs' band leaves out of the frequencies the sweep excites: the structure's
        stiffness, which turns the deflection into a share, rests on the FRFs below its
        modes (:class:`~tcpmm.ident.frf.excited.BandCover`) [-].
    """

    velocity: float
    deflection: float
    deflection_std: float
    drift: float = 0.0
    cover: object = None

    def to_dict(self) -> dict:
        """Plain dictionary for the JSON report, SI units [-]."""
        return {"velocity_m_per_s": self.velocity, "deflection_m": self.deflection,
                "deflection_std_m": self.deflection_std}


def travel_speed(sweep) -> float:
    """Steady travel speed of a sweep record, zero when it travels less than
    :data:`MIN_SWEEP_TRAVEL_M` [m/s]."""
    return abs(travel_velocity(sweep, MIN_SWEEP_TRAVEL_M))


def travel_velocity(sweep, min_travel: float) -> float:
    """Steady travel velocity of a sweep record, signed: the slope of a line through its
    scale; zero when it travels less than ``min_travel``.

    Parameters
    ----------
    sweep : SweepRecord
        The servo-excitation record [SI].
    min_travel : float
        Travel below which the record counts as standing (its friction does not slide
        in one direction) [m].

    Returns
    -------
    float
        The velocity [m/s].
    """
    t = np.asarray(sweep.time_s, dtype=float)
    v = float(np.polyfit(t - t[0], np.asarray(sweep.scale_m, dtype=float), 1)[0])
    return v if abs(v) * (t[-1] - t[0]) >= min_travel else 0.0


def sweep_deflection(sweep, velocity: float, zero_std: float = 0.0) -> SweepDeflection | None:
    """Mean scale-minus-TCP deflection of a sweep that travels.

    Its standard deviation counts the scatter over the record and how well the TCP
    device's zero is known against the scale's (``zero_std``): an offset between the two
    zeros adds to the mean deflection whole, and on a column of 15 N/um a step of a 1 um
    scale moves the share read from it by about 0.15.

    Parameters
    ----------
    sweep : SweepRecord
        The servo-excitation record [SI].
    velocity : float
        Its travel velocity (:func:`travel_velocity`), zero for a sweep that stands [m/s].
    zero_std : float
        Standard deviation of the TCP device's zero against the scale's
        (:func:`tcpmm.ident.steps.fitcontext.zero_std_of`) [m].

    Returns
    -------
    SweepDeflection or None
        ``None`` without a TCP record, or when the sweep does not travel, or reverses [-].
    """
    scale = np.asarray(sweep.scale_m, dtype=float)
    n = scale.size // N_BLOCKS
    if sweep.tcp_m is None or velocity == 0.0 or n < 2:
        return None
    ends = scale[::n][: N_BLOCKS + 1]
    if np.any(np.sign(np.diff(ends)) != np.sign(velocity)):
        return None  # the sweep went back somewhere: no single direction of friction
    d = scale - np.asarray(sweep.tcp_m, dtype=float)
    blocks = d[: n * N_BLOCKS].reshape(N_BLOCKS, n).mean(axis=1)
    drift, scatter = deflection_drift(blocks)
    if drift == 0.0:
        return SweepDeflection(velocity, float(d.mean()),
                               math.hypot(scatter / math.sqrt(N_BLOCKS), zero_std))
    where = sweep.source or f"axis {sweep.axis}"
    warnings.warn(f"{where}: the deflection between scale and TCP drifts by "
                  f"{drift * 1e6:.2f} um over the sweep (a TCP device drifting, or its scale "
                  "against the linear scale's): its mean, which the guideway share is read "
                  "from, is taken uncertain by half that", InputWarning, stacklevel=2)
    return SweepDeflection(velocity, float(d.mean()),
                           math.hypot(scatter / math.sqrt(N_BLOCKS), 0.5 * drift, zero_std),
                           drift)


def deflection_drift(blocks: np.ndarray) -> tuple[float, float]:
    """The change over the record of the blocks' mean deflections along a line through
    them where its slope stands :data:`DRIFT_T` standard errors out of their scatter about
    it and the change is over :data:`DRIFT_MIN_M`, else 0; and the blocks' scatter about
    that line (about their mean where there is no drift) [m].

    A sweep at constant speed holds a constant friction force, and its deflection has no
    reason to trend: a trend is the TCP device drifting (heat), or its scale against the
    linear scale's (33 ppm over 150 mm of travel is 5 um). The benches' sweeps trend by
    0.6 um at most, under 2 standard errors."""
    x = np.arange(blocks.size) - 0.5 * (blocks.size - 1)
    slope = float(np.dot(x, blocks - blocks.mean()) / np.dot(x, x))
    resid = blocks - blocks.mean() - slope * x
    se = float(resid.std(ddof=2)) / math.sqrt(float(np.dot(x, x)))
    change = slope * blocks.size
    if abs(slope) > DRIFT_T * se and abs(change) > DRIFT_MIN_M:
        return change, float(resid.std(ddof=2))
    return 0.0, float(blocks.std(ddof=1))


def share_from_sweep(defl: SweepDeflection, mechanics, level: float, table_viscous: float,
                     K_h_rel_std: float = 0.0, table_viscous_std: float = 0.0):
    """Share of the Coulomb and Stribeck friction on the guideway from the sweep's
    deflection.

    Parameters
    ----------
    defl : SweepDeflection
        Mean deflection of the travelling sweep [SI].
    mechanics : AxisMechanics
        Identified mechanics; ``K_h`` and ``K_b`` are used [SI].
    level : float
        Coulomb and Stribeck part of the steady friction at the sweep's speed, all
        contacts, in the direction of travel (positive) [N].
    table_viscous : float
        Viscous force per speed on the table side of the nut (``C_t`` plus the
        guideway's viscous friction) [N s/m].
    K_h_rel_std : float
        Relative standard deviation of ``K_h`` [-].
    table_viscous_std : float
        Standard deviation of ``table_viscous`` [N s/m].

    Returns
    -------
    tuple of float or None
        ``(share, std)``, the share clipped to [0, 1]; ``None`` when the friction level
        is not positive, the share lies more than :data:`OUTSIDE_Z` standard
        deviations outside [0, 1] or its standard deviation exceeds
        :data:`SHARE_STD_MAX` [-].
    """
    m = mechanics
    v = defl.velocity
    share, nut = read_share(defl, m, level, table_viscous)
    if not math.isfinite(share):
        return None
    var = ((m.K_h * defl.deflection_std) ** 2 + (nut * K_h_rel_std) ** 2
           + (table_viscous_std * v) ** 2) / level**2
    std = math.sqrt(var)
    if share < -OUTSIDE_Z * std or share > 1.0 + OUTSIDE_Z * std or not std <= SHARE_STD_MAX:
        return None
    return min(max(share, 0.0), 1.0), std


def read_share(defl: SweepDeflection, mechanics, level: float, table_viscous: float) -> tuple:
    """The share the sweep's deflection reads, not clipped, and the nut's force it rests
    on (:func:`share_from_sweep`); NaN where the friction level is not positive [-], [N]."""
    m, v = mechanics, defl.velocity
    nut = m.K_h * (defl.deflection - (m.C_t * v - m.load_force) / m.K_b)  # signed [N]
    if not (level > 0 and math.isfinite(nut)):
        return float("nan"), nut
    return math.copysign(1.0, v) * (nut + m.load_force - table_viscous * v) / level, nut


def sweep_share_outside(sweep, mechanics, curve: dict, lm, C_t_std: float) -> float | None:
    """The share a travelling sweep reads where it lies outside 0 to 1 by more than
    :data:`OUTSIDE_Z` standard deviations of its deflection alone (a TCP device zeroed
    apart from the scale reads such a share), else ``None``; arguments as for
    :func:`sweep_share` [-]."""
    level, tv, _ = _sweep_terms(sweep, mechanics, curve, lm, C_t_std)
    share, _ = read_share(sweep, mechanics, level, tv)
    if not math.isfinite(share) or level <= 0.0:
        return None
    sd = mechanics.K_h * sweep.deflection_std / level
    return share if share < -OUTSIDE_Z * sd or share > 1.0 + OUTSIDE_Z * sd else None


def _sweep_terms(sweep, mechanics, curve: dict, lm, C_t_std: float) -> tuple:
    """What a sweep's share is read on: the Coulomb and Stribeck level of the steady curve
    at the sweep's speed, and the table's viscous force per speed with its standard
    deviation (:func:`table_viscous_estimate`) [N], [N s/m], [N s/m]."""
    tv, tv_sd = table_viscous_estimate(lm, mechanics, float(curve["Fv"]), C_t_std)
    level = abs(float(coulomb_stribeck(curve)(np.array([sweep.velocity]))[0]))
    return level, tv, tv_sd


def table_viscous_estimate(lm, mechanics, total_viscous: float, C_t_std: float):
    """The viscous force per speed on the table side of the nut from its two measures:
    the plateaus' nut deflection (``lm``) and the sweep's FRFs (``C_t``).

    Each is weighted by its inverse variance, and the standard deviation is widened by
    the scatter of the two about their mean where they disagree by more than their
    standard deviations say (Birge's ratio). An estimate without a finite, positive
    standard deviation does not count, nor the FRFs' ``C_t`` where they do not determine it
    (:data:`FRF_C_T_REL_STD`). Without either, the FRFs' ``C_t``, at most the
    steady force's slope less the screw side's damping (a sweep also sees the friction's
    local slope as damping).

    Parameters
    ----------
    lm : LostMotionEstimate
        The plateaus' estimate, with ``table_viscous`` and its standard deviation
        [N s/m].
    mechanics : AxisMechanics
        Identified mechanics: ``C_t``, ``B_m``, ``B_L`` and ``R_L`` are used [SI].
    total_viscous : float
        Slope of the steady motor force over the speed, at the table [N s/m].
    C_t_std : float
        Standard deviation of the FRFs' ``C_t``; 0 or NaN when unknown [N s/m].

    Returns
    -------
    tuple of float
        ``(table_viscous, std)``, the value within ``[0, total_viscous]`` [N s/m].
    """
    m = mechanics
    frf = (m.C_t, C_t_std if C_t_std <= FRF_C_T_REL_STD * m.C_t else math.nan)
    found = [(float(v), float(sd)) for v, sd in ((lm.table_viscous, lm.table_viscous_std), frf)
             if np.isfinite(v) and np.isfinite(sd) and sd > 0.0]
    if not found:
        room = total_viscous - (m.B_m + m.B_L) / m.R_L**2
        return min(m.C_t, max(room, 0.0)), float(C_t_std)
    vals = np.array([v for v, _ in found])
    w = 1.0 / np.array([sd for _, sd in found]) ** 2
    mean = float(np.sum(w * vals) / np.sum(w))
    sd = float(1.0 / math.sqrt(np.sum(w)))
    if vals.size > 1:
        sd *= max(1.0, math.sqrt(float(np.sum(w * (vals - mean) ** 2)) / (vals.size - 1)))
    return min(max(mean, 0.0), max(total_viscous, 0.0)), sd


def sweep_share(sweep, mechanics, curve: dict, lm, K_h_rel_std: float, C_t_std: float):
    """Share from a travelling sweep's deflection on the friction runs' steady curve.

    A record whose Coulomb levels differ by direction more than :data:`SWEEP_ASYMMETRY`
    carries a constant force (a weight the mechanics do not hold) that a sweep in one
    direction does not tell from friction. The table's viscous force is the plateaus' and
    the FRFs' measures of it together (:func:`table_viscous_estimate`).

    Parameters
    ----------
    sweep : SweepDeflection
        Mean deflection of the travelling sweep [SI].
    mechanics : AxisMechanics
        Identified mechanics [SI].
    curve : dict
        Steady friction curve by name (``Fc+, Fc-, Fs+, Fs-, vs, Fv``) [N, N, N, N, m/s,
        N s/m].
    lm : LostMotionEstimate
        The plateau estimate, for its measure of the table damping [-].
    K_h_rel_std, C_t_std : float
        Uncertainty of the FRFs' ``K_h`` (relative) and ``C_t`` (standard deviation)
        [-, N s/m].

    Returns
    -------
    tuple or None
        ``(share, share_std, table_viscous, table_viscous_std)`` [-, -, N s/m, N s/m], or
        ``None`` when the sweep does not determine the share.
    """
    m = mechanics
    up, down = abs(float(curve["Fc+"])), abs(float(curve["Fc-"]))
    if abs(up - down) > SWEEP_ASYMMETRY * 0.5 * (up + down):
        return None  # a constant force (a weight) that one direction of travel cannot tell
    level, tv, tv_sd = _sweep_terms(sweep, m, curve, lm, C_t_std)
    got = share_from_sweep(sweep, m, level, tv, K_h_rel_std=K_h_rel_std,
                           table_viscous_std=tv_sd)
    return None if got is None else (*got, tv, tv_sd)


def settle_sweep_share(from_sweep, plateaus_at, share_from):
    """The sweep's share and the table damping, each worked out on the other in turn until
    the share moves by at most :data:`SWEEP_SHARE_TOL`.

    The plateaus with the share held give the lost motion and the table damping (with the
    share free, the share takes part of the damping's slope); the sweep's share rests on
    that damping.

    Parameters
    ----------
    from_sweep : tuple
        ``(share, share_std, table_viscous, table_viscous_std)`` of the first round
        [-, -, N s/m, N s/m].
    plateaus_at : callable
        Plateau estimate with the share held at its argument [-].
    share_from : callable
        The sweep's ``(share, share_std, table_viscous, table_viscous_std)`` on a plateau
        estimate, or ``None`` [-].

    Returns
    -------
    tuple
        The settled ``from_sweep`` and the last plateau estimate [-].
    """
    lm = None
    for _ in range(SWEEP_ITERATIONS):
        lm = plateaus_at(from_sweep[0])
        again = share_from(lm)
        if again is None:
            break
        done = abs(again[0] - from_sweep[0]) <= SWEEP_SHARE_TOL
        from_sweep = again
        if done:
            break
    return from_sweep, lm
