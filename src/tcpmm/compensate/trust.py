"""Where the compensation is trusted, sample by sample, and the record of what the draws
say of it on the compensation.

A region is judged by its largest error (:mod:`.robust`): the shares are chosen so that it
falls on every draw. Below it a sample may still rise: on a square, the corner's error
falls from 40 to 21 µm while the approach to it, along one axis alone and exactly on the
path before, leaves it by 0.4 µm. So each sample is also held to its own error before: it
is trusted only where its region is and one more draw's error after, at its upper bound,
stays below the largest error before within :data:`RISE_WINDOW_S` (its envelope), at its
lower bound, by the margin (:func:`.robust.margin`; :func:`local_rises`). The largest rise
the draws cannot rule out is recorded with where it is.
"""

from __future__ import annotations

import numpy as np
from scipy.ndimage import maximum_filter1d

from ..uncertainty.verdict import CALIBRATION

#: Half-width of the window whose largest error before is a sample's envelope [s]: a peak
#: the correction moves by less (a ringing's phase; the ramp between two regions' shares,
#: :data:`.regional.RAMP_S`) is the same error moved, not a new one.
RISE_WINDOW_S = 0.03

#: The chance a verdict may leave of the machine falling short of it, as one more draw
#: (:func:`next_draw`) [-].
BEYOND = 0.05


def next_draw(x: np.ndarray):
    """The lower bound of one more draw of ``x`` at 95 %, from the draws' mean and
    scatter (Student's t prediction bound, the scatter widened by the prediction
    intervals' calibration factor, :data:`tcpmm.uncertainty.verdict.CALIBRATION`), and
    never above their least: the least of a few draws is no bound for the next (of 7, one
    more falls below it one time in 8); of each column where ``x`` has two dimensions [-].

    Parameters
    ----------
    x : ndarray
        The draws' values along the first axis, such as the logarithm of a ratio [-].
    """
    x = np.asarray(x, float)
    least = np.min(x, axis=0)
    if x.shape[0] < 3 or not np.all(np.isfinite(x)):
        return float(least) if x.ndim == 1 else least
    from scipy.stats import t

    # widened as the prediction intervals are for the machines beyond the draws
    n = x.shape[0]
    spread = CALIBRATION["factor"] * np.std(x, axis=0, ddof=1) * np.sqrt(1.0 + 1.0 / n)
    bound = np.minimum(least, np.mean(x, axis=0) - t.ppf(1.0 - BEYOND, n - 1) * spread)
    return float(bound) if x.ndim == 1 else bound


def local_rises(before: np.ndarray, after: np.ndarray, target, margin,
                window_s: float = RISE_WINDOW_S) -> tuple:
    """The samples where the draws cannot rule out a rise: the error after of one more
    draw, at its upper bound (:func:`next_draw`), is above its envelope before (the
    largest error within ``window_s``) at its lower bound by more than ``margin`` of it;
    and the largest such rise: ``(mask, summary)``. The summary gives the share of
    samples and of the largest rise its time, where on the path, and both bounds
    [-, s, mm, µm].

    Draw by draw, a machine whose error before is below every draw's (the model wrong on
    what it corrects) can rise where none of them does: the correction then removes more
    than there was. So the bounds are taken apart, every machine the draws span held to
    every other, and the machine itself is one more draw beyond them, as the regions'
    verdicts take it.

    Parameters
    ----------
    before, after : ndarray
        Distance of the TCP from the path per draw and sample, without and with the
        compensation, shape (machines, n) [m].
    target : Command
        The path, sampled as the errors are [m].
    margin : callable
        The least rise of an error that counts, from the error before [m].
    window_s : float
        Half-width of the envelope's window [s].
    """
    w = 2 * max(1, round(window_s / target.period_s)) + 1
    env = next_draw(maximum_filter1d(np.asarray(before, float), size=w, axis=1,
                                     mode="nearest"))
    top = -next_draw(-np.asarray(after, float))
    excess = top - env - margin(env)
    mask = excess > 0
    if not mask.any():
        return mask, {"share": 0.0, "window_s": window_s}
    k = int(np.argmax(excess))
    return mask, {"share": float(mask.mean()), "window_s": window_s,
                  "time_s": float(target.time_s[k]),
                  "position_mm": {a: float(p[k] * 1e3) for a, p in target.positions.items()},
                  "before_um": float(env[k] * 1e6), "after_um": float(top[k] * 1e6)}


def record(comp, shares: list, rows: list, circle: dict, labels: np.ndarray,
           extra: dict, rises=None) -> None:
    """Set the chosen shares per axis, the samples trusted and what the draws say on the
    compensation, in place [-].

    Parameters
    ----------
    comp : Compensation
        The compensation [-].
    shares : list of float or ndarray
        Share of the correction per axis, one or one per sample; ``robustness["factors"]``
        holds its mean along the path [-].
    rows, circle
        Per region and for a circle the draws' verdicts (:func:`.robust.choose`) [-].
    labels : ndarray
        Region per sample (:func:`.robust.regions`) [-].
    extra : dict
        Further entries of ``comp.robustness``, first: the draws and their seed [-].
    rises : tuple, optional
        :func:`local_rises` of the shares: its samples are not trusted [-].
    """
    for a, f in zip(comp.reference.axes, shares, strict=True):
        comp.factors[a] = np.broadcast_to(np.asarray(f, dtype=float), labels.shape).copy()
    good = {r["region"] for r in rows if r["verdict"] != "uncertain"}
    firm = {r["region"] for r in rows if r["verdict"] == "firm"}
    rising, rise = (np.zeros(labels.shape, bool), None) if rises is None else rises
    comp.trusted = np.isin(labels, list(good)) & ~rising
    comp.robustness = {**extra, "regions": rows,
                       "factors": {a: float(np.mean(f)) for a, f in zip(
                           comp.reference.axes, shares, strict=True)},
                       "trusted_share": float(np.mean(comp.trusted)),
                       "firm_share": float(np.mean(np.isin(labels, list(firm)) & ~rising))}
    if rise is not None:
        comp.robustness["local_rise"] = rise
    if circle:
        comp.robustness["circle"] = circle


def rise_words(rise: dict) -> str:
    """How far the samples' errors may rise over the draws, in words: of
    :func:`local_rises`'s summary [-]."""
    span = f"within ±{rise['window_s'] * 1e3:.0f} ms"
    if not rise["share"]:
        return (f"no sample's error after may be above its largest before {span}, by the "
                "draws")
    at = ", ".join(f"{a} {v:.3f}" for a, v in rise["position_mm"].items())
    return (f"on {rise['share']:.1%} of the samples the draws cannot rule out a rise (not "
            f"trusted): the error after may be above the largest before {span} by more "
            f"than the model's error, up to {rise['before_um']:.2f} → "
            f"{rise['after_um']:.2f} µm at {rise['time_s']:.3f} s ({at} mm)")
