"""The figures a compensation is judged by: the TCP's contour error along any program, and
for a circle its reversal spikes and circular deviation G."""

from __future__ import annotations

import warnings

import numpy as np

from ..analysis.circular import analyse_circle
from ..analysis.contour import contour_error
from ..path.command import Command
from ..path.limits import peak
from ..sim.simulate import simulate
from .drive import controlled_run
from .learning import extended


def programmed_path(comp, programmed=None) -> Command:
    """The command run and judged before the compensation: ``comp.reference``, or
    ``programmed`` (the program at the axes' full limits, :mod:`.headroom`) held at its end
    as long as the compensated command is, for the same time to settle [m]."""
    if programmed is None:
        return comp.reference
    return extended(programmed, 0, comp.settings.get("hold_samples", 0))[0]


def runs_before_after(machine, comp, quantise_feedback: bool = True, programmed=None,
                      compensated=None):
    """The model run on the programmed and on the compensated command; each run's command
    signals are the path its circle is judged on (the programmed path, delayed for the
    compensated run), its G0 rapids those of the command it runs: the program's, as a run
    of the compensated command records them [-].

    ``programmed``, where given, is the command run before instead of ``comp.reference``:
    the program at the axes' full limits where the compensation was planned with headroom
    (:mod:`.headroom`).

    Where every share is 0 the compensated command is the programmed one and is judged on
    the same path: a lagging machine's G read over passes a few milliseconds apart differs
    by tens of micrometres, which is no effect of the compensation.

    A command learned with controller-side parameters (``comp.controller``) is run with
    them, as the controller applies them; the programmed command without.

    ``compensated``, where given, is ``comp.command`` already built (it is fitted to the
    limits anew at each access).
    """
    programmed = programmed_path(comp, programmed)
    compensated = comp.command if compensated is None else compensated
    before = simulate(machine, programmed, quantise_feedback=quantise_feedback)
    after = controlled_run(machine, compensated, comp.controller, quantise_feedback)
    for run, path, ran in ((before, programmed, programmed),
                           (after, judged_path(comp), comp.reference)):
        for a, r in run.axes.items():
            if a in path.positions:
                r.cmd = path.positions[a][:run.time_s.size]
        with_program_flags(run, ran)
    return before, after


def with_program_flags(run, command: Command):
    """``run`` with the NC line and the G0 rapid flag of each sample of the program
    ``command`` ran, as a run of it records them, in place; as it was where the command
    holds none [-]."""
    blocks = command.blocks()
    if blocks is not None:
        run.nc_line, run.rapid = (b[:run.time_s.size] for b in blocks)
    return run


#: What a command asks of an axis, by the order of the difference taken [-].
DEMANDS = ((1, "velocity_m_per_s"), (2, "accel_m_per_s2"), (3, "jerk_m_per_s3"))
#: Each demand (and limit) by its name and unit, as the console and the report say it [-].
DEMAND_WORDS = {"velocity_m_per_s": ("velocity", "m/s"),
                "accel_m_per_s2": ("acceleration", "m/s²"),
                "jerk_m_per_s3": ("jerk", "m/s³"), "current_A": ("current", "A")}


def axis_demands(command: Command, run) -> dict:
    """Per axis the command moves: the largest velocity, acceleration and jerk its samples
    ask (backward differences from rest before the first sample, as the limits are kept,
    :func:`.bounds.excess`) and the largest current of the model's run on it [SI].

    Parameters
    ----------
    command : Command
        The command [m].
    run : SimulationResult
        The model's run on it [SI].
    """
    out = {}
    for a, x in command.positions.items():
        if np.ptp(x) == 0.0:
            continue
        d = {k: peak(x, n, command.period_s, from_rest=True) for n, k in DEMANDS}
        current = run.axes[a].peak_current() if a in run.axes else None
        d["current_A"] = None if current is None else float(np.max(current))
        out[a] = d
    return out


#: The figures of a score shown before and after: ``(part, key, label)`` [-].
SCORE_FIGURES = (("path", "contour_error_um", "contour error"),
                 ("path", "contour_rms_um", "contour rms over the motion"),
                 ("circle", "largest_spike_um", "largest reversal spike"),
                 ("circle", "circular_deviation_um", "G"))
#: The corners' largest overshoot (:func:`corner_overshoot`): no figure the correction
#: claims to improve, but one it must not make worse [-].
CORNER_FIGURE = ("path", "corner_overshoot_um", "corner overshoot")


def before_after(scores: dict, keys=None, figures=SCORE_FIGURES
                 ) -> list[tuple[str, float, float]]:
    """``(label, before, after)`` of each figure both scores hold, in the order of
    ``figures``, of those named in ``keys`` when given [um].

    Parameters
    ----------
    scores : dict
        ``{"before": ..., "after": ...}`` of :func:`judge` [-].
    keys : collection of str, optional
        The figures' keys to keep [-].
    figures : sequence of tuple, optional
        ``(part, key, label)`` of the figures, :data:`SCORE_FIGURES` by default [-].
    """
    out = []
    for part, key, label in figures:
        b = scores.get("before", {}).get(part, {}).get(key)
        a = scores.get("after", {}).get(part, {}).get(key)
        if b is not None and a is not None and (keys is None or key in keys):
            out.append((label, b, a))
    return out


def judged_path(comp) -> Command:
    """The path the compensated command's TCP is to follow, on which its circle is judged:
    the delayed path, or the programmed one where no share of the correction is applied.
    Its contour error is measured against the program (:func:`predicted_scores`) [m]."""
    return comp.target if comp.applied else comp.reference


def contour_figures(run, path: Command, hold: int = 0) -> dict:
    """Largest and rms TCP contour error along the path, G0 rapids left out as
    :func:`tcpmm.analysis.contour.contour_error` leaves them out, in um: the largest over
    the whole run, as the TCP still swinging after the axes stop is error too; the rms
    over the program's motion, the last ``hold`` samples of the path left out (the hold
    appended for the TCP to settle, :func:`.learning.extended`): its errors, of the TCP
    coming to rest and the correction fading out, would weigh the more the longer the
    hold is, and a run of the program alone has none of them [-]."""
    res = contour_error(run, command=path)
    e = np.abs(res.errors["tcp"])
    counted = np.isfinite(e) & (True if res.counted is None else res.counted)
    moving = counted.copy()
    moving[max(path.time_s.size - hold, 0):] = False
    if not moving.any():  # a path that is all hold: the rms of what there is
        moving = counted
    return {"contour_error_um": float(np.max(e[counted]) * 1e6),
            "contour_rms_um": float(np.sqrt(np.mean(e[moving] ** 2)) * 1e6),
            **corner_overshoot(res)}


def corner_overshoot(res) -> dict:
    """The TCP's largest overshoot past a corner of the path, its end included, as
    ``tcpmm contour`` gives it, and where that corner is: ``corner_overshoot_um`` [um]
    (0 without corners), ``corner_overshoot_at_mm`` [mm] (``None`` without); and every
    corner's, in the path's order: ``corners``, ``{"at_mm", "overshoot_um"}`` each, 0
    where none is read (a TCP still moving there, NaN in ``tcpmm contour``) [mm, um]. A
    correction that takes a corner's rounding away can take the TCP outside the path past
    it, which the contour error's magnitude does not tell from the rounding [-]."""
    rows = res.corner_rows(sensors=["tcp"])
    every = [{"at_mm": [r[f"{a.lower()}_mm"] for a in res.axes],
              "overshoot_um": float(np.nan_to_num(r["overshoot_um"]))} for r in rows]
    read = [c for c, r in zip(every, rows, strict=True) if np.isfinite(r["overshoot_um"])]
    if not read:
        return {"corner_overshoot_um": 0.0, "corner_overshoot_at_mm": None, "corners": every}
    top = max(read, key=lambda c: c["overshoot_um"])
    return {"corner_overshoot_um": top["overshoot_um"], "corner_overshoot_at_mm": top["at_mm"],
            "corners": every}


def corner_rises(scores: dict, equal_um: float) -> list[tuple]:
    """The corners whose overshoot ``scores["after"]`` holds above ``scores["before"]``'s
    by more than ``equal_um``, as ``(at_mm or None, before, after)``: corner by corner
    where both read the same corners (a path and its plan with headroom turn at the same
    places, in the same order), else the largest of each (:data:`CORNER_FIGURE`) [mm, um].

    Parameters
    ----------
    scores : dict
        ``{"before": ..., "after": ...}`` of :func:`judge` [-].
    equal_um : float
        The rise below which an overshoot counts as the same [um].
    """
    b, a = (scores.get(k, {}).get("path", {}) for k in ("before", "after"))
    cb, ca = b.get("corners"), a.get("corners")
    if cb is not None and ca is not None and len(cb) == len(ca):
        return [(y["at_mm"], x["overshoot_um"], y["overshoot_um"])
                for x, y in zip(cb, ca, strict=True)
                if y["overshoot_um"] > x["overshoot_um"] + equal_um]
    return [(a.get("corner_overshoot_at_mm"), x, y)
            for _, x, y in before_after(scores, figures=(CORNER_FIGURE,))
            if y > x + equal_um]


def settling_hold(comp, path: Command) -> int:
    """The samples held at the end of a path of ``comp`` (its ``reference``, its
    ``target`` or the program held as long, :func:`programmed_path`) for the TCP to
    settle, after the program's motion: the target is the program delayed, its motion
    ends as many samples later [-]."""
    hold = comp.settings.get("hold_samples", 0)
    return hold - round(comp.delay_s / path.period_s) if path is comp.target else hold


def circle_figures(run, radius_m: float, centre_m=(0.0, 0.0), plane=("X", "Y"),
                   warn: bool = False) -> dict:
    """Per circle pass at the TCP: contour error, G and spikes A-D, all in um [-].

    ``warn`` lets the circle analysis say what it cannot report (a quadrant point the
    circle starts on, and so never crosses, has no spike): said of the program's own run,
    as the one place it holds for, not again of every run and draw judged after it [-].
    """
    with warnings.catch_warnings():
        if not warn:
            warnings.simplefilter("ignore")
        res = analyse_circle(run, radius_m, centre_m, plane=plane, sensors=("cmd", "tcp"),
                             settling=False)
    out = []
    for p in res.passes:
        s = p.sensors["tcp"]
        spikes = {k: float(v * 1e6) for k, v in s.spikes.items()}
        out.append({"direction": p.direction, "contour_error_um": s.contour_error * 1e6,
                    "circular_deviation_um": s.circular_deviation * 1e6,
                    "spikes_um": spikes,
                    "largest_spike_um": _largest(abs(v) for v in spikes.values())})
    return {"passes": out,
            "contour_error_um": _largest(p["contour_error_um"] for p in out),
            "largest_spike_um": _largest(p["largest_spike_um"] for p in out),
            "circular_deviation_um": _largest(p["circular_deviation_um"] for p in out)}


def _largest(values) -> float:
    """Largest of the values that are numbers; NaN where none is, as for a quadrant point
    the circle starts on and so never crosses [-]."""
    v = [x for x in values if np.isfinite(x)]
    return max(v) if v else float("nan")


def judge(run, path: Command, radius_m=None, centre_m=(0.0, 0.0), plane=("X", "Y"),
          warn: bool = False, hold: int = 0) -> dict:
    """Contour figures of a run, and the circle's when a radius is given; ``warn`` as
    :func:`circle_figures` has it, ``hold`` as :func:`contour_figures` [-]."""
    out = {"path": contour_figures(run, path, hold)}
    if radius_m is not None:
        out["circle"] = circle_figures(run, radius_m, centre_m, plane, warn)
    return out


def predicted_scores(machine, comp, radius_m=None, centre_m=(0.0, 0.0),
                     plane=("X", "Y"), programmed=None) -> dict:
    """Figures of the model's TCP before and after the compensation.

    Parameters
    ----------
    machine : Machine
        The model the figures are predicted with [SI].
    comp : Compensation
        The compensation [-].
    radius_m : float, optional
        Radius of a circular test: its spikes and G are judged too [m].
    centre_m : tuple of float
        Centre of the circle [m].
    plane : tuple of str
        Axes of the circle's plane [-].
    programmed : Command, optional
        The command judged before, where not ``comp.reference`` (:func:`runs_before_after`)
        [m].

    Returns
    -------
    dict
        ``{"before": ..., "after": ...}``, each from :func:`judge` (the rms over the
        program's motion, its settling hold left out); with ``programmed`` also
        ``"planned"``: the command the correction was learned on, uncorrected (the program
        planned with headroom), so that what the slower plan gives and what the correction
        gives are told apart; ``"demands"``: ``{"before": ..., "after": ...}`` of
        :func:`axis_demands`, what the programmed and the compensated command ask of each
        axis [-].
    """
    compensated, judged = comp.command, judged_path(comp)
    path = programmed_path(comp, programmed)
    before, after = runs_before_after(machine, comp, programmed=programmed,
                                      compensated=compensated)
    where = (radius_m, centre_m, plane)
    # the compensated run's contour error is measured against the program, with its own
    # rapids, as the uncompensated one is: the TCP still on a rapid's line when a cut
    # begins is late by the correction's delay, and counted as the servo's lag is before
    # (the delayed path's rapids, ending that delay later, would leave it out of after
    # alone); the rms over the delayed motion
    out = {"before": judge(before, path, *where, warn=True, hold=settling_hold(comp, path)),
           "after": judge(after, comp.reference, *where, hold=settling_hold(comp, judged)),
           "demands": {"before": axis_demands(path, before),
                       "after": axis_demands(compensated, after)}}
    if programmed is not None:
        out["planned"] = judge(simulate(machine, comp.reference), comp.reference, *where,
                               hold=settling_hold(comp, comp.reference))
    return out
