"""The headline spikes of one sensor's circle: after the terms of the pair it belongs to
(a CCW and a CW circle: backlash, lateral play, bows and cyclic errors too, which one
circle leaves in its spikes), else after those fitted to it alone
(:mod:`.circle_terms`); each with its 95 % uncertainty (:mod:`.circle_spike_sigma`)."""

from __future__ import annotations

import warnings

import numpy as np

from ..errors import InputError
from .circle_spikes import QUADRANTS
from .circle_terms import spikes_with_uncertainty


def pair_diagnosis(sc):
    """The diagnostics of ``sc``'s pair (:func:`tcpmm.analysis.diagnostics.diagnose_pair`,
    fitted once for both circles); None where it has no pair or the pair cannot be
    fitted [-].

    Parameters
    ----------
    sc : SensorCircle
        One sensor's circle, its pair set by :meth:`.circular.CircleResult.paired` [-].
    """
    if sc._pair is None:
        return None
    from .diagnostics import diagnose_pair  # diagnostics builds on this module's users

    other, radius, rates, shared = sc._pair
    if "fit" not in shared:
        ccw, cw = (sc, other) if sc.direction == "ccw" else (other, sc)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                shared["fit"] = diagnose_pair((ccw.angle_rad, ccw.radial_error),
                                              (cw.angle_rad, cw.radial_error), radius, rates)
        except (InputError, np.linalg.LinAlgError):
            shared["fit"] = None
    return shared["fit"]


def after_terms(sc) -> tuple[dict, dict, dict]:
    """``(spikes, u95, u95 from the sample-to-sample noise)``: the signed reversal spike
    per quadrant point of ``sc`` after the terms (module docstring), its 95 % uncertainty,
    and that from the noise from sample to sample alone; NaN where there is none [m]."""
    diag = pair_diagnosis(sc)
    if diag is None:
        spikes, *u95 = spikes_with_uncertainty(sc.angle_rad, sc.radial_error, sc.direction)
    else:
        keys = {q: f"spike_{q}_{sc.direction}" for q in QUADRANTS}
        spikes = {q: diag.terms[k][0] for q, k in keys.items()}
        u95 = [{q: u.get(k, float("nan")) for q, k in keys.items()}
               for u in (diag.spike_u95, diag.spike_u95_sample)]
    # a spike the pair leaves open (an arc too short for terms) has no uncertainty either
    return (spikes, *({q: v if np.isfinite(spikes.get(q, np.nan)) else float("nan")
                       for q, v in u.items()} for u in u95))
