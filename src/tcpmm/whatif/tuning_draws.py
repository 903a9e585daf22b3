"""A tuning proposal judged on machines drawn from an identified model's uncertainty.

The path figures before and after (:func:`tcpmm.whatif.tuning_paths.path_figures`) are the
model's; the machine is not the model. Each machine drawn (:mod:`tcpmm.whatif.draws`, with
the floors of :data:`tcpmm.whatif.draws.MODEL_ERROR`, as ``tcpmm spread`` draws) runs the
path with the settings before and with the proposal's; the range of each figure after,
and of its change, say how far the prediction may be off and whether the proposal helps on
every draw. The change is taken draw by draw: the same machine with both settings.
The proposal's margins are taken on the same machines (:func:`drawn_margins`): met on
the model, they are met on the machine only as far as the model is right.
"""

from __future__ import annotations

import numpy as np

from ..model import Machine
from ..servo.margins import axis_margins
from .draws import MODEL_ERROR, draw_machine
from .tuning_paths import path_figures

#: Machines drawn from the model's uncertainty that a proposal is judged on [-].
TUNE_DRAWS = 8
#: A figure that grows by more than this share and :data:`WORSE_UM` is worse [-].
WORSE_SHARE = 0.02
#: ... and by more than this [um].
WORSE_UM = 0.1


def drawn_paths(machine: Machine, tuned: Machine, command, circle: bool,
                n: int = TUNE_DRAWS, seed: int = 0) -> dict | None:
    """The path figures before and after the proposal on ``n`` machines drawn from the
    model's uncertainty; ``None`` for a model that carries none.

    Parameters
    ----------
    machine : Machine
        The model with the settings before [SI].
    tuned : Machine
        The model with the proposal's settings [SI].
    command : Command
        The path [m].
    circle : bool
        Whether the path is the paper's circle [-].
    n : int
        Number of draws [-].
    seed : int
        Seed of the draws [-].

    Returns
    -------
    dict or None
        ``draws``, ``faulty`` (draws whose run before or after is no prediction, left
        out), ``proposal_fails`` (of those, the draws the settings before run on and the
        proposal's do not: an unstable loop, an axis running away) with
        ``proposal_faults``, what goes wrong there, and per case and figure
        ``after_low``, ``after_high``, ``change_low``, ``change_high`` over the other draws
        and ``worse``: the draws on which it grows [um, -].
    """
    drawn = drawn_machines(machine, n, seed)
    if drawn is None:
        return None
    pairs = []
    for m in drawn:
        t = m.model_copy(update={"axes": {k: a.replace(servo=tuned.axes[k].servo)
                                          for k, a in m.axes.items()}})
        pairs.append((path_figures(m, command, circle), path_figures(t, command, circle)))
    return _summary(pairs)


def drawn_machines(machine: Machine, n: int = TUNE_DRAWS, seed: int = 0) -> list | None:
    """The ``n`` machines a proposal is judged on, drawn from the model's uncertainty with
    the floors of :data:`~tcpmm.whatif.draws.MODEL_ERROR`; ``None`` for a model that
    carries none. The same ``seed`` gives the same machines [SI]."""
    if all(a.uncertainty is None for a in machine.axes.values()):
        return None
    rng = np.random.default_rng(seed)
    return [draw_machine(machine, rng, MODEL_ERROR) for _ in range(n)]


def drawn_margins(machine: Machine, tuned: Machine, gm_db: float, pm_deg: float,
                  n: int = TUNE_DRAWS, seed: int = 0) -> dict | None:
    """The proposal's margins on the ``n`` machines :func:`drawn_paths` draws; ``None``
    for a model that carries no uncertainty.

    Parameters
    ----------
    machine : Machine
        The model [SI].
    tuned : Machine
        The model with the proposal's settings [SI].
    gm_db, pm_deg : float
        The margins asked [dB, deg].
    n : int
        Number of draws [-].
    seed : int
        Seed of the draws, :func:`drawn_paths`'s for the same machines [-].

    Returns
    -------
    dict or None
        Per axis and loop (``velocity``, ``position``): ``draws``, ``missed`` (the draws
        on which a margin falls short of the one asked) and ``missed_draws`` (their
        numbers, from 0), ``gain_margin_db`` and
        ``phase_margin_deg`` as ``[least, largest]`` over the draws (``None`` for an
        infinite margin) [-, dB, deg].
    """
    drawn = drawn_machines(machine, n, seed)
    if drawn is None:
        return None
    got: dict = {}
    for m in drawn:
        for name, a in m.axes.items():
            for loop, lm in axis_margins(a.mechanics, tuned.axes[name].servo).items():
                got.setdefault(name, {}).setdefault(loop, []).append(lm)
    return {name: {loop: _margin_range(v, gm_db, pm_deg) for loop, v in loops.items()}
            for name, loops in got.items()}


def _margin_range(margins: list, gm_db: float, pm_deg: float) -> dict:
    """:func:`drawn_margins`'s entry of one loop [-, dB, deg]."""
    def span(values):
        v = np.array(values, float)
        return [float(x) if np.isfinite(x) else None for x in (v.min(), v.max())]

    missed = [i for i, m in enumerate(margins) if not m.meets(gm_db, pm_deg)]
    return {"draws": len(margins), "missed": len(missed), "missed_draws": missed,
            "gain_margin_db": span([m.gain_margin_db for m in margins]),
            "phase_margin_deg": span([m.phase_margin_deg for m in margins])}


def margins_missed(drawn: dict | None) -> int:
    """The draws on which some loop of the axis misses a margin asked (each draw once,
    whichever loops miss on it), of :func:`drawn_margins`'s entry of the axis; 0 without
    draws [-]."""
    return len({i for d in (drawn or {}).values() for i in d.get("missed_draws", ())})


def _summary(pairs: list) -> dict:
    """:func:`drawn_paths`'s summary of ``(before, after)`` figures per draw [um, -]."""
    good = [(b, a) for b, a in pairs if not (b.faults or a.faults)]
    broken = [a.faults for b, a in pairs if a.faults and not b.faults]
    # what fails, without the figure of each draw: "axis X's sampled servo loop is unstable"
    kinds = [f.split(" (")[0] for faults in broken for f in faults]
    out = {"draws": len(pairs), "faulty": len(pairs) - len(good), "figures": {},
           "proposal_fails": len(broken),
           "proposal_faults": {k: kinds.count(k) for k in sorted(set(kinds))}}
    if not good:
        return out
    for case, figs in good[0][0].items():
        out["figures"][case] = {}
        for key in figs:
            b = np.array([p[0][case][key] for p in good], float)
            a = np.array([p[1][case][key] for p in good], float)
            ok = np.isfinite(a) & np.isfinite(b)
            if not ok.any():
                continue
            b, a = b[ok], a[ok]
            d = a - b
            out["figures"][case][key] = {
                "after_low": float(a.min()), "after_high": float(a.max()),
                "change_low": float(d.min()), "change_high": float(d.max()),
                "worse": int(np.sum(a > b * (1 + WORSE_SHARE) + WORSE_UM)),
                "judged": int(ok.sum())}
    return out


def drawn_note(drawn: dict | None, before: dict, after: dict) -> list[str]:
    """A note on what the draws say: the figures the proposal improves on the model but
    makes worse on some drawn machine, or that it improves them on every draw [-]."""
    if drawn and drawn.get("proposal_fails"):
        return [proposal_fails(drawn)]
    if not drawn or not drawn["figures"]:
        return []
    n = drawn["draws"] - drawn["faulty"]
    head = (f"on {n} machine{'s' if n != 1 else ''} drawn from the model's uncertainty"
            + (f" ({drawn['faulty']} more are no prediction and are left out)"
               if drawn["faulty"] else ""))
    split, level, better = [], [], 0
    for case, figs in drawn["figures"].items():
        for key, f in figs.items():
            if not after.get(case, {}).get(key, np.nan) < before.get(case, {}).get(key,
                                                                                 np.nan):
                continue
            better += 1
            name = f"{case} {key.removesuffix('_um').replace('_', ' ')}"
            if f["worse"]:
                split.append(f"{name} worse on {f['worse']} of {f['judged']}")
            elif f["change_high"] >= 0.0:
                level.append(f"{name} up to {f['change_high']:+.2f} µm")
    if not better:  # nothing the model calls better: the note on the worse path says it
        return []
    if split:
        return [f"{head}, the proposal is not better everywhere: {'; '.join(split)}; the "
                "ranges in the table say how far"]
    if level:
        return [f"{head}, the proposal is worse on no draw beyond the model's error, but "
                f"not smaller on every one: {'; '.join(level)}; the ranges in the table "
                "say how far"]
    return [f"{head}, each figure the proposal improves on the model improves on every "
            "draw; the ranges in the table say by how much"]


def proposal_fails(drawn: dict) -> str:
    """What to say where the proposal fails on machines drawn from the model's
    uncertainty that the settings before run on: its figures and margins hold on the
    model as identified only [-]."""
    said = "; ".join(f"{k} on {n} of them" for k, n in drawn["proposal_faults"].items())
    return (f"the proposal fails on {drawn['proposal_fails']} of {drawn['draws']} machines "
            f"drawn from the model's uncertainty that the settings before run on ({said}): "
            "its margins and figures hold on the model as identified, not within what "
            "identification leaves uncertain; do not apply it as it is: keep the modes' "
            "tolerance (--mode-tolerance, 5 % by default) or ask for wider margins")
