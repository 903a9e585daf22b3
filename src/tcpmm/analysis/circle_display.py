"""Circle diagnostics for a reader: display units, what the sign of each term means, and
the terms ranked by what they contribute to the circle's form."""

from __future__ import annotations

import math

#: SI unit -> (display unit, factor); the cyclic periods are shown in mm
DISPLAY_UNITS = {"m": ("µm", 1e6), "s": ("ms", 1e3), "m/m": ("µm/m", 1e6), "-": ("ppm", 1e6),
                 "rad": ("µrad", 1e6)}


def display_unit(term: str, unit: str) -> tuple[str, float]:
    """``(display unit, factor)`` of a term of SI unit ``unit``: :data:`DISPLAY_UNITS`, mm
    for the cyclic periods [-]."""
    return ("mm", 1e3) if term.startswith("cyclic_period") else DISPLAY_UNITS[unit]


def display_digits(term: str, shown: str) -> int:
    """Decimals of a term in its display unit ``shown``: a servo mismatch in ms is read to
    microseconds, the reversals' tails' time constant to tenths of a millisecond (its
    interval spans milliseconds), the rest to hundredths [-]."""
    if term == "reversal_tail_decay":
        return 1
    return 3 if shown == "ms" else 2

#: What the sign of a term means, by term name or its name without the axis; ``{a}`` and
#: ``{b}`` stand for the plane's first and second axis
TERM_NOTES = {"hysteresis": "largest CCW-CW radial difference",
              "centre_offset": "circle centre - nominal",
              "backlash": "+: radius steps out at reversal",
              "take_up_width": "= backlash: dead band; 0: step",
              "lateral_play_{a}": "+: moving +{a} shifts {a} to +{b}",
              "lateral_play_{b}": "+: moving +{b} shifts {b} to +{a}",
              "servo_mismatch": "+: {b} lags {a}",
              "squareness": "+: angle +{a} to +{b} over 90 deg",
              "squareness_or_servo": "+: radius short at 45 deg",
              "scale_mismatch": "+: {a} travels further than {b}",
              "straightness_{a}": "+: {a} bows to +{b} mid-travel",
              "straightness_{b}": "+: {b} bows to +{a} mid-travel",
              # n/a: none stood out of what the other terms leave (its residual rms)
              "cyclic_amplitude": "e.g. pitch error; n/a: unresolved",
              "command_radial_deviation": "command radius - nominal",
              "reversal_tail": "+: radius out past the window",
              "reversal_tail_decay": "the tails' time constant",
              "residual_rms": "what the terms leave unexplained"}


def display_terms(diag, ascii_units: bool = False) -> list[tuple]:
    """``(term, value, unit)`` of the diagnostics in display units: µm, ms, µm/m, ppm,
    µrad, and mm for the cyclic periods.

    Parameters
    ----------
    diag : CircleDiagnostics
        The diagnostics [SI].
    ascii_units : bool
        Write µ as u [-].
    """
    rows = []
    for term, (value, unit) in diag.terms.items():
        shown, k = display_unit(term, unit)
        rows.append((term, value * k, shown.replace("µ", "u") if ascii_units else shown))
    return rows


def term_note(term: str, axes=("X", "Y")) -> str:
    """What the sign of a diagnostics term means; empty when nothing needs saying [-].

    Parameters
    ----------
    term : str
        Term name, e.g. ``lateral_play_Z`` [-].
    axes : tuple of str
        The plane's first and second axis (``CircleDiagnostics.axes``) [-].
    """
    a, b = axes
    notes = {k.format(a=a, b=b): v.format(a=a, b=b) for k, v in TERM_NOTES.items()}
    return notes.get(term) or notes.get(term.rsplit("_", 1)[0], "")


def rename_axes(term: str, axes) -> str:
    """A term's name with the plane's axes for X and Y, e.g. ``backlash_Z`` [-].

    Parameters
    ----------
    term : str
        Name with the axis last as ``_X`` or ``_Y`` where it has one [-].
    axes : tuple of str
        The plane's first and second axis [-].
    """
    names = {"X": axes[0], "Y": axes[1]}
    return term[:-1] + names[term[-1]] if term[-2:] in ("_X", "_Y") else term


#: A circular deviation below this is none to share out: a circle of no error, where a
#: term's share of G would be a ratio of roundings [m].
G_RESOLUTION_M = 1e-9


def ranking_rows(contributions: dict, g: float = float("nan")) -> list[dict]:
    """The terms ranked by the G each makes alone, largest first (the contribution breaks
    a tie): ``term``, ``contribution_m``, the peak-to-valley radial error it makes alone
    about the nominal centre [m], ``g_alone_m``, the G it alone makes (0 for the centre
    offset) [m], ``share`` of the sum of the contributions [-], ``share_of_G``, the G it
    alone makes over the circular deviation G [-], and ``rank`` (1 the largest) [-].

    Parameters
    ----------
    contributions : dict of str to (float, float)
        Per term the contribution and the G it alone makes; NaN for a term not determined,
        which is left out [m].
    g : float
        Circular deviation: G(b) of a pair, G of one direction [m].
    """
    have = {k: (float(c), float(a)) for k, (c, a) in contributions.items() if c == c}
    total = sum(c for c, _ in have.values())
    order = sorted(have, key=lambda k: (-have[k][1], -have[k][0]))
    big = g >= G_RESOLUTION_M
    return [{"term": k, "contribution_m": have[k][0], "g_alone_m": have[k][1],
             "share": have[k][0] / total if total > G_RESOLUTION_M else float("nan"),
             "share_of_G": have[k][1] / g if big else float("nan"), "rank": i + 1}
            for i, k in enumerate(order)]


def beyond_g_note(ranking, g_name: str = "G") -> str:
    """Why a term's share of G is above 100 %, where one is: the G a term alone makes is
    more than the circles' where the other terms cancel part of it; empty otherwise [-].

    Parameters
    ----------
    ranking : list of dict
        :func:`ranking_rows` [-].
    g_name : str
        What G is called: ``G(b)`` of a pair [-].
    """
    over = [r["term"].replace("_", " ") for r in ranking if r["share_of_G"] > 1.0]
    if not over:
        return ""
    return (f"{', '.join(over)} alone make{'s' if len(over) == 1 else ''} more {g_name} than "
            f"the circles: the other terms cancel part of {'it' if len(over) == 1 else 'them'}"
            f", so over 100 % of {g_name} is no error")


def undetermined_lines(undetermined: dict) -> list[str]:
    """What the circles leave open, a line per reason: the terms of one reason named
    together (an arc that gives none of its terms gave the same sentence for each) [-]."""
    by = {}
    for term, why in undetermined.items():
        by.setdefault(why, []).append(term.replace("_", " "))
    return [f"{', '.join(terms)}: not determined; {why}" for why, terms in by.items()]


#: The coverage factor of the uncertainty shown: about 95 % for a normal scatter [-]
COVERAGE = 2.0


#: the part of a term's G at the tool that a sensor nearer the drive must see for the
#: term to be called the axis' own [-]
SHARED_PART = 0.5


#: Terms of the geometry between the axes, which a sensor reading its own axis cannot see:
#: where such a term shows in its circle, it is the loops' response to the path [-].
_GEOMETRY = ("scale_mismatch", "squareness", "squareness_or_servo")


def term_place(g: float, g_ref: float, sensor_name: str, term: str = "") -> str:
    """Where a term of G ``g`` at the tool lies, given the G ``g_ref`` the same term makes
    in the circle of a sensor nearer the drive (the linear scale): what that sensor does
    not see of it happened between the sensor and the tool; "" for a term of no G [-].

    Parameters
    ----------
    g : float
        The G the term alone makes at the tool [m].
    g_ref : float
        The G it alone makes at the other sensor [m].
    sensor_name : str
        That sensor, in words ("linear scale") [-].
    term : str, optional
        The term's name: a term of the geometry between the axes (scale mismatch,
        squareness) that the sensor sees too is the servo's, not the geometry's [-].
    """
    if not g > 0.0:
        return ""
    if g_ref < SHARED_PART * g and term in _GEOMETRY:
        return (f"mostly past the {sensor_name}: the geometry between the axes, or the "
                "structure between the table and the tool deflecting with the path's "
                "acceleration; a circle at a lower feed tells them apart (the geometry "
                "stays)")
    if g_ref < SHARED_PART * g:
        return (f"mostly past the {sensor_name}: the structure between the table and the "
                "tool (deflection, ringing), not the drive")
    if term in _GEOMETRY:
        return (f"at the {sensor_name} too: the loops' response, not the geometry (the "
                f"{sensor_name} reads its own axis and cannot see the angle or the scale "
                "between two): a dynamic error, it changes with the feed")
    return f"at the {sensor_name} too: in the axis"


def placed_terms(diag, reference, sensor_name: str) -> dict | None:
    """Per term ranked in ``diag`` (a TCP's diagnostics), the G it alone makes in
    ``reference``'s (the same circles at a sensor nearer the drive) [m] and where it lies
    (:func:`term_place`; "" for the centre offset, a set-up, and for a term within the
    residual rms of ``diag``, whose G at either sensor is as much the residual's as its
    own); None without ``reference``. NaN, and not determined there, for a term
    ``reference`` leaves open, and for spikes of which it gives some too few to tell. A
    term whose ±95% is not known at either sensor is not placed: a G of no known
    uncertainty may lie on either side of half.

    Parameters
    ----------
    diag, reference : CircleDiagnostics
        The diagnostics at the tool and at the other sensor [SI].
    sensor_name : str
        The other sensor, in words ("linear scale") [-].
    """
    if reference is None:
        return None
    # a term the other sensor's circles leave open is not ranked there: not a G of 0
    at = {r["term"]: float(r["g_alone_m"]) for r in reference.ranking}
    floor = diag["residual_rms"] if "residual_rms" in diag.terms else 0.0
    out, partial = {}, partial_spikes(reference)
    for r in diag.ranking:
        term, g = r["term"], float(r["g_alone_m"])
        g_ref = at.get(term, float("nan"))
        if term in partial and g_ref < SHARED_PART * g:
            g_ref = float("nan")  # the largest of some spikes: the others may pass it
        placed = term != "centre_offset" and g > floor
        # each G within its ±95% (per unit of the term, the tool's): placed where all agree
        k, u = g_spread(diag, term, g)
        lo, hi, u_ref = g - k * u, g + k * u, k * g_spread(reference, term, g_ref)[1]
        where = (f"not determined at the {sensor_name}" if g_ref != g_ref else
                 _not_known(term, sensor_name) if not math.isfinite(u + u_ref) else
                 term_place(lo, g_ref + u_ref, sensor_name, term)
                 if g_ref + u_ref < SHARED_PART * lo else
                 term_place(hi, g_ref - u_ref, sensor_name, term)
                 if g_ref - u_ref >= SHARED_PART * hi else
                 f"not placed: within their ±95% the {sensor_name}'s circles may see less or "
                 "more than half of it")
        out[term] = (g_ref, where if placed else "")
    return out


def _not_known(term: str, sensor_name: str) -> str:
    """Where a ranked term's ±95% is not known at the tool or at ``sensor_name``: a G
    within its noise may lie on either side of half, so no place is said [-]."""
    why = (" (one direction alone gives its spikes after its own terms none; a CCW and a "
           "CW circle do)" if term == "reversal_spikes" else "")
    return (f"not placed: its ±95% is not known{why}, so whether the {sensor_name}'s "
            "circles see less or more than half of it is not told")


def g_spread(diag, term: str, g: float) -> tuple[float, float]:
    """``(G per unit, ±95%)`` of a ranked term of ``diag`` whose G alone is ``g``: two
    standard uncertainties from what the terms leave (:mod:`.circle_sigma`), for the
    reversal spikes the ranked spike's own ±95% (G per unit 1); a ±95% of NaN where none is
    estimated (one direction's spikes after its own terms) [m/unit, unit]."""
    if term == "reversal_spikes":
        given = [(abs(v), diag.spike_u95.get(k, float("nan")))
                 for k, (v, _) in diag.terms.items() if k.startswith("spike_") and v == v]
        return 1.0, max(given)[1] if given else float("nan")
    name = f"cyclic_amplitude_{term[-1]}" if term.startswith("cyclic_") else term
    value = diag.terms.get(name, (float("nan"),))[0]
    sigma = diag.sigma.get(name, float("nan"))
    k = g / abs(value) if value == value and value != 0 and g == g else 0.0
    return k, COVERAGE * sigma


def partial_spikes(diag) -> set:
    """``{"reversal_spikes"}`` where some spikes after the terms are n/a and some are not:
    the size ranked is then the largest of those given, no bound on the others [-]."""
    values = [v for k, (v, _) in diag.terms.items() if k.startswith("spike_")]
    given = sum(v == v for v in values)
    return {"reversal_spikes"} if 0 < given < len(values) else set()


def pass_names(passes, paired: bool | None = None) -> list[str]:
    """Each pass's name in a table: its direction, numbered where the run has more than
    one in it ("CCW 2"), and marked "*" where others are paired and it is not; ``paired``
    whether any is, found from the passes where not given [-]."""
    if paired is None:
        paired = any(s.after_pair for p in passes for s in p.sensors.values())
    count = {d: sum(p.direction == d for p in passes) for d in ("ccw", "cw")}
    seen = {"ccw": 0, "cw": 0}
    out = []
    for p in passes:
        seen[p.direction] += 1
        name = p.direction.upper() + (f" {seen[p.direction]}" if count[p.direction] > 1 else "")
        alone = paired and not any(s.after_pair for s in p.sensors.values())
        out.append(name + ("*" if alone else ""))
    return out
