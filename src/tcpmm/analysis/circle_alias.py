"""How the terms a circle's fit gives depend on the errors it cannot determine.

A term the circles do not determine (over 220 deg arcs from -20 deg, the bow of the first
axis and its lateral play; in one direction, the lateral play) is left out of the fit, and
so taken as 0. Where the machine has it all the same, the terms whose radial error shares
its shape take it over: over those arcs a bow of the first axis of 2.3 um reads as a scale
mismatch of 52 ppm, a lateral play of 1.4 um as a squareness of 8 um/m. The fit gives those
moves per unit of each left-out term (:func:`tcpmm.analysis.circle_model.alias_slopes`);
here they are named by the reported terms, and kept where a term's radial size moves by
:data:`ALIAS_SHARE` of the left-out term's own or more: those terms are then conditional on
the left-out one being 0, and by how much is said.
"""

from __future__ import annotations

import numpy as np

from .circle_display import DISPLAY_UNITS, partial_spikes, rename_axes
from .circle_sigma import noisy_ranked, zero_ranked
from .circle_tails import as_reported, moving_ranked, radial_size, ranked_names

#: A term depends on a left-out one where its radial size moves by this share of the
#: left-out term's radial size: a term not named moves by less than 0.1 um, the resolution
#: the terms are otherwise recovered to, under a left-out bow or play of 5 um [-].
ALIAS_SHARE = 0.02


def _reported_name(name: str, rename=None) -> str:
    """The reported name of a fitted column [-]."""
    if name.startswith("centre_"):
        return f"centre_offset_{name.split('_')[1]}"
    if name == "servo_angle":
        return "servo_mismatch_angle"
    return (rename or {}).get(name, name)


def _by_reported(aliases: dict, rename=None) -> dict:
    """``aliases`` by reported name, the slopes of columns reported as one added: each
    arc's centre is a column, and a centre offset moves them all (read one at a time, the
    pair's radial deviation moved by half of what each direction's did) [SI/SI]."""
    out = {}
    for left, slopes in aliases.items():
        acc = out.setdefault(_reported_name(left, rename), {})
        for k, v in slopes.items():
            acc[k] = acc.get(k, 0.0) + v
    return out


def alias_terms(fit, n_arcs, shared, terms, radius, axes, mean_rate=float("nan"),
                rename=None, unfitted=None) -> dict:
    """Per term the fit leaves out (:attr:`.circle_fit.TermFit.aliases`), by its reported
    name, the reported terms that depend on it (module docstring) and how much each moves
    per unit of it [SI/SI].

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
    radius : float
        Nominal radius [m].
    axes : tuple of str
        The plane's axes [-].
    mean_rate : float
        The circles' angular speed, for the servo mismatch as a time [rad/s].
    rename : dict, optional
        Fitted name -> reported name [-].
    unfitted : dict, optional
        Per axis the fitted columns' moves per unit of a cyclic error the arcs do not fit,
        one per period and phase (:func:`.circle_unfitted.cyclic_slopes`): each reported
        term's largest move over them, at ``cyclic_amplitude_<axis>`` [SI/m].
    """
    def moved_by(slopes):
        moved = as_reported(lambda n: slopes.get(n, 0.0), n_arcs, shared, mean_rate, rename)
        moved.update(_cyclic_moved(fit, slopes))
        moved.update(_deviations_moved(slopes, n_arcs, terms))
        return moved

    out = {}
    for name, slopes in _by_reported(fit.aliases, rename).items():
        _keep_moved(out, name, moved_by(slopes), terms, radius, axes)
    for axis, per_period in (unfitted or {}).items():
        moves = [moved_by(s) for s in per_period]
        pairs = list(zip(moves[::2], moves[1::2], strict=True))  # a period's sine, cosine
        worst = {t: max(float(np.hypot(s[t], c[t])) for s, c in pairs) for t in moves[0]}
        _keep_moved(out, f"cyclic_amplitude_{axis}", worst, terms, radius, axes)
    return out


def _keep_moved(out: dict, name: str, moved: dict, terms: dict, radius: float, axes) -> None:
    """Put in ``out`` under the left-out term ``name`` the reported terms it ``moved`` by
    :data:`ALIAS_SHARE` of its own radial size or more (module docstring) [SI/SI]."""
    per = radial_size(name, 1.0, radius)  # a unit of the left-out term, radially
    big = {t: v for t, v in moved.items()
           if t != name and t in terms and np.isfinite(terms[t][0]) and np.isfinite(v)
           and radial_size(t, v, radius) >= ALIAS_SHARE * per}
    big.update(_spikes_moved(name, moved, terms, ALIAS_SHARE * per))
    if "servo_mismatch_angle" in big and np.isfinite(moved["servo_mismatch"]):
        # said as a time, as the terms give it, where the angular speed is known
        big["servo_mismatch"] = moved["servo_mismatch"]
        del big["servo_mismatch_angle"]
    if big:
        out.setdefault(rename_axes(name, axes), {}).update(
            {rename_axes(t, axes): float(v) for t, v in big.items()})


def _deviations_moved(slopes: dict, n_arcs: int, terms: dict) -> dict:
    """How far each arc's radial deviation, and the pair's, moves per unit of a left-out
    term: its radius' slope. Over an arc the radius takes the mean of what the terms left
    out make along it (a centre offset, the servo's ellipse), which over a full turn is
    none [m/SI]."""
    names = [k for k in terms if k.startswith("radial_deviation_")
             and k != "radial_deviation_pair"][:n_arcs]
    out = {k: slopes.get(f"radius_{i}", 0.0) for i, k in enumerate(names)}
    if "radial_deviation_pair" in terms and len(out) == 2:
        out["radial_deviation_pair"] = float(np.mean(list(out.values())))
    return out


def _cyclic_moved(fit, slopes: dict) -> dict:
    """Per axis with a cyclic error found, how far its amplitude moves per unit of a
    left-out term: the length of its sine's and cosine's slopes, at most what a term
    that makes the cyclic error alone moves it by (a step at the reversals of one
    direction's lateral play has harmonics the cyclic scan takes for one) [m/SI]."""
    return {f"cyclic_amplitude_{axis}": float(np.hypot(slopes.get(f"cyclic_sin_{axis}", 0.0),
                                                       slopes.get(f"cyclic_cos_{axis}", 0.0)))
            for axis, k in zip("XY", fit.waves, strict=True) if k is not None}


#: Terms that step at a reversal: the spikes after the terms are what is left of the
#: step there, so a change of theirs is a change of the spikes [-].
_STEPS = ("backlash_", "lateral_play_")


def _spikes_moved(left: str, moved: dict, terms: dict, least: float) -> dict:
    """``{"reversal_spikes": change per unit}`` where the spikes after the terms depend on
    the left-out term ``left``: it steps at a reversal itself (one direction's lateral
    play), or moves a term that does by ``least`` or more; empty otherwise [m/SI]."""
    if not any(k.startswith("spike_") and np.isfinite(v) for k, (v, _) in terms.items()):
        return {}
    steps = [abs(v) for t, v in moved.items() if t.startswith(_STEPS) and t != left
             and np.isfinite(v)]
    size = 1.0 if left.startswith(_STEPS) else max(steps, default=0.0)
    return {"reversal_spikes": size} if size >= least else {}


def alias_display(diag, ascii_units: bool = False) -> dict:
    """:attr:`CircleDiagnostics.aliases` in display units: ``left-out term -> {"per": its
    unit, "moves": {term: (change per that unit, unit)}}`` (``u`` for ``µ`` with
    ``ascii_units``) [-]."""
    def unit(u):
        shown = DISPLAY_UNITS[u]
        return (shown[0].replace("µ", "u") if ascii_units else shown[0]), shown[1]

    out = {}
    for left, moves in diag.aliases.items():
        per, k_left = unit(diag.terms.get(left, (0.0, "m"))[1])
        out[left] = {"per": per, "moves": {}}
        for term, slope in moves.items():
            shown, k = unit(diag.terms.get(term, (0.0, "m"))[1])  # the spikes: a length
            out[left]["moves"][term] = (slope * k / k_left, shown)
    return out


def alias_line(diag) -> str:
    """The terms that depend on what the circles do not determine, in words and display
    units; empty where none does [-]."""
    parts = []
    for left, shown in alias_display(diag).items():
        # a cyclic error's move is its largest over the periods and phases: either sign
        cyclic = left.startswith("cyclic_")
        items = [f"{t.replace('_', ' ')} {_move(v, u, cyclic)} {u}"
                 for t, (v, u) in shown["moves"].items()]
        parts.append(f"per {shown['per']} of {left.replace('_', ' ')}"
                     + (" (any period the scan of a full circle searches)" if cyclic else "")
                     + ", " + ", ".join(items))
    if not parts:
        return ""
    return ("conditional on what the circles do not determine, taken as 0: "
            + "; ".join(parts) + " (where the machine has it, these terms carry it; what "
            "would determine it is said with why it is not determined)")


def _move(value: float, unit: str, largest: bool) -> str:
    """A move per unit of a left-out term in display digits: signed, or where it is the
    ``largest`` over periods and phases, ``up to ±`` its size [-]."""
    n = 4 if unit == "ms" else 2
    return f"up to ±{abs(value):.{n}f}" if largest else f"{value:+.{n}f}"


def aliased_ranked(diag) -> set:
    """The ranked terms that depend on a term the circles do not determine [-]."""
    return ranked_names(diag, {t for moves in diag.aliases.values() for t in moves})


#: The ranking's marks: of a term that moves with the window after the reversals
#: (:func:`.circle_tails.moving_ranked`), of one what the terms leave unexplained leaves
#: short of the tolerance (:func:`.circle_sigma.noisy_ranked`), of one conditional on a
#: term the circles do not determine (:func:`aliased_ranked`), of one within its ±95% of
#: zero (:func:`.circle_sigma.zero_ranked`); and what each means [-]
MARKS = (("~", "uncertain by the reversals' tails"),
         ("±", "uncertain by what the terms leave unexplained"),
         ("?", "conditional on a term the circles do not determine"),
         ("≥", "at least: the largest of the spikes after the terms that are given, "
               "others n/a"),
         ("0", "within its ±95% of zero: not told from no error"))


def ranking_marks(diag) -> tuple[dict, list]:
    """Per ranked term its marks (``" ~ ?"``, empty for none), and what each mark used
    means (:data:`MARKS`) [-]."""
    marked = (moving_ranked(diag), noisy_ranked(diag), aliased_ranked(diag),
              partial_spikes(diag), zero_ranked(diag))
    marks = {r["term"]: "".join(f" {m}" for (m, _), terms in zip(MARKS, marked, strict=True)
                                if r["term"] in terms) for r in diag.ranking}
    return marks, [f"{m}: {what}" for (m, what), terms in zip(MARKS, marked, strict=True)
                   if terms]
