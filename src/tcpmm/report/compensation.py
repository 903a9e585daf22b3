"""The compensation section of a report: the TCP error before and after, the figures the
model predicts, and what the command was given per axis."""

from __future__ import annotations

import warnings

from ..analysis.circular import analyse_circle
from ..compensate import runs_before_after
from ..compensate.bounds import over_limit_words
from ..compensate.cornerguard import held_words
from ..compensate.robust import FIRM_RATIO
from ..compensate.scores import DEMAND_WORDS, before_after
from ..compensate.trust import rise_words
from ..errors import InputError
from ..plot.circle import plot_circle
from .html import figure, para, section, table


def _figures_frame(scores: dict):
    """Before, after and their ratio per predicted figure [µm, -]."""
    import pandas as pd

    return pd.DataFrame([{"figure": f"{label} [µm]", "before": b, "after": a,
                          "reduced by [x]": b / a if a > 0 else float("inf")}
                         for label, b, a in before_after(scores)])


def _axes_frame(comp):
    """Per axis: the share of the correction applied, its size, and per quantity its limit
    ("none" where none is set) and what the programmed and the compensated command ask
    (the largest velocity, acceleration, jerk and current)."""
    import pandas as pd

    d = comp.to_dict()
    demands = comp.scores.get("demands", {})
    shares = comp.robustness.get("factors", {})
    share = ("share applied, mean along the path (chosen by region)"
             if comp.robustness.get("by_region") else "share applied")
    rows = []
    for a, c in d["correction"].items():
        if a not in comp.moved_axes:  # a standing axis has nothing to correct
            continue
        row = {"axis": a, share: shares.get(a, 1.0),
               "largest correction [µm]": c["applied_max_um"]}
        for key, (what, unit) in DEMAND_WORDS.items():
            limit = d["bounds"].get(a, {}).get(key)
            row[f"{what} limit [{unit}]"] = "none" if limit is None else limit
            for who, part in (("program", "before"), ("compensated", "after")):
                v = demands.get(part, {}).get(a, {}).get(key)
                if v is not None:
                    row[f"{what}, {who} [{unit}]"] = v
        rows.append(row)
    return pd.DataFrame(rows)


def _polar(machine, comp, circle):
    """The model's TCP on the circle ``(radius, centre, plane)`` before (solid) and after
    (dotted) the compensation, one polar panel per pass; ``None`` where the circle is not
    found whole."""
    before, after = runs_before_after(machine, comp)
    radius_m, centre_m, plane = circle
    try:
        # what the analysis cannot report of the circle, the scores said of the program
        # (:func:`tcpmm.compensate.scores.predicted_scores`): not again for these runs
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            rb = analyse_circle(before, radius_m, centre_m, plane=plane,
                                sensors=("cmd", "tcp"), settling=False)
            ra = analyse_circle(after, radius_m, centre_m, plane=plane,
                                sensors=("cmd", "tcp"), settling=False)
    except InputError:
        return None
    return plot_circle(rb, sensors=["tcp"], overlay=ra,
                       title="TCP before (solid) and after (dotted) the compensation")


def compensation_section(comp, source=None, machine=None, circle=None, controller=None,
                         planner=None):
    """The compensation: the model's TCP on the circle before and after (polar, with the
    model and the circle's radius), the correction and its share along the path, the
    figures with their reduction, per axis the share of the correction applied, its size
    and the limits it keeps, and the controller-side parameters when computed.

    Parameters
    ----------
    comp : Compensation
        From :func:`tcpmm.compensate.compensate`, with its scores [-].
    source : str, optional
        The programmed command or program, for the record [-].
    machine : Machine, optional
        The model it was computed on, for the polar plot [SI].
    circle : tuple, optional
        ``(radius, centre, plane)`` of the circle, for the polar plot [m, m, -].
    controller : ControllerCompensation, optional
        Friction pulses and cross-talk feed-forward (:mod:`tcpmm.compensate.controller`) [-].
    planner : dict of str to AxisBounds, optional
        The interpolator's own limits, where the command was planned from an NC program
        (:func:`tcpmm.compensate.bounds.over_limit_words`) [-].
    """
    trusted = comp.to_dict().get("trusted_share")
    firm = (comp.robustness or {}).get("firm_share")
    lead = ("The programmed command pre-compensated on the identified model: the model's "
            "TCP error before and after, as it predicts them"
            + (f" (from {source})" if source else "") + ".")
    if trusted is not None:
        lead += (" The compensation lowers the largest error of each region (a reversal "
                 "or a stretch between) on every machine drawn from the model's "
                 f"uncertainty, and no sample's error rises, on {trusted:.0%} of the "
                 "samples (trusted)")
        lead += ("." if firm is None else
                 f", and at least {FIRM_RATIO:g} times on {firm:.0%} (firm).")
        rob = comp.robustness or {}
        for words in ("" if rob.get("local_rise") is None else rise_words(rob["local_rise"]),
                      "" if rob.get("corner_held") is None else held_words(rob["corner_held"])):
            lead += f" {words[:1].upper()}{words[1:]}." if words else ""
    body = para(lead, "lead")
    polar = None if machine is None or circle is None else _polar(machine, comp, circle)
    if polar is not None:
        body += figure(polar, "TCP before and after on the circle")
    body += figure(comp.plot(), "correction and its share along the path")
    frame = _figures_frame(comp.scores)
    if len(frame):
        body += "<h3>Predicted figures</h3>" + table(frame, "compensation_figures.csv")
    body += ("<h3>Per axis</h3>" + table(_axes_frame(comp), "compensation_axes.csv"))
    for line in over_limit_words(comp.command, comp.reference, comp.bounds, planner,
                                 comp.settings.get("headroom", 0.0)):
        body += para(f"Beyond a limit, {line}.")
    if controller is not None:
        body += ("<h3>Controller-side compensation</h3>"
                 + para("Instead of a new command: a friction pulse at each reversal and a "
                        "cross-talk feed-forward per axis, to type into the controller, and "
                        "the figures the model predicts with them.")
                 + table(controller.to_pandas(), "controller_parameters.csv", None)
                 + table(_figures_frame(controller.scores), "controller_figures.csv"))
    return section("compensation", "Compensation", body)
