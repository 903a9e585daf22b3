"""What keeps a misleading identified model from passing silently: the gates that make a
physically suspect record or model an error (:mod:`~tcpmm.ident.gates.findings`, the time
base of a record in :mod:`~tcpmm.ident.gates.timebase`, the columns in
:mod:`~tcpmm.ident.gates.columns`, the masses and the TCP device's gain against the
FRFs' static gains in :mod:`~tcpmm.ident.gates.masses`), and the sanity checks that warn
before a model misleads a prediction (:mod:`~tcpmm.ident.gates.sanity`)."""

from .finding import Finding, SuspectModelError
from .findings import (
    FIT_TRIM,
    STANDING_SWEEP,
    STATIC_OVER_COULOMB,
    axis_findings,
    check_fit_percent,
    check_sampled_loop,
    check_static_friction_vs_drive,
    check_static_over_coulomb,
    drive_force_limit,
    skew_findings,
    slowest_plateau_speed,
    trimmed_fit_percent,
)
from .masses import TCP_GAIN_RANGE, check_tcp_gain
from .sanity import (
    FRICTION_LEAD_DEG,
    LOW_BAND_HZ,
    FrictionHold,
    friction_holds_sweep,
    warn_friction_holds_sweep,
    warn_unstable_sampled_loop,
)
from .timebase import (
    MAX_DAQ_PERIOD_S,
    MAX_FEED_SPEED,
    MIN_DAQ_PERIOD_S,
    check_time_base,
    time_base_findings,
)

__all__ = ["FIT_TRIM", "FRICTION_LEAD_DEG", "LOW_BAND_HZ", "MAX_DAQ_PERIOD_S", "MAX_FEED_SPEED",
           "MIN_DAQ_PERIOD_S", "STANDING_SWEEP", "STATIC_OVER_COULOMB", "TCP_GAIN_RANGE",
           "Finding",
           "FrictionHold",
           "SuspectModelError", "axis_findings", "check_fit_percent", "check_sampled_loop",
           "check_static_friction_vs_drive", "check_static_over_coulomb", "check_tcp_gain",
           "check_time_base", "drive_force_limit", "friction_holds_sweep", "skew_findings",
           "slowest_plateau_speed",
           "time_base_findings", "trimmed_fit_percent", "warn_friction_holds_sweep",
           "warn_unstable_sampled_loop"]
