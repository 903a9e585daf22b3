"""The sensitivity warnings of an identified axis, told together.

Each simulates the model on a circle (:func:`tcpmm.ident.friction.sensitivity.spike_range`).
A suspect model written all the same may not run as a machine does: its sampled loop
unstable, or its run no circle at all. Its spikes then are no prediction, and the circle
analysis, made for a user's measured file, would blame that file's columns for what the
model did; so the sensitivities of such an axis are left out, with one warning saying why.
"""

from __future__ import annotations

from ...io.csvutil import warn_input
from .sensitivity import (
    NoSpikePrediction,
    warn_lost_motion_sensitivity,
    warn_presliding_sensitivity,
    warn_share_sensitivity,
)

__all__ = ["SENSITIVITY_WARNINGS", "warn_spike_sensitivities"]

#: The sensitivities told per axis, in this order [-].
SENSITIVITY_WARNINGS = (warn_share_sensitivity, warn_lost_motion_sensitivity,
                        warn_presliding_sensitivity)


def warn_spike_sensitivities(name: str, a, machine, friction) -> None:
    """Tell each of :data:`SENSITIVITY_WARNINGS` for axis ``name``; where the model's run
    of their circle is no prediction (:class:`NoSpikePrediction`), the rest are left out
    and one warning says why.

    Parameters
    ----------
    name : str
        Axis name [-].
    a : AxisIdentification
        The identified axis [-].
    machine : Machine
        The identified machine [SI].
    friction : FrictionRecord or None
        Its friction runs, for the file the warnings name [-].
    """
    for warn in SENSITIVITY_WARNINGS:
        try:
            warn(name, a, machine, friction)
        except NoSpikePrediction as why:
            warn_input(f"axis {name}: the sensitivities of the TCP spikes to what the "
                       f"friction runs leave open were not computed: {why}")
            return
