"""Excitation signals for the current command: swept sines, multisines, PRBS, and the
design of one for a frequency band (:mod:`~tcpmm.ident.excitation.waveforms`)."""

from .waveforms import (
    KINDS,
    Excitation,
    design_excitation,
    linear_sweep,
    log_sweep,
    multisine,
    prbs,
    prbs_for_band,
    schroeder_phases,
)

__all__ = ["KINDS", "Excitation", "design_excitation", "linear_sweep", "log_sweep", "multisine",
           "prbs", "prbs_for_band", "schroeder_phases"]
