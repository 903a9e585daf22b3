"""Spectra and frequency responses from records: signal conditioning
(:mod:`~tcpmm.ident.frf.signals`), Welch FRF estimators against the measured input or the
injected reference (:mod:`~tcpmm.ident.frf.response`), and the sampling and band checks
behind them (:mod:`~tcpmm.ident.frf._spectral`), the response of a sweep from the whole
record (:mod:`~tcpmm.ident.frf.wholerecord`), and the frequencies a sweep excites and what
the FRFs' band leaves out of them (:mod:`~tcpmm.ident.frf.excited`)."""

from .response import (
    FRF,
    estimate_frf,
    frf_against_reference,
    reduced_frfs,
    remove_trend,
    sample_rate_hz,
)
from .signals import central_difference, decimate, lowpass_filtfilt
from .wholerecord import WholeRecord, combine_estimates, reduced_with_whole_record

__all__ = ["FRF", "WholeRecord", "central_difference", "combine_estimates", "decimate",
           "estimate_frf", "frf_against_reference", "lowpass_filtfilt",
           "reduced_frfs", "reduced_with_whole_record", "remove_trend", "sample_rate_hz"]
