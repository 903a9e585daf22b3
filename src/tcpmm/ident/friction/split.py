"""Friction of an axis from its constant-speed runs, split between guideway and screw.

``identify_friction`` takes the steady friction curve of the ``friction.csv`` record of an
axis (:mod:`tcpmm.ident.friction.steadycurve`) and divides it between guideway and screw-nut:
from the deflection between encoder and scale on the plateaus
(:mod:`tcpmm.ident.friction.lostmotion`) and, when the record shows lost motion in the nut,
from the nut stiffness over the whole record (:mod:`tcpmm.ident.friction.nutstiffness`).
When the runs do not determine the split, :data:`GUIDEWAY_SHARE` is used.
:class:`~tcpmm.ident.friction.frictionsplit.FrictionSplit` records the share, the lost
motion and where they came from. ``place_steady_viscous`` puts the viscous force of steady
motion into the damping of the mechanics, on the side of the nut where the runs say it acts.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from dataclasses import dataclass

import numpy as np

from ...errors import InputError, InputWarning
from ...mechanics.friction import StribeckFriction
from ...model import AxisFriction
from .frictionsplit import SHARE_WARN_STD, FrictionSplit, share_uncertainty_warning
from .hump import without_undetermined_hump
from .lostmotion import estimate_lost_motion
from .nutstiffness import LOST_MOTION_Z, estimate_nut
from .recorddrift import record_drift, without_drift
from .steadycurve import slowest_read, steady_curve, stribeck_from_record
from .stribeck import coulomb_stribeck
from .sweepforce import settle_sweep_share, sweep_share, sweep_share_outside

__all__ = ["GUIDEWAY_SHARE", "LEVEL_FIXED_REL_STD", "SHARE_WARN_STD", "FrictionSplit",
           "identify_friction", "place_steady_viscous", "share_uncertainty_warning",
           "unfixed_level"]

#: Share of the identified friction put on the guideway when the friction runs do not
#: determine it (see :mod:`tcpmm.ident.friction.lostmotion`): preloaded, sealed linear guides
#: usually carry most of the friction of a feed axis.
GUIDEWAY_SHARE = 0.7
#: Largest standard deviation of the Coulomb level (both directions'), against the level,
#: that the friction runs fix: beyond it two deviations reach zero. Runs that do not reach
#: the speeds where the viscous force dominates leave the two to trade (bench C's kept to
#: 0.5-5 mm/s: 0.9 +- 13 N against 139 N) [-].
LEVEL_FIXED_REL_STD = 0.5


def identify_friction(record, cfg, mechanics, guideway_share: float | None = None, *,
                      axis: str = "", stiffness_rel_std: float = 0.0,
                      viscous: str = "fit", neglect_motor_bearing: bool = False,
                      sweep=None, K_h_rel_std: float = 0.0, C_t_std: float = 0.0,
                      warn_prior: bool = True):
    """Stribeck friction and lost motion of an axis from its ``friction.csv`` record.

    The steady motor force at constant speed balances all friction (table units); the
    viscous part that the linear mechanics already carries (``B_m``, ``B_L``, ``C_t``) is
    taken off. The split between guideway and screw and the lost motion of the nut come
    from the encoder-to-scale deflection on the plateaus (one offset per speed:
    :func:`~tcpmm.ident.friction.lostmotion.estimate_lost_motion`), else the prior
    :data:`GUIDEWAY_SHARE`, of which an :class:`InputWarning` tells.

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
        Fit the deflection proportional to the speed, or take the damping of ``mechanics``
        (``B_m``, ``B_L``, ``C_t``) as known in the split; see
        :func:`tcpmm.ident.friction.lostmotion.estimate_lost_motion` [-].
    neglect_motor_bearing : bool
        Take ``B_m`` as zero in the split (it does not twist the shaft); the friction's
        viscous part is still net of the mechanics' ``B_m`` [-].
    sweep : SweepDeflection, optional
        Mean TCP-structure deflection of a travelling sweep; when it determines the share
        (:func:`tcpmm.ident.friction.sweepforce.share_from_sweep`), the share is taken from
        it and the plateaus give only the lost motion [-].
    K_h_rel_std : float
        Relative standard deviation of the identified ``K_h`` [-].
    C_t_std : float
        Standard deviation of the identified ``C_t`` [N s/m].
    warn_prior : bool
        Warn where the prior share is used; ``False``: the caller tells it
        (:meth:`FrictionSplit.prior_warning`) once, for the fit it keeps [-].

    Returns
    -------
    AxisFriction, ParameterEstimate, FrictionSplit
        The friction element, the fitted curve with standard deviations, and the split
        with the lost-motion estimate [-].
    """
    runs, est = _runs_of(record, cfg, mechanics, axis, viscous, sweep, K_h_rel_std, C_t_std)
    given = None if guideway_share is None else min(max(float(guideway_share), 0.0), 1.0)
    m_split = mechanics.replace(B_m=0.0) if neglect_motor_bearing else mechanics
    split = _split_of_runs(runs, m_split, stiffness_rel_std, given, axis)
    if warn_prior and split.source == "prior":
        warnings.warn(split.prior_warning(axis), InputWarning, stacklevel=2)
    return _axis_friction(runs.curve, mechanics, split), est, split


def _runs_of(record, cfg, mechanics, axis, viscous, sweep, K_h_rel_std, C_t_std):
    """The runs the split rests on (:class:`_Runs`) and their steady curve [-]."""
    t, force, est, plateaus = _steady_fit(record, cfg, mechanics, axis)
    record = without_drift(record, record_drift(record, cfg, plateaus))
    runs = _Runs(t, record, force, plateaus, cfg, mechanics,
                 dict(zip(est.names, est.values, strict=True)), viscous, sweep, K_h_rel_std,
                 C_t_std, dict(zip(est.names, est.std, strict=True)))
    return runs, est


def _steady_fit(record, cfg, mechanics, axis: str):
    """Time [s], motor force at the table [N], the steady friction curve and the plateaus
    of the record, the curve's hump taken out where the runs leave it open
    (:func:`~tcpmm.ident.friction.hump.without_undetermined_hump`; the warning it keeps
    in the curve is told for the fit kept, not for each refit of the mechanics) [-]."""
    t, _, force, est, plateaus = stribeck_from_record(record, cfg, axis)
    curve = steady_curve(t, record, force, est, plateaus, mechanics)
    est, _ = without_undetermined_hump(curve, slowest_read(curve, plateaus))
    return t, force, est, plateaus


@dataclass(frozen=True)
class _Runs:
    """What the split of an axis's friction rests on: the record with its time ``t`` [s],
    motor force at the table ``force`` [N] and plateaus, the axis's configuration and
    mechanics, the steady curve by name (``curve``), how the plateaus take the viscous
    force, the travelling sweep with the uncertainties its share is worked out with, and
    the curve's standard deviations by name (``curve_std``) [SI]."""

    t: np.ndarray
    record: object
    force: np.ndarray
    plateaus: list
    cfg: object
    mechanics: object
    curve: dict
    viscous: str
    sweep: object
    K_h_rel_std: float
    C_t_std: float
    curve_std: dict

    def plateaus_at(self, mech, rel_std: float, **kw):
        """Share and lost motion from the plateau deflections, with the mechanics ``mech``
        of the split and ``rel_std`` the relative standard deviation of their ``K_t``
        (:func:`~tcpmm.ident.friction.lostmotion.estimate_lost_motion`) [-]."""
        sensors = self.cfg.sensors
        return estimate_lost_motion(
            self.t, self.record.motor_angle_rad, self.record.scale_m, self.force,
            self.mechanics.R_L, mech, self.plateaus,
            encoder_quantum=sensors.encoder_resolution_rad,
            scale_resolution=sensors.scale_resolution_m,
            stiffness_rel_std=rel_std, viscous=self.viscous, offset="per_speed",
            total_viscous=float(self.curve["Fv"]), **kw)  # the Stribeck fit's: it models the hump

    def nut(self, mech, share: float):
        """Nut stiffness, share and lost motion from the whole record, or ``None`` when the
        record has too little of it (see :func:`~tcpmm.ident.friction.estimate_nut`)."""
        try:
            return estimate_nut(self.t, self.record.motor_angle_rad, self.record.scale_m,
                                mech.R_L, mech, coulomb_stribeck(self.curve),
                                float(self.curve["Fv"]),
                                share=min(max(float(share), 0.0), 1.0),
                                scale_resolution=self.cfg.sensors.scale_resolution_m)
        except InputError:
            return None

    def share_of_sweep(self, lm):
        """The travelling sweep's share on the plateau estimate ``lm``, or ``None``
        (:func:`~tcpmm.ident.friction.sweepforce.sweep_share`) [-]."""
        return sweep_share(self.sweep, self.mechanics, self.curve, lm, self.K_h_rel_std,
                           self.C_t_std)


def _split_of_runs(runs: _Runs, mech, rel_std: float, given, axis) -> FrictionSplit:
    """The split from the plateaus and the nut estimate, or the sweep's share where it
    gives one and the record shows no play; ``mech`` are the mechanics of the split and
    ``rel_std`` the relative standard deviation of their ``K_t``, ``given`` the share the
    user set or ``None`` [-]."""
    lm = first = runs.plateaus_at(mech, rel_std, share=given)
    nut = runs.nut(mech, lm.guideway_share if np.isfinite(lm.guideway_share)
                   else GUIDEWAY_SHARE)
    play = given is None and nut is not None and nut.lost_motion_found()
    coarse = None
    if play and nut.at_resolution() and runs.sweep is not None:
        # a lost motion of about a scale step may be rounding: where the travelling sweep
        # gives the share without it, the play is left open rather than modelled
        coarse = runs.share_of_sweep(lm)
        play = coarse is None
    if play:
        # free play: the sweep saw a soft nut. The accelerations give the nut in contact
        # and the lost motion; with both, the plateaus give the share.
        mech = mech.replace(K_t=nut.stiffness)
        rel_std = nut.stiffness_std / nut.stiffness
        lm = runs.plateaus_at(mech, rel_std, backlash=nut.backlash,
                              backlash_std=nut.backlash_std)
    # with play K_h changes with each refit of the nut (playdf): the share stays with the runs
    from_sweep = (None if given is not None or runs.sweep is None or play
                  else runs.share_of_sweep(lm))
    if from_sweep is not None:
        from_sweep, lm = settle_sweep_share(
            from_sweep, lambda s: runs.plateaus_at(mech, rel_std, share=s), runs.share_of_sweep)
        split = FrictionSplit(from_sweep[0], lm.backlash if lm.determined else 0.0, "sweep",
                              lm, None, from_sweep[1], viscous_on_table=from_sweep[2],
                              viscous_on_table_std=from_sweep[3])
    else:
        note = ("" if given is not None or runs.sweep is None or play
                else _sweep_outside_words(runs, lm, axis))
        split = dataclasses.replace(_split_of(lm, nut, play, given), sweep_note=note)
    return _with_open_quantities(split, nut, coarse is not None, first)


def _sweep_outside_words(runs: _Runs, lm, axis) -> str:
    """What to say where the travelling sweep's deflection reads a share outside 0 to 1,
    which the split then leaves for the friction runs', or ``""``: a friction level the
    runs do not fix (:func:`unfixed_level`) reads so, as the level divides the deflection's
    force; else a TCP device zeroed apart from the scale, or a structure whose stiffness
    the FRFs could not show, their band starting above its modes [-]."""
    share = sweep_share_outside(runs.sweep, runs.mechanics, runs.curve, lm, runs.C_t_std)
    if share is None:
        return ""
    said = (f"axis {axis or runs.record.axis}: the travelling sweep's deflection between "
            f"scale and TCP ({runs.sweep.deflection * 1e6:.2f} um)")
    level = unfixed_level(runs.curve, runs.curve_std)
    if level:
        return (f"{said} cannot be read as a guideway share: the friction runs do not fix the "
                f"friction level it is read against ({level}), so the share is taken from "
                "the friction runs; friction runs over a wider range of speeds (the "
                "benches' 0.5 to 100 mm/s) fix the level")
    cover = getattr(runs.sweep, "cover", None)
    band = None if cover is None else cover.words(runs.mechanics, above=False)
    zeroed = "is the TCP device zeroed to the scale (formats.md)?"
    return (f"{said} reads a guideway share of {share:.2f}, outside 0 to 1, so the share is "
            f"taken from the friction runs; "
            f"{zeroed if band is None else f'{band}; failing that, {zeroed}'}")


def unfixed_level(curve: dict, curve_std: dict) -> str:
    """The Coulomb levels with their standard deviations where the friction runs do not fix
    the friction level (known no better than :data:`LEVEL_FIXED_REL_STD` of it), else
    ``""``.

    Parameters
    ----------
    curve, curve_std : dict
        Fitted steady friction and its standard deviations, by name (``Fc+``, ``Fc-``)
        [N].
    """
    fc = float(curve["Fc+"]) + float(curve["Fc-"])
    sd = math.hypot(float(curve_std.get("Fc+", 0.0)), float(curve_std.get("Fc-", 0.0)))
    if fc > 0.0 and sd <= LEVEL_FIXED_REL_STD * fc:
        return ""
    return (f"Coulomb levels {float(curve['Fc+']):.3g} +- {float(curve_std['Fc+']):.2g} and "
            f"{float(curve['Fc-']):.3g} +- {float(curve_std['Fc-']):.2g} N")


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


def _split_of(lm, nut, play: bool, given) -> FrictionSplit:
    """The split from the plateaus (``lm``) and the nut estimate: with free play, given
    by the user, determined by the plateaus, or else the prior
    (:meth:`FrictionSplit.prior_warning` says why) [-]."""
    if play:
        used = lm if lm.determined else nut
        return FrictionSplit(min(max(used.guideway_share, 0.0), 1.0), nut.backlash, "data",
                             lm, nut, used.guideway_share_std)
    if given is not None:
        return FrictionSplit(given, lm.backlash if lm.determined else 0.0, "given", lm)
    if lm.determined:
        return FrictionSplit(lm.guideway_share, lm.backlash, "data", lm,
                             guideway_share_std=lm.guideway_share_std)
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
