"""How far a reversal spike may lie from the one the circle would read without noise, its
terms known exactly.

A spike is the extreme of ``e - b`` over the 20 deg after a quadrant point, ``b`` the
median over 30 to 5 deg before it (:mod:`.circle_spikes`), taken on what the fitted terms
leave. Three things move it:

- the noise on the window's samples. The extreme picks its sample by its value, so a spike
  no larger than the noise reads the noise's extreme over the window, not one sample's
  noise: a window of 400 samples of 0.05 um noise reads 0.17 um where there is no spike.
  The bound at 95 % is the quantile of the largest of as many independent samples as the
  window holds: ``sigma z``, ``z`` Student's quantile of ``1 - 0.025 / n`` with the window
  before's samples less one as degrees of freedom, as ``sigma`` is read off them (the
  normal's let the extreme of white noise past it in 10.7 % of windows of 23 samples,
  8.2 % of 60). Noise that
  stays alike over neighbouring samples has a smaller largest value (Slepian's
  inequality), but a short window reads its level low (AR(1) noise with phi 0.9 passes
  the bound in 20 % of windows of 23 samples, 11 % of 100); taking the window's samples
  over their correlation length instead covered 57-68 % of the extremes of noise alike
  over 19 samples, and the degrees of freedom over it blew a slow residual's bound up
  (bench H's scale 5.2 -> 13.5 um);
- the noise on the median ``b``: ``sqrt(pi / 2) sigma / sqrt(n_before / tau)``;
- the terms' own uncertainty, which moves the model under both windows: ``g^T C g``, ``g``
  the model's columns at the spike's sample less their mean over the window before, ``C``
  the terms' covariance (:func:`.circle_noise.coef_covariance`).

The noise is the window before's own: its scatter about its median, over its samples
less its correlation length (:func:`.circle_noise.autocovariance`); a slow transient
there counts as noise, on the safe side. The second and third shift every sample of the
window alike: the bound is that of the extreme of the samples less a normal shift of
their standard uncertainty (:func:`.extreme_bound.extreme_bound`). Where a
transient lasts past the window (:func:`.circle_reversal_tail.lingering`), the terms the
spike is read after are not determined: the spike moves with the tail the fit is given,
and that move, over every tail the samples allow, is added whole (:func:`family_moves`).
"""

from __future__ import annotations

import numpy as np

from .circle_design import base_columns, with_columns
from .circle_model import reversal_lead_deg
from .circle_noise import correlation_length
from .circle_open import open_terms
from .circle_spikes import spike_windows, spikes_in
from .circle_tail_terms import LINGER
from .circle_takeup import spike_moves
from .extreme_bound import extreme_bound

#: The probability the bound is exceeded: the two tails of a 95 % coverage [-]
BEYOND = 0.05
#: The tables' columns of the spikes' uncertainty, as a reader reads them
U95_COLUMNS = {f"spike_after_terms_{q}_uncertainty_95_um": f"± spike {q} (95 %) [µm]"
               for q in "ABCD"}
#: The share of the uncertainty the noise from sample to sample leaves below which what
#: the terms leave before the points is said to be mostly slower than the samples [-]
SLOW_SHARE = 0.5
#: What the uncertainty shown with the spikes is, in a phrase
NOTE = ("the largest of the spikes' 95 % uncertainties from the noise (the extreme of a "
        "window picks the noise's largest sample) and the terms (per point in --json), and "
        "where a transient lasts past the window how far they move over the tails it may "
        "be (reversal tail, below)")


def spike_uncertainty(angle_rad, rest, direction: str, lead_deg: float = 0.0,
                      columns=None, cov=None) -> tuple[dict, dict]:
    """The 95 % uncertainty of the reversal spike at A-D of ``rest`` (module docstring),
    and that from the noise from sample to sample alone: the scatter of the differences
    over the square root of 2, the terms as they are, so that what the terms leave more
    slowly, an oscillation they do not model, is taken as the machine's own (right for
    white noise only, short for noise that stays alike: :func:`slow_line`); NaN where the
    path does not hold the point's windows [m].

    Parameters
    ----------
    angle_rad : ndarray
        Angle about the nominal centre, CCW from the first axis, unwrapped [rad].
    rest : ndarray
        What the fitted terms leave of the radial error, whose spikes are taken [m].
    direction : {"ccw", "cw"}
        Direction of travel [-].
    lead_deg : float
        How far before each point the spike's window starts [deg].
    columns : ndarray, optional
        The fit's design matrix on the samples, one row each [m/unit].
    cov : ndarray, optional
        The covariance of the fit's coefficients, zero for a column not fitted [unit^2].
    """
    rest = np.asarray(rest, float)
    u95, sample = {}, {}
    for name, before, after in spike_windows(angle_rad, direction, lead_deg):
        if before is None:
            u95[name] = sample[name] = np.nan
            continue
        u95[name] = _bound(rest, before, after, columns, cov)
        sample[name] = _bound(rest, before, after, None, None, sample_noise=True)
    return u95, sample


def _bound(rest, before, after, columns, cov, sample_noise=False, beyond=BEYOND) -> float:
    """The 95 % uncertainty of one spike from its windows' masks; with ``sample_noise``
    from the noise from sample to sample alone (:func:`spike_uncertainty`); passed with
    the probability ``beyond`` instead of 5 % [m]."""
    b = np.median(rest[before])
    base = rest[before] - b
    if sample_noise:
        tau = 1.0
        sigma = float(np.std(np.diff(base)) / np.sqrt(2.0)) if base.size > 2 else 0.0
    else:
        tau = correlation_length(base)
        # a window's scatter falls short of the noise's by the samples each one repeats
        sigma = float(np.sqrt(np.sum(base**2) / max(base.size - tau, 1.0)))
    # sigma is read off the window before: the extreme's quantile is Student's, of the
    # window's degrees of freedom, not the normal's (over the samples, not their
    # correlation length: a slow residual is no noise of few samples, and the bound
    # already takes it whole)
    dof = max(np.count_nonzero(before) - 1.0, 1.0)
    var = 0.5 * np.pi * sigma**2 * tau / np.count_nonzero(before)
    if columns is not None and cov is not None:
        at = np.flatnonzero(after)[np.argmax(np.abs(rest[after] - b))]
        g = columns[at] - columns[before].mean(axis=0)
        var += max(float(g @ cov @ g), 0.0)
    # the level's noise and the terms' shift every sample of the window alike
    return extreme_bound(sigma, dof, np.count_nonzero(after), np.sqrt(var), beyond)


def is_slow(u95: float, fast: float) -> bool:
    """Whether a spike's uncertainty ``u95`` is mostly what the terms leave more slowly
    than from sample to sample, ``fast`` the bound from the sample-to-sample noise
    alone [-]."""
    return bool(u95 >= 0.1e-6 and fast < SLOW_SHARE * u95)


def slow_line(rows) -> str:
    """A line naming the circles whose spikes' uncertainty is mostly what the terms leave
    slowly, each with the bound from the sample-to-sample noise alone; empty where none
    is. ``rows``: ``(label, u95 per point, sample-noise u95 per point)`` [-]."""
    # the table's ±95% is the largest over the points: so is the bound beside it, named
    items = [f"{label} ±{largest(fast) * 1e6:.2f} µm at {_largest_at(fast)}"
             for label, u95, fast in rows if is_slow(largest(u95), largest(fast))]
    if not items:
        return ""
    return ("±95% counts what the terms leave before the points as noise; it changes there "
            "more slowly than from sample to sample (a transient or an oscillation the "
            "terms do not model, or noise that stays alike) for " + ", ".join(items)
            + ": the bound were it the machine's own, from the sample-to-sample noise "
            "alone, the terms as they are, the largest over the points")


def _largest_at(u95: dict) -> str:
    """The point whose uncertainty is the largest of ``u95``'s [-]."""
    return max((v, q) for q, v in u95.items() if v == v)[1]


def largest(u95: dict) -> float:
    """The largest of the points' uncertainties; NaN where none is given [m]."""
    vals = [v for v in u95.values() if v == v]
    return max(vals) if vals else float("nan")


#: A jump of the model between two samples larger than this many times its median one
#: is a step (a backlash's or lateral play's at a reversal) [-]
STEP_JUMP = 20.0


def step_sides(e, model):
    """The residual ``e - model``, where a sample next to a step of the model is measured
    from the nearest value the step takes between its two sides: a sample on the reversal
    point to the rounding has no side, and one taken while the axis crosses its play lies
    between them (started on a round angle, a circle read a spike the size of the
    backlash, 3 um for none, from that one sample) [m].

    So is a sample about the step, or the take-up the model spreads over samples, that
    lies at the level of its other side (:func:`_across`): the model reverses an axis
    where the tool's angle, less the other axis' lost motion, says it does, and the other
    axis' other errors there (a squareness) turn that angle by their size over the
    radius. Sampled finely, the measured step lies samples away: at F1000 and 10 kHz on
    R 35 mm, 150 um/m put Y's 6 um step two samples off, and the samples between read a
    spike of 6.5 um for 3."""
    r = np.asarray(e - model, float)
    jump = np.abs(np.diff(model))
    if jump.size < 2:
        return r
    steps = np.flatnonzero(jump > STEP_JUMP * np.median(jump) + 1e-9)
    for k in steps:
        lo, hi = sorted((model[k], model[k + 1]))
        for j in (k, k + 1):
            r[j] = e[j] - min(max(e[j], lo), hi)
    for k0, k1 in _runs(steps):
        lo, hi = sorted((model[k0], model[k1 + 1]))
        for j in _across(e, model, k0, k1):
            r[j] = e[j] - min(max(e[j], lo), hi)
    return r


def _runs(steps) -> list:
    """``(first, last)`` of each run of consecutive indices of ``steps`` [-]."""
    if not len(steps):
        return []
    cut = np.flatnonzero(np.diff(steps) > 1)
    return list(zip(steps[np.r_[0, cut + 1]].tolist(),
                    steps[np.r_[cut, len(steps) - 1]].tolist(), strict=True))


#: The most samples either side of a model's step taken as across it (:func:`_across`) [-]
_ACROSS_MAX = 64


def _across(e, model, k0: int, k1: int) -> list:
    """The samples about the model's step from sample ``k0`` to ``k1 + 1`` that lie at
    the level of its other side, within a quarter of the step: before it, those at
    ``model[k1 + 1]``, after it those at ``model[k0]``, each run from the step on,
    :data:`_ACROSS_MAX` at most; on it, those at either. Noise puts a sample there across
    a step the size of the noise, not one several times it; a transient the terms do not
    model lies off both levels [-]."""
    before, after = model[k0], model[k1 + 1]
    near = 0.25 * abs(after - before)
    out = [j for j in range(k0, k1 + 2)
           if min(abs(e[j] - before), abs(e[j] - after)) < near]
    for start, step, other in ((k0 - 1, -1, after), (k1 + 2, 1, before)):
        j = start
        while (0 <= j < e.size and abs(j - start) < _ACROSS_MAX
               and abs(e[j] - other) < near):
            out.append(j)
            j += step
    return out


def pair_spikes(fit, arcs, radius, shared, curves, opened=(), parts=None) -> tuple:
    """The spikes after a fit's terms, ``spike_{P}_{direction}``, taken from where the
    leading axis reverses (the fit leaves its transient out) on what the terms leave
    (:func:`step_sides`), their 95 % uncertainty (:func:`spike_uncertainty`), that from
    the noise from sample to sample alone, how far each moves over the tails of a
    transient lasting past the window (:func:`family_moves`, 0 for none), and their
    bound at 95 % for the spikes together
    (:func:`.circle_spike_bounds.spikes_in_noise`) [m].

    Parameters
    ----------
    fit : TermFit
        The fit [SI].
    arcs : list of Arc
        The arcs fitted, in the order of ``curves`` [-].
    radius : float
        Nominal radius [m].
    shared : sequence of str
        The shared terms fitted [-].
    curves : dict
        ``direction -> (angle, radial error, fitted model)`` [rad, m, m].
    opened : tuple of int
        The axes whose take-up width is left open whatever its interval
        (:func:`.circle_takeup.spike_moves`) [-].
    parts : dict, optional
        Per direction, what is read of its circle whatever width is left open
        (:func:`_circle_parts`), filled where missing: a second reading of the same fit
        with a width opened reads the rest again from it [-].
    """
    parts = {} if parts is None else parts
    spikes, u95, fast, tails, together = {}, {}, {}, {}, {}
    for i, (d, curve) in enumerate(curves.items()):
        if d not in parts:
            parts[d] = _circle_parts(fit, arcs, i, radius, shared, d, curve, len(curves))
        pos, centre, windows, rest, got, bounds, lingers = parts[d]
        for out, values in zip((spikes, u95, fast), got, strict=True):
            out.update({f"spike_{q}_{d}": v for q, v in values.items()})
        together.update(bounds)
        # the take-up's own interval, which the fit's covariance does not hold
        moves = spike_moves(fit, arcs[i], radius, pos, centre, got[0],
                            lambda dr, w=windows, rest=rest: spikes_in(w, rest + dr), opened)
        for q, v in moves.items():
            k = f"spike_{q}_{d}"
            for bound in (u95, together):
                if k in bound and np.isfinite(bound[k]):
                    bound[k] = float(np.hypot(bound[k], v)) + lingers.get(q, 0.0)
        tails.update({f"spike_{q}_{d}": v for q, v in lingers.items()})
    return spikes, u95, fast, tails, together


def _circle_parts(fit, arcs, i, radius, shared, d, curve, count) -> tuple:
    """What :func:`pair_spikes` reads of the circle ``i`` in the direction ``d``, its
    ``curve`` ``(angle, radial error, model)``, whatever take-up width is left open:
    its positions and centre, its spike windows, what the terms leave, its spikes and
    their uncertainties, its bounds for the spikes together (of ``count`` circles) and
    their moves over a lingering transient's tails [m]."""
    a, e, model = curve
    cov = None if fit.cov is None else np.nan_to_num(fit.cov)
    lead = reversal_lead_deg(a, fit.mu) if fit.mu else 0.0
    rest = step_sides(e, model)
    pos, centre = (arcs[i].positions(radius, None, e),
                   fit.centres[i] if fit.centres else (0.0, 0.0))
    # the columns of the terms, which every tail and every change of the spikes share
    base = base_columns(arcs[i], i, len(arcs), radius, shared, fit.mu, arcs[i].angle,
                        pos, centre, fit.take_up)
    cols = with_columns(base, arcs[i], i, len(arcs), fit.mu, fit.waves, arcs[i].angle,
                        fit.tail)
    windows = list(spike_windows(a, d, lead))
    got = (spikes_in(windows, rest), *spike_uncertainty(a, rest, d, lead, cols, cov))
    bounds = {f"spike_{q}_{d}": _bound(rest, before, after, cols, cov,
                                       beyond=BEYOND / (4 * count))
              for q, before, after in windows if before is not None}
    lingers = family_moves(fit, cols, lambda c, t, w: with_columns(
        base, arcs[i], i, len(arcs), fit.mu, w, arcs[i].angle, t) @ np.nan_to_num(c),
        got[0], lambda dr: spikes_in(windows, rest - dr))
    return pos, centre, windows, rest, got, bounds, lingers


def widen_for_opened(fit, arcs, radius, shared, curves, terms, spike_u95,
                     parts=None) -> None:
    """Where a take-up width the search read within an interval is left open after the
    spikes were (:func:`.circle_takeup.width_follows_backlash`: beside a transient, or
    one lasting past the window), each spike's ±95% in ``spike_u95`` over the whole span
    the width may take, as for a width the search leaves open: the spikes are read with
    the width that fits best, which took part of the transient (a 5 um spike peaking 0.8
    deg after each point, beside dead bands of 4 and 6 um, read 4.21 ± 0.19 um) [m].

    Parameters
    ----------
    fit, arcs, radius, shared, curves
        As for :func:`pair_spikes` [SI].
    terms : dict
        The terms by the fit's axis names, the widths as left [SI].
    spike_u95 : dict
        The spikes' 95 % uncertainties, widened in place; NaN stays [m].
    parts : dict, optional
        :func:`pair_spikes`' parts of the same fit and curves [-].
    """
    opened = tuple(k for k, a in enumerate("XY") if np.isfinite(fit.widths[k][1])
                   and not np.isfinite(terms.get(f"take_up_width_{a}", (np.nan,))[0]))
    if not opened:
        return
    for k, v in pair_spikes(fit, arcs, radius, shared, curves, opened, parts)[1].items():
        if np.isfinite(spike_u95.get(k, np.nan)) and np.isfinite(v):
            spike_u95[k] = max(spike_u95[k], v)


#: Why spikes are open where a transient lasts past the window and moves them by more than
#: the whole radial error the circles show (``{points}``: which)
SPIKES_OPEN = (LINGER + ", and over the tails it may be (see reversal tail) the spikes "
               "after the terms at {points} move by more than the whole radial error the "
               "circles show (their peak to valley): these circles do not determine them "
               "(the raw e - b are in --json). Circles at a lower feed or a larger radius, "
               "over which the window lasts longer than the transient, settle them")


def open_spikes(terms: dict, tails: dict, span: float, *uncertainties: dict) -> dict:
    """Leave open each spike of ``terms`` that moves over the tails of a transient lasting
    past the window (``tails``, :func:`pair_spikes`) by more than ``span``, the whole
    radial error the circles show: its value and its ``uncertainties`` become NaN; the
    reason as ``reversal_spikes``, empty for none [-].

    Parameters
    ----------
    terms : dict
        The reported terms, ``spike_{P}_{direction} -> (value, unit)``; changed in place
        [SI].
    tails : dict
        Each spike's move over the tails [m].
    span : float
        Peak to valley of the circles' radial error, the larger of the two [m].
    *uncertainties : dict
        The spikes' uncertainties by the same keys; changed in place [m].
    """
    open_ = [k for k, v in tails.items()
             if k in terms and np.isfinite(terms[k][0]) and v > span]
    open_terms(terms, open_, "", *uncertainties)
    points = ", ".join(f"{k.split('_')[1]} {k.split('_')[2].upper()}" for k in open_)
    return {"reversal_spikes": SPIKES_OPEN.format(points=points)} if open_ else {}


def family_moves(fit, cols, model_of, base, spikes_of) -> dict:
    """How far each spike moves over the fits of a transient lasting past the window
    (:attr:`TermFit.tail_family`, empty for none): the spikes ``spikes_of(change)`` of
    what the terms leave with each fit's model ``model_of(coef, tail, waves)`` in place of
    the fit's own ``cols @ coef``, the largest change per point. Added to the spike's
    ±95% whole: the data do not tell which of the fits holds, so it is a bound, not a
    scatter [m]."""
    moves = dict.fromkeys(base, 0.0)
    if not fit.tail_family:
        return moves
    now = cols @ np.nan_to_num(fit.coef)
    for tail, coef, waves in fit.tail_family:
        moved = spikes_of(model_of(coef, tail, waves) - now)
        for q, v in moved.items():
            if np.isfinite(v) and np.isfinite(base[q]):
                moves[q] = max(moves[q], abs(v - base[q]))
    return moves
