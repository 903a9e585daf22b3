"""The section a customer reads first: the circular test's conditions, its pass or fail
against the user's tolerance (or, without one, the ISO 230-4 circular deviations), and the
error sources ranked by the radial error each causes on that circle.

The verdict judges the bidirectional circular deviation G(b) and G of each direction
(ISO 230-4: the radial band about the least-squares centre that holds the path) of the
best sensor the run has (TCP, else linear scale, motor encoder, command): PASS when every
one is within the tolerance. The ranking gives each fitted term the peak-to-valley radial
error it makes on a circle of radius R: backlash and lateral play their radial step,
squareness ``a`` and scale mismatch ``m`` an ellipse of ``R |a|`` and ``R |m|``, servo
mismatch of angle ``phi`` one of ``R |phi|``, a cyclic error twice its amplitude; the
largest reversal spike after the terms enters as its height.
"""

from __future__ import annotations

import math

from ..analysis.circle_display import pass_names, placed_terms
from ..analysis.circle_tails import unranked
from ..analysis.diagnostics import PREFERRED_SENSORS, term_note
from .circles import SENSOR_NAMES, file_names
from .html import facts, number, para, section, table

#: What a ranked term's sign says where the terms table has no note of it
_MEANING = {"reversal_spikes": "dynamics of the reversal: friction, lost motion, servo",
            "centre_offset": "set-up: the circle's centre off the nominal"}
#: What a ballbar's "backlash" of an axis is at the TCP: the radius stepping out at its
#: reversal, which lost motion in the drive makes, and as well a deflection that flips with
#: the friction (the column bending under the guideway's friction): not the nut alone.
_BACKLASH = ("+: radius steps out at reversal: lost motion in the drive, or a deflection "
             "that flips with the friction (the structure at the TCP); compare the scale's "
             "circle before blaming the nut")


def ranked_sources(diag, reference=None) -> list[tuple[str, float, str, float]]:
    """Error sources of a circle's diagnostics, largest share of G first: the terms as
    ``tcpmm circle`` ranks them (``diag.ranking``: the G each makes alone over the
    circle), so that the report and the command give one figure per term.

    Parameters
    ----------
    diag : CircleDiagnostics
        The diagnostics [SI].
    reference : CircleDiagnostics, optional
        The same circles' diagnostics at a sensor nearer the drive (the linear scale under
        a TCP's): each term's meaning then says whether that sensor sees it too, or
        whether it lies between that sensor and the tool [SI].

    Returns
    -------
    list of tuple
        ``(source, the G it alone makes [m], what its sign says, its share of G
        as the ranking gives it: 0 for the centre offset, about which G is not taken)``
        [-].
    """
    placed = placed_terms(diag, reference,
                          "" if reference is None else SENSOR_NAMES.get(reference.sensor,
                                                                        reference.sensor))
    from ..analysis.circle_alias import ranking_marks

    marks, _ = ranking_marks(diag)  # as tcpmm circle marks them: moving, noisy, aliased
    rows = []
    for r in sorted(diag.ranking, key=lambda r: r["rank"]):
        term = r["term"]
        base, _, axis = term.rpartition("_")
        # the scale's figure beside it says what _BACKLASH asks the reader to compare
        backlash = _BACKLASH if placed is None else term_note(term, diag.axes)
        note = _MEANING.get(term) or (backlash if base == "backlash" else term_note(
            f"cyclic_amplitude_{axis}" if base == "cyclic" else term, diag.axes))
        note = note.split("; n/a:")[0]  # a ranked term is one found
        g = float(r["g_alone_m"])
        where = placed[term][1] if placed is not None else ""
        if where:
            # a pitch error is the screw's: one the scale does not see is no screw's
            note = where if base == "cyclic" and where.startswith("mostly") else \
                f"{where}; {note}"
        rows.append((term.replace("_", " ") + marks.get(term, ""), g, note,
                     float(r["share_of_G"])))
    return rows


def circle_conditions(result, sensor: str, sample_rate_hz=None, source=None,
                      measured_on=None) -> list:
    """``(name, value)`` of the circle's test conditions, in mm, mm/min and Hz, and the
    date of the test where given (``measured_on``, ISO 230-4 asks for it) [-]."""
    # the steady speed: the mean would count the ramp of a circle run from standstill
    rates = [p.feed_rate_rad_s for p in result.passes]
    rates = [r for r in rates if math.isfinite(r)]
    feed = (f"{number(60e3 * result.radius * sum(rates) / len(rates), 0)} mm/min"
            if rates else "not known")
    items = [("radius", f"{result.radius * 1e3:g} mm about ({result.centre[0] * 1e3:g}, "
                        f"{result.centre[1] * 1e3:g}) mm"),
             ("feed", feed), ("plane", "".join(result.plane)),
             ("direction", " then ".join(
                 p.direction.upper() + (f" (an arc of {p.arc_deg:.0f} deg)" if p.is_arc
                                        else "") for p in result.passes)),
             ("sample rate", f"{number(sample_rate_hz, 0)} Hz" if sample_rate_hz else
              "not known"),
             ("sensor", SENSOR_NAMES.get(sensor, sensor))]
    if source:
        items.append(("run", file_names(source)))
    items.append(("measured on", str(measured_on) if measured_on else
                  "not given (--measured-on)"))
    return items


def _deviations(result, sensor, diag) -> list[tuple[str, float]]:
    """``(figure, value [m])``: G per direction and, with both, G(b) [-]."""
    out = [(f"G {name}", p.sensors[sensor].circular_deviation)
           for p, name in zip(result.passes, pass_names(result.passes), strict=True)]
    if diag is not None and "circularity_pair" in diag.terms:
        out.append(("G(b), both directions", diag["circularity_pair"]))
    return out


def acceptance_section(result, diagnostics=None, tolerance_m=None, sample_rate_hz=None,
                       source=None, reference=None, cautions=(), measured_on=None,
                       specified=False):
    """The circle verdict: test conditions, pass or fail, ranked error sources.

    Parameters
    ----------
    result : CircleResult
        The circular test judged [-].
    diagnostics : CircleDiagnostics, optional
        Its diagnostics (a CCW and a CW circle), for G(b) and the ranking [-].
    tolerance_m : float, optional
        Largest circular deviation accepted; without it the deviations are given as
        ISO 230-4 figures, unjudged [m].
    sample_rate_hz : float, optional
        Sample rate of the run [Hz].
    source : str or list of str, optional
        The run file or files [-].
    reference : CircleDiagnostics, optional
        The diagnostics at the linear scale, where ``diagnostics`` are the TCP's: each
        source says whether the scale sees it (:func:`ranked_sources`) [-].
    cautions : sequence of str
        What the analysis of the circle warned of (a feed still changing, a quadrant point
        at the circle's start): the verdict is then not firm, and they follow it [-].
    measured_on : datetime.date or str, optional
        Date of the test [-].
    specified : bool
        Whether ``tolerance_m`` is the machine's specification (its model file's
        ``specification``) rather than a tolerance the user gave [-].
    """
    sensor = diagnostics.sensor if diagnostics is not None else next(
        s for s in PREFERRED_SENSORS if all(s in p.sensors for p in result.passes))
    body = facts(circle_conditions(result, sensor, sample_rate_hz, source, measured_on))
    devs = _deviations(result, sensor, diagnostics)
    shown = ", ".join(f"{k} {number(v * 1e6, 2)} µm" for k, v in devs)
    if tolerance_m is None:
        body += para(f"Circular deviation (ISO 230-4): {shown}. No tolerance was given "
                     "(--tolerance-um), nor does the machine's model state one "
                     "(specification), so nothing is judged.", "open")
    else:
        body += _judged(devs, tolerance_m, bool(cautions), specified)
    if cautions:
        body += para("Cautions from the analysis of this circle:", "warn")
        body += "".join(para(c, "warn") for c in cautions)
    if diagnostics is not None and not diagnostics.ranking:
        body += para("No error source is ranked: the circles determine no term well enough "
                     "to rank it. " + (_unranked_pointer(diagnostics)
                                          or "The diagnostics below say why."), "warn")
    elif diagnostics is not None:
        body += _sources_table(diagnostics, reference)
    else:
        body += para("No error sources: the circle's diagnostics could not be made (the "
                     "warnings say why).", "warn")
    return section("verdict", f"Circle verdict ({SENSOR_NAMES.get(sensor, sensor)})", body)


def _judged(devs, tolerance_m: float, cautioned: bool, specified: bool) -> str:
    """PASS or FAIL of the circular deviations ``devs`` (name, G) against ``tolerance_m``,
    the largest named; not firm where the analysis ``cautioned``; the ``specified``
    tolerance named as the machine's specification [m, -]."""
    worst = max(devs, key=lambda kv: kv[1])
    ok = all(v <= tolerance_m for _, v in devs)
    # as many decimals as show the deviation on its side of the tolerance (to 0.1 nm)
    digits = next((d for d in (2, 3) if number(worst[1] * 1e6, d)
                   != number(tolerance_m * 1e6, d)), 4)
    rest = ", ".join(f"{k} {number(v * 1e6, 2)} µm" for k, v in devs if k != worst[0])
    firm = " (not firm: see the cautions below)" if cautioned else ""
    what = ("the machine's specification (ISO 230-4, from its model; --tolerance-um "
            "judges against another)" if specified else "the tolerance")
    return para(f"{'PASS' if ok else 'FAIL'}{firm}: {worst[0]} {number(worst[1] * 1e6, digits)} "
                f"µm {'within' if ok else 'beyond'} {what} of "
                f"{number(tolerance_m * 1e6, digits)} µm"
                + (f" ({rest})" if rest else ""), "pass" if ok else "fail")


def _sources_table(diagnostics, reference) -> str:
    """The ranked error sources as a table, with the G of each at ``reference``'s sensor
    where given [-]."""
    import pandas as pd

    rows = ranked_sources(diagnostics, reference)
    # one direction's diagnostics have no G(b): the share is of that circle's G
    of = "of G(b) [%]" if "circularity_pair" in diagnostics.terms else "of G [%]"
    g_alone = of.replace(" [%]", "").replace("of ", "") + " alone [µm]"
    at = None
    if reference is not None:
        name = SENSOR_NAMES.get(reference.sensor, reference.sensor)
        seen, at = placed_terms(diagnostics, reference, name), f"at the {name} [µm]"
    terms = [r["term"] for r in sorted(diagnostics.ranking, key=lambda r: r["rank"])]
    frame = pd.DataFrame([{"rank": i + 1, "source": s, g_alone: e * 1e6, of: 100 * g,
                           **({at: 1e6 * seen[t][0]} if at else {}), "meaning": n}
                          for i, ((s, e, n, g), t) in enumerate(zip(rows, terms,
                                                                    strict=True))])
    lead = ("The circular deviation each fitted term alone makes on this circle, about its "
            "own least-squares centre, and its share of the circles' own circular "
            "deviation; the shares need not add up to 100 % (terms add and cancel). ")
    if at:
        lead += ("Beside it, what the same term makes in the linear scale's circle: what "
                 "the scale does not see lies between the table and the tool (the column "
                 "and headstock deflecting, or ringing after a reversal), not in the drive. ")
    from ..analysis.circle_alias import ranking_marks
    legend = " ".join(f"{m}." for m in ranking_marks(diagnostics)[1])
    left = _unranked_pointer(diagnostics)
    return ("<h3>Error sources, largest first</h3>"
            + para(lead + "The diagnostics below give the terms with their signs and their "
                   "radial errors." + (f" Marks: {legend}" if legend else ""))
            + table(frame, "error_sources.csv",
                    digits={g_alone: 2, of: 0, "rank": 0, **({at: 2} if at else {})})
            + (para(left, "warn") if left else ""))


def _unranked_pointer(diagnostics) -> str:
    """The terms left out of the ranking, named, with a pointer to the diagnostics below,
    which say why: the verdict does not repeat their paragraph [-]."""
    names = [k.replace("_", " ") for k in unranked(diagnostics) if k != "reversal_spikes"]
    names += ["reversal spikes"] if diagnostics.quiet_spikes else []
    return (f"Not ranked: {', '.join(names)} (the diagnostics below say why)."
            if names else "")
