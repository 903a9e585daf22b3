"""The reversals' tails of a fitted pair of full turns as reported: the largest tail per
axis and its time constant (:func:`tail_terms`), which of :data:`TAIL_STATES` they are,
and why a tail reads none (:mod:`.circle_reversal_tail` fits them)."""

from __future__ import annotations

import numpy as np

#: Why the reversal tails read none (``{rms}``: what the terms leave unexplained)
NONE_WHY = ("no part of the reversals' transients past the window left out of the fit "
            "stood out of what the terms leave unexplained ({rms}) more than the same tails "
            "away from the reversals do: the transients end within the window, or one of "
            "about that size is not resolved")


#: The start of why the tails read none where a transient lasts past the window
LINGER = "a transient lasts past the window left out after each reversal"
#: Why they do (``{rms}``: what the terms leave unexplained)
LINGER_WHY = (LINGER + " ({rms} left unexplained): its tails past the window stand out of "
              "the noise from sample to sample, and one as long as the half turn to the "
              "axis' next reversal, a step like a backlash, fits the samples as well as any, "
              "so the samples bound neither their level nor their decay. The terms of a "
              "step at the reversals (the backlash above all) and the spikes after the terms "
              "take what the fit does not: their uncertainty by the reversals' tails and the "
              "spikes' ±95% hold how far they move over every tail up to that long, and one "
              "that moves by more than its value is not determined by these circles. "
              "Circles at a lower feed or a larger radius, over which the window lasts "
              "longer than the transient, settle them")
#: Why the tails read none where their time constant's ± exceeds it (the time constant,
#: and the ends of its interval)
OPEN_WHY = (LINGER + ", and its time constant is not determined: the time constants that "
            "fit the samples as well run from {1} to {2}, more than the best ({0}) above "
            "it, and the tails' levels at the window's end are read at it; the terms are "
            "uncertain by the tails that fit as well (their uncertainty by the reversals' "
            "tails)")


def largest_tail(fit, axis: str):
    """The column of ``fit`` of the largest of ``axis``' tails, the one reported; None
    where none is fitted [-]."""
    tails = [j for j, n in enumerate(fit.names) if n.startswith(f"tail_{axis}")
             and np.isfinite(fit.coef[j])]
    return max(tails, key=lambda j: abs(fit.coef[j])) if tails else None


#: What the reversals' tails of a fit are, by :func:`tail_state`
TAIL_STATES = {"fitted": "a tail is fitted past the window",
               "open": "a tail is fitted whose time constant the samples do not determine",
               "lingers": "a transient lasts past the window: no tail, the terms and spikes "
                          "uncertain by every tail it may be",
               "none": "no tail stood out of what the terms leave"}


def tail_state(fit) -> str:
    """Which of :data:`TAIL_STATES` the reversals' tails of ``fit`` (a ``TermFit`` of a
    pair of full turns) are, as :func:`tail_terms` reports them [-]."""
    if fit.tail_family:
        return "lingers"
    if fit.tail is None:
        return "none"
    lo, hi = fit.tail_interval or (fit.tail[0], fit.tail[0])
    return "open" if max(fit.tail[0] - lo, hi - fit.tail[0]) > fit.tail[0] else "fitted"


def tail_terms(fit, mean_rate) -> tuple:
    """The reported tails of a pair of full turns and why any reads NaN: per axis the
    largest of its reversals' tails at the window's end (signed, + the radius out) [m],
    and their time constant [s]; all NaN where none is fitted [SI, -].

    Parameters
    ----------
    fit : TermFit
        The fit [SI].
    mean_rate : float
        The circles' angular speed; NaN where it is not known [rad/s].
    """
    out = {}
    for axis in "XY":
        j = largest_tail(fit, axis)
        out[f"reversal_tail_{axis}"] = (float("nan") if j is None else float(fit.coef[j]), "m")
    decay = fit.tail[0] / mean_rate if fit.tail is not None else float("nan")
    out["reversal_tail_decay"] = (float(decay), "s")
    rms = f"{fit.residual_rms * 1e6:.2f} µm rms"
    state = tail_state(fit)
    if state == "lingers":
        return out, dict.fromkeys(out, LINGER_WHY.format(rms=rms))
    if state == "none":
        return out, dict.fromkeys(out, NONE_WHY.format(rms=rms))
    lo, hi = fit.tail_interval or (fit.tail[0], fit.tail[0])
    if state == "open":  # its ± exceeds it
        # the tails' levels at the window's end are read at that time constant
        nan = dict.fromkeys(out, float("nan"))
        return {k: (nan[k], u) for k, (_, u) in out.items()}, dict.fromkeys(out, OPEN_WHY.format(
            *(f"{v / mean_rate * 1e3:.1f} ms" if np.isfinite(mean_rate)
              else f"{np.degrees(v):.1f} deg of travel" for v in (fit.tail[0], lo, hi))))
    why = {} if np.isfinite(decay) else {"reversal_tail_decay": (
        "the circles' angular speed is not known, so the tails' time constant is not "
        f"either: {np.degrees(fit.tail[0]):.1f} deg of travel")}
    return out, why
