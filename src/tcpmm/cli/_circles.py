"""Printing of the circular test and its diagnostics for ``tcpmm circle``."""

from __future__ import annotations

from ._app import out
from ._tables import fixed, plain_table, print_plain


def diagnostics_json(diag, result=None) -> dict:
    """The diagnostics in display units (um, ms, ...), with the terms not determined and
    why, what the reversals' tails are (``reversal_tails``), and the ranking; with the
    circles ``result`` they come from, each ranked term's G alone at the linear scale and
    where it lies, where the TCP's circles have the scale too [-]."""
    from ..analysis.circle_alias import alias_display, ranking_marks
    from ..analysis.circle_sigma import noisy_terms, shown_uncertainty
    from ..analysis.circle_tails import moving_terms, unranked

    at = _at_scale(diag, result)
    moving, noisy = moving_terms(diag), noisy_terms(diag)
    marks, legend = ranking_marks(diag)
    aliases = {left: {"per_unit": a["per"], "moves": {t: {"value": v, "unit": u}
                                                      for t, (v, u) in a["moves"].items()}}
               for left, a in alias_display(diag, ascii_units=True).items()}
    return {"sensor": diag.sensor, "directions": list(diag.directions),
            "terms": [{"term": t, "value": None if v != v else v, "unit": u,
                       "tail_shift": _shift(diag, t), "uncertain_by_tails": t in moving,
                       "uncertainty_95": _json_number(shown_uncertainty(diag, t)),
                       "uncertain_by_residual": t in noisy}
                      for t, v, u in _display_terms(diag, ascii_units=True)],
            "undetermined": dict(diag.undetermined),
            "reversal_tails": diag.tails or None,
            "aliases": aliases,
            "unranked": unranked(diag),
            "spikes_in_noise": diag.quiet_spikes or None,
            "ranking": [{"term": r["term"], "contribution_um": r["contribution_m"] * 1e6,
                         "g_alone_um": r["g_alone_m"] * 1e6,
                         "share_percent": _json_number(100.0 * r["share"]),
                         "percent_of_G": _json_number(100.0 * r["share_of_G"]),
                         "rank": r["rank"], "marks": marks[r["term"]].split(),
                         **_placed(r["term"], at)}
                        for r in diag.ranking],
            "marks": dict(m.split(": ", 1) for m in legend)}


def _shift(diag, term: str):
    """A term's change when the fit leaves 40 deg after each reversal out instead of 20,
    in its display unit; None where it is not computed [-]."""
    from ..analysis.circle_display import display_unit

    if term not in diag.tail_shift:
        return None
    return diag.tail_shift[term] * display_unit(term, diag.terms[term][1])[1]


def _at_scale(diag, result) -> dict | None:
    """Per ranked term, its G alone at the linear scale and where it lies
    (:func:`tcpmm.analysis.circle_display.placed_terms`, on
    :func:`tcpmm.analysis.circle_single.scale_diagnostics`); None without it [m, -]."""
    from ..analysis.circle_display import placed_terms
    from ..analysis.circle_single import scale_diagnostics

    reference = None if result is None else scale_diagnostics(diag, result)
    return placed_terms(diag, reference, "linear scale")


def _placed(term: str, at) -> dict:
    """The JSON fields of a ranked term at the linear scale: its G alone there and where
    it lies (None where that is not said); none for the centre offset or without the
    scale [-]."""
    if at is None or term == "centre_offset":
        return {}
    g_ref, where = at[term]
    return {"scale_g_alone_um": _json_number(g_ref * 1e6), "where": where or None}


def _json_number(v: float):
    """A number for JSON; NaN as None [-]."""
    return None if v != v else v


def _nan(v) -> float:
    """A JSON number back: None as NaN [-]."""
    return float("nan") if v is None else v


def _display_terms(diag, ascii_units=False):
    """``(term, value, unit)`` in the display units (µm, ms, µm/m, ppm, mm)."""
    from ..analysis.diagnostics import display_terms

    return display_terms(diag, ascii_units)


def _cell(v: float, digits: int = 2) -> str:
    return "n/a" if v != v else fixed(v, digits)


def print_passes(res, title: str) -> None:
    """Spikes A-D, the largest of their uncertainties, contour error and G per pass and
    sensor [µm], 80 columns wide."""
    from ..analysis.circle_display import pass_names
    from ..analysis.circle_spike_sigma import NOTE as SPIKE_U95_NOTE
    from ..analysis.circle_spike_sigma import largest, slow_line

    t = plain_table(("dir", "sensor", "A", "B", "C", "D", "±95%", "contour", "G"),
                    left=("dir", "sensor"))
    paired = any(s.after_pair for p in res.passes for s in p.sensors.values())
    names = pass_names(res.passes, paired)
    for p, name in zip(res.passes, names, strict=True):
        for row in p.table():
            t.add_row(name, row["sensor"],
                      *[_cell(row[f"spike_after_terms_{q}_um"]) for q in "ABCD"],
                      _cell(largest({q: row[f"spike_after_terms_{q}_uncertainty_95_um"]
                                     for q in "ABCD"})),
                      _cell(row["contour_error_um"]), _cell(row["circular_deviation_um"]))
    terms = ("the pair's terms (a CCW and a CW circle: also backlash, lateral play, "
             "straightness and cyclic error)" if paired else "the fitted terms (centre, "
             "radius, servo and scale mismatch, squareness)"
             + ("; an arc alone gives none (below)" if any(p.is_arc for p in res.passes)
                else ""))
    alone = ("; *: a circle the run pairs with none (the k-th CCW and CW circles are "
             "pairs): after its own terms, its spikes carry its backlash and lateral play"
             if any(n.endswith("*") for n in names) else "")
    print_plain(t, out, f"{title} [µm]", f"A-D: reversal spike after {terms}{alone}; n/a: "
                f"left out or not determined; ±95%: {SPIKE_U95_NOTE}; raw e - b in --json "
                "(spike_A_um ...); "
                "contour max |e| of the radial error about the nominal circle (tcpmm "
                "contour measures against the command); G circular deviation")
    slow = slow_line((f"{name} {n}", sc.spike_uncertainty(),
                      sc.spike_uncertainty(sample_noise=True))
                     for p, name in zip(res.passes, names, strict=True)
                     for n, sc in p.sensors.items())
    for line in [slow] if slow else []:
        out.print(line, highlight=False)
    for p in res.passes:
        for line in _pass_notes(p):
            out.print(line, highlight=False)


def _several(result) -> bool:
    """Whether ``result`` holds more than one circle of a direction [-]."""
    dirs = [p.direction for p in (result.passes if result is not None else [])]
    return dirs.count("ccw") > 1 or dirs.count("cw") > 1


def _pass_notes(p) -> list[str]:
    """What a reader should know of a pass: an arc, a command off the nominal radius."""
    notes = []
    if p.is_arc:
        alone = not any(s.after_pair for s in p.sensors.values())
        notes.append(f"{p.direction.upper()}: an arc of {p.arc_deg:.0f} deg (the run holds "
                     "no full circle); spikes only where it holds a quadrant point"
                     + ("; one direction over an arc (or a pair under 210 deg) gives no "
                        "terms, so no spike after them: the raw e - b, which carry the "
                        "terms, are in --json" if alone else ""))
    dev = p.command_radial_deviation * 1e6
    if abs(dev) >= 0.5:
        side = "inside" if dev < 0 else "outside"
        notes.append(f"{p.direction.upper()}: the command lies {abs(dev):.2f} µm {side} the "
                     "nominal radius (command_radial_deviation_um: a controller's filter "
                     "pulls a circle in, a radius offset moves it); the radial errors are "
                     "about the nominal radius")
    return notes


def print_diagnostics(diag, result=None) -> None:
    """The diagnostics: per direction, the terms with their signs, the terms ranked by
    what each contributes (with the circles ``result``, at the linear scale too), and what
    the circles leave undetermined and why."""
    from ..analysis.circle_alias import alias_line
    from ..analysis.circle_display import display_digits, undetermined_lines
    from ..analysis.circle_sigma import noise_line, shown_uncertainty
    from ..analysis.circle_tails import moving_line
    from ..analysis.diagnostics import term_note

    rows = {t: (v, u) for t, v, u in _display_terms(diag)}
    cols = [*diag.directions, *(("pair",) if len(diag.directions) == 2 else ())]
    t = plain_table(("", *(c.upper() if c != "pair" else c for c in cols)), left=("",))
    nan = (float("nan"),)
    for label, base in (("radial deviation", "radial_deviation"),
                        ("circularity G" + (", G(b)" if len(cols) == 3 else ""),
                         "circularity")):
        t.add_row(label, *[_cell(rows.get(f"{base}_{d}", nan)[0]) for d in cols])
    whose = "the pair's" if len(cols) == 3 else "its own (backlash among them)"
    for q in "ABCD":
        t.add_row(f"spike {q} after {whose} terms",
                  *[_with_pm(rows[f"spike_{q}_{d}"][0], shown_uncertainty(diag, f"spike_{q}_{d}"))
                    for d in diag.directions],
                  *([""] if len(cols) == 3 else []))
    which = ", of CCW 1 and CW 1" if len(cols) == 3 and _several(result) else ""
    print_plain(t, out, f"circle diagnostics ({diag.sensor}{which}) [µm]",
                "±: a spike's 95 % uncertainty (the terms', the take-up's and the tails')")
    t = plain_table(("term", "value", "±95%", "unit", "sign"),
                    left=("term", "unit", "sign"))
    for term, (v, u) in rows.items():
        if term.startswith(("radial_deviation", "circularity", "spike")):
            continue
        n = display_digits(term, u)
        pm = shown_uncertainty(diag, term)
        t.add_row(term.replace("_", " "), _cell(v, n), "" if pm != pm else _cell(pm, n), u,
                  term_note(term, diag.axes))
    print_plain(t, out, None, "±95%: 2 standard uncertainties from what the terms leave "
                "unexplained; the reversals' tails and the terms not determined may add to it "
                "(below, where they do)")
    for line in (moving_line(diag), noise_line(diag), alias_line(diag)):
        if line:
            out.print(line, highlight=False)
    _print_ranking(diag, result)
    for line in undetermined_lines(diag.undetermined):
        out.print(line, highlight=False)


def _with_pm(v: float, pm: float) -> str:
    """A value and, where it has one, its ±95%: ``3.39 ± 1.84`` [-]."""
    return _cell(v) if pm != pm or v != v else f"{_cell(v)} ± {_cell(pm)}"


def _print_ranking(diag, result=None) -> None:
    """The terms by the radial error each makes alone over the circle; with the circles
    ``result``, beside each its G alone at the linear scale and, for a term the scale sees
    less than half of, a mark that it lies past the scale."""
    from ..analysis.circle_tails import unranked_line

    g = "G(b)" if len(diag.directions) == 2 else "G"
    if not diag.ranking:  # an arc that gives no terms: nothing to rank, and it says why
        out.print(f"terms ranked by their share of {g}: none determined (below)",
                  highlight=False)
        if left := unranked_line(diag):
            out.print(left, highlight=False)
        return
    from ..analysis.circle_alias import ranking_marks
    from ..analysis.circle_display import beyond_g_note

    at = _at_scale(diag, result)
    scale = ("scale µm",) if at is not None else ()
    t = plain_table(("rank", "term", f"{g} alone µm", f"% {g}", "p-v µm", "share %", *scale),
                    left=("term",))
    marks, legend = ranking_marks(diag)
    for r in diag.ranking:
        placed = _placed(r["term"], at)
        mark = "*" if (placed.get("where") or "").startswith("mostly past") else ""
        name = r["term"].replace("_", " ") + marks[r["term"]]
        t.add_row(str(r["rank"]), name, _cell(r["g_alone_m"] * 1e6),
                  _cell(100 * r["share_of_G"], 1), _cell(r["contribution_m"] * 1e6),
                  _cell(100 * r["share"], 1),
                  *((_cell(_nan(placed["scale_g_alone_um"])) + mark if placed else "",)
                    if scale else ()))
    tails = "".join(f"; {m} (above)" for m in legend)
    beyond = beyond_g_note(diag.ranking, g)
    tails += f"; {beyond}" if beyond else ""
    print_plain(t, out, f"terms ranked by their share of {g}",
                f"{g} alone: the {g} the term's radial error alone makes; % {g}: of the "
                f"circles' {g}; p-v: its peak to valley about the nominal centre (a centre "
                f"offset makes no {g}: it shows in the contour error), share: of the sum "
                "of those" + tails + ("; scale: the term's G alone in the linear scale's "
                                      "circle, * where the scale sees less than half of it "
                                      "(a term above the residual rms): it lies past the "
                                      "scale, in the structure between the table and the "
                                      "tool, not in the drive" if scale else ""))
    if left := unranked_line(diag):
        out.print(left, highlight=False)


def circle_diagnostics_asked(res, pair: bool, asked: bool, sensor):
    """The diagnostics of the first pair of ``res``, the runs' passes together, where
    there are both directions or a second run (refused without), else of the one there is;
    errors raised where ``asked`` (a sensor or a plot of them)."""
    import warnings

    from ..analysis.circle_single import one_direction_diagnostics
    from ..analysis.diagnostics import circle_diagnostics
    from ..errors import InputError, InputWarning

    dirs = {p.direction for p in res.passes}
    diagnose = one_direction_diagnostics if len(dirs) == 1 and not pair else \
        circle_diagnostics
    if pair or asked:
        return diagnose(res, sensor=sensor)
    try:  # not asked for: the circle's table stands without them
        return diagnose(res, sensor=sensor) if dirs else None
    except InputError as exc:
        warnings.warn(f"no diagnostics: {exc.message}", InputWarning, stacklevel=2)
        return None
