"""Spectra and frequency responses from records: signal conditioning
(:mod:`~tcpmm.ident.frf.signals`), Welch FRF estimators against the measured input or the
injected reference (:mod:`~tcpmm.ident.frf.response`), and the sampling and band checks
behind them (:mod:`~tcpmm.ident.frf._spectral`)."""

from .response import (
    FRF,
    estimate_frf,
    frf_against_reference,
    reduced_frfs,
    remove_trend,
    sample_rate_hz,
)
from .signals import central_difference, decimate, lowpass_filtfilt

__all__ = ["FRF", "central_difference", "decimate", "estimate_frf", "frf_against_reference",
           "lowpass_filtfilt", "reduced_frfs", "remove_trend", "sample_rate_hz"]
