"""Report sections on tests run on the machine: circles, measured against predicted, and
any analysis that has a table and a plot (the contour error of a program run, for one); the
spread of a prediction is in :mod:`.spread`."""

from __future__ import annotations

from pathlib import Path

from ..analysis.circle_alias import alias_line
from ..analysis.circle_display import display_digits, pass_names, undetermined_lines
from ..analysis.circle_sigma import noise_line, shown_uncertainty
from ..analysis.circle_spike_sigma import is_slow
from ..analysis.circle_tails import moving_line, sign_open, unranked_sentences
from ..analysis.compare import raw_spike_named
from ..analysis.diagnostics import PREFERRED_SENSORS, display_terms, term_note
from ..plot.circle import plot_circle
from .circle_columns import SENSOR_NAMES, um_columns
from .html import esc, facts, figure, number, para, section, table

#: Diagnostics shown per direction in the first table rather than among the terms.
_PER_DIRECTION = ("radial_deviation", "circularity", "spike")


def circle_section(result, key: str, title: str, diagnostics=None, source=None):
    """A circular test: polar plot with µm rings, per-sensor table and, for a CCW and a CW
    circle, the diagnostics.

    Parameters
    ----------
    result : CircleResult
        The analysis [-].
    key : str
        Section anchor, ``circle-...`` [-].
    title : str
        Section title [-].
    diagnostics : CircleDiagnostics, optional
        Diagnostics of the CCW and CW circle [-].
    source : str or list of str, optional
        The run file or files, for the record [-].
    """
    body = para(f"Nominal radius {result.radius * 1e3:g} mm about "
                f"({result.centre[0] * 1e3:g}, {result.centre[1] * 1e3:g}) mm"
                + (f", run {file_names(source)}" if source else "")
                + f". Spikes A-D: reversal spikes at 0, 90, 180, 270 deg after {_whose(result)}"
                  " (n/a: the pass does not hold the point's windows, as where a circle "
                  "starts or ends there or an arc does not reach it); raw spikes: the radial "
                  "error's own step, which those terms enter; contour "
                  "error: largest |radial error|; G: circular deviation about the "
                  "least-squares centre (ISO 230-4)"
                + "".join(f"; the {p.direction.upper()} pass is an arc of {p.arc_deg:.0f} deg"
                          for p in result.passes if p.is_arc) + ".", "lead")
    body += key_figures(result, diagnostics)
    body += figure(result_plot(result), "circle plot",
                   "radial error magnified about the nominal circle; the dotted rings are "
                   "whole steps of radial error, labelled in µm")
    stem = key.replace("circle-", "circle_") if key != "circle" else "circle"
    body += table(um_columns(result.to_pandas()), f"{stem}.csv")
    if diagnostics is not None:
        body += diagnostics_html(diagnostics, stem)
    return section(key, title, body)


def key_figures(result, diag=None) -> str:
    """What a reader looks at first: per pass G, contour error and the largest spike of the
    best sensor there is; with diagnostics, backlash, squareness, scale and servo mismatch
    and G(b) [-]."""
    sensor = next((s for s in PREFERRED_SENSORS if all(s in p.sensors for p in result.passes)),
                  None)
    if sensor is None:
        return ""
    items = []
    for p, name in zip(result.passes, pass_names(result.passes), strict=True):
        sc = p.sensors[sensor]
        spikes = {q: v for q, v in sc.spikes_after_terms().items() if v == v}
        text = (f"G {number(sc.circular_deviation * 1e6, 2)} µm, contour error "
                f"{number(sc.contour_error * 1e6, 2)} µm")
        if spikes:
            q = max(spikes, key=lambda k: abs(spikes[k]))
            whose = ("the pair's" if sc.after_pair else "its own (paired with no circle: "
                     "backlash among them)" if name.endswith("*") else "the fitted")
            u, fast = sc.spike_uncertainty()[q], sc.spike_uncertainty(sample_noise=True)[q]
            text += (f", largest reversal spike after {whose} terms "
                     f"{number(spikes[q] * 1e6, 2)} ± {number(u * 1e6, 2)} µm (95 %) at {q}"
                     + _of_those(spikes, sc.spikes_after_terms()))
            if is_slow(u, fast):
                text += (" (the ± counts what the terms leave before the points as noise; "
                         "from sample to sample alone, the terms as they are, ± "
                         f"{number(fast * 1e6, 2)} µm at {q})")
        elif (diag is not None and diag.sensor == sensor
              and "reversal_spikes" in diag.undetermined):
            whose = ("the pair's terms not determined by these circles"
                     if len(diag.directions) == 2 else
                     "its own terms (backlash among them) not determined")
            text += f", reversal spikes after {whose} (diagnostics: reversal spikes)"
        if p.is_arc:
            text += f"; an arc of {p.arc_deg:.0f} deg"
        dev = p.command_radial_deviation
        if abs(dev) >= 0.5e-6:
            text += (f"; the command lies {number(abs(dev) * 1e6, 2)} µm "
                     f"{'inside' if dev < 0 else 'outside'} the nominal radius")
        items.append((f"{name} ({SENSOR_NAMES.get(sensor, sensor)})", text))
    if diag is not None and len(diag.directions) == 2:
        t = {k: _with_pm(diag, k, v, u) for k, v, u in display_terms(diag)}
        x, y = diag.axes
        items += [("backlash", f"{x} {t[f'backlash_{x}']}, {y} {t[f'backlash_{y}']}"),
                  *((label, t[k]) for k, label in (
                      ("squareness", "squareness"), ("scale_mismatch", "scale mismatch"),
                      ("servo_mismatch", "servo mismatch"), ("circularity_pair", "G(b)")))]
    return facts(items)


def _with_pm(diag, term: str, value: float, unit: str) -> str:
    """A term in its display unit and digits, with its ±95% where one is estimated (the
    table of terms below gives the same); n/a where it has no value [-]."""
    if value != value:
        return "n/a"
    n = display_digits(term, unit)
    pm = shown_uncertainty(diag, term)
    text = f"{number(value, n)}" + ("" if pm != pm else f" ± {number(pm, n)}") + f" {unit}"
    # a term the tails leave open in sign is said so where its value is shown
    if term in sign_open(diag.terms, diag.tail_shift, diag.radius):
        text += " (not determined, not even its sign: see the terms not ranked)"
    return text


def _of_those(shown: dict, every: dict) -> str:
    """Where some points' spikes are n/a, which the largest is of: the largest of those
    given is no bound on the others [-]."""
    missing = [q for q in every if q not in shown]
    if not missing:
        return ""
    return (f", the largest of {', '.join(shown)}; {', '.join(missing)} n/a (left out or not "
            "determined: see the table and the diagnostics)")


def file_names(files) -> str:
    """File names joined: a path by its name without its folders, text as given (a name
    made unique among the report's files by :func:`distinct_names`) [-]."""
    files = [files] if isinstance(files, str | Path) else files
    return " and ".join(f.name if isinstance(f, Path) else str(f) for f in files)



def result_plot(result, overlay=None):
    """The polar plot of a circular test, with a prediction drawn over it [-]."""
    if overlay is None:
        return plot_circle(result)
    return plot_circle(result, sensors=["tcp"], overlay=overlay)


def diagnostics_html(diag, stem: str) -> str:
    """Circle diagnostics: radial error with the fitted terms, per-direction figures, the
    terms with units and sign conventions, their ranking and what is left undetermined
    [-]."""
    import pandas as pd

    rows = {t: (v, u) for t, v, u in display_terms(diag)}
    dirs = diag.directions
    cols = {d: f"{d.upper()} [µm]" for d in dirs}
    if len(dirs) == 2:
        cols["pair"] = "pair [µm]"
    nan = (float("nan"),)
    per = [{"figure": label, **{c: rows.get(f"{base}_{d}", nan)[0] for d, c in cols.items()}}
           for base, label in (("radial_deviation", "radial deviation"),
                               ("circularity", "circularity G, G(b)"))]
    # after the terms of this fit (with two directions, the pair's; with one, backlash
    # among them, which the circle table's own fit leaves in: its spikes differ)
    after = ("after the pair's terms" if len(dirs) == 2 else
             "after this direction's terms, backlash among them")
    per += [{"figure": f"reversal spike {q} ({after})",
             **{c: rows.get(f"spike_{q}_{d}", nan)[0] for d, c in cols.items()}}
            for q in "ABCD"]
    terms = pd.DataFrame([{"term": t.replace("_", " "), "value": v,
                           "±95%": shown_uncertainty(diag, t), "unit": u,
                           "sign": term_note(t, diag.axes)}
                          for t, (v, u) in rows.items() if not t.startswith(_PER_DIRECTION)])
    what = ("The CCW and the CW circle fitted together" if len(dirs) == 2 else
            f"The {dirs[0].upper()} circle alone fitted")
    alone = "" if len(dirs) == 2 else f" of the {dirs[0].upper()} circle alone"
    return (f"<h3>Diagnostics{alone} ({esc(SENSOR_NAMES.get(diag.sensor, diag.sensor))})</h3>"
            + para(f"{what} to the usual ballbar error terms; the 20 deg after each "
                   "quadrant point are left out of the fit.")
            + figure(diag.plot(), "circle diagnostics plot",
                     "radial error of the circles (dots) and the fitted terms (lines)")
            + table(pd.DataFrame(per), f"{stem}_diagnostics_per_direction.csv")
            + table(terms, f"{stem}_diagnostics.csv", digits={"value": 3, "±95%": 3})
            + ranking_html(diag, stem) + undetermined_html(diag))


def ranking_html(diag, stem: str) -> str:
    """The terms ranked by the radial error each makes alone [-]."""
    import pandas as pd

    if not diag.ranking:
        left = unranked_sentences(diag)
        return para(f"No term is ranked. {left}", "warn") if left else ""
    from ..analysis.circle_alias import ranking_marks
    from ..analysis.circle_display import beyond_g_note

    marks, legend = ranking_marks(diag)
    beyond = beyond_g_note(diag.ranking, "G(b)" if len(diag.directions) == 2 else "G")
    frame = pd.DataFrame([{"rank": r["rank"], "term": r["term"].replace("_", " ")
                           + marks[r["term"]],
                           "G alone [µm]": r["g_alone_m"] * 1e6,
                           "of G [%]": 100 * r["share_of_G"],
                           "peak to valley [µm]": r["contribution_m"] * 1e6,
                           "share [%]": 100 * r["share"]} for r in diag.ranking])
    return (para("Terms ranked by their share of G (G(b) of a pair): the G the radial error "
                 "of each alone makes, about its own least-squares centre, and what of the "
                 "circles' G that is; then its peak to valley about the nominal centre (a "
                 "centre offset makes no G: it shows in the contour error) and its share of "
                 "the sum of those." + "".join(f" {m} (below)." for m in legend)
                 + (f" {beyond[0].upper()}{beyond[1:]}." if beyond else ""))
            + table(frame, f"{stem}_diagnostics_ranking.csv",
                    digits={"share [%]": 1, "of G [%]": 1})
            + (para(left, "warn") if (left := unranked_sentences(diag)) else ""))


def undetermined_html(diag) -> str:
    """Terms not determined and why; terms the tails or the residual make uncertain [-]."""
    lines = [line for line in (moving_line(diag), noise_line(diag), alias_line(diag)) if line]
    lines += undetermined_lines(diag.undetermined)
    return "".join(para(f"{line}.", "warn") for line in lines)


def comparison_section(comparison, measured=None, predicted=None, sources=(),
                       key: str = "comparison", judged=None):
    """Measured minus predicted (the paper's Table 2), with the two circles overlaid.

    Parameters
    ----------
    comparison : Comparison
        :func:`tcpmm.analysis.compare.compare_circles` [-].
    measured, predicted : CircleResult, optional
        The two analyses, for the overlay plot [-].
    sources : tuple of str
        The measured and the predicted run file, for the record [-].
    key : str
        Section anchor, ``comparison-...`` when there are several [-].
    judged : pandas.DataFrame, optional
        The TCP differences against the prediction's 90 % intervals, one row per direction
        and figure (``tcpmm.demo.judged_table2``) [um].
    """
    files = file_names(sources).replace(" and ", " against ")
    body = para("Reversal spikes A-D and contour error of the measured run minus those of "
                "the prediction, per direction and sensor; radial rms and max: point by "
                "point difference of the radial error over the circle."
                + (f" Runs: {files}." if files else ""), "lead")
    if measured is not None and predicted is not None:
        body += figure(result_plot(measured, predicted), "measured and predicted circles",
                       "measured TCP (blue) and predicted TCP (orange dashed)")
    body += table(um_columns(comparison.to_pandas()),
                  f"measured_minus_predicted{key[len('comparison'):].replace('-', '_')}.csv")
    for line in comparison.notes():
        body += para(line)
    if judged is not None and not hasattr(judged, "columns"):  # the rows, as judged_long
        import pandas as pd

        judged = pd.DataFrame(judged)
    if judged is not None and len(judged):
        body += ("<h3>At the TCP, against the prediction's 90 % interval</h3>"
                 + para("Each difference beside the half-width of the predicted figure's 90 % "
                        "interval and its verdict (firm, uncertain or undetermined, from what "
                        "the identification data leave open).")
                 + table(_judged_columns(judged),
                         f"table2_judged{key[len('comparison'):].replace('-', '_')}.csv"))
    return section(key, comparison_title(comparison, sources), body)


def comparison_title(comparison, sources=()) -> str:
    """Title of a comparison's section: its directions and the measured run, so that the
    sections of two pairs (a CCW and a CW circle) are told apart [-]."""
    seen = [r.get("direction", "").upper() for r in comparison.rows]
    named = [" and ".join(dict.fromkeys(d for d in seen if d))]
    if len(sources):
        named.append(file_names(sources[0]))
    named = " of ".join(n for n in named if n)
    return "Measured − predicted (Table 2)" + (f": {named}" if named else "")


def result_section(result, key: str, title: str, note: str | None = None):
    """A section for any analysis with the shared interface: ``to_pandas()`` for its table
    and ``plot(ax=None)`` returning a figure. The contour error of a program run is shown
    this way.

    Parameters
    ----------
    result : object
        The analysis [-].
    key : str
        Section anchor; its part before the first ``-`` names the kind [-].
    title : str
        Section title [-].
    note : str, optional
        A line under the title [-].
    """
    body = para(note, "lead") if note else ""
    if hasattr(result, "plot"):
        body += figure(result.plot(), title)
    body += table(result.to_pandas(), f"{key.replace('-', '_')}.csv")
    return section(key, title, body)


def _whose(result) -> str:
    """Whose terms the spikes of a circle section are after: the pair's where it holds a
    CCW and a CW circle (:meth:`~tcpmm.analysis.circular.CircleResult.paired`) [-]."""
    if any(sc.after_pair for p in result.passes for sc in p.sensors.values()):
        return ("the terms of the CCW and CW circles fitted together (centre, radius, "
                "servo and scale mismatch, squareness, backlash, lateral play, "
                "straightness, cyclic error)")
    return ("the error terms fitted to each circle (centre, radius, servo and scale "
            "mismatch, squareness; backlash and lateral play are left in)")


def _judged_columns(judged):
    """The judged rows under the names the page uses elsewhere, the raw spikes named raw
    and yes/no for inside (the CSV as the page) [-]."""
    out = judged.rename(columns={"direction": "pass",
                                 "measured_minus_predicted_um": "measured − predicted [µm]",
                                 "half_width_90_um": "90 % interval ± [µm]"})
    out["figure"] = [raw_spike_named(f, "−") for f in out["figure"]]
    out["inside"] = ["–" if v is None or v != v else "yes" if v else "no"
                     for v in out["inside"]]
    return out
