"""How to identify: the options every step of :mod:`tcpmm.ident.chain` reads."""

from __future__ import annotations

from dataclasses import dataclass

#: Bins of an FRF with a coherence below this carry no weight in the fits and are left out
#: of the fit percentages: less than half of the output's power there follows the input [-].
MIN_COHERENCE = 0.5


@dataclass(frozen=True)
class IdentifyOptions:
    """The choices identification leaves to the user, shared by its steps.

    Parameters
    ----------
    fmin_hz : float, optional
        Lower end of the FRFs' band; ``None``: 2 Hz or eight periods of the sweep's
        duration, whichever is higher [Hz].
    fmax_hz : float, optional
        Upper end of the FRFs' band; ``None``: the bins the excitation reaches [Hz].
    fit_current_loop : bool
        Also fit a first-order current-loop bandwidth from G_M [-].
    guideway_share : float, optional
        Share of the friction put on the guideway, the rest on the screw; ``None``: from
        each axis's friction runs (encoder-minus-scale deflection) [-].
    presliding : float, optional
        Pre-sliding displacement given to the identified contacts (LuGre); ``0``: static
        friction that sticks rigidly; ``None``: fitted to the reversals of the friction
        runs (:mod:`tcpmm.ident.friction.preslidingfit`), or
        :data:`~tcpmm.ident.friction.presliding.PRESLIDING` where they do not determine
        it [m].
    accept_suspect : bool
        Return a model the gates find physically suspect, marked, instead of raising [-].
    verdict : bool
        Judge the figures the model predicts on the reference circles
        (:func:`tcpmm.uncertainty.prediction_verdict`) [-].
    """

    fmin_hz: float | None = None
    fmax_hz: float | None = None
    fit_current_loop: bool = True
    guideway_share: float | None = None
    presliding: float | None = None
    accept_suspect: bool = False
    verdict: bool = True
