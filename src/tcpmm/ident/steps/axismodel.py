"""Model step: the identified axis as it goes into the model file, with the servo and
sensors of the bundle's configuration, the loop timing read from the sweep and the
parameters' uncertainty; and the check of its loop as the drive samples it."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from ...model import Axis, Sensors
from ...servo.params import ServoParams
from ..gates.sanity import warn_unstable_sampled_loop
from ..physical.loop_timing import COMPUTATION_DELAY, LoopTiming
from ..physical.loop_warnings import sweep_timing
from ..physical.uncertainty import axis_uncertainty

if TYPE_CHECKING:
    from ..chain import AxisRun
    from ..options import IdentifyOptions


@dataclass(frozen=True)
class AxisModel:
    """The identified axis and what its assembly found.

    Parameters
    ----------
    axis : Axis
        The axis as it goes into the model file [SI].
    loop_timing : LoopTiming, optional
        Computation delay and velocity estimate read from the sweep [-].
    sampled_loop_spectral_radius : float, optional
        Spectral radius of the axis's loop as the drive samples it (below 1: stable) [-].
    """

    axis: Axis
    loop_timing: LoopTiming | None = None
    sampled_loop_spectral_radius: float | None = None


def build_axis(run: AxisRun, options: IdentifyOptions) -> AxisModel:
    """The identified axis: kept mechanics, model friction, servo and sensors, with the
    uncertainty of its parameters; warns where its sampled loop is unstable.

    Parameters
    ----------
    run : AxisRun
        The axis with its kept fit and model friction [-].
    options : IdentifyOptions
        Not read by this step [-].
    """
    name, cfg, kept, phys = run.name, run.cfg, run.kept, run.kept.physical
    model_friction = run.model_friction
    timing = sweep_timing(name, run.sweep, cfg)
    axis = Axis(
        mechanics=kept.mechanics,
        servo=axis_config_to_servo(cfg, phys.current_bandwidth_hz, timing),
        sensors=axis_config_to_sensors(cfg),
        friction=kept.friction if model_friction is None else model_friction.friction,
        uncertainty=axis_uncertainty(
            phys, kept.mechanics, kept.curve, kept.split,
            None if model_friction is None else model_friction.presliding_fit),
    )
    return AxisModel(axis, timing, warn_unstable_sampled_loop(name, axis, phys.undetermined,
                                                                run.frfs.cover))


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
