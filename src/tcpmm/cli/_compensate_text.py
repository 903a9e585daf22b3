"""What compensate prints: the TCP error before and after, and the draws' verdicts."""

from __future__ import annotations

import math
from pathlib import Path

from ._app import out
from ._compensate_dense import dense_line
from ._tables import percent


def _row(label: str, fig: dict) -> str:
    path = fig["path"]
    # the rms leaves out the hold after the program (scores.contour_figures), the max not
    text = f"  {label:7s} contour error to the command {path['contour_error_um']:8.2f} µm (rms " \
           f"{path['contour_rms_um']:.2f} over the program's motion)"
    if path.get("corner_overshoot_um"):
        text += f", corner overshoot {path['corner_overshoot_um']:.2f} µm"
    if "circle" in fig:
        c = fig["circle"]
        text += f", largest raw spike (e - b) {c['largest_spike_um']:.2f} µm, G " \
                f"{c['circular_deviation_um']:.2f} µm"
    return text


def say_compensation(output: Path, report, comp, controller_out, cc, reference=None,
                     planner: dict | None = None) -> None:
    """Print what was written and the TCP error before and after, on the console.

    Parameters
    ----------
    output : Path
        The compensated command file [-].
    report, controller_out : Path or None
        The report page and the controller parameters file, where written [-].
    comp : Compensation
        The compensation [-].
    cc : ControllerCompensation or None
        The controller-side compensation, where computed [-].
    reference : Path or None
        The program as planned for the correction, where written [-].
    planner : dict of str to AxisBounds, optional
        The interpolator's own limits per axis, where the command was planned from an NC
        program, not read from a file [-].
    """
    out.print(f"wrote {output} ({comp.reference.time_s.size} samples, TCP delayed by "
              f"{comp.delay_s * 1e3:.1f} ms)" + (f" and the report {report}" if report else ""))
    planned = "planned" in comp.scores  # then "before" is the program at the full limits
    out.print(_row("before", comp.scores["before"]) + (" (as programmed)" if planned else ""))
    if planned:
        out.print(_row("planned", comp.scores["planned"]) + f" (planned with headroom "
                  f"{comp.settings.get('headroom', 0.0):g}, uncorrected)")
    out.print(_row("after", comp.scores["after"]))
    for line in demand_lines(comp.scores.get("demands"), comp.bounds):
        out.print(line, highlight=False)
    for line in _kept_lines(comp):
        out.print(line, highlight=False)
    for line in _plan_lines(comp.settings, comp.bounds):
        out.print(line, highlight=False)
    if comp.robustness:
        for line in _verdict_lines(comp.robustness, comp.moved_axes):
            out.print(line)
    if cc is not None and cc.robustness and cc.robustness["share"] == 0:
        out.print(f"wrote {controller_out} (controller-side compensation: the draws keep "
                  "none of the friction pulses and cross-talk feed-forward tuned, every "
                  f"parameter 0; {output} needs none on the controller)")
    elif cc is not None:
        out.print(f"wrote {controller_out} (controller-side compensation: friction pulses "
                  f"and cross-talk feed-forward; {output} was learned with them and is "
                  "right only with them on the controller; the figures above are with "
                  f"both: tcpmm simulate MODEL --command {output} --controller "
                  f"{controller_out} runs them)")
        if cc.robustness:
            out.print(f"  share of the tuned parameters kept: {cc.robustness['share']:g}")
        for line in adaptation_lines(cc):
            out.print(line)
    _said_written(reference, comp.settings.get("gcode_out"), output)


def _plan_lines(st: dict, bounds: dict) -> list[str]:
    """What the headroom did to an NC program, and the S-curve it was planned with in
    place of the model's trapezoid, where so [-]."""
    from ..compensate.headroom import scurve_words

    if not st.get("headroom"):
        return []
    steps = math.isfinite(min((b.jerk for b in bounds.values()), default=math.inf))
    return [f"  planned with headroom {st['headroom']:g}: {percent(1 - st['headroom'])} of "
            "the axes' acceleration and jerk, the rest left to the correction: "
            f"{st['planned_duration_s']:.3g} s instead of "
            f"{st['programmed_duration_s']:.3g} s as programmed (longer ramps and "
            f"corners{', slower where the curvature steps' * steps}; on a curve, the "
            "feed the rest of the acceleration allows)" + _corner_words(st)
            ] + ([f"  {scurve_words(st['scurve_plan'])}"] if st.get("scurve_plan") else [])


def _said_written(reference, dense: dict | None, output: Path) -> None:
    """Print where the program as planned (``--reference-out``) and the dense program
    (``--gcode-out``) were written, where they were [-]."""
    if reference is not None:
        out.print(f"wrote {reference}: the program as planned for the correction, "
                  "uncompensated; measure runs of the compensated command against it")
    dense_line(dense, output)


#: How much more jerk than the program's own the correction asks before a note says so [-].
JERK_NOTE_RATIO = 2.0


def demand_lines(demands: dict | None, bounds: dict) -> list[str]:
    """A line per axis: the largest acceleration, jerk and current the program as
    programmed (at the axes' full limits, not the plan with headroom) and the compensated
    command ask (:func:`tcpmm.compensate.scores.axis_demands`), each with its limit; where
    no jerk limit is set and the correction asks much more than the program, what a drive
    that limits its jerk would do with it [-]."""
    from ..compensate.scores import DEMAND_WORDS

    if not demands:
        return []
    lines = []
    for a, after in demands["after"].items():
        before, b = demands["before"].get(a, {}), bounds[a].to_dict()
        parts = []
        for key in ("accel_m_per_s2", "jerk_m_per_s3", "current_A"):
            what, unit = DEMAND_WORDS[key]
            if after.get(key) is None or before.get(key) is None:
                continue
            lim = b.get(key)
            parts.append(f"{what} {_num(before[key])} -> {_num(after[key])} {unit} ("
                         + (f"limit {_num(lim)}" if lim is not None else "no limit") + ")")
        line = f"  {a} asks (as programmed -> compensated): " + ", ".join(parts)
        jb, ja = before.get("jerk_m_per_s3"), after.get("jerk_m_per_s3")
        if b.get("jerk_m_per_s3") is None and jb and ja > JERK_NOTE_RATIO * jb:
            line += (f"; the correction asks {_num(ja / jb)} times the jerk as programmed: a "
                     "drive that limits its jerk smooths part of it away (give its limit "
                     "with --jerk-m-per-s3)")
        lines.append(line)
    return lines


def _kept_lines(comp) -> list[str]:
    """What was kept of a correction planned with headroom, where not all of it: learned
    again on the program as programmed, or none of it applied [-]."""
    lines = []
    if comp.robustness.get("relearned"):
        lines.append("  planned with the headroom, the correction kept made "
                     f"{'; '.join(comp.robustness['relearned'])}: it was learned again on "
                     "the program as programmed, at the axes' full limits")
    if comp.robustness.get("as_programmed"):
        lines.append("  no share of the correction is applied: the program is written as "
                     "programmed, at the axes' full limits (the headroom serves only the "
                     "correction)")
    elif not comp.applied:
        lines.append("  no share of the correction is applied: the figures after are those "
                     "of the command as planned")
    return lines


def _num(v: float) -> str:
    """Three digits, and no exponent below a million [-]."""
    return f"{v:.0f}" if 99.5 <= abs(v) < 1e6 else f"{v:.3g}"


def warn_worse(comp) -> None:
    """With no draws to scale the correction back, a warning (on stderr, and in
    ``--json``'s ``warnings``) for each figure the correction makes worse on the model
    itself by more than the sensors' resolution (at the end of a move, the TCP can
    overshoot a point it approached from one side before); with draws or without, one
    where it overshoots a corner further (:func:`warn_overshoot`) [-]."""
    import warnings

    from ..compensate.headroom import worse_than_programmed
    from ..errors import InputWarning

    worse = [] if comp.robustness else worse_than_programmed(comp.scores)
    if worse:
        warnings.warn(f"the correction makes the model's own TCP worse: {'; '.join(worse)}; "
                      "with --draws N (default 16) it is scaled back where it does not help",
                      InputWarning, stacklevel=2)
    warn_overshoot(comp)


def warn_overshoot(comp) -> None:
    """A warning where the compensated command takes the model's TCP further outside the
    path past a corner than the program does, by more than the sensors' resolution: the
    contour error's magnitude falls where a corner's rounding turns into overshoot, and
    neither the draws nor the figures before and after tell the two apart [-]."""
    import warnings

    from ..compensate.cornerguard import corner_place
    from ..compensate.robust import EQUAL_M
    from ..compensate.scores import corner_rises
    from ..errors import InputWarning

    rises = corner_rises(comp.scores, EQUAL_M * 1e6)
    if not rises:
        return
    at, b, a = max(rises, key=lambda r: r[2])  # the corner passed furthest of those
    more = f"; {len(rises)} corners so" if len(rises) > 1 else ""
    warnings.warn(f"the correction takes the model's TCP further outside the path past "
                  f"a corner: overshoot up to {a:.2f} µm after, against {b:.2f} µm "
                  f"before,{corner_place(at)}{more} (the contour error does not tell "
                  "overshoot from rounding; on an outside contour it is a gouge; tcpmm "
                  "contour on a run of the compensated command lists the corners)",
                  InputWarning, stacklevel=2)


def warn_current(comp) -> None:
    """A warning per axis whose compensated command's run on the model, feedback
    quantised as ``tcpmm simulate`` runs it, comes within
    :data:`tcpmm.compensate.currentlimit.CLAMP_MARGIN` of its current limit, with what the
    program as programmed asks itself: the correction is held below it
    (:mod:`tcpmm.compensate.currentlimit`), but not below the program's own peak, and the
    draws' shares and the ripple of the velocity read from encoder counts can take it
    there [-]."""
    import warnings

    from ..compensate.currentlimit import CLAMP_MARGIN
    from ..errors import InputWarning

    demands = comp.scores.get("demands") or {}
    for a, after in demands.get("after", {}).items():
        asked, lim = after.get("current_A"), comp.bounds[a].current
        if asked is None or asked < (1 - CLAMP_MARGIN) * lim:
            continue
        own = demands.get("before", {}).get(a, {}).get("current_A")
        warnings.warn(
            f"{a}: the compensated command asks up to {asked:.3g} A of the drive on the "
            f"model, within {CLAMP_MARGIN:.0%} of its current limit of {lim:.3g} A"
            + ("; the drive clamps it at the limit" if asked >= lim * (1 - 1e-6) else "")
            + ("" if own is None else f"; the program as programmed asks {own:.3g} A "
               "itself") + ", with the ripple of the velocity read from encoder counts: "
            "the model's TCP after is then not to be relied on there; lower the feed or "
            "the acceleration", InputWarning, stacklevel=2)


def warn_over_limits(comp, planner: dict | None) -> None:
    """A warning per axis and limit the compensated command goes beyond, with its cause
    (:func:`tcpmm.compensate.bounds.over_limit_words`): on stderr, and in ``--json`` [-]."""
    import warnings

    from ..compensate.bounds import over_limit_words
    from ..errors import InputWarning

    for line in over_limit_words(comp.command, comp.reference, comp.bounds, planner,
                                 comp.settings.get("headroom", 0.0)):
        warnings.warn(InputWarning(line), stacklevel=2)


#: How each verdict over the draws reads [-].
_VERDICT_TEXT = {"firm": "firm: the machine, as one more draw, at least {b:.1f}x smaller "
                         "(every draw at least {r:.1f}x)",
                 "improves": "improves: every draw and the machine, as one more draw, "
                             "smaller by more than the model's error, by {b:.1f}x at 95 % "
                             "(every draw at least {r:.1f}x)",
                 "uncertain": "uncertain: some draw, or the machine as one more draw, not "
                              "smaller by more than the model's error; the share applied "
                              "keeps it from growing"}


def _verdict_lines(robustness: dict, moved: list) -> list[str]:
    """The shares applied and what the draws of the model say of them, on the console.

    Parameters
    ----------
    robustness : dict
        ``Compensation.robustness`` (:func:`tcpmm.compensate.robust_factors`) [-].
    moved : list of str
        The axes the path moves; a standing axis has no share to give [-].
    """
    from ..compensate.robust import FIRM_RATIO

    f = ", ".join(f"{a} {v:.2g}" for a, v in robustness["factors"].items() if a in moved)
    if robustness.get("by_region"):
        f += " (the mean along the path: chosen region by region)"
    n = robustness["draws"]
    return [f"  share of the correction applied: {f}; over {n} draw{'s' * (n != 1)} of "
            "the model the largest contour error of a region (a reversal or a stretch "
            "between) falls on every draw, and on the machine as one more draw, and no "
            "sample's error rises, on "
            f"{percent(robustness['trusted_share'])} of the samples (trusted), at least "
            f"{FIRM_RATIO:g}x on the machine (firm) on {percent(robustness['firm_share'])}",
            *_rise_lines(robustness.get("local_rise")), *_held_lines(robustness),
            *_worst_after(robustness),
            *_figure_verdicts(robustness.get("circle", {}))]


def _corner_words(settings: dict) -> str:
    """Where the sharp corners' smaller velocity step is a tenth or more of the time the
    headroom adds, how much and what to do (:func:`tcpmm.compensate.headroom.
    corner_steps_s`), else nothing [-]."""
    from ..compensate.headroom import planned_step_share

    corners = settings.get("corner_steps_s", 0.0)
    added = settings["planned_duration_s"] - settings["programmed_duration_s"]
    if corners < 0.1 * added or corners <= 0.0:
        return ""
    return (f"; {corners:.3g} s of it at sharp corners between blocks, each taken with a "
            f"velocity step of {planned_step_share(settings['headroom']):.0%} of the axes' "
            "acceleration (G64 without P keeps them sharp, and a curve posted as short "
            "lines turns at every block): G64 P<tolerance> rounds them, --headroom 0 "
            "plans the program as programmed")


def _rise_lines(rise) -> list[str]:
    """The line of :func:`tcpmm.compensate.trust.rise_words`, none where not judged [-]."""
    from ..compensate.trust import rise_words

    return [] if rise is None else [f"  {rise_words(rise)}"]


def _held_lines(robustness: dict) -> list[str]:
    """Where the corners' guard held more of the correction back, the line of
    :func:`tcpmm.compensate.cornerguard.held_words` [-]."""
    from ..compensate.cornerguard import held_words

    held = robustness.get("corner_held")
    return [] if held is None else [f"  {held_words(held)}"]


def _worst_after(robustness: dict) -> list[str]:
    """The contour error after on the worst draw, region by region the largest: how far
    the figure after, which is the model's, may be from the machine's [-]."""
    worst = [r["worst_after_um"] for r in robustness.get("regions", [])]
    if not worst:
        return []
    n = robustness["draws"]
    on = "the one draw" if n == 1 else f"the worst of the {n} draws"
    top = robustness.get("worst_after_to_command_um", max(worst))
    return [f"  contour error after to the command, on {on}: up to {top:.2f} µm (the "
            "figures after above, the largest and the rms, are the model's)"]


def _figure_verdicts(figures: dict) -> list[str]:
    """A line per circle figure with the draws' verdict on it.

    Parameters
    ----------
    figures : dict
        ``{"spike": ..., "circular_deviation": ...}``, each of
        :func:`tcpmm.compensate.robust.over_draws` [-].
    """
    names = {"spike": "largest raw reversal spike (e - b)", "circular_deviation": "G"}
    return [f"  {name}: " + _VERDICT_TEXT[figures[key]["verdict"]].format(
        r=figures[key]["least_ratio"], b=figures[key]["ratio_bound"])
        + f"; after up to {figures[key]['worst_after_um']:.2f} µm on the worst draw"
        for key, name in names.items() if key in figures]


def warn_extra_reversals(compensated, reference, cc) -> None:
    """Warn where the compensated command turns an axis back more often than the program
    and the parameters fire a friction pulse there: the model predicts those pulses, but
    on friction it has wrong they push the axis where nothing else moves it [-]."""
    import warnings

    from ..compensate.drive import extra_reversals
    from ..errors import InputWarning

    for a, (got, want) in extra_reversals(compensated, reference).items():
        c = cc.axes.get(a)
        if c is not None and c.pulse_A:
            warnings.warn(
                f"axis {a}: the compensated command reverses {got} times where the program "
                f"reverses {want}, and the controller fires its friction pulse "
                f"({c.pulse_A:.3g} A, {c.decay_s * 1e3:.0f} ms) at each: the correction's "
                "own turns (about the program's reversals, or where its share changes along "
                "the path) are predicted with the model's friction, which may be wrong; "
                "check the run on the machine, or compensate without --controller-out",
                InputWarning, stacklevel=2)


def adaptation_lines(cc) -> list[str]:
    """Per axis whose pulse has an adaptation characteristic, what it is: the amplitude
    over the acceleration at the reversal, as the parameter file gives it [-]."""
    out = []
    for a, c in cc.axes.items():
        ch = c.characteristic
        if ch is None or c.pulse_A == 0.0:
            continue
        a1, a2, a3 = ch.accel_m_per_s2
        out.append(f"  {a}: the pulse adapted to the acceleration at the reversal "
                   f"(FRICT_COMP_ADAPT_ENABLE 1): from 0 to {c.pulse_A:.3g} A up to "
                   f"{a1:.3g} m/s^2, held to {a2:.3g}, {c.pulse_A * ch.low_ratio:.3g} A "
                   f"from {a3:.3g} m/s^2 on (tuned on the circle at 1/4, 1/2 and all of "
                   "its feed, and checked on draws of the model; below 1/16 of the "
                   "circle's acceleration nothing was tuned)")
    return out
