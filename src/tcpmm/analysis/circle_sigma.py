"""The terms' uncertainty from what they leave unexplained, by the names they are
reported under, and the terms it leaves short of the tolerance they are recovered to.

What the terms leave over (noise, or an error they do not model: a servo transient, a
cyclic error too small to be found) scatters them as noise of its size and correlation
would (:func:`.circle_noise.coef_covariance`). A term is uncertain by it where twice its
standard uncertainty (a coverage of about 95 %) makes a radial error of
:data:`.circle_tails.MOVES_M` and :data:`.circle_tails.MOVES_SHARE` of its own: lateral
play over circles whose 0.1 um of noise stays alike over 19 samples scatters by 0.13 um,
and a value read once is no firmer than that.
"""

from __future__ import annotations

import numpy as np

from .circle_display import COVERAGE, display_unit, rename_axes
from .circle_tail_terms import largest_tail
from .circle_tails import (
    MOVES_M,
    MOVES_SHARE,
    as_reported,
    pair_text,
    radial_size,
    ranked_names,
)


def term_sigma(fit, n_arcs, shared, terms, axes, mean_rate=float("nan"),
               rename=None) -> dict:
    """Standard uncertainty of each reported term of ``terms`` that has a value, by its
    reported name (the plane's axes), from the fit's covariance (:attr:`TermFit.cov`);
    empty where it is not estimated [SI].

    Parameters
    ----------
    fit : TermFit
        The fit [SI].
    n_arcs : int
        Arcs fitted together [-].
    shared : sequence of str
        The shared terms fitted [-].
    terms : dict
        The reported terms, ``name -> (value, unit)``, axes X and Y [SI].
    axes : tuple of str
        The plane's axes [-].
    mean_rate : float
        The circles' angular speed, for the servo mismatch as a time [rad/s].
    rename : dict, optional
        Fitted name -> reported name [-].
    """
    if fit.cov is None:
        return {}
    kept = np.isfinite(fit.coef)
    cov = np.nan_to_num(fit.cov)
    if not np.all(np.isfinite(fit.cov[np.ix_(kept, kept)])):
        return {}
    weights = [as_reported(lambda n, j=j: float(n == fit.names[j]), n_arcs, shared,
                           mean_rate, rename) for j in range(len(fit.names))]
    out = {}
    for term in weights[0]:
        w = np.array([wj[term] for wj in weights])
        out[term] = float(np.sqrt(w @ cov @ w)) if np.all(np.isfinite(w)) else np.nan
    for axis, k, sk in zip("XY", fit.waves, fit.wave_sigma, strict=True):
        if k is not None:
            out[f"cyclic_amplitude_{axis}"] = _amplitude_sigma(fit, cov, axis)
            out[f"cyclic_period_{axis}"] = sk / k**2  # of 1 / k, to first order
        j = largest_tail(fit, axis)
        if j is not None:  # the one reported, at the tails' time constant
            out[f"reversal_tail_{axis}"] = float(np.sqrt(cov[j, j]))
    if fit.tail_interval is not None:  # its 95 % interval as two standard uncertainties,
        lo, hi = fit.tail_interval    # the larger side of it: the interval may be lopsided
        out["reversal_tail_decay"] = max(fit.tail[0] - lo, hi - fit.tail[0]) / 2.0 / mean_rate
    for axis, (_, u95) in zip("XY", fit.widths, strict=True):  # its interval's larger side
        out[f"take_up_width_{axis}"] = u95 / 2.0
    return {rename_axes(k, axes): v for k, v in out.items()
            if k in terms and np.isfinite(terms[k][0]) and np.isfinite(v)}


def _amplitude_sigma(fit, cov, axis) -> float:
    """Standard uncertainty of a cyclic error's amplitude, to first order in its sine and
    cosine; the larger of theirs where it is too small to have a direction [m]."""
    i, j = fit.names.index(f"cyclic_sin_{axis}"), fit.names.index(f"cyclic_cos_{axis}")
    c = cov[np.ix_([i, j], [i, j])]
    amp = fit.cyclic_amplitude(axis)
    if amp <= np.sqrt(np.trace(c)):
        return float(np.sqrt(np.max(np.diag(c))))
    g = np.array([fit[f"cyclic_sin_{axis}"], fit[f"cyclic_cos_{axis}"]]) / amp
    return float(np.sqrt(g @ c @ g))


def noisy_terms(diag) -> dict:
    """The terms of ``diag`` uncertain by what the terms leave (module docstring):
    ``term -> (value, expanded uncertainty)`` [SI]."""
    out = {}
    for term, sigma in diag.sigma.items():
        value = diag.terms[term][0]
        u = radial_size(term, COVERAGE * sigma, diag.radius)
        if u >= MOVES_M and u >= MOVES_SHARE * radial_size(term, value, diag.radius):
            out[term] = (value, COVERAGE * sigma)
    if "servo_mismatch_angle" in out and "servo_mismatch" in diag.sigma:
        out["servo_mismatch"] = (diag.terms["servo_mismatch"][0],
                                 COVERAGE * diag.sigma["servo_mismatch"])
    return out


def noise_line(diag) -> str:
    """The terms uncertain by what the terms leave, in words and display units; empty
    where none is [-]."""
    noisy, spikes = noisy_terms(diag), spikes_reach(diag)
    if not noisy and spikes is None:
        return ""
    items = [pair_text(diag, term, v, u, "±") for term, (v, u) in noisy.items()]
    if spikes is not None:
        items.append("the largest reversal spike after the terms {:.2f} µm, up to {:.2f} µm "
                     "within the spikes' ±95%".format(*(1e6 * v for v in spikes)))
    rms = diag.terms.get("residual_rms", (float("nan"),))[0] * 1e6
    return (f"uncertain by what the terms leave unexplained (± {COVERAGE:g} standard "
            f"uncertainties from its {rms:.2f} µm rms and how long it stays alike): "
            + ", ".join(items)
            + "; noise narrows with more samples per turn or a repeated circle, an error the "
            "terms do not model (a servo transient, a cyclic error not found) does not")


def noisy_ranked(diag) -> set:
    """The ranked terms uncertain by what the terms leave (:func:`noisy_terms`), and the
    reversal spikes where their ±95% leaves the largest short of the tolerance
    (:func:`spikes_reach`) [-]."""
    spikes = {"reversal_spikes"} if spikes_reach(diag) is not None else set()
    return ranked_names(diag, noisy_terms(diag)) | (spikes & {r["term"] for r in diag.ranking})


def zero_ranked(diag) -> set:
    """The ranked terms whose value lies within its ±95% of zero (:attr:`sigma`): the
    circles do not tell it from no error, whatever share of the sum it has (a pair of
    noise alone ranked lateral plays of 0.15 ± 0.12 and -0.13 ± 0.12 µm first, with 43
    and 38 % of the sum). A centre offset and a cyclic error, of two parts each, are not
    judged so [-]."""
    within = [t for t, sigma in diag.sigma.items()
              if not t.startswith(("centre_offset", "cyclic_")) and sigma > 0
              and abs(diag.terms[t][0]) <= COVERAGE * sigma]
    return ranked_names(diag, within)


def spikes_reach(diag) -> tuple[float, float] | None:
    """``(largest, reach)``: the largest |spike| after the terms, as ranked, and the
    largest |spike| plus its ±95% over the spikes given, where that reach passes the
    largest by :data:`.circle_tails.MOVES_M` and :data:`.circle_tails.MOVES_SHARE` of it,
    the tolerance the terms are held to; None where it does not, or no spike has a ±95%
    (one direction) [m]."""
    given = {k: abs(v) for k, (v, _) in diag.terms.items()
             if k.startswith("spike_") and np.isfinite(v)}
    reach = [v + diag.spike_u95[k] for k, v in given.items()
             if np.isfinite(diag.spike_u95.get(k, np.nan))]
    if not reach:
        return None
    top = max(given.values())
    short = max(reach) - top >= max(MOVES_M, MOVES_SHARE * top)
    return (top, max(reach)) if short else None


def shown_uncertainty(diag, term: str) -> float:
    """The expanded uncertainty (:data:`COVERAGE` standard uncertainties) of ``term`` in
    its display unit (:func:`.circle_display.display_terms`); NaN where none is
    estimated. A spike's is its own (``spike_u95``: the terms' covariance, the take-up
    and the tails), as the table of the passes gives it [-]."""
    if term.startswith("spike_") and np.isfinite(diag.spike_u95.get(term, np.nan)):
        return diag.spike_u95[term] * display_unit(term, diag.terms[term][1])[1]
    if term not in diag.sigma:
        return float("nan")
    return COVERAGE * diag.sigma[term] * display_unit(term, diag.terms[term][1])[1]
