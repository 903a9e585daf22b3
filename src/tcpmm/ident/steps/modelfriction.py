"""Pre-sliding step: the friction as it goes into the model, with a static level the runs
do not fix and the uncertainty of its guideway share told, and the pre-sliding of its
contacts given or fitted to the reversals of the friction runs."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from ...io.csvutil import warn_input
from ..friction.presliding import PRESLIDING, with_presliding
from ..friction.preslidingfit import PreslidingFit, fit_presliding
from ..friction.split import share_uncertainty_warning

if TYPE_CHECKING:
    from ..chain import AxisRun
    from ..options import IdentifyOptions


@dataclass(frozen=True)
class ModelFriction:
    """The friction of the model and the pre-sliding it was given.

    Parameters
    ----------
    friction : AxisFriction
        The identified friction with its pre-sliding [-].
    presliding_m : float
        Pre-sliding displacement given to its contacts [m].
    presliding_fit : PreslidingFit, optional
        The fit of that displacement to the runs' reversals, when it was not given [-].
    """

    friction: object
    presliding_m: float
    presliding_fit: PreslidingFit | None = None


def friction_for_model(run: AxisRun, options: IdentifyOptions) -> ModelFriction | None:
    """The friction of the kept fit as it goes into the model; ``None`` without runs.

    Parameters
    ----------
    run : AxisRun
        The axis with its kept fit [-].
    options : IdentifyOptions
        ``presliding``: the displacement given, or ``None`` to fit it [-].
    """
    if run.runs is None:
        return None
    kept = run.kept
    held = kept.curve.extra.get("static_held_warning")
    share = share_uncertainty_warning(run.name, kept.split, kept.curve, kept.mechanics,
                                      run.cfg)
    prior = kept.split.prior_warning(run.name)
    for message in (prior, f"axis {run.name}: {held}" if held else None, share):
        if message is not None:
            warn_input(message, file=getattr(run.runs, "source", None))
    return ModelFriction(*with_fitted_presliding(kept.friction, kept.mechanics, run.runs,
                                                 options.presliding))


def with_fitted_presliding(fr, mech, record, presliding):
    """The friction with its pre-sliding, given or fitted, the distance used [m] and the
    fit when there was one.

    Parameters
    ----------
    fr : AxisFriction
        The identified friction [-].
    mech : AxisMechanics
        The mechanics it acts on [SI].
    record : FrictionRecord
        The friction runs, whose reversals the fit reads [-].
    presliding : float, optional
        The displacement given; ``None``: fitted, :data:`PRESLIDING` where the runs do not
        determine it [m].
    """
    if presliding is not None:
        return with_presliding(fr, mech, presliding), presliding, None
    fit = fit_presliding(record, mech, fr)
    if not fit.determined:
        return with_presliding(fr, mech, PRESLIDING), PRESLIDING, fit
    return with_presliding(fr, mech, fit.presliding, fit.damping_ratio), fit.presliding, fit
