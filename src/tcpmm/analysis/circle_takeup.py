"""How each axis takes up its lost motion after it reverses.

Backlash is a dead band: on reversal the table stands while the motor crosses the play
``b``, so the axis' offset goes from ``-b/2`` to ``+b/2`` over ``b`` of commanded travel
after the reversal (at R 35 mm, 4 um of it lasts 0.9 deg after the quadrant point, the
axis' travel growing with the square of the angle). Modelled as a step at the reversal it
leaves a dip of about ``-b`` there, which the reversal spike after the terms would read as
a transient (a dead band of 4 and 6 um read spikes of -3.6 to -5.9 um where there were
none). The take-up is modelled as linear in the travel since the reversal over a width
``w`` (:func:`.circle_model.take_up`): ``w = b`` for a dead band, 0 for a step.

The fit leaves the 20 deg after each reversal out, so the backlash is read past the
take-up, whatever ``w``, and the design stays linear in it; ``w`` is kept within that
window (:func:`_reach`). Each reversal of the axis (each end of its travel, in each
circle) gives the width that best fits what the terms leave over the travel from the
reversal to :data:`SPAN` times the backlash: the ``b`` of travel a dead band takes, the
drive's wind-up past the play (the built-in machine's 8 um of nut play and its screw's own
lost motion, 10.9 um together, took 15 um; bench D's axes 2.6 and 2.3 times their
backlash, alike over spans of 3 and 4 times it), and the travel beyond, where the whole
lost motion is taken up and a width that ran past it shows. A span much longer would let
the reversal's own transient, which no term models, pass for a take-up. The width is the
median of the reversals' own, which a transient at one reversal alone does not move.
Its 95 % uncertainty is the larger of the widths whose sum of squares over all the
reversals lies within :data:`.circle_reversal_tail.AS_WELL` noise variances of the least
(as the reversals' tails are judged) and half the reversals' own widths' interquartile
range; NaN where that reaches over the whole span (a backlash in the noise), where the
width is the span's end (what the terms leave there is the transient, not a take-up), or
where fewer than :data:`MIN_SAMPLES` samples lie within the span. The width is also left
open where the reversals' transient stands out in the spikes after the terms
(:func:`beside_transient`) or lasts past the window: it shares the span's samples, and the
take-up takes part of it (a spike of half the backlash read its width a quarter short).
"""

from __future__ import annotations

import numpy as np

from .circle_model import angle_step, backlash_take_up, reversal_angle
from .circle_noise import correlation_length
from .circle_reversal_tail import AS_WELL
from .circle_travel import axis_phase, travel_since_reversal

#: The travel after a reversal searched for the take-up, per unit of the backlash [-]
SPAN = 3.0
#: Widths tried over the span, before the best is refined [-]
TRIES = 81
#: Fewest samples within the span for a width to be read [-]
MIN_SAMPLES = 3
NAN = float("nan")


def _reach(pb, mu) -> float:
    """The longest travel after a reversal that stays in every arc's window left out of
    the fit, a sample short of its end, where each axis reverses ``|mu|`` off its
    quadrant point [m]."""
    phi = min(np.radians(a.after_deg) - abs(a.ratio * mu) - angle_step(a.angle)
              for a in pb.arcs)
    return pb.radius * (1.0 - np.cos(max(phi, 0.0)))


def _near(pb, mu, rests, axis, span) -> list:
    """Per arc and reversal point of ``axis`` (0 or 1; its two ends of travel), ``(arc,
    angle about its centre, angle, rest)`` of the samples within ``span`` of travel after
    the axis reverses there [-, rad, rad, m]."""
    out = []
    for arc, rest, c in zip(pb.arcs, rests, pb.centres, strict=True):
        rev = reversal_angle(arc.positions(pb.radius), c)
        own = arc.angle if rev is None else rev
        u = travel_since_reversal(axis_phase(own, arc.s, pb.radius, arc.ratio * mu, pb.lost),
                                  arc.s, pb.radius, arc.ratio * mu, axis)
        end = np.cos(own) > 0 if axis == 0 else np.sin(own) > 0
        for near in ((u <= span) & arc.ends & end, (u <= span) & arc.ends & ~end):
            near = _reversed(near, arc.ends)
            if near.any():
                out.append((arc, own[near], arc.angle[near], rest[near]))
    return out


def _reversed(near, steady):
    """The runs of ``near`` that the axis reached by reversing: each preceded by a steady
    sample (``steady``) that is not in it. A run from the pass's start, where the axis
    started from rest at its quadrant point, took up its lost motion, or had it taken up,
    before the record: what the terms leave there is no take-up [-]."""
    idx = np.flatnonzero(near)
    if not idx.size:
        return near
    out = near.copy()
    firsts = np.flatnonzero(np.r_[True, np.diff(idx) > 1])
    for j, k in enumerate(firsts):
        last = idx[firsts[j + 1] - 1] if j + 1 < firsts.size else idx[-1]
        if idx[k] == 0 or not steady[idx[k] - 1]:
            out[idx[k]:last + 1] = False
    return out


def _noise(pb, rests) -> float:
    """What the fit leaves over its fitted samples: its variance times its correlation
    length (:func:`.circle_reversal_tail.noise_level`) [m^2]."""
    res = np.concatenate([r[m] for r, m in zip(rests, pb.masks, strict=True)])
    return float(np.mean(res**2)) * correlation_length(res) if res.size > 1 else 0.0


def _backlash_column(axis: int, widths, arc, angle, rev, radius, mu):
    """``column(width)``: the radial error per unit of ``axis``' backlash (0 or 1) on
    ``arc`` at ``angle``, taken up over ``width``, the other axis' over its width of
    ``widths`` [m/m]."""
    return backlash_take_up(axis, angle, arc.s, radius, arc.ratio, mu, rev, widths)


def _costs(pb, mu, parts, b, axis):
    """``ssr(w)``: per part of ``parts`` (:func:`_near`), the sum of squares with the
    backlash ``b`` of ``axis`` taken up over ``w`` instead of the fit's width; ``ssr(w, j)``
    that of part ``j`` alone [m^2]."""
    now = pb.take_up

    base = []
    for arc, own, ang, rest in parts:
        col = _backlash_column(axis, now, arc, ang, own, pb.radius, mu)
        base.append((rest, col, col(now[axis])))

    def one(width, part):
        rest, col, c0 = part
        return np.sum((rest - b * (col(width) - c0)) ** 2)

    def ssr(width, j=None):
        """Per part, or of part ``j`` alone [m^2]."""
        return one(width, base[j]) if j is not None else np.array([one(width, p)
                                                                   for p in base])
    return ssr


def _axis_width(pb, mu, rests, coef, axis, level) -> tuple:
    """``(width, its 95 % uncertainty)`` of ``axis`` (0 or 1), ``(0, NaN)`` where the fit
    has no backlash for it or no sample lies within the span (module docstring) [m]."""
    name = f"backlash_{'XY'[axis]}"
    if name not in pb.shared:
        return 0.0, NAN
    b = float(coef[3 * len(pb.arcs) + pb.shared.index(name)])
    span = min(SPAN * abs(b), _reach(pb, mu)) if np.isfinite(b) else 0.0
    parts = _near(pb, mu, rests, axis, span) if span > 0 else []
    if sum(p[2].size for p in parts) < MIN_SAMPLES:
        return 0.0, NAN
    ssr = _costs(pb, mu, parts, b, axis)
    tried = np.linspace(0.0, span, TRIES)
    step = span / (TRIES - 1)
    cost = np.array([ssr(w) for w in tried])  # widths x parts
    # each reversal's best, refined beside the best tried (the sum of squares is smooth
    # there), and their median: a transient that starts at one reversal alone would move
    # a width fitted to all (a 5 um spike at one of four read the others down to -0.3 um)
    each = []
    for j, k in enumerate(np.argmin(cost, axis=0)):
        near = np.clip(tried[k] + np.linspace(-step, step, 21), 0.0, span)
        each.append(near[np.argmin([ssr(w, j) for w in near])])
    best = float(np.median(each))
    total = cost.sum(axis=1)
    alike = tried[total <= total.min() + AS_WELL * level]
    spread = float(np.subtract(*np.percentile(each, [75, 25]))) / 2
    lo = min(alike.min(initial=best), best - spread)
    hi = max(alike.max(initial=best), best + spread)
    # a best width at the span's end is no take-up the span holds: the reversal's
    # transient runs on past it (bench D's read twice its backlash over a span of 2)
    if (lo <= 0.0 and hi >= span) or best >= span - step:
        return best, NAN
    return best, max(best - lo, hi - best, step / 2)


def lost_motion(pb, coef) -> tuple:
    """Each axis' backlash of ``coef``, 0 where the fit has none, for the axes' own angle
    the take-up's travel is read at (:func:`.circle_travel.axis_phase`) [m]."""
    return tuple(float(np.nan_to_num(coef[3 * len(pb.arcs) + pb.shared.index(n)]))
                 if n in pb.shared else 0.0 for n in ("backlash_X", "backlash_Y"))


def search_widths(pb, mu, waves, coef) -> tuple:
    """Per axis, ``(width, its 95 % uncertainty)`` of the backlash's take-up after each
    reversal that best fits what the terms ``coef`` leave near the reversals (module
    docstring), the servo mismatch ``mu`` [rad] and cyclic errors ``waves`` [1/m] as
    fitted [m]; ``pb.lost`` set to the backlashes of ``coef`` (:func:`lost_motion`).

    Parameters
    ----------
    pb : FitProblem
        The fit's arcs and columns (:class:`.circle_fit.FitProblem`) [-].
    mu : float
        Servo mismatch angle [rad].
    waves : tuple
        Wavenumbers of the cyclic errors fitted, None for none [1/m].
    coef : ndarray
        The fit's coefficients [SI].
    """
    rests = pb.rest(mu, waves, coef)
    level = _noise(pb, rests)
    pb.lost = lost_motion(pb, coef)  # the take-ups' travel at the axes' own angle
    return tuple(_axis_width(pb, mu, rests, coef, axis, level) for axis in (0, 1))


def _width_span(width, u95, b, opened, within_step):
    """The widths :func:`spike_moves` reads the spikes at, ``(lo, hi)``, for an axis of
    backlash ``b`` whose width is left ``opened`` or not; None for none [m]."""
    step = SPAN * abs(b) / (TRIES - 1)
    if within_step:
        if opened or not (np.isfinite(width) and np.isfinite(u95)
                          and 0.0 < width <= u95 <= step):
            return None
        return 0.0, width  # the step its interval holds, against the width read
    if not opened and u95 <= step:
        return None  # within the search's own step: the width is read to its grid
    return ((width - u95, width + u95) if np.isfinite(u95) and not opened
            else (0.0, SPAN * abs(b)))


def spike_moves(fit, arc, radius, pos, centre, base, spikes_of, opened=(),
                within_step=False) -> dict:
    """How far each reversal spike moves as its axis' take-up width runs over the width's
    95 % interval (the width is searched, so the fit's covariance does not hold it): the
    spikes ``spikes_of(rest)`` of what the terms leave with the take-up at either end of
    the interval against those at the width fitted, the largest change per point; the
    width open, over the whole span :data:`SPAN` times the backlash; none where the
    interval is within the search's step [m].

    Parameters
    ----------
    fit : TermFit
        The fit, with its widths [SI].
    arc : Arc
        The circle [-].
    radius : float
        Nominal radius [m].
    pos : tuple of ndarray
        The tool's positions on the circle (where its axes reverse) [m].
    centre : tuple of float
        The circle's own centre as fitted [m].
    base : dict
        The spikes per point with the take-up as fitted [m].
    spikes_of : callable
        A change to what the terms leave, with the take-up as fitted, to the spikes per
        point [m].
    opened : tuple of int
        The axes (0, 1) whose width is left open whatever its interval (beside a
        transient): over the whole span [-].
    within_step : bool
        Instead, for a width read above 0 whose interval lies within the search's step
        and holds 0, the move from the width read to a step (left out otherwise): the
        first samples after a reversal, whose travel grows with the square of the angle,
        move by much of the backlash over a fraction of the step [-].
    """
    moves = dict.fromkeys(base, 0.0)
    rev = reversal_angle(pos, centre)
    for axis, (width, u95) in enumerate(fit.widths):
        name = f"backlash_{'XY'[axis]}"
        if name not in fit.names or not np.isfinite(fit[name]) or fit[name] == 0.0:
            continue
        b = float(fit[name])
        if (span := _width_span(width, u95, b, axis in opened, within_step)) is None:
            continue
        lo, hi = span

        col = _backlash_column(axis, fit.take_up, arc, arc.angle, rev, radius, fit.mu)
        now = col(width)
        for w in (max(lo, 0.0), hi):
            moved = spikes_of(-b * (col(w) - now))
            for q, v in moved.items():
                if np.isfinite(v) and np.isfinite(base[q]):
                    moves[q] = max(moves[q], abs(v - base[q]))
    return moves


#: Why a take-up width reads n/a
WIDTH_WHY = ("the samples after the axis' reversals do not tell how its backlash is taken "
             f"up: fewer than {MIN_SAMPLES} lie within {SPAN:g} times the backlash's travel "
             "after them, or a take-up of any width up to that fits them as well (a "
             "backlash in the noise), or the best runs to that end (what the terms leave "
             "there is the reversal's transient more than a take-up); the spikes after the "
             "terms are read with the width that fits best ({width})")


def width_terms(fit) -> dict:
    """Per axis its backlash's take-up width, ``take_up_width_{axis} -> (value, "m")``,
    NaN where the data cannot tell it (:func:`width_why`) [m]."""
    return {f"take_up_width_{axis}": (float(width) if np.isfinite(u95) else NAN, "m")
            for axis, (width, u95) in zip("XY", fit.widths, strict=True)}


def width_follows_backlash(terms: dict, why: dict, rename, spike_u95=None,
                           lingers=False) -> None:
    """Leave each take-up width open whose backlash is (a NaN value, or a reason in
    ``why``): the width is the backlash's, and a backlash the data cannot place or read
    has no take-up to read either; and, given the spikes' uncertainties, each whose axis
    reverses into a transient (:func:`beside_transient`) [-].

    Parameters
    ----------
    terms : dict
        ``name -> (value, unit)`` by the fit's axis names X and Y, the spikes after the
        terms among them [SI].
    why : dict
        Reasons by the reported names [-].
    rename : callable
        A fit's name to its reported one [-].
    spike_u95 : dict, optional
        The spikes' 95 % uncertainties, ``spike_{P}_{direction} -> u95`` [m].
    lingers : bool
        A transient lasts past the window (:func:`.circle_reversal_tail.lingering`), and
        so through the samples the take-up is read from [-].
    """
    for a in "XY":
        b, w = f"backlash_{a}", f"take_up_width_{a}"
        said = why.get(rename(b))
        if w in terms and (said is not None or not np.isfinite(terms[b][0])):
            terms[w] = (NAN, "m")
            why[rename(w)] = ("the backlash it takes up is open, for the reason given for "
                              + rename(b).replace("_", " "))
        elif w in terms and np.isfinite(terms[w][0]) and spike_u95 is not None:
            said = (LINGERS_WHY if lingers else
                    beside_transient(terms, spike_u95, REVERSES_AT[a]))
            if said:
                terms[w] = (NAN, "m")
                why[rename(w)] = said


#: One direction has no spikes' ±95%: a spike of noise alone is within this many times
#: what the fit leaves, rms, the extreme of the noise over its window [-]
EXTREME_RMS = 4.5


def noise_extremes(terms: dict, rms: float) -> dict:
    """The bound of a spike of noise alone for each spike of ``terms``, from the fit's
    residual ``rms`` (:data:`EXTREME_RMS`), in place of the spikes' ±95% [m]."""
    return {k: EXTREME_RMS * rms for k in terms if k.startswith("spike_")}


#: The quadrant points where each axis reverses [-]
REVERSES_AT = {"X": "AC", "Y": "BD"}
#: Nor where the spikes are below this: a spike moves the width by about half its height,
#: within the terms' tolerance of 0.1 um [m]
TRANSIENT_M = 0.1e-6
#: Why a take-up width reads n/a beside a transient (``{size}``, ``{points}``)
TRANSIENT_WHY = ("the reversals' own transient, spikes after the terms of {size} µm at "
                 "{points}, more than noise makes, lies in the samples after the reversals the "
                 "take-up is read from and reads as part of it: a spike of 5 µm 3 deg after "
                 "each point read dead bands of 4 and 6 µm as 1.9 and 3.5 µm, ± 0.1 µm. The "
                 "backlash itself is read past the window, and stands")


#: Why it does where a transient lasts past the window
LINGERS_WHY = ("a transient lasts past the window after each reversal (see reversal tail), "
               "and so through the samples after the reversals the take-up is read from, "
               "which it reads as part of the take-up. The backlash is read past the window, "
               "uncertain by the reversals' tails")


def beside_transient(terms: dict, spike_u95: dict, points: str) -> str:
    """Why the take-up width of the axis reversing at ``points`` is open where a transient
    follows its reversals: the median of the sizes of its spikes after the terms
    (``terms``) beyond the median of their 95 % uncertainties (``spike_u95``) and
    :data:`TRANSIENT_M` (a spike of noise alone passes its ± one time in twenty, two of
    four one time in seventy). Empty where no transient stands out [-]."""
    keys = [k for k in terms if k.startswith("spike_") and k.split("_")[1] in points
            and np.isfinite(terms[k][0]) and np.isfinite(spike_u95.get(k, NAN))]
    if not keys:
        return ""
    size = float(np.median([abs(terms[k][0]) for k in keys]))
    if size <= max(float(np.median([spike_u95[k] for k in keys])), TRANSIENT_M):
        return ""
    held = sorted({k.split("_")[1] for k in keys})  # an arc holds some of the points
    return TRANSIENT_WHY.format(size=f"{size * 1e6:.2f}", points=" and ".join(held))


def width_why(fit) -> dict:
    """Why each take-up width the data cannot tell reads n/a [-]."""
    return {f"take_up_width_{axis}": WIDTH_WHY.format(
        width="a step" if not width > 0 else f"{width * 1e6:.2f} µm")
        for axis, (width, u95) in zip("XY", fit.widths, strict=True) if not np.isfinite(u95)}
