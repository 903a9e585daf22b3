"""Identification of a machine from a measurement bundle: FRFs, transfer-function fits and
the physical (grey-box) fit per axis, into a model that simulates like the built-in one."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from .._threads import limit_blas_threads
from ..mechanics.friction import friction_params_array
from ..model import Axis, Machine, Sensors
from ..servo.params import ServoParams
from ..sim.contact import sliding_friction
from .frf.response import reduced_frfs
from .frf.wholerecord import reduced_with_whole_record
from .friction.nutstiffness import LOST_MOTION_Z
from .friction.playdf import nut_deflection_amplitude, play_gain, sweep_motion
from .friction.presliding import PRESLIDING, with_presliding
from .friction.preslidingfit import fit_presliding
from .friction.sensitivity import (
    warn_lost_motion_sensitivity,
    warn_presliding_sensitivity,
    warn_share_sensitivity,
)
from .friction.split import (
    share_uncertainty_warning,
    stribeck_from_record,
)
from .friction.sweepforce import sweep_deflection, travel_velocity
from .gates.findings import (
    SuspectModelError,
    axis_findings,
    time_base_findings,
)
from .gates.sanity import warn_friction_holds_sweep, warn_unstable_sampled_loop
from .identification import AxisFit, AxisIdentification, Identification
from .physical.greybox import PhysicalFit, SweepPlay
from .physical.loop_timing import COMPUTATION_DELAY, sweep_timing
from .physical.structure import fit_structure
from .physical.uncertainty import axis_uncertainty
from .steps.fitcontext import (
    FitContext,
    current_hold,
    fit_values,
    friction_on,
    physical_fit,
)
from .steps.frfs import MIN_COHERENCE, fit_data
from .steps.ltifits import TF_DELAY, TF_ORDERS, fit_transfer_functions

__all__ = ["MIN_COHERENCE", "TF_DELAY", "TF_ORDERS", "AxisFit", "AxisIdentification",
           "Identification", "axis_config_to_sensors", "axis_config_to_servo",
           "identify_axis", "identify_bundle"]

#: Refits of the mechanics with the nut's lost motion as the sweep saw it; each one takes
#: the nut deflection through the torsion of the previous fit. They can swing about their
#: fixed point before they settle (M_t 1.34 -> 1.10 -> 1.04 -> 1.09 -> 1.05 -> 1.06 of the
#: truth on one axis, self-consistent from the fourth) [-].
PLAY_ITERATIONS = 8
#: A refit with the play counts only when it is a solution of its own describing function:
#: its table mass and the nut stiffness of the runs on it within this of those the
#: describing function was computed with. Where the FRFs barely fix the table mass, the
#: refits wander (0.9 -> 1.26 -> 0.56 -> 0.79 of the truth on one axis), and the least
#: cost among them is chance [-].
SELF_CONSISTENT_REL = 0.05
#: ... and the nut stiffness the FRFs give through the play's factor within this of the one
#: the factor was computed with (the friction runs'): 4-12 % on one unseen axis whose refits
#: settle (M_t 1.04-1.08 of the truth), 1.8-5.8 times on one where they wander, one of
#: them a false fixed point at M_t 0.45 of the truth with a nut fitted 5.8 times stiffer
#: than the factor assumed [-].
FITTED_STIFFNESS_REL = 0.25
#: Refits stop once one comes back within this of the fit before it: the next would
#: repeat it [-].
CONVERGED_REL = 0.01
#: A refit with the play replaces the linear fit only when it explains the FRFs better by
#: more than this share of the linear fit's cost: a tie is not decided by rounding [-].
COST_MARGIN_REL = 0.01
#: Travel over a sweep record below which it counts as standing still: the guideway
#: friction then holds the nut on no particular flank [m].
MIN_SWEEP_TRAVEL_M = 1e-3


def axis_config_to_servo(cfg, current_bandwidth_hz=None, timing=None) -> ServoParams:
    """Servo parameters from a bundle's axis configuration, with the computation delay and
    the velocity estimate read from the sweep (``timing``, a
    :class:`~tcpmm.ident.physical.loop_timing.LoopTiming`) or, without it, those of
    :data:`COMPUTATION_DELAY` and a differenced encoder angle."""
    s = cfg.servo
    delay, kind = COMPUTATION_DELAY, "difference"
    if timing is not None and timing.determined:
        delay, kind = timing.delay_samples, timing.velocity_feedback
    return ServoParams.create(
        position_feedback=s.position_feedback,
        K_pp=s.position_gain_1_per_s,
        K_vp=s.velocity_gain_A_s_per_rad,
        K_vi=s.velocity_integral_gain_A_per_rad,
        k_ff=s.velocity_feedforward,
        T_p=s.position_loop_period_s,
        T_v=s.velocity_loop_period_s,
        current_limit=s.current_limit_A,
        current_bandwidth_hz=current_bandwidth_hz,
        delay_samples=delay,
        velocity_feedback=kind,
        feedforward="segment",
        filters=list(s.current_setpoint_filters),
    )


def axis_config_to_sensors(cfg) -> Sensors:
    """Sensor resolutions from a bundle's axis configuration."""
    s = cfg.sensors
    return Sensors(
        encoder_counts_per_rev=s.encoder_counts_per_rev,
        scale_resolution=s.scale_resolution_m,
        tcp_resolution=s.tcp_resolution_m or 0.0,
    )


def identify_axis(
    name: str, sweep, cfg, fmin_hz=None, fmax_hz=None, fit_current_loop: bool = True,
    friction=None, guideway_share: float | None = None, presliding: float | None = None,
) -> AxisIdentification:
    """Identify one axis from its sweep record and its known configuration.

    With friction runs that show lost motion in the nut and a sweep that travels, the
    mechanics are fitted again with the nut as soft as the sweep saw it (the describing
    function of the play at the measured nut deflection, the guideway friction holding the
    nut on one flank; :mod:`tcpmm.ident.friction.playdf`), and the friction on those mechanics.

    Parameters
    ----------
    name : str
        Axis name [-].
    sweep : SweepRecord
        Servo-excitation record (SI) [-].
    cfg : AxisConfig
        What the user knows: lead, torque constant, servo, sensors [-].
    fmin_hz, fmax_hz : float, optional
        Band of the FRFs [Hz].
    fit_current_loop : bool
        Also fit a first-order current-loop bandwidth from G_M [-].
    friction : FrictionRecord, optional
        Constant-velocity runs; their Stribeck curve becomes the axis friction [-].
    guideway_share : float, optional
        Share of that friction put on the guideway, the rest on the screw; ``None``: from
        the friction runs (encoder-minus-scale deflection) [-].
    presliding : float, optional
        Pre-sliding displacement given to the identified contacts (LuGre); ``0``: static
        friction that sticks rigidly; ``None``: fitted to the reversals of the friction
        runs (:mod:`tcpmm.ident.friction.preslidingfit`), or :data:`PRESLIDING` where they
        do not determine it [m].
    """
    limit_blas_threads()
    fmin = fmin_hz if fmin_hz is not None else max(2.0, 8.0 / sweep.duration_s)
    fmax = fmax_hz  # default: the bins the excitation reaches
    frfs = reduced_frfs(
        sweep.excitation_A,
        sweep.current_cmd_A,
        sweep.motor_angle_rad,
        sweep.scale_m,
        sweep.tcp_m,
        time_s=sweep.time_s,
        fmin_hz=fmin,
        fmax_hz=fmax,
        file=sweep.source,
    )
    velocity = travel_velocity(sweep, MIN_SWEEP_TRAVEL_M)
    v_travel = abs(velocity)
    held = warn_friction_holds_sweep(name, sweep, frfs["G_M"], MIN_COHERENCE,
                                     standing=v_travel == 0.0)
    if v_travel == 0.0:
        from ..io.csvutil import warn_input
        from .gates.findings import STANDING_SWEEP

        warn_input(f"axis {name}: {STANDING_SWEEP}; the model fitted to it can be off by "
                   "micrometres at the reversals", file=getattr(sweep, "source", None))
    tf_fits = fit_transfer_functions(frfs)
    data = fit_data(frfs)
    ctx = FitContext(name, cfg, fit_current_loop, tf_fits,
                     current_hold(sweep, cfg.servo.velocity_loop_period_s), friction,
                     guideway_share,
                     sweep_deflection(sweep, velocity) if friction is not None else None)
    phys: PhysicalFit = physical_fit(ctx, data)
    kept = AxisFit(phys, phys.mechanics)
    presliding_m = presliding_fit = None
    if friction is not None:
        kept = _fit_with_friction(ctx, sweep, frfs, data, phys, v_travel, (fmin, fmax))
        message = share_uncertainty_warning(name, kept.split, kept.curve, kept.mechanics, cfg)
        if message is not None:
            from ..io.csvutil import warn_input

            warn_input(message, file=getattr(friction, "source", None))
        fr, presliding_m, presliding_fit = _presliding(kept.friction, kept.mechanics, friction,
                                                       presliding)
        kept = replace(kept, friction=fr)
    phys = kept.physical
    timing = sweep_timing(name, sweep, cfg)
    axis = Axis(
        mechanics=kept.mechanics,
        servo=axis_config_to_servo(cfg, phys.current_bandwidth_hz, timing),
        sensors=axis_config_to_sensors(cfg),
        friction=kept.friction,
        uncertainty=axis_uncertainty(phys, kept.mechanics, kept.curve, kept.split,
                                     presliding_fit),
    )
    return AxisIdentification(
        name, frfs, tf_fits, phys, axis, sweep, kept.curve, kept.split, friction_hold=held,
        sampled_loop_spectral_radius=warn_unstable_sampled_loop(name, axis, phys.undetermined),
        presliding_m=presliding_m, presliding_fit=presliding_fit, loop_timing=timing)


def _presliding(fr, mech, record, presliding):
    """The friction with its pre-sliding, given or fitted, the distance used [m] and the
    fit when there was one."""
    if presliding is not None:
        return with_presliding(fr, mech, presliding), presliding, None
    fit = fit_presliding(record, mech, fr)
    if not fit.determined:
        return with_presliding(fr, mech, PRESLIDING), PRESLIDING, fit
    return with_presliding(fr, mech, fit.presliding, fit.damping_ratio), fit.presliding, fit


def _whole_record_data(sweep, frfs: dict) -> dict:
    """The FRFs weighed against their estimates from the whole record, as fit data
    (:func:`~tcpmm.ident.frf.wholerecord.reduced_with_whole_record`)."""
    f = reduced_with_whole_record(frfs, sweep.excitation_A, sweep.current_cmd_A,
                                  sweep.motor_angle_rad, sweep.scale_m, sweep.tcp_m)
    return fit_data(f)


def _fit_with_friction(ctx: FitContext, sweep, frfs: dict, data: dict, phys: PhysicalFit,
                       v_travel: float, band: tuple) -> AxisFit:
    """The friction runs on the physical fit; with lost motion that the sweep crosses, the
    structure held at what ``G_tcp`` alone says and the refits with the play
    (:func:`_refit_with_play`), or a warning where the play cannot be modelled.

    Parameters
    ----------
    ctx : FitContext
        The axis's known values, TF fits, hold and friction runs [-].
    sweep : SweepRecord
        The sweep record [-].
    frfs : dict
        The measured FRFs; with a TCP record whose sweep does not cross lost motion, the
        fits weigh them against the whole record [SI].
    data : dict
        The FRFs to fit, :class:`FRFData` per name [SI].
    phys : PhysicalFit
        The linear fit [SI].
    v_travel : float
        Steady travel speed of the sweep, 0 when it stands [m/s].
    band : tuple
        ``(fmin_hz, fmax_hz)`` of the FRFs [Hz].
    """
    kept = AxisFit(phys, *friction_on(ctx, phys))
    structure = None
    if "G_tcp" in data:
        # G_tcp does not see the nut force, so nothing that distorts G_M and G_T (lost
        # motion crossed by the sweep, the friction it travels against, a drive mode the
        # model lacks) reaches it: hold the bed and TCP structure at what G_tcp alone
        # says, relative to the table. A joint fit let G_M and G_T pull the head damping
        # 12-16 % above what G_tcp alone gives. The segments cut the ringing of a lightly
        # damped mode, so from here on each FRF weighs in the whole record, except where
        # the sweep crosses the play: there the refits with the play, which swing about
        # their fixed point, stopped settling, and G_M and G_T went into other minima.
        if not _play_significant(kept.split):
            data = _whole_record_data(sweep, frfs)
        structure, _ = fit_structure(data["G_tcp"], [phys.mechanics])
        phys = physical_fit(ctx, data, initial=fit_values(phys), structure=structure)
        kept = AxisFit(phys, *friction_on(ctx, phys))
    bias = _bias_force(v_travel, kept.mechanics, kept.friction)
    if _play_significant(kept.split) and bias > 0:
        kept = _refit_with_play(ctx, sweep, data, kept, structure, v_travel, bias, band)
        if kept.physical.nut_gain is None:
            _warn_sweep_crosses_play(ctx.name, sweep, kept.split, modelled=True)
    elif kept.split.nut is not None or _play_significant(kept.split):
        _warn_sweep_crosses_play(ctx.name, sweep, kept.split)
    return kept


def _refit_with_play(ctx: FitContext, sweep, data: dict, kept: AxisFit, structure,
                     v_travel: float, bias: float, band: tuple) -> AxisFit:
    """Refit with the nut as soft as the sweep saw it, and keep whichever fit, linear or
    with the play, explains the FRFs best; a refit counts only if it agrees with the
    describing function it was fitted with (:data:`SELF_CONSISTENT_REL`).

    Parameters
    ----------
    ctx : FitContext
        The axis's known values, TF fits, hold and friction runs [-].
    sweep : SweepRecord
        The sweep record [-].
    data : dict
        The FRFs to fit, :class:`FRFData` per name [SI].
    kept : AxisFit
        The linear fit with the friction on it [SI].
    structure : dict or None
        Bed and TCP structure held in proportion to ``M_t`` [SI / kg].
    v_travel : float
        Steady travel speed of the sweep [m/s].
    bias : float
        Friction force holding the nut on one flank on the linear fit [N].
    band : tuple
        ``(fmin_hz, fmax_hz)`` of the FRFs [Hz].
    """
    best, current = kept, kept
    freq, theta_m, scale = sweep_motion(sweep, *band)
    for _ in range(PLAY_ITERATIONS):
        seen = current.mechanics
        amp = nut_deflection_amplitude(freq, theta_m, scale, seen)
        gain = play_gain(freq, amp, current.split.backlash, bias, seen.K_t)
        phys = physical_fit(ctx, data, initial=fit_values(current.physical) if structure
                            else None, nut_gain=gain, structure=structure)
        current = AxisFit(phys, *friction_on(ctx, phys))
        if (phys.cost < (1.0 - COST_MARGIN_REL) * best.cost
                and _self_consistent(seen, current.mechanics, fitted=phys.mechanics)):
            g = gain(freq)
            lowest = int(np.argmin(g))
            phys.sweep_play = SweepPlay(bias_force_N=bias, lowest_nut_gain=float(g[lowest]),
                                        at_hz=float(freq[lowest]),
                                        nut_amplitude_there_m=float(amp[lowest]))
            best = current
        bias = _bias_force(v_travel, current.mechanics, current.friction)
        converged = _self_consistent(seen, current.mechanics, CONVERGED_REL)
        if converged or not (_play_significant(current.split) and bias > 0):
            break
    return best


def _self_consistent(seen, mech, rel: float = SELF_CONSISTENT_REL, fitted=None) -> bool:
    """Whether a refit with the play's describing function came back to the table mass
    and nut stiffness the describing function was computed with, within ``rel`` [-].

    ``fitted``, the mechanics as the FRFs gave them before the friction runs replaced the
    nut stiffness, must also have the contact stiffness the describing function assumed:
    the fit scales ``K_t`` by the factor per frequency, and a fit that needs a nut several
    times stiffer than the one the factor was computed for is not a solution of it, even
    where the runs then hand back the same stiffness and table mass."""
    same = all(abs(getattr(mech, p) / getattr(seen, p) - 1.0) <= rel for p in ("M_t", "K_t"))
    return same and (fitted is None
                     or abs(fitted.K_t / seen.K_t - 1.0) <= FITTED_STIFFNESS_REL)


def _play_significant(split, z: float = LOST_MOTION_Z) -> bool:
    """Whether the friction runs found lost motion beyond ``z`` standard deviations."""
    if split is None or not split.backlash > 0:
        return False
    if split.nut is not None:
        return split.nut.lost_motion_found(z)
    lm = split.estimate
    return bool(lm is not None and lm.determined and split.backlash > z * lm.backlash_std)


def _travel_speed(sweep) -> float:
    """Steady travel speed of a sweep record, zero when it travels less than
    :data:`MIN_SWEEP_TRAVEL_M` [m/s]."""
    return abs(travel_velocity(sweep, MIN_SWEEP_TRAVEL_M))


def _bias_force(v: float, mech, fr) -> float:
    """Friction force on the table at travel speed ``v``: it holds the nut on one flank of
    its play [N]. Zero without travel or guideway friction."""
    if v <= 0 or fr is None or fr.guideway is None:
        return 0.0
    return float(sliding_friction(v, friction_params_array(fr.guideway))) + mech.C_t * v


def _warn_sweep_crosses_play(name: str, sweep, split, modelled: bool = False) -> None:
    """Warn that the sweep crossed the nut's play and the mechanics fitted to it are
    those of a linear axis.

    Parameters
    ----------
    name : str
        Axis name [-].
    sweep : SweepRecord
        The sweep, for the file named in the warning [-].
    split : FrictionSplit
        The split of the kept fit: its lost motion and that estimate's std [m].
    modelled : bool
        The play was modelled in refits, none of which was kept [-].
    """
    from ..io.csvutil import warn_input

    remedy = ("no refit with the play modelled both fitted the FRFs better and came back to "
              "the table mass and nut stiffness its describing function was computed with, "
              "so the linear fit is kept"
              if modelled else "a sweep recorded while the axis travels at constant speed "
              "lets the play be modelled (the guideway friction holds the nut on one flank)")
    stiffness = ("The nut stiffness is taken from the friction runs" if split.nut is not None
                 else "The friction runs do not determine the nut stiffness either: K_t is "
                 "the sweep's, as soft as the play made it look")
    warn_input(
        f"axis {name}: the friction runs show {split.backlash * 1e6:.2f} +/- "
        f"{split.backlash_std * 1e6:.2f} um of lost motion in the nut, which the sweep crosses "
        "every cycle; around the axial modes its FRFs are not those of a linear axis, and "
        "the fitted split of inertia between motor side and table (M_t, and with it the "
        f"structure's M_b, K_b, M_h, K_h) can be off by tens of per cent. {stiffness}; "
        f"{remedy}. A larger excitation amplitude (within "
        "the current limit) makes the play a smaller part of the vibration; a smaller one "
        "makes it worse", file=getattr(sweep, "source", None))


def identify_bundle(
    bundle, fmin_hz=None, fmax_hz=None, progress=None, fit_current_loop: bool = True,
    guideway_share: float | None = None, presliding: float | None = None,
    accept_suspect: bool = False,
) -> Identification:
    """Identify every axis of a measurement bundle.

    The records and the identified axes pass the gates of :mod:`tcpmm.ident.gates`
    (time base, static friction, fit quality, sampled-loop stability); a physically
    suspect result is an error unless ``accept_suspect``, and the model then carries the
    findings (``Machine.suspect``).

    Parameters
    ----------
    bundle : Bundle
        Read with :func:`tcpmm.io.bundle.read_bundle` [-].
    fmin_hz, fmax_hz : float, optional
        Band of the FRFs [Hz].
    progress : callable, optional
        Called with the axis name after each axis [-].
    fit_current_loop : bool
        Fit a first-order current-loop bandwidth per axis [-].
    guideway_share : float, optional
        Share of the friction put on the guideway, the rest on the screw; ``None``: from
        each axis's friction runs [-].
    presliding : float, optional
        Pre-sliding displacement of the identified friction contacts; ``0``: static
        friction; ``None``: fitted to each axis's friction-run reversals where they
        determine it (:mod:`tcpmm.ident.friction.preslidingfit`) [m].
    accept_suspect : bool
        Return a model the gates find physically suspect, marked, instead of raising [-].

    Raises
    ------
    SuspectModelError
        The gates found the records or the identified model physically suspect (and
        ``accept_suspect`` is false); raised before the FRF fits for a bad time base.
    """
    source = getattr(bundle, "path", None)
    findings = time_base_findings(bundle)  # before the FRF fits: a bad record fails fast
    if findings and not accept_suspect:
        raise SuspectModelError(findings, file=source)
    for name, rec in bundle.axes.items():
        if rec.friction is not None:
            stribeck_from_record(rec.friction, bundle.machine.axes[name], name)
    axes = {}
    for name, rec in bundle.axes.items():
        cfg = bundle.machine.axes[name]
        axes[name] = identify_axis(
            name, rec.sweep, cfg, fmin_hz, fmax_hz, fit_current_loop, rec.friction,
            guideway_share, presliding,
        )
        findings += axis_findings(axes[name], rec, cfg)
        if progress is not None:
            progress(name)
    if findings and not accept_suspect:
        raise SuspectModelError(findings, file=source)
    machine = Machine(
        name=f"{bundle.machine.name} (identified)", axes={n: a.axis for n, a in axes.items()},
        suspect=tuple(str(f) for f in findings),
    )
    for name, a in axes.items():
        warn_share_sensitivity(name, a, machine, bundle.axes[name].friction)
        warn_lost_motion_sensitivity(name, a, machine, bundle.axes[name].friction)
        warn_presliding_sensitivity(name, a, machine, bundle.axes[name].friction)
    return Identification(axes, machine, {"source": str(getattr(bundle, "path", ""))},
                          findings)
