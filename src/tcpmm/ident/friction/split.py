"""Friction of an axis from its constant-speed runs, split between guideway and screw.

``identify_friction`` fits the Stribeck curve to the ``friction.csv`` record of an axis
(:mod:`tcpmm.ident.friction.stribeck`) and divides it between guideway and screw-nut: from the
deflection between encoder and scale on the plateaus (:mod:`tcpmm.ident.friction.lostmotion`) and,
when the record shows lost motion in the nut, from the nut stiffness over the whole record
(:mod:`tcpmm.ident.friction.nutstiffness`). When the runs do not determine the split,
:data:`GUIDEWAY_SHARE` is used. ``FrictionSplit`` records the share, the lost motion and
where they came from. ``place_steady_viscous`` puts the viscous force of steady motion into
the damping of the mechanics, on the side of the nut where the runs say it acts.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
import weakref
from dataclasses import dataclass

import numpy as np

from ...errors import InputError, InputWarning
from ...mechanics.friction import StribeckFriction
from ...model import AxisFriction
from .lostmotion import estimate_lost_motion
from .nutstiffness import LOST_MOTION_Z, estimate_nut
from .stribeck import (
    PLATEAU_DURATIONS_S,
    NoPlateauError,
    _stribeck_curve,
    friction_record_arrays,
    identify_stribeck_run,
    without_undetermined_hump,
)
from .sweepforce import share_from_sweep, table_viscous_estimate
from .transients import fit_stribeck_transients

__all__ = ["GUIDEWAY_SHARE", "SHARE_WARN_STD", "FrictionSplit", "identify_friction",
           "place_steady_viscous", "share_uncertainty_warning"]

#: Share of the identified friction put on the guideway when the friction runs do not
#: determine it (see :mod:`tcpmm.ident.friction.lostmotion`): preloaded, sealed linear guides
#: usually carry most of the friction of a feed axis.
GUIDEWAY_SHARE = 0.7
#: Standard deviation of a guideway share from the data above which identification warns:
#: the friction that holds the table at a reversal, and with it the predicted reversal
#: spikes, follows the share, and a shift of 0.15 in it moves them by micrometres on an
#: axis with lost motion [-].
SHARE_WARN_STD = 0.1
#: Highest low-pass cut-off of the fit to the whole friction record; at most a quarter of
#: the drive's first axial mode, below which the axis moves as one body [Hz].
TRANSIENT_CUTOFF_HZ = 30.0
#: Largest relative standard deviation of the Stribeck speed and static levels of a fit to
#: the plateaus that is taken as determining the hump [-].
HUMP_REL_STD = 0.25
#: Largest difference of the Coulomb levels of the two directions, relative to their mean,
#: for which a sweep travelling one way gives the share [-].
SWEEP_ASYMMETRY = 0.2
#: Rounds of plateau damping and sweep share, each resting on the other, and the change of
#: the share that ends them [-].
SWEEP_ITERATIONS, SWEEP_SHARE_TOL = 5, 1e-4


def _or_none(x: float):
    """``x`` as a float, ``None`` when it is not finite (JSON has no NaN) [-]."""
    return float(x) if math.isfinite(x) else None


@dataclass(frozen=True)
class FrictionSplit:
    """How the identified friction was split between guideway and screw.

    Parameters
    ----------
    guideway_share : float
        Share of the friction put on the guideway, the rest on the screw [-].
    backlash : float
        Lost motion of the screw-nut put into the model [m].
    source : str
        ``"data"`` (from the encoder-minus-scale deflection), ``"sweep"`` (from the TCP
        structure's deflection in a travelling sweep), ``"prior"`` (not determined
        by the data: :data:`GUIDEWAY_SHARE`) or ``"given"`` (set by the user) [-].
    estimate : LostMotionEstimate or None
        The estimate from the friction runs, with standard deviations and plateaus [-].
    nut : NutEstimate or None
        Nut stiffness, share and lost motion from the whole record (accelerations and
        plateaus); set when they were used, i.e. when the record shows lost motion [-].
    guideway_share_std : float
        Standard deviation of the share used, from the estimate it came from; NaN when
        the share is the prior or given [-].
    unfound_backlash_std : float
        Standard deviation of the lost motion the whole record gives where it does not
        find any, the scale for how much could hide; NaN otherwise [m].
    viscous_on_table : float
        Viscous force per speed on the table side that a share from the sweep was
        worked out with, which the model then takes; NaN otherwise [N s/m].
    viscous_on_table_std : float
        Its standard deviation; NaN otherwise [N s/m].
    backlash_at_resolution : float
        The largest lost motion the whole record cannot tell from the scale's rounding,
        where it shows one within two scale steps (its value plus three standard
        deviations); NaN otherwise [m].
    plateau_share, plateau_share_std : float
        Where the share came from a sweep: the share the plateaus of the friction runs give
        alone and its standard deviation, a second measure a verdict can weigh the sweep's
        against; NaN otherwise, or where the plateaus do not determine it [-].
    """

    guideway_share: float
    backlash: float
    source: str
    estimate: object = None
    nut: object = None
    guideway_share_std: float = float("nan")
    unfound_backlash_std: float = float("nan")
    viscous_on_table: float = float("nan")
    viscous_on_table_std: float = float("nan")
    backlash_at_resolution: float = float("nan")
    plateau_share: float = float("nan")
    plateau_share_std: float = float("nan")

    @property
    def backlash_std(self) -> float:
        """Standard deviation of the lost motion, from the estimate it came from: the nut
        estimate when there is one, else the plateaus; NaN without either [m]."""
        play_from = self.nut if self.nut is not None else self.estimate
        return float(play_from.backlash_std) if play_from is not None else float("nan")

    @property
    def _table_viscous_from(self):
        """The estimate whose table damping the model takes: the plateaus' when they
        determine it, else the nut estimate's (``None`` without either) [-]."""
        lm = self.estimate
        if self.nut is not None and not (lm is not None and lm.determined
                                         and np.isfinite(lm.table_viscous)):
            return self.nut
        return lm

    @property
    def table_viscous(self) -> float:
        """Viscous force per speed that passes through the nut (``C_t`` plus the
        guideway's viscous friction), from :attr:`_table_viscous_from`; NaN without an
        estimate [N s/m]."""
        if np.isfinite(self.viscous_on_table):
            return float(self.viscous_on_table)
        src = self._table_viscous_from
        return float(src.table_viscous) if src is not None else float("nan")

    @property
    def table_viscous_std(self) -> float:
        """Standard deviation of :attr:`table_viscous` [N s/m]."""
        if np.isfinite(self.viscous_on_table):
            return float(self.viscous_on_table_std)
        src = self._table_viscous_from
        return float(src.table_viscous_std) if src is not None else float("nan")

    def to_dict(self) -> dict:
        """Plain dictionary for the JSON report.

        Returns
        -------
        dict
            Share and lost motion used, their standard deviations when they come from the
            data, the source and the full estimate [-].
        """
        e = self.estimate

        def sd(x, sources):
            ok = e is not None and self.source in sources and np.isfinite(x)
            return float(x) if ok else None

        return {
            "guideway_share": {"value": float(self.guideway_share),
                               "std": sd(self.guideway_share_std, ("data", "sweep"))},
            "backlash_m": {"value": float(self.backlash),
                           "std": sd(self.backlash_std, ("data", "given", "sweep"))},
            "table_viscous_N_s_per_m": {
                "value": _or_none(self.table_viscous if self.source != "prior" else math.nan),
                "std": _or_none(self.table_viscous_std if self.source != "prior" else math.nan)},
            "source": self.source,
            "estimate": e.to_dict() if e is not None else None,
            "nut": self.nut.to_dict() if self.nut is not None else None,
        }


def stribeck_from_record(record, cfg, axis: str | None = None):
    """The Stribeck fit of a friction record, or an error naming its file and axis.

    Parameters
    ----------
    record : FrictionRecord
        Back-and-forth runs at constant speeds (formats.md section 1) [SI].
    cfg : AxisConfig
        The axis's bundle configuration (lead, torque constant) [SI].
    axis : str, optional
        Axis name, for messages [-].

    Returns
    -------
    tuple
        ``(t, x, force, ParameterEstimate, list of Plateau)``: time [s], scale position
        [m], motor force at the table [N], the fitted curve and its plateaus [-].

    Raises
    ------
    InputError
        When the record holds no constant-speed passes long enough for the fit.
    """
    t, x, force = friction_record_arrays(record, cfg.lead_m, cfg.torque_constant)
    _check_uniform(t, record.source)
    try:
        est, plateaus = _memo(record, ("plateaus", cfg.lead_m, cfg.torque_constant),
                              lambda: identify_stribeck_run(t, x, force))
    except NoPlateauError:
        name = axis or record.axis
        raise InputError(
            (f"axis {name}: " if name else "")
            + "no constant-speed passes found in the friction runs; record back-and-forth "
            "passes at several constant speeds, each held for at least "
            f"{min(PLATEAU_DURATIONS_S)} s in both directions (docs/formats.md section 1)",
            file=record.source,
            column="scale_mm",
        ) from None
    except InputError as exc:  # the fit knows the column, not the file
        raise exc.in_file(record.source) from None
    return t, x, force, est, plateaus


def _check_uniform(t, source) -> None:
    """Refuse friction runs whose sampling is not uniform within the 1 % the fit needs,
    naming the file and the first step that differs [-]."""
    dt = np.diff(t)
    step = float(np.median(dt))
    off = np.flatnonzero(~(np.abs(dt - step) <= 0.01 * step))
    if off.size:
        i = int(off[0])
        raise InputError(
            f"the friction runs must be sampled uniformly (1 % tolerance): the step after "
            f"t = {t[i]:.6g} s is {dt[i]:.6g} s, {step:.6g} s elsewhere; record without gaps, "
            "or resample", file=source, column="time_s")


def slowest_plateau(plateaus) -> float:
    """Speed of the slowest constant-speed plateau [m/s]."""
    return float(min(abs(p.velocity) for p in plateaus))


#: Fits of a record already made, by the record (held weakly) and what they depend on: the
#: refits of the mechanics ask for the same friction fits several times.
_FITS: dict = {}


def _memo(record, key, make):
    """``make()`` once per record and key; an error is raised again each time."""
    ref, fits = _FITS.get(id(record), (None, None))
    if ref is None or ref() is not record:
        fits = {}
        _FITS[id(record)] = (weakref.ref(record, lambda _, i=id(record): _FITS.pop(i, None)),
                             fits)
    if key not in fits:
        try:
            fits[key] = (make(), None)
        except InputError as exc:
            fits[key] = (None, exc)
    value, exc = fits[key]
    if exc is not None:
        raise exc
    return value


def _plateaus_fix_the_hump(fit, slowest: float) -> bool:
    """Whether a fit to the plateaus determines its Stribeck hump: a Stribeck speed no
    lower than the slowest plateau's ``slowest`` [m/s], and it and the static levels known
    within :data:`HUMP_REL_STD`."""
    v = dict(zip(fit.names, fit.values, strict=True))
    sd = dict(zip(fit.names, fit.std, strict=True))
    rel = [sd[k] / v[k] if v[k] > 0 else np.inf for k in ("vs", "Fs+", "Fs-")]
    return bool(v["vs"] >= slowest and np.all(np.isfinite(rel))
                and max(rel) <= HUMP_REL_STD)


def steady_curve(t, record, force, plateau_fit, plateaus, mechanics):
    """The steady friction curve from the whole record (accelerations included), or the
    plateaus' fit when the record has too little slow motion for it.

    The plateaus alone fix static level and Stribeck speed only in combination when the
    slowest pass is near the Stribeck speed (:mod:`tcpmm.ident.friction.transients`);
    where they fix both (:func:`_plateaus_fix_the_hump`) their fit is kept, since the
    accelerations see the drive's compliance and any free play of the nut as well.

    Parameters
    ----------
    t : ndarray
        Time [s].
    record : FrictionRecord
        The runs, SI [-].
    force : ndarray
        Motor force at the table [N].
    plateau_fit : ParameterEstimate
        The fit to the plateaus [-].
    plateaus : list of Plateau
        The plateaus found [-].
    mechanics : AxisMechanics
        Identified mechanics, for ``R_L`` and the drive's first mode [SI].

    Returns
    -------
    ParameterEstimate
        ``Fc+, Fc-, Fs+, Fs-, vs, Fv`` [N, N, N, N, m/s, N s/m].
    """
    slowest = slowest_plateau(plateaus)
    if _plateaus_fix_the_hump(plateau_fit, slowest):
        return plateau_fit
    m = mechanics
    k_axial = 1.0 / (m.R_L**2 / m.K_L + 1.0 / m.K_t)
    f_axial = math.sqrt(k_axial / (m.M_t + (m.J_m + m.J_L) / m.R_L**2)) / (2 * math.pi)
    cutoff = min(TRANSIENT_CUTOFF_HZ, 0.25 * f_axial)
    try:
        key = ("transients", m.R_L, cutoff, slowest, hash(np.asarray(force).tobytes()))
        return _memo(record, key,
                     lambda: fit_stribeck_transients(t, record.motor_angle_rad * m.R_L, force,
                                                     slowest_plateau=slowest,
                                                     cutoff_hz=cutoff))
    except InputError:
        return plateau_fit


def identify_friction(record, cfg, mechanics, guideway_share: float | None = None, *,
                      axis: str = "", stiffness_rel_std: float = 0.0,
                      viscous: str = "fit", neglect_motor_bearing: bool = False,
                      sweep=None, K_h_rel_std: float = 0.0, C_t_std: float = 0.0):
    """Stribeck friction and lost motion of an axis from its ``friction.csv`` record.

    The steady motor force at constant speed balances all friction (table units); the
    viscous part that the linear mechanics already carries (``B_m``, ``B_L``, ``C_t``) is
    taken off. The split between guideway and screw and the lost motion of the nut come
    from the deflection between encoder and scale on the plateaus
    (:func:`tcpmm.ident.friction.lostmotion.estimate_lost_motion`, one encoder-to-scale offset per
    speed so that lead errors of the screw cancel); when the data do not determine the
    split, :data:`GUIDEWAY_SHARE` is used and an :class:`InputWarning` says why.

    Parameters
    ----------
    record : FrictionRecord
        Constant-velocity runs, SI [-].
    cfg : AxisConfig
        Lead, torque constant and sensors of the axis [-].
    mechanics : AxisMechanics
        Identified mechanics of the axis [SI].
    guideway_share : float, optional
        Share of the friction put on the guideway; ``None``: from the data [-].
    axis : str
        Axis name, for messages [-].
    stiffness_rel_std : float
        Relative standard deviation of the identified ``K_t`` [-].
    viscous : {"fit", "known"}
        Fit the deflection proportional to the speed, or take the damping of
        ``mechanics`` (``B_m``, ``B_L``, ``C_t``) as known in the split; see
        :func:`tcpmm.ident.friction.lostmotion.estimate_lost_motion` [-].
    neglect_motor_bearing : bool
        Take the motor-bearing damping ``B_m`` as zero in the split: it does not twist
        the shaft, so with it less of the steady viscous force would pass through the
        nut. The friction's viscous part is still net of the mechanics' ``B_m`` [-].
    sweep : SweepDeflection, optional
        Mean TCP-structure deflection of a travelling sweep; when it determines the
        share (:func:`tcpmm.ident.friction.sweepforce.share_from_sweep`), the share is taken from
        it and the plateaus give only the lost motion [-].
    K_h_rel_std : float
        Relative standard deviation of the identified ``K_h`` [-].
    C_t_std : float
        Standard deviation of the identified ``C_t`` [N s/m].

    Returns
    -------
    AxisFriction, ParameterEstimate, FrictionSplit
        The friction element, the fitted curve with standard deviations, and the split
        with the lost-motion estimate [-].
    """
    t, _, force, est, plateaus = stribeck_from_record(record, cfg, axis)
    m = mechanics
    est, why = without_undetermined_hump(steady_curve(t, record, force, est, plateaus, m))
    if why:
        warnings.warn(f"axis {axis or record.axis}: {why}", InputWarning, stacklevel=2)
    v = dict(zip(est.names, est.values, strict=True))
    given = None if guideway_share is None else min(max(float(guideway_share), 0.0), 1.0)

    def plateau_split(mech, rel_std, **kw):
        return estimate_lost_motion(
            t, record.motor_angle_rad, record.scale_m, force, m.R_L, mech, plateaus,
            encoder_quantum=cfg.sensors.encoder_resolution_rad,
            scale_resolution=cfg.sensors.scale_resolution_m,
            stiffness_rel_std=rel_std, viscous=viscous, offset="per_speed",
            total_viscous=float(v["Fv"]), **kw)  # the Stribeck fit's: it models the hump

    m_split = m.replace(B_m=0.0) if neglect_motor_bearing else m
    lm = first = plateau_split(m_split, stiffness_rel_std, share=given)
    nut = _nut_estimate(t, record, m_split, v, cfg.sensors.scale_resolution_m,
                        share=lm.guideway_share
                        if np.isfinite(lm.guideway_share) else GUIDEWAY_SHARE)
    play = given is None and nut is not None and nut.lost_motion_found()
    coarse = None
    if play and nut.at_resolution() and sweep is not None:
        # a lost motion of about a scale step may be rounding: where the travelling sweep
        # gives the share without it, the play is left open rather than modelled
        coarse = _sweep_share(sweep, m, v, lm, K_h_rel_std, C_t_std)
        play = coarse is None
    if play:
        # free play: the sweep saw a soft nut. The accelerations give the nut in contact
        # and the lost motion; with both, the plateaus give the share.
        m_split = m_split.replace(K_t=nut.stiffness)
        stiffness_rel_std = nut.stiffness_std / nut.stiffness
        lm = plateau_split(m_split, stiffness_rel_std, backlash=nut.backlash,
                           backlash_std=nut.backlash_std)
    # with play K_h changes with each refit of the nut (playdf): the share stays with the runs
    from_sweep = None if given is not None or sweep is None or play else _sweep_share(
        sweep, m, v, lm, K_h_rel_std, C_t_std)
    if from_sweep is not None:
        from_sweep, lm = _settle_sweep_share(
            from_sweep, lambda s: plateau_split(m_split, stiffness_rel_std, share=s),
            lambda est: _sweep_share(sweep, m, v, est, K_h_rel_std, C_t_std))
        split = FrictionSplit(from_sweep[0], lm.backlash if lm.determined else 0.0, "sweep",
                              lm, None, from_sweep[1], viscous_on_table=from_sweep[2],
                              viscous_on_table_std=from_sweep[3])
    else:
        split = _split_of(lm, nut, play, given, axis)
    split = _with_open_quantities(split, nut, coarse is not None, first)
    return _axis_friction(v, m, split), est, split


def _with_open_quantities(split, nut, at_resolution: bool, first):
    """The split with the lost motion the nut's runs leave open (the deviation of a play
    not found, or the bound of one found within the scale's rounding) and, for a share
    from the sweep, the plateaus' own share (``first``, their estimate before it) [-]."""
    if (split.source == "sweep" and first.determined and np.isfinite(first.guideway_share)
            and np.isfinite(first.guideway_share_std)):
        split = dataclasses.replace(split, plateau_share=float(first.guideway_share),
                                    plateau_share_std=float(first.guideway_share_std))
    if nut is not None and not nut.lost_motion_found() and np.isfinite(nut.backlash_std):
        split = dataclasses.replace(split, unfound_backlash_std=float(nut.backlash_std))
    if at_resolution:
        split = dataclasses.replace(split, backlash_at_resolution=float(
            nut.backlash + LOST_MOTION_Z * nut.backlash_std))
    return split


def _settle_sweep_share(from_sweep, plateaus_at, share_from):
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


def _split_of(lm, nut, play: bool, given, axis) -> FrictionSplit:
    """The split from the plateaus (``lm``) and the nut estimate: with free play, given
    by the user, determined by the plateaus, or else the prior, with a warning [-]."""
    if play:
        used = lm if lm.determined else nut
        return FrictionSplit(min(max(used.guideway_share, 0.0), 1.0), nut.backlash, "data",
                             lm, nut, used.guideway_share_std)
    if given is not None:
        return FrictionSplit(given, lm.backlash if lm.determined else 0.0, "given", lm)
    if lm.determined:
        return FrictionSplit(lm.guideway_share, lm.backlash, "data", lm,
                             guideway_share_std=lm.guideway_share_std)
    name = f"axis {axis}" if axis else "axis"
    warnings.warn(
        f"{name}: the friction runs do not determine how the friction divides between "
        f"guideway and screw ({lm.reason}); using the prior guideway share "
        f"{GUIDEWAY_SHARE} and no lost motion", InputWarning, stacklevel=3)
    return FrictionSplit(GUIDEWAY_SHARE, 0.0, "prior", lm)


def _axis_friction(v: dict, m, split: FrictionSplit) -> AxisFriction:
    """The Stribeck curve ``v`` of the runs divided between guideway and screw by the
    split's share, less the viscous forces of the linear mechanics ``m`` [-]."""
    linear = (m.B_m + m.B_L) / m.R_L**2 + m.C_t
    fv = max(float(v["Fv"]) - linear, 0.0)

    def part(k):
        return StribeckFriction(
            fc_pos=k * max(v["Fc+"], 0.0), fc_neg=k * max(v["Fc-"], 0.0),
            fs_pos=k * max(v["Fs+"], 0.0), fs_neg=k * max(v["Fs-"], 0.0),
            vs=max(float(v["vs"]), 1e-6), fv_pos=k * fv, fv_neg=k * fv)

    share = split.guideway_share
    return AxisFriction(guideway=part(share) if share > 0 else None,
                        screw=part(1 - share) if share < 1 else None,
                        backlash=split.backlash, guideway_velocity="relative")


def _sweep_share(sweep, mechanics, curve: dict, lm, K_h_rel_std: float, C_t_std: float):
    """Share from a travelling sweep's deflection, or ``None`` when the sweep does not
    determine it; with it the viscous force per speed the table side is given and its
    standard deviation [-].

    A record whose Coulomb levels differ by direction more than :data:`SWEEP_ASYMMETRY`
    carries a constant force (a weight the mechanics do not hold) that a sweep in one
    direction does not tell from friction. The table's viscous force is the plateaus' and
    the FRFs' measures of it together (:func:`table_viscous_estimate`)."""
    m = mechanics
    up, down = abs(float(curve["Fc+"])), abs(float(curve["Fc-"]))
    if abs(up - down) > SWEEP_ASYMMETRY * 0.5 * (up + down):
        return None  # a constant force (a weight) that one direction of travel cannot tell
    tv, tv_sd = table_viscous_estimate(lm, m, float(curve["Fv"]), C_t_std)
    level = abs(float(coulomb_stribeck(curve)(np.array([sweep.velocity]))[0]))
    got = share_from_sweep(sweep, m, level, tv, K_h_rel_std=K_h_rel_std,
                           table_viscous_std=tv_sd)
    return None if got is None else (*got, tv, tv_sd)


def share_uncertainty_warning(axis: str, split: FrictionSplit, curve, mechanics,
                              cfg, max_std: float = SHARE_WARN_STD) -> str | None:
    """What to tell the user when the friction runs determine the guideway share poorly.

    Parameters
    ----------
    axis : str
        Axis name [-].
    split : FrictionSplit
        The split used [-].
    curve : ParameterEstimate or dict
        Fitted steady friction, by name (``Fc+``, ``Fc-``), table units [N].
    mechanics : AxisMechanics
        Identified mechanics; ``K_t`` is the nut in contact, ``R_L`` the screw ratio [SI].
    cfg : AxisConfig
        Sensors of the axis [-].
    max_std : float
        Standard deviation of the share above which there is something to say [-].

    Returns
    -------
    str or None
        The message, or ``None`` when the share is from the data and within ``max_std``,
        or not from the data at all [-].
    """
    sd = float(split.guideway_share_std)
    if split.source != "data" or not sd > max_std:
        return None
    s = split.guideway_share
    fc = 0.5 * (abs(float(curve["Fc+"])) + abs(float(curve["Fc-"])))
    um = 1e6
    nut = split.nut
    play = (f", told from the {nut.backlash * um:.2f} +/- {nut.backlash_std * um:.2f} um of "
            f"lost motion only by the braking between the plateaus" if nut is not None else "")
    step = mechanics.R_L * cfg.sensors.encoder_resolution_rad
    return (f"axis {axis}: the friction runs determine the guideway share only to {s:.2f} "
            f"+/- {sd:.2f}: the guideway's part of the nut deflection is "
            f"{s * fc / mechanics.K_t * um:.2g} um{play}, and the sensors step by "
            f"{step * um:.3g} um (encoder, at the table) and "
            f"{cfg.sensors.scale_resolution_m * um:.3g} um (scale). The predicted reversal "
            f"spikes follow the share. Finer sensors, or runs to a higher top speed with more "
            f"reversals, determine it; if it is known, set it with --guideway-share")


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
        return _stribeck_curve(p, vel, 2.0, False)

    return part


def _nut_estimate(t, record, mechanics, curve: dict, scale_resolution: float, share: float):
    """Nut stiffness, share and lost motion from the whole friction record, or ``None``
    when the record has too little of it (see :func:`~tcpmm.ident.friction.estimate_nut`)."""
    try:
        return estimate_nut(t, record.motor_angle_rad, record.scale_m, mechanics.R_L,
                            mechanics, coulomb_stribeck(curve), float(curve["Fv"]),
                            share=min(max(float(share), 0.0), 1.0),
                            scale_resolution=scale_resolution)
    except InputError:
        return None


def place_steady_viscous(mechanics, friction, total_viscous: float, table_viscous: float):
    """Put the viscous force of steady motion where the friction runs say it acts.

    A sweep sees the friction's local slope as damping as well, and the FRFs rarely
    determine ``B_m``, ``B_L`` and ``C_t``; the constant-speed runs measure the total
    viscous force per speed and, through the nut deflection, the part that passes
    through the nut (table side). The table side becomes ``C_t``, the rest is shared by
    ``B_m`` and ``B_L`` in their identified proportion, and the friction keeps no
    viscous part.

    Parameters
    ----------
    mechanics : AxisMechanics
        Identified mechanics [SI].
    friction : AxisFriction
        Identified friction (Stribeck, table units) [SI].
    total_viscous : float
        Slope of the steady motor force over the speed, at the table [N s/m].
    table_viscous : float
        Part of it that passes through the nut [N s/m].

    Returns
    -------
    AxisMechanics, AxisFriction
        Mechanics and friction with the viscous force placed [SI].
    """
    m = mechanics
    total = max(float(total_viscous), 0.0)
    c_tab = min(max(float(table_viscous), 0.0), total)
    motor = (total - c_tab) * m.R_L**2  # [N m s/rad]
    b_sum = m.B_m + m.B_L
    B_m, B_L = (m.B_m * motor / b_sum, m.B_L * motor / b_sum) if b_sum > 0 else (0.0, motor)

    def no_fv(c):
        return None if c is None else c.model_copy(update={"fv_pos": 0.0, "fv_neg": 0.0})

    fr = friction.model_copy(update={"guideway": no_fv(friction.guideway),
                                     "screw": no_fv(friction.screw)})
    return m.replace(B_m=B_m, B_L=B_L, C_t=c_tab), fr
