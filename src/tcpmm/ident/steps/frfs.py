"""FRF step: the reduced FRFs of a sweep, and how much each of their bins weighs in the
physical fit."""

from __future__ import annotations

import numpy as np

from ..physical.greybox import FRFData

#: Bins of an FRF with a coherence below this carry no weight in the fits and are left out
#: of the fit percentages: less than half of the output's power there follows the input [-].
MIN_COHERENCE = 0.5


def frf_weights(frf) -> np.ndarray:
    """Weight of each bin of an FRF in the physical fit: the inverse of its relative
    standard deviation (at most 100), zero below :data:`MIN_COHERENCE` [-]."""
    w = 1.0 / np.maximum(frf.rel_std, 0.01)
    return np.where(frf.coherence >= MIN_COHERENCE, w, 0.0)


def fit_data(frfs: dict) -> dict:
    """The FRFs as data of the physical fit, :class:`FRFData` per name [SI]."""
    return {k: FRFData(f.freq_hz, f.H, frf_weights(f)) for k, f in frfs.items()}
