"""How far each fitted term of a circle depends on where the reversals' transients are
taken to end.

The fit leaves out the 20 deg after each reversal, where the transient lies that no term
models. Where the transient rings or creeps on beyond them (a column flipping with the
friction, a slow position loop), what of it lies past the window reads as the terms that
share its shape: backlash, scale mismatch, a centre offset. The terms are fitted again
with :data:`WIDER_DEG` left out, the cyclic periods kept; a term whose radial size moves
by :data:`MOVES_M` and by :data:`MOVES_SHARE` of its own, more than the terms are recovered
to, is owed to that window as much as to the machine's geometry, and is reported uncertain
by at least that much (bench C's TCP at F10000: backlash Y 14.8 um at 20 deg, 21.8 um at
40 deg): a transient longer than the wider window moves it less than it biases it.

The fit models what of a transient lies past the window as a decaying tail
(:mod:`.circle_reversal_tail`); a term is also uncertain by as far as it moves over the
tails that fit the samples as well as the one fitted, whichever is larger.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..errors import InputError
from .circle_display import display_digits, display_unit, rename_axes
from .circle_fit import fit_terms
from .circle_open import open_terms
from .circle_tail_terms import LINGER

#: The angle after each reversal left out when the terms are fitted again [deg].
WIDER_DEG = 40.0
#: A term moves with the window when its radial size moves by this much [m] ...
MOVES_M = 0.1e-6
#: ... and by this share of its own radial size [-]: the two are the tolerance the terms
#: are recovered to (2 % or 0.1 um of radial error), so a term not flagged moves by less.
#: A tail decaying over 60 deg moves a backlash by only 14 % while it biases it by 34 %.
MOVES_SHARE = 0.02
#: Terms whose radial size is their value times this over the radius (an ellipse's
#: half axis difference: squareness, scale and servo mismatch) [-].
_HALF_R = ("squareness", "squareness_or_servo", "scale_mismatch", "servo_mismatch_angle")


def tail_shift(fit, arcs, radius, shared, terms, axes, mean_rate=float("nan"),
               rename=None) -> dict:
    """How much each reported term changes when the fit leaves out :data:`WIDER_DEG` after
    each reversal instead of the arcs' own window, by the name it is reported under (the
    plane's axes; ``rename`` maps a fitted name to the reported one), for the terms of
    ``terms`` that have a value [SI]; empty where the wider window leaves too little to fit.
    The wider window fits the columns the arcs' own window does, whatever it determines
    itself: a column it would leave out (over 220 deg arcs, a bow) is taken over by the
    terms that share its shape (a bow of 2.3 um read as a scale mismatch of 45 ppm), which
    says nothing of the transient.

    Parameters
    ----------
    fit : TermFit
        The fit with the arcs' own window [SI].
    arcs : list of Arc
        The arcs fitted [-].
    radius : float
        Nominal radius [m].
    shared : sequence of str
        The shared terms fitted [-].
    terms : dict
        The reported terms, ``name -> (value, unit)``, axes X and Y [SI].
    axes : tuple of str
        The plane's axes [-].
    mean_rate : float
        The circles' angular speed, for the servo mismatch as a time; NaN leaves it out
        [rad/s].
    rename : dict, optional
        Fitted name -> reported name [-].
    """
    wide = [dataclasses.replace(a, after_deg=WIDER_DEG) for a in arcs]
    fitted = [n for n, c in zip(fit.names, fit.coef, strict=True) if np.isfinite(c)
              and not n.startswith(("cyclic_", "tail_"))]
    try:
        other = fit_terms(wide, radius, shared, cyclic=False, waves=fit.waves,
                          columns=fitted, tail=fit.tail)
    except (InputError, np.linalg.LinAlgError, ValueError):
        return {}
    out = as_reported(lambda n: other[n] - fit[n], len(arcs), shared, mean_rate, rename)
    # or as far as it moves over the reversals' tails that fit the samples as well
    alike = as_reported(lambda n: fit.tail_spread.get(n, 0.0), len(arcs), shared,
                        mean_rate, rename)
    out = {k: alike[k] if abs(alike[k]) > abs(v) else v for k, v in out.items()}
    for axis, k in zip("XY", fit.waves, strict=True):
        if k is not None:
            out[f"cyclic_amplitude_{axis}"] = (other.cyclic_amplitude(axis)
                                               - fit.cyclic_amplitude(axis))
    return {rename_axes(k, axes): float(v) for k, v in out.items()
            if k in terms and np.isfinite(terms[k][0])}


def as_reported(value, n_arcs, shared, mean_rate=float("nan"), rename=None) -> dict:
    """The reported terms of a fit's quantities ``value(name)``: a centre offset per axis
    as the mean over the arcs, the servo mismatch angle also as a time, the other shared
    terms by their name (``rename`` maps one to another); axes X and Y [SI].

    Parameters
    ----------
    value : callable
        Fitted column name -> its value (or its change) [SI].
    n_arcs : int
        Arcs fitted together [-].
    shared : sequence of str
        The shared terms fitted [-].
    mean_rate : float
        The circles' angular speed, for the servo mismatch as a time [rad/s].
    rename : dict, optional
        Fitted name -> reported name [-].
    """
    out = {}
    for axis in "XY":
        out[f"centre_offset_{axis}"] = float(np.mean(
            [value(f"centre_{axis}_{i}") for i in range(n_arcs)]))
    for name in shared:
        v = value(name)
        if name == "servo_angle":
            out["servo_mismatch_angle"] = v
            out["servo_mismatch"] = v / mean_rate
        else:
            out[(rename or {}).get(name, name)] = v
    return out


def radial_size(term: str, value: float, radius: float) -> float:
    """The radial error a term's value makes over the circle, to compare terms of any
    unit: the value for a length, the ellipse's half axis difference ``R |v| / 2`` for
    squareness, scale and servo mismatch angle; NaN for a time, and for a backlash's
    take-up width, a travel that makes no radial error of its own [m].

    Parameters
    ----------
    term : str
        Reported term name [-].
    value : float
        Its value [SI].
    radius : float
        Nominal radius [m].
    """
    if term == "servo_mismatch" or term.startswith("take_up_width"):
        return float("nan")
    return abs(value) * (radius / 2 if term in _HALF_R else 1.0)


#: Why a term is open where a transient lasts past the window and moves it by more than the
#: whole radial error the circles show
OPEN_BY_TAILS = (LINGER + ", and over the tails it may be, up to one as long as the half "
                 "turn to the axis' next reversal (see reversal tail), this moves by more "
                 "than the whole radial error the circles show (their peak to valley): the "
                 "samples bound it no better than that, so these circles do not determine "
                 "it (the move is in --json, tail_shift). Circles at a lower feed or a "
                 "larger radius, over which the window lasts longer than the transient, "
                 "settle it")


def open_by_tails(fit, terms: dict, shift: dict, radius: float, span: float) -> dict:
    """Where a transient lasts past the window (``fit.tail_family``), leave open each term
    whose radial size moves over the tails it may be (``shift``, :func:`tail_shift` by
    the names X and Y) by more than ``span``, the whole radial error the circles show:
    fits with terms that large cancel one another, and the samples bound the term no
    better than the error itself. Their values become NaN, and the fit's columns too, so
    that the ranking leaves them out; the reasons by the names X and Y [-]. A cyclic
    error, searched for apart, is not judged so.

    Parameters
    ----------
    fit : TermFit
        The fit [SI].
    terms : dict
        The reported terms, ``name -> (value, unit)``, names X and Y; changed in place [SI].
    shift : dict
        Each term's move, by the names X and Y [SI].
    radius : float
        Nominal radius [m].
    span : float
        Peak to valley of the circles' radial error, the larger of the two [m].
    """
    if not fit.tail_family:
        return {}
    keys = [k for k, d in shift.items()
            if not k.startswith("cyclic_") and np.isfinite(terms.get(k, (np.nan,))[0])
            and radial_size(k, d, radius) > span]
    if "servo_mismatch_angle" in keys and "servo_mismatch" in terms:
        keys.append("servo_mismatch")
    return open_terms(terms, keys, OPEN_BY_TAILS, fit=fit)


def sign_open(terms: dict, shift: dict, radius: float) -> list:
    """The terms that move with the window after the reversals (``shift``,
    :func:`tail_shift`) by more than their own radial size, at least :data:`MOVES_M`: the
    circles do not determine even their sign, and they are not ranked among the error
    sources (a ranking of the demo's circle listed a backlash of 2.08 um that reads -12.92
    with the wider window as its fourth source). Names as ``terms`` and ``shift`` give them;
    a centre offset also as ``centre_offset`` where its vector moves by more than it is
    long, a servo mismatch with its angle [-].

    Parameters
    ----------
    terms : dict
        The reported terms, ``name -> (value, unit)`` [SI].
    shift : dict
        Each term's move with the window [SI].
    radius : float
        Nominal radius [m].
    """
    out = []
    for k, d in shift.items():
        v = terms.get(k, (float("nan"),))[0]
        if k.startswith(("cyclic_", "take_up_")) or not np.isfinite(v):
            continue
        moved = radial_size(k, d, radius)
        if moved >= MOVES_M and moved > radial_size(k, v, radius):
            out.append(k)
    if "servo_mismatch_angle" in out and "servo_mismatch" in terms:
        out.append("servo_mismatch")
    centre = [k for k in shift if k.startswith("centre_offset_")
              and np.isfinite(terms.get(k, (float("nan"),))[0])]
    if centre:
        moved = float(np.linalg.norm([shift[k] for k in centre]))
        if moved >= MOVES_M and moved > float(np.linalg.norm([terms[k][0] for k in centre])):
            out.append("centre_offset")
    return out


def unranked(diag) -> list:
    """The ranked terms' names (:attr:`CircleDiagnostics.ranking`'s) that :func:`sign_open`
    leaves out of the ranking, and the reversal spikes where none stands out of the
    noise [-]."""
    return [k for k in sign_open(diag.terms, diag.tail_shift, diag.radius)
            if not k.startswith("centre_offset_") and k != "servo_mismatch_angle"] + (
        ["reversal_spikes"] if diag.quiet_spikes else [])


def unranked_line(diag) -> str:
    """The terms left out of the ranking (:func:`unranked`), in words, a line for each
    reason; empty where none is [-]."""
    return "\n".join(unranked_lines(diag))


def unranked_sentences(diag) -> str:
    """:func:`unranked_line` as sentences, for a page; empty where none is [-]."""
    return " ".join(f"{line[0].upper()}{line[1:]}." for line in unranked_lines(diag))


def unranked_lines(diag) -> list:
    """The lines of :func:`unranked_line` [-]."""
    left = [k for k in unranked(diag) if k != "reversal_spikes"]
    lines = []
    if left:
        lines.append("not ranked: " + ", ".join(k.replace("_", " ") for k in left)
                     + ": fitted again with 40 deg after each reversal left out instead of "
                     "20, each moves by more than its own value (uncertain by the reversals' "
                     "tails), so these circles do not determine it, not even its sign")
    if diag.quiet_spikes:
        lines.append(f"not ranked: reversal spikes: {diag.quiet_spikes}")
    return lines


def moving_terms(diag) -> dict:
    """The terms of ``diag`` that move with the window (module docstring): ``term ->
    (value, value with the wider window)`` [SI]."""
    out = {}
    for term, delta in diag.tail_shift.items():
        value = diag.terms.get(term, (float("nan"),))[0]
        moved = radial_size(term, delta, diag.radius)
        if moved >= MOVES_M and moved >= MOVES_SHARE * radial_size(term, value, diag.radius):
            out[term] = (value, value + delta)
    if "servo_mismatch_angle" in out and "servo_mismatch" in diag.tail_shift:
        value = diag.terms["servo_mismatch"][0]
        out["servo_mismatch"] = (value, value + diag.tail_shift["servo_mismatch"])
    return out


def moving_line(diag) -> str:
    """The terms that move with the window after the reversals, in words and display
    units; empty where none does [-]."""
    moving = moving_terms(diag)
    if not moving:
        return ""
    items = [pair_text(diag, term, a, b, "->") for term, (a, b) in moving.items()]
    unfitted = sorted({t.replace("_", " ") for t in diag.undetermined
                       if not t.startswith(("cyclic_", "reversal_", "take_up_"))})
    also = (f", or an error the circles do not determine ({', '.join(unfitted)}) does"
            if unfitted else "")
    # the tails that fit as well were only tried where a tail was fitted, or where a
    # transient lasts past the window, up to one as long as the half turn
    alike = (", or with another tail past the window that fits the samples as well"
             if diag.tails in ("fitted", "open", "lingers") else "")
    if diag.tails == "lingers":
        alike += " (any up to the half turn to the axis' next reversal: see reversal tail)"
    return (f"uncertain by the reversals' tails: fitted again with {WIDER_DEG:.0f} deg after "
            f"each reversal left out instead of 20{alike}, " + ", ".join(items)
            + "; a transient lasting past the window, or an error the terms do not model "
            "there (a cyclic error not found), reads partly as these terms, and one lasting "
            f"past {WIDER_DEG:.0f} deg moves them further still" + also)


def pair_text(diag, term: str, a: float, b: float, sep: str) -> str:
    """``"<term> <a> <sep> <b> <unit>"`` of two values of a term in its display unit [-]."""
    shown, k = display_unit(term, diag.terms[term][1])
    n = display_digits(term, shown)
    return f"{term.replace('_', ' ')} {a * k:.{n}f} {sep} {b * k:.{n}f} {shown}"


def moving_ranked(diag) -> set:
    """The ranked terms (:attr:`CircleDiagnostics.ranking` names) that move with the window
    after the reversals (:func:`moving_terms`, :func:`ranked_names`) [-]."""
    return ranked_names(diag, moving_terms(diag))


def ranked_names(diag, reported) -> set:
    """The ranked terms (:attr:`CircleDiagnostics.ranking` names) of the ``reported`` term
    names: a centre offset where either of the plane's axes' is, a cyclic error by its
    amplitude, a squareness by either name [-]."""
    out = set()
    for r in diag.ranking:
        term = r["term"]
        names = {term, *(f"{term}_{a}" for a in diag.axes), f"{term}_angle",
                 f"{term}_or_servo"}
        if term.startswith("cyclic_"):
            names.add(term.replace("cyclic_", "cyclic_amplitude_"))
        if names & set(reported):
            out.add(term)
    return out
