"""Excitation signals for the current command: the signal type and swept sines
(:mod:`~tcpmm.ident.excitation.waveforms`), multisines
(:mod:`~tcpmm.ident.excitation.multisines`), PRBS (:mod:`~tcpmm.ident.excitation.prbsignal`)
and the design of one for a frequency band (:mod:`~tcpmm.ident.excitation.kinds`)."""

from .kinds import KINDS, design_excitation
from .multisines import multisine, schroeder_phases
from .prbsignal import prbs, prbs_for_band
from .waveforms import Excitation, linear_sweep, log_sweep

__all__ = ["KINDS", "Excitation", "design_excitation", "linear_sweep", "log_sweep", "multisine",
           "prbs", "prbs_for_band", "schroeder_phases"]
