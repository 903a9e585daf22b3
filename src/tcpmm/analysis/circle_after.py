"""The headline spikes of one sensor's circle: after the terms of the pair it belongs to
(a CCW and a CW circle: backlash, lateral play, bows and cyclic errors too, which one
circle leaves in its spikes), else after those fitted to it alone
(:mod:`.circle_terms`); each with its 95 % uncertainty (:mod:`.circle_spike_sigma`)."""

from __future__ import annotations

import numpy as np

from .circle_spikes import QUADRANTS
from .circle_terms import spikes_with_uncertainty


def pair_diagnosis(sc):
    """The diagnostics of ``sc``'s pair (:func:`tcpmm.analysis.diagnostics.pair_fit`,
    fitted once for both circles); None where it has no pair or the pair cannot be
    fitted [-].

    Parameters
    ----------
    sc : SensorCircle
        One sensor's circle, its pair set by :meth:`.circular.CircleResult.paired` [-].
    """
    if sc.pair is None:
        return None
    from .diagnostics import pair_fit  # diagnostics builds on this module's users

    return pair_fit(sc)[0]


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
