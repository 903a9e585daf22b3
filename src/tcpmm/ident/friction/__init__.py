"""Friction and lost motion from constant-velocity runs: the Stribeck curve of the plateaus
(:mod:`~tcpmm.ident.friction.plateaus`, :mod:`~tcpmm.ident.friction.stribeck`) and of the
transients between them (:mod:`~tcpmm.ident.friction.transients`), the one kept per record
(:mod:`~tcpmm.ident.friction.steadycurve`); its split between guideway and screw-nut
(:mod:`~tcpmm.ident.friction.split`, recorded in :mod:`~tcpmm.ident.friction.frictionsplit`)
from the deflection between encoder and scale (:mod:`~tcpmm.ident.friction.lostmotion`), the
nut's stiffness and play from the runs' accelerations (:mod:`~tcpmm.ident.friction.nutstiffness`)
or the force a travelling sweep shows (:mod:`~tcpmm.ident.friction.sweepforce`); the play as
the sweep sees it (:mod:`~tcpmm.ident.friction.playdf`); pre-sliding given to the identified
contacts (:mod:`~tcpmm.ident.friction.presliding`) or fitted to the runs' reversals
(:mod:`~tcpmm.ident.friction.preslidingfit`); and how much the circles care about what the
runs leave open (:mod:`~tcpmm.ident.friction.sensitivity`, told per axis by
:mod:`~tcpmm.ident.friction.spikewarnings`)."""

from .estimate import ParameterEstimate
from .frictionsplit import FrictionSplit
from .lostmotion import (
    LostMotionEstimate,
    LostMotionOptions,
    estimate_lost_motion,
    quantisation_bias_std,
)
from .nutstiffness import CUTOFFS_HZ, LOST_MOTION_Z, NutEstimate, estimate_nut
from .plateaus import Plateau, find_plateaus
from .playdf import dead_zone_gain, nut_deflection_amplitude, play_gain, sweep_motion
from .presliding import BRISTLE_DAMPING_RATIO, PRESLIDING, with_presliding
from .preslidingfit import fit_presliding
from .preslidingresult import PreslidingFit
from .sensitivity import (
    LostMotionSensitivity,
    NoSpikePrediction,
    PreslidingSensitivity,
    ShareSensitivity,
    lost_motion_spike_range,
    presliding_spike_range,
    share_spike_range,
    spike_range,
    warn_lost_motion_sensitivity,
    warn_presliding_sensitivity,
    warn_share_sensitivity,
    with_share,
)
from .spikewarnings import warn_spike_sensitivities
from .split import (
    GUIDEWAY_SHARE,
    SHARE_WARN_STD,
    identify_friction,
    place_steady_viscous,
    share_uncertainty_warning,
)
from .steadycurve import slowest_plateau, steady_curve, stribeck_from_record
from .stribeck import (
    PLATEAU_DURATIONS_S,
    NoPlateauError,
    fit_stribeck,
    friction_record_arrays,
    identify_stribeck_run,
    read_friction_csv,
)
from .sweepforce import (
    SweepDeflection,
    share_from_sweep,
    sweep_deflection,
    table_viscous_estimate,
    travel_velocity,
)
from .transients import fit_stribeck_transients

__all__ = [
    "BRISTLE_DAMPING_RATIO", "CUTOFFS_HZ", "GUIDEWAY_SHARE", "LOST_MOTION_Z",
    "PLATEAU_DURATIONS_S", "PRESLIDING", "SHARE_WARN_STD", "FrictionSplit",
    "LostMotionEstimate", "LostMotionOptions", "LostMotionSensitivity", "NoPlateauError",
    "NoSpikePrediction",
    "NutEstimate", "ParameterEstimate", "Plateau", "PreslidingFit", "PreslidingSensitivity",
    "ShareSensitivity",
    "SweepDeflection", "dead_zone_gain", "estimate_lost_motion", "estimate_nut",
    "find_plateaus", "fit_presliding", "fit_stribeck", "fit_stribeck_transients",
    "friction_record_arrays", "identify_friction", "identify_stribeck_run",
    "lost_motion_spike_range", "nut_deflection_amplitude", "place_steady_viscous", "play_gain",
    "presliding_spike_range",
    "quantisation_bias_std", "read_friction_csv", "share_from_sweep", "share_spike_range",
    "share_uncertainty_warning", "slowest_plateau", "spike_range", "steady_curve",
    "stribeck_from_record", "sweep_deflection", "sweep_motion", "table_viscous_estimate",
    "travel_velocity",
    "warn_lost_motion_sensitivity", "warn_presliding_sensitivity", "warn_share_sensitivity",
    "warn_spike_sensitivities",
    "with_presliding", "with_share",
]
