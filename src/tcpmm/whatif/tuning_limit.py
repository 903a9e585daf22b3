"""What the current limit costs a tuning proposal: the feedforward it holds down, and the
raised velocity gain that drives the current to the limit.

A faster velocity loop draws more current on the same path. A feedforward fraction whose
path holds a current at its limit is no prediction and is left out of the choice
(:func:`tcpmm.whatif.tuning._best_feedforward`); where that leaves an axis a smaller
fraction than its settings', its reason says so, and where an axis's raised ``K_vp`` is what
holds the current at its limit with the settings' fraction (with its ``K_vp`` and ``K_vi``
as before it does not), the note of that gain says what it costs the path.
"""

from __future__ import annotations

from dataclasses import replace

from ..model import Machine
from .tuning_paths import path_figures


def held_down(dropped: dict, k_ff: float) -> list:
    """The fractions above ``k_ff`` left out because their path holds a current at its
    limit, smallest first [-]."""
    return sorted(k for k, f in dropped.items() if f.limited and k > k_ff)


def held_words(dropped: dict, k_ff: float) -> str:
    """Why the feedforward chosen is ``k_ff`` where the current limit left out the larger
    fractions: ``""`` where it did not [-]."""
    held = held_down(dropped, k_ff)
    if not held:
        return ""
    faults = list(dict.fromkeys(x for k in held for x in dropped[k].faults))
    return (f", held down by the current limit: k_ff = {', '.join(f'{k:g}' for k in held)} "
            f"left out ({'; '.join(faults)})")


def _with(machine: Machine, servo: dict) -> Machine:
    """``machine`` with the settings of ``servo`` (axis name to a dict of them) [SI]."""
    return machine.model_copy(update={"axes": {
        n: (a.replace(servo=a.servo.model_copy(update=servo[n])) if n in servo else a)
        for n, a in machine.axes.items()}})


def gain_costs(tuned: Machine, axes: dict, chosen: tuple, path: tuple, change: tuple) -> dict:
    """Per axis of ``met`` whose raised ``K_vp`` holds its current at its limit with the
    settings' feedforward (with its ``K_vp`` and ``K_vi`` as before it does not), the
    words its ``K_vp`` note ends with [-].

    Parameters
    ----------
    tuned : Machine
        The proposal, with the feedforward chosen [SI].
    axes : dict of str to AxisTuning
        The proposals [-].
    chosen : tuple of (list of str, dict)
        The axes the feedforward was chosen for, and the fractions left out of the choice
        with their path figures [-].
    path : tuple
        The command and whether it is the circle (:func:`path_figures`) [-].
    change : tuple of (float, float)
        The figure the path is judged by (:func:`tcpmm.whatif.tuning._worst`), before
        and after [um].
    """
    met, dropped = chosen
    if not any(held_down(dropped, axes[n].after.k_ff) for n in met):
        return {}
    own = {n: {"k_ff": axes[n].before.k_ff} for n in met}
    first = path_figures(_with(tuned, own), *path)
    out = {}
    for n in met:
        b, a = axes[n].before, axes[n].after
        if a.K_vp <= b.K_vp or a.k_ff >= b.k_ff or not _held(first, n):
            continue
        if _held(path_figures(_with(tuned, {**own, n: {**own[n], "K_vp": b.K_vp,
                                                        "K_vi": b.K_vi}}), *path), n):
            continue  # not this gain: the current is held at its limit without it
        what = ("largest contour error of the circle passes" if path[1] else
                "RMS deviation from the program's path")
        was, now = change
        cost = (f" and the {what} grows from {was:.2f} to {now:.2f} µm"
                if was < now < float("inf") else "")
        out[n] = (f"; with it the settings' feedforward (k_ff {b.k_ff:g}) holds this axis's "
                  f"current at its limit of {a.current_limit:g} A, with K_vp {b.K_vp:.4g} it "
                  f"does not: k_ff falls to {a.k_ff:g}{cost}")
    return out


def _held(figures, name: str) -> bool:
    """Whether the run of ``figures`` holds axis ``name``'s current at its limit [-]."""
    return figures.limited and any(f.startswith(f"axis {name} holds its current")
                                   for f in figures.faults)


def costed(tuned: Machine, axes: dict, chosen: tuple, path: tuple, change: tuple) -> dict:
    """``axes`` with the ``K_vp`` note of each axis :func:`gain_costs` names ending with
    what that gain costs the path (the parameters are its) [-]."""
    costs = gain_costs(tuned, axes, chosen, path, change)
    return {n: replace(t, notes=[x + costs[n] if x.startswith("K_vp ") else x
                                 for x in t.notes]) if n in costs else t
            for n, t in axes.items()}
