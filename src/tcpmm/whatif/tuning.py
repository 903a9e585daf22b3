"""Tune a machine's servos for margins and predict the path before and after.

The proposal comes from :func:`tcpmm.servo.tune.tune_machine`; the prediction simulates
the paper's circle (R35 mm, F5000 mm/min, CCW and CW,
:func:`tcpmm.machines.paper.paper_circle_command`) or an NC program with the model as given
and as tuned.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from ..analysis.runaway import unheld_loads, unheld_words
from ..machines.paper import RADIUS_MM, SETTLED_TURNS, circle_test_command, paper_circle_command
from ..model import Machine
from ..servo.modeshift import current_tolerance
from ..servo.tune import meets_margins
from ..units import mm_to_m
from .tuning_axes import axis_reasons, contouring_axes, left_out_note, moved_axes, tune_axes
from .tuning_draws import drawn_margins, drawn_note, drawn_paths, margins_missed
from .tuning_limit import costed
from .tuning_paths import path_figures

#: Feedforward fractions tried on the path [-].
FEEDFORWARD_GRID = (0.0, 0.25, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0)
#: Where the fractions' figures on the path lie within this of each other, the path does
#: not judge the feedforward (a straight line's contour error has no lag in it) and it is
#: kept [um].
FEEDFORWARD_RESOLUTION_UM = 0.1


@dataclass(frozen=True)
class TuneResult:
    """A tuning proposal and its predicted effect.

    Parameters
    ----------
    tuned : Machine
        The machine with the proposed servo settings [SI].
    axes : dict of str to AxisTuning
        Per-axis proposal, margins before and after [-].
    path_before, path_after : dict
        Predicted path figures: per pass (circle) or for the program, the largest spike
        and the contour error of the TCP [um].
    notes : list of str
        What was decided for all axes at once (the feedforward) and why [-].
    matched, moved : tuple of str
        The contouring axes, whose position gains and feedforward are matched, and the
        axes the path moves [-].
    reasons : dict of str to str
        Per axis, whether the path moves it and what became of its matched settings [-].
    drawn : dict or None
        The path figures after and their change on machines drawn from the model's
        uncertainty (:func:`tcpmm.whatif.tuning_draws.drawn_paths`); ``None`` for a model
        that carries none [um].
    margins_drawn : dict or None
        Per axis and loop, the proposal's margins over the same machines
        (:func:`tcpmm.whatif.tuning_draws.drawn_margins`); ``None`` without uncertainty
        [dB, deg].
    """

    tuned: Machine
    axes: dict
    path_before: dict
    path_after: dict
    notes: list = field(default_factory=list)
    matched: tuple = ()
    moved: tuple = ()
    reasons: dict = field(default_factory=dict)
    drawn: dict | None = None
    margins_drawn: dict | None = None

    def to_dict(self) -> dict:
        """JSON-ready summary; an axis's ``met`` is the proposal's margins met on the model
        and on every machine drawn from its uncertainty (``met_on_model`` and
        ``draws_not_met`` apart)."""
        def axis(k, v):
            drawn = (self.margins_drawn or {}).get(k)
            missed = margins_missed(drawn) if drawn else None
            return {**v.to_dict(), "met": bool(v.met and not missed), "met_on_model": v.met,
                    "draws_not_met": missed, "reason": self.reasons.get(k),
                    "margins_after_drawn": drawn}

        return {"axes": {k: axis(k, v) for k, v in self.axes.items()},
                "matched_axes": list(self.matched), "moved_axes": list(self.moved),
                "path_before_um": self.path_before, "path_after_um": self.path_after,
                "path_drawn_um": self.drawn, "notes": list(self.notes)}

    def to_pandas(self):
        """Table: per axis, gains, margins and bandwidths before and after (SI gains;
        dB, deg, Hz); then the path figures [um]."""
        import pandas as pd

        rows = []
        for name, t in self.axes.items():
            for key in ("K_vp", "K_vi", "K_pp", "k_ff"):
                rows.append((name, key, getattr(t.before, key), getattr(t.after, key)))
            for loop in ("velocity", "position"):
                b, a = t.margins_before[loop].to_dict(), t.margins_after[loop].to_dict()
                rows += [(name, f"{loop}_{k}", b[k], a[k]) for k in b]
        for case, figs in self.path_before.items():
            rows += [("path", f"{case}_{k}", v, self.path_after[case][k])
                     for k, v in figs.items()]
        return pd.DataFrame(rows, columns=["axis", "quantity", "before", "after"])

    def plot(self, ax=None, path=None):
        """Open velocity loops before and after, per axis; the figure.

        Parameters
        ----------
        ax : matplotlib Axes or array-like of Axes, optional
            Two per axis (magnitude over phase); a new figure when omitted [-].
        path : str or Path, optional
            Also save it there (PNG/PDF/SVG) [-].
        """
        from ..plot.tune import plot_tuning  # tcpmm.plot is a floor above this one

        return plot_tuning(self, path, ax=ax)


def tune_and_predict(machine: Machine, gm_db: float, pm_deg: float, command=None,
                     axes=None, jobs: int | None = 1) -> TuneResult:
    """Propose servo settings and predict the path before and after.

    Parameters
    ----------
    machine : Machine
        The model [SI].
    gm_db : float
        Required gain margin of both loops, in (0, 40] [dB].
    pm_deg : float
        Required phase margin of both loops, in (0, 90) [deg].
    command : Command, optional
        Path to predict; default the paper's circle [m].
    axes : str or sequence of str, optional
        The contouring axes, whose position gains and feedforward are matched, e.g.
        ``"XY"``; default the axes the path moves (:mod:`tcpmm.whatif.tuning_axes`) [-].
    jobs : int, optional
        Processes for the axes' own loops (:func:`tcpmm.servo.tune.tune_machine`) [-].

    Returns
    -------
    TuneResult
        The tuned machine, the proposal per axis and the path figures [-].
    """
    circle = command is None
    cmd = paper_circle_command(machine, SETTLED_TURNS) if circle else command
    moved = moved_axes(machine, cmd)
    matched = moved if axes is None else contouring_axes(machine, axes)
    roles = (tuple(matched), tuple(moved))
    axes, named = tune_axes(machine, gm_db, pm_deg, matched, jobs), axes is not None
    tuned = machine.model_copy(update={"axes": {
        n: a.replace(servo=axes[n].after) for n, a in machine.axes.items()}})
    if circle and not {"X", "Y"} <= set(machine.axes):  # no XY plane to run the circle in
        lacks = " and ".join(sorted({"X", "Y"} - set(machine.axes)))
        note = (f"no circle predicted: the machine has no {lacks} axis; give a program "
                "(--gcode) to predict its path")
        return TuneResult(tuned, axes, {}, {}, [note], tuple(matched), (),  # no path
                          axis_reasons(axes, matched, moved, named, path=False),
                          margins_drawn=drawn_margins(machine, tuned, gm_db, pm_deg))
    # the feedforward is judged on the path: only for the contouring axes it moves
    met = [n for n in matched if n in moved and axes[n].met]
    tuned, after, dropped, spread = _best_feedforward(tuned, met, cmd, circle)
    axes = {n: replace(t, after=tuned.axes[n].servo) if n in met else t
            for n, t in axes.items()}
    runs = (after, dropped, spread)
    notes = left_out_note(matched, moved) + _matched_notes(tuned, axes, matched, met, runs,
                                                           circle)
    before = path_figures(machine, cmd, circle)
    axes = costed(tuned, axes, (met, dropped), (cmd, circle), (_worst(before), _worst(after)))
    settled = bool(_grown(before, after)) and all(meets_margins(  # read only if it grew
        machine.axes[n].mechanics, machine.axes[n].servo, gm_db, pm_deg) for n in axes)
    notes += _path_notes(before, after, axes, gm_db, pm_deg, dropped, settled,
                         _unmatched(machine, tuned, matched, moved), unheld_loads(tuned))
    drawn = drawn_paths(machine, tuned, cmd, circle)
    notes += drawn_note(drawn, before, after) + (_faster_note(machine, tuned) if circle else [])
    return TuneResult(tuned, axes, before, after, notes, *roles,
                      axis_reasons(axes, matched, moved, named, _worst(after) < float("inf"),
                                   spread > FEEDFORWARD_RESOLUTION_UM, dropped),
                      drawn, drawn_margins(machine, tuned, gm_db, pm_deg))


def _matched_notes(tuned: Machine, axes: dict, matched: list, met: list, runs: tuple,
                   circle: bool) -> list:
    """The notes on the matched settings: the feedforward chosen for the axes ``met`` (with
    the path figures and the fractions left out, ``runs``), and position gains the
    ``matched`` axes do not share [-]."""
    notes = []
    after, dropped, spread = runs
    what = "largest contour error of the circle passes" if circle else \
        "RMS deviation from the program's path"
    if met and spread <= FEEDFORWARD_RESOLUTION_UM:
        kept = ", ".join(f"{n} {tuned.axes[n].servo.k_ff:g}" for n in met)
        notes.append(f"feedforward kept (k_ff {kept}): k_ff = "
                     f"{', '.join(f'{k:g}' for k in FEEDFORWARD_GRID)} give the {what} within "
                     f"{spread:.2g} µm of each other, so the path does not judge it")
    elif met and _worst(after) < float("inf"):
        # one fraction for the axes it is chosen for: the note belongs to them all at once
        k_ff = tuned.axes[met[0]].servo.k_ff
        notes.append(f"feedforward k_ff = {k_ff:g} on axes {', '.join(met)}: of k_ff = "
                     f"{', '.join(f'{k:g}' for k in FEEDFORWARD_GRID)} it gives the smallest "
                     f"{what} ({_worst(after):.2f} µm); it does not change the margins"
                     + _dropped_words(dropped))
    kpp = {n: axes[n].after.K_pp for n in matched}
    if kpp and max(kpp.values()) > min(kpp.values()) * (1 + 1e-9):
        kept = [n for n in matched if not axes[n].met]
        notes.append("the axes do not share one position gain ("
                     + ", ".join(f"{n} {v:.4g}" for n, v in kpp.items()) + " 1/s): "
                     + (f"{', '.join(kept)} keep their settings; " if kept else "")
                     + "a path through axes of different position gains is distorted (a "
                       "circle becomes an ellipse); give them one by hand")
    return notes


def _unmatched(machine: Machine, tuned: Machine, matched, moved) -> tuple:
    """The position gains of the axes the path moves, as text, and the remedy, where the
    proposal leaves them different and the settings before did not; ``()`` otherwise [-]."""
    before = {n: machine.axes[n].servo.K_pp for n in moved}
    after = {n: tuned.axes[n].servo.K_pp for n in moved}
    if len(after) < 2 or max(after.values()) <= min(after.values()) * (1 + 1e-9) or \
            max(before.values()) > min(before.values()) * (1 + 1e-9):
        return ()
    fix = ("name every axis it moves in --axes" if set(moved) - set(matched) else
           "give them one position gain by hand")
    return ", ".join(f"{n} {v:.4g}" for n, v in after.items()) + " 1/s", fix


def _path_notes(before: dict, after: dict, axes: dict, gm_db: float, pm_deg: float,
                dropped: dict, settled: bool, unmatched: tuple = (), unheld=None):
    """Notes on the paths before and after: one that is no prediction and why, and the
    figures the proposal makes worse (:func:`_worse_note`; ``unmatched``: the path's
    position gains the proposal leaves different, :func:`_unmatched`; ``unheld``: the
    axes that cannot hold their load, :func:`.runaway.unheld_loads`) [-]."""
    notes = unheld_words(unheld or {})
    if _worst(before) == float("inf"):
        why = "; ".join(before.faults) or "its run holds no circle to measure"
        notes.append(f"before: the settings as they are are no prediction on the model "
                     f"({why}), so their path is left out")
    kept = [n for n, t in axes.items() if not t.met]
    if _worst(after) == float("inf"):
        why = "; ".join(after.faults) or "its run holds no circle to measure"
        keep = "" if before.limited else "keep the settings, or "
        held = (f"raise the current limit of {', '.join(unheld)} (above); then " if unheld
                else "")
        notes.append(f"after: the proposal's path is no prediction ({why}): " + (
            f"{held}{keep}lower the gains or the feed until the current stays within its "
            "limit" if after.limited else
            f"{', '.join(kept)} keep{'s' if len(kept) == 1 else ''} settings that no gain "
            "meeting the margins replaces; tune by hand" if kept else
            f"the margins asked, {gm_db:g} dB / {pm_deg:g} deg, leave this machine's loops "
            "too slow; ask for smaller ones"))
    limited = any(f.limited for f in dropped.values())
    return notes + _worse_note(before, after, axes, (gm_db, pm_deg), limited, settled,
                               unmatched)


def _dropped_words(dropped: dict) -> str:
    """What the feedforward fractions left out of the choice did: ``""`` for none [-]."""
    if not dropped:
        return ""
    return (f"; k_ff = {', '.join(f'{k:g}' for k in dropped)} left out: their path is no "
            f"prediction ({'; '.join(next(iter(dropped.values())).faults)})")


#: Feed of the second circle the proposal is checked on: the paper's faster one [mm/min].
FASTER_FEED_MM_PER_MIN = 10000.0


def _faster_note(machine: Machine, tuned: Machine) -> list[str]:
    """A note where the proposal, chosen on the paper's circle, makes the same circle at
    :data:`FASTER_FEED_MM_PER_MIN` worse [-]."""
    cmd = circle_test_command(mm_to_m(RADIUS_MM), FASTER_FEED_MM_PER_MIN / 6e4,
                              turns=SETTLED_TURNS)
    grown = _grown(path_figures(machine, cmd, True), path_figures(tuned, cmd, True))
    if not grown:
        return []
    return [f"at F{FASTER_FEED_MM_PER_MIN:g} the proposal's circle is worse: "
            + "; ".join(grown) + " (chosen on the F5000 circle; judge your own feed with "
            "--gcode)"]


def _grown(before: dict, after: dict) -> list[str]:
    """The figures of a path that grow by more than 2 % and 0.1 um, as text [-]."""
    out = []
    for case, figs in before.items():
        for key, b in figs.items():
            a = after.get(case, {}).get(key, float("nan"))
            if np.isfinite(b) and np.isfinite(a) and a > b * 1.02 + 0.1:
                out.append(f"{case} {key.removesuffix('_um').replace('_', ' ')} "
                           f"{b:.2f} -> {a:.2f} µm")
    return out


def _worse_note(before: dict, after: dict, axes: dict, margins: tuple, limited: bool,
                settled: bool, unmatched: tuple = ()):
    """A note where a figure of the proposal's path is worse than the settings' before (any
    of them: a program's largest deviation can double while its RMS falls): where the
    proposal leaves the path's axes with different position gains (``unmatched``: their
    gains and the remedy, :func:`_unmatched`), that first; the margins it restores, and
    how to trade them back; where the current limit held the feedforward back
    (``limited``), that it is not the margins; where the settings meet them already, also
    with the modes off (``settled``), to keep the settings [-]."""
    gm_db, pm_deg = margins
    grown = _grown(before, after)
    if not grown or _worst(before) == float("inf"):
        return []
    if unmatched:
        gains, fix = unmatched
        return [f"the predicted path is worse after: {'; '.join(grown)}; the axes it moves "
                f"end with different position gains ({gains}), and a path through axes of "
                f"different gains is distorted (a circle becomes an ellipse): {fix}"]
    short = []
    for name, t in axes.items():
        for loop, m in t.margins_before.items():
            d = m.to_dict()
            if d["phase_margin_deg"] < pm_deg or d["gain_margin_db"] < gm_db:
                short.append(f"{name} {loop} {_below(d['gain_margin_db'], gm_db)} dB / "
                             f"{_below(d['phase_margin_deg'], pm_deg)} deg")
    tol = current_tolerance()
    meet = (f"the settings before meet {gm_db:g} dB / {pm_deg:g} deg already"
            + (f", also with the modes up to {100 * tol:g} % off the model's frequencies,"
               if tol > 0 else "") + " and predict the smaller error")
    if not short and not limited and settled:
        return [f"the predicted path is worse after: {'; '.join(grown)}; {meet}: keep them, "
                "unless the proposal's velocity loops are wanted for their stiffness against "
                "the cutting forces"]
    why = (f"the settings before leave less than {gm_db:g} dB / {pm_deg:g} deg ("
           + "; ".join(short) + "), and the proposal buys the margins with it") if short else \
        meet if settled else ("the settings before meet them as modelled but not with the "
                              "modes off the model's frequencies, and the proposal buys that "
                              "with it")
    trade = ("the current limit holds the feedforward back (above), not the margins: keep "
             "the settings or raise the limit" if limited else
             "smaller margins (--margins) trade some back")
    return [f"the predicted path is worse after: {'; '.join(grown)}; {why}; {trade}"]


def _below(value: float, need: float) -> str:
    """``value`` to one decimal, or to as many more (up to four) as keep a value short of
    ``need`` from reading as it: 5.957 dB against 6 dB reads 5.96, not 6.0 [-]."""
    n = 1
    while n < 4 and value < need <= round(value, n):
        n += 1
    return f"{value:.{n}f}"


def _worst(figures: dict) -> float:
    """The figure a path is judged by: the largest contour error of the circle passes, or
    the RMS deviation from a program's path; infinite for a run that is no prediction
    [um]."""
    keys = ("contour_error_um", "rms_deviation_um")
    v = max(v[k] for v in figures.values() for k in keys if k in v)
    return v if v == v else float("inf")


def _best_feedforward(tuned: Machine, names: list, cmd, circle: bool):
    """Feedforward fraction of :data:`FEEDFORWARD_GRID` (the same for the axes ``names``)
    with the smallest :func:`_worst` on the path; the machine and its path figures, the
    fractions that are no prediction and the spread of the others' figures. Where that
    spread stays within :data:`FEEDFORWARD_RESOLUTION_UM` the path does not judge the
    feedforward: the machine keeps its own. The feedforward acts outside the loops: the
    margins stay as they are."""
    if not names:
        return tuned, path_figures(tuned, cmd, circle), {}, float("inf")
    tried, dropped = [], {}
    for k in FEEDFORWARD_GRID:
        m = tuned.model_copy(update={"axes": {
            n: (a.replace(servo=a.servo.model_copy(update={"k_ff": k}))
                if n in names else a) for n, a in tuned.axes.items()}})
        figs = path_figures(m, cmd, circle)
        if figs.faults:
            dropped[k] = figs
        tried.append((m, figs))
    worst = [_worst(f) for _, f in tried]
    best = tried[min(range(len(tried)), key=worst.__getitem__)]  # the first of the least
    if _worst(best[1]) == float("inf"):  # no fraction is a prediction: none is chosen
        return tuned, _own_figures(tuned, names, tried, cmd, circle), dropped, float("inf")
    spread = max(worst) - min(worst)
    if spread <= FEEDFORWARD_RESOLUTION_UM:
        return tuned, _own_figures(tuned, names, tried, cmd, circle), dropped, spread
    return (*best, dropped, spread)


def _own_figures(tuned: Machine, names: list, tried: list, cmd, circle: bool):
    """The path figures of ``tuned`` with its own feedforward: those the grid ran where
    every axis of ``names`` has one fraction of it (the same machine), else run [-]."""
    for k, (_, figs) in zip(FEEDFORWARD_GRID, tried, strict=True):
        if all(tuned.axes[n].servo.k_ff == k for n in names):
            return figs
    return path_figures(tuned, cmd, circle)
