"""Identification of a machine from a measurement bundle: FRFs, transfer-function fits and
the physical (grey-box) fit per axis, into a model that simulates like the built-in one."""

from __future__ import annotations

from dataclasses import replace

from .._threads import limit_blas_threads
from ..model import Axis, Machine, Sensors
from ..servo.params import ServoParams
from .frf.response import reduced_frfs
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
from .physical.greybox import PhysicalFit
from .physical.loop_timing import COMPUTATION_DELAY, sweep_timing
from .physical.uncertainty import axis_uncertainty
from .steps.fitcontext import (
    FitContext,
    current_hold,
    physical_fit,
)
from .steps.frfs import MIN_COHERENCE, fit_data
from .steps.frictionfit import fit_friction
from .steps.ltifits import TF_DELAY, TF_ORDERS, fit_transfer_functions
from .steps.playrefit import fit_with_play

__all__ = ["MIN_COHERENCE", "TF_DELAY", "TF_ORDERS", "AxisFit", "AxisIdentification",
           "Identification", "axis_config_to_sensors", "axis_config_to_servo",
           "identify_axis", "identify_bundle"]

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
        kept = fit_with_play(ctx, sweep, fit_friction(ctx, sweep, frfs, data, phys), v_travel,
                             (fmin, fmax))
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


def _travel_speed(sweep) -> float:
    """Steady travel speed of a sweep record, zero when it travels less than
    :data:`MIN_SWEEP_TRAVEL_M` [m/s]."""
    return abs(travel_velocity(sweep, MIN_SWEEP_TRAVEL_M))


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
