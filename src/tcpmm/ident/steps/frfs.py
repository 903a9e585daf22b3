"""FRF step: the reduced FRFs of a sweep in the identification's band, and how much each
of their bins weighs in the physical fit."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..frf.excited import BandCover, band_cover, lowest_band_hz
from ..frf.response import reduced_frfs
from ..options import MIN_COHERENCE
from ..physical.fitdata import FRFData

if TYPE_CHECKING:
    from ..chain import AxisRun
    from ..options import IdentifyOptions


@dataclass(frozen=True)
class BandFRFs:
    """The FRFs of a sweep and the band they were estimated in.

    Parameters
    ----------
    frfs : dict
        ``G_M``, ``G_T`` and, with a TCP record, ``G_tcp``
        (:class:`~tcpmm.ident.frf.response.FRF`) [SI].
    fmin_hz : float
        Lower end of the band [Hz].
    fmax_hz : float, optional
        Upper end; ``None``: the bins the excitation reaches [Hz].
    cover : BandCover, optional
        What a band the user set leaves out of the frequencies the sweep excites; ``None``
        without such a band [-].
    """

    frfs: dict
    fmin_hz: float
    fmax_hz: float | None = None
    cover: BandCover | None = None

    @property
    def band(self) -> tuple:
        """``(fmin_hz, fmax_hz)`` [Hz]."""
        return (self.fmin_hz, self.fmax_hz)


def measure_frfs(run: AxisRun, options: IdentifyOptions) -> BandFRFs:
    """The FRFs of an axis's sweep against the injected excitation.

    Parameters
    ----------
    run : AxisRun
        The axis and its sweep [-].
    options : IdentifyOptions
        Its band, ``fmin_hz`` and ``fmax_hz`` [-].
    """
    sweep = run.sweep
    floor = lowest_band_hz(sweep.duration_s)
    fmin = options.fmin_hz if options.fmin_hz is not None else floor
    frfs = reduced_frfs(
        sweep.excitation_A,
        sweep.current_cmd_A,
        sweep.motor_angle_rad,
        sweep.scale_m,
        sweep.tcp_m,
        time_s=sweep.time_s,
        fmin_hz=fmin,
        fmax_hz=options.fmax_hz,
        file=sweep.source,
    )
    asked = (options.fmin_hz is not None, options.fmax_hz is not None)
    cover = band_cover(frfs["G_M"], sweep.excitation_A, asked, floor)
    return BandFRFs(frfs, fmin, options.fmax_hz, cover)


def frf_weights(frf) -> np.ndarray:
    """Weight of each bin of an FRF in the physical fit: the inverse of its relative
    standard deviation (at most 100), zero below :data:`MIN_COHERENCE` [-]."""
    w = 1.0 / np.maximum(frf.rel_std, 0.01)
    return np.where(frf.coherence >= MIN_COHERENCE, w, 0.0)


def fit_data(frfs: dict) -> dict:
    """The FRFs as data of the physical fit, :class:`FRFData` per name [SI]."""
    return {k: FRFData(f.freq_hz, f.H, frf_weights(f)) for k, f in frfs.items()}
