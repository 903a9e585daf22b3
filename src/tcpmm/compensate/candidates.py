"""The correction learned two ways within the axes' limits, and the one the draws vouch
more for kept.

Where the program leaves an axis too little room for the correction, the learning scales
back either its fast part alone, keeping the slow part (the servo's lag, the structure's
deflection), or the whole (:func:`.bounds.fit_within`, :func:`.bounds.scaled_within`).
Neither is better on every machine. Keeping the slow part let bench C's circle at F10000
keep its whole correction on the draws (contour error 269.6 -> 88.1 µm on the true
machine, where scaled back whole the draws kept none: the lag came back about every
reversal and the spikes doubled). Kept through the stop at the end of the built-in
machine's R 20 mm circle at F5000, it ran the model's TCP past the path's end, and the
corners' guard (:mod:`.cornerguard`) then kept none of it, where scaled back whole three
quarters and more of it were kept. So both are learned and scaled back over the same
draws (:func:`.robust.robust_factors`), and the one whose worst draw leaves the smaller
contour error over the path is kept; the other only where it is lower by more than the
margin (:func:`.robust.margin`) of that error.
"""

from __future__ import annotations

from .learning import compensate
from .robust import margin, robust_factors

__all__ = ["compensate_within_draws", "worst_after"]


def worst_after(comp) -> float:
    """The largest contour error after the shares kept, over the regions and the draws
    (:func:`.robust.robust_factors`'s ``regions``) [m]."""
    return max(r["worst_after_um"] for r in comp.robustness["regions"]) * 1e-6


def compensate_within_draws(machine, command, *, n_draws: int, bounds=None,
                            iterations: int = 30, seed: int = 0, **where):
    """The compensation of ``command`` learned with the fast part scaled back first and
    with the whole, each scaled back over ``n_draws`` draws; the one whose worst draw
    leaves less contour error kept (module docstring). Without draws, the first alone.

    Parameters
    ----------
    machine : Machine
        The identified model with its uncertainty [SI].
    command : Command
        The command to compensate [m].
    n_draws : int
        Machines drawn from the uncertainty; 0 for the model alone [-].
    bounds : dict of str to AxisBounds, optional
        The axes' limits; default the model's [-].
    iterations : int
        Learning steps per axis [-].
    seed : int
        Seed of the draws [-].
    **where
        ``radius_m``, ``centre_m``, ``plane`` of a circle (:func:`.robust.robust_factors`).

    Returns
    -------
    Compensation
        With its shares and robustness [-].
    """
    first = compensate(machine, command, iterations=iterations, bounds=bounds)
    if n_draws <= 0:
        return first
    robust_factors(machine, first, n_draws=n_draws, seed=seed, **where)
    other = compensate(machine, command, iterations=iterations, bounds=bounds,
                       keep_slow=False)
    if all((first.correction[a] == other.correction[a]).all() for a in first.correction):
        return first  # the limits left room: the two are the same
    robust_factors(machine, other, n_draws=n_draws, seed=seed, **where)
    a, b = worst_after(first), worst_after(other)
    return other if b < a - float(margin(a)) else first
