"""Shares of the correction chosen region by region, where one share per axis would be held
back by its worst region.

One share per axis (:func:`.robust.choose`) must be vouched for in every region at once: a
corner where the correction cannot help (the lead-in's kink into a circle, limited by the
axes' acceleration) keeps the whole path uncorrected. Here each region takes the shares
whose worst draw there is smallest among those the draws vouch for in that region
(:func:`.robust.vouched`), read off the runs of each share alone; the shares change
between regions on a ramp that lies inside the region of the larger share (an erosion,
then a smoothing of the same length), so a region never gets more than it chose. What a
region's correction does to the next one is not in those runs: the composed command is
therefore run on every draw, and each region the draws do not vouch for on it, and the one
before it, is given a step less (every region, where only a circle's spike or G is not
vouched for), until every region, spike and G are, or :data:`ROUNDS` are spent and the
shares per axis stay.
"""

from __future__ import annotations

import itertools

import numpy as np
from scipy.ndimage import minimum_filter1d

from .learning import plain

#: Length of the ramp between the shares of two regions [s].
RAMP_S = 0.03

#: Rounds of running the composed command and lowering the regions it leaves worse [-].
ROUNDS = 12


def profile(shares: np.ndarray, labels: np.ndarray, period_s: float) -> np.ndarray:
    """Share per sample from one share per region: held within a region, ramped between
    two inside the one of the larger share, and never above the region's own [-].

    Parameters
    ----------
    shares : ndarray
        Share per region [-].
    labels : ndarray of int
        Region per sample [-].
    period_s : float
        Sample period [s].
    """
    f = np.asarray(shares, dtype=float)[labels]
    w = max(3, round(RAMP_S / period_s)) | 1
    low = minimum_filter1d(f, size=w, mode="nearest")
    kernel = np.hanning(w + 2)[1:-1]
    smooth = np.convolve(np.pad(low, w // 2, mode="edge"), kernel / kernel.sum(), "valid")
    return np.minimum(smooth, f)


def per_combo(errs: np.ndarray, judge) -> dict:
    """``{combo: judge(combo)}`` for every combination of share levels per axis [-]."""
    n_ax, n_lev = errs.shape[1], errs.shape[2]
    return {c: judge(c) for c in itertools.product(range(n_lev), repeat=n_ax)}


def pick(per: dict, before: np.ndarray, n_reg: int, vouched, margin) -> np.ndarray:
    """Per region the combination of share levels whose worst draw there is smallest,
    lower than before by more than ``margin``, among those ``vouched`` for there; none
    (zeros) where no combination is, shape (regions, axes) [-]."""
    n_ax = len(next(iter(per)))
    out = np.zeros((n_reg, n_ax), dtype=int)
    for r in range(n_reg):
        b = before[:, r]
        best = b.max() - margin(b.max())
        for c, figs in per.items():
            a = figs[:, r]
            if a.max() < best and vouched(b, a):
                out[r], best = c, a.max()
    return out


def tcp_errors(machines, comp, commands: dict, plants=None, progress=None) -> np.ndarray:
    """TCP error per machine, axis and sample of the position ``commands`` per axis, the
    path to follow less the TCP, shape (machines, axes, n); each axis run as ``plants``
    says (:func:`.learning.learn_axis`), default the command alone, its feedback quantised
    as ``tcpmm simulate`` runs it; ``progress`` called with no argument after each
    machine [m].

    The learning runs unquantised, so that the error it learns from is not the sensors'
    rounding; what the draws say after it is said of the machine, whose position loop
    reads counts: on the built-in machine (a scale of 1 µm) the TCP's overshoot past a
    circle's end is 0.91 µm unquantised and 1.06 µm as the machine runs, apart by more
    than the resolution the draws judge a figure's rise to."""
    t = comp.reference.time_s
    axes = comp.reference.axes
    out = np.empty((len(machines), len(axes), t.size))
    for i, m in enumerate(machines):
        for j, a in enumerate(axes):
            run = (plants or {}).get(a, plain)(m.axes[a], t, commands[a],
                                               quantise_feedback=True)
            y = run.tcp
            out[i, j] = comp.target.positions[a] - y
        if progress is not None:
            progress()
    return out


def composed_errors(machines, comp, factors: dict, plants=None) -> np.ndarray:
    """:func:`tcp_errors` of the command with the share ``factors`` per axis and sample,
    as :meth:`Compensation.command_with` makes it [m]."""
    return tcp_errors(machines, comp, comp.command_with(factors).positions, plants)


def settle_regions(machines, comp, levels: np.ndarray, labels: np.ndarray, before, check,
                   judge_errors, steps, plants=None, progress=None):
    """The composed command lowered region by region until ``check(before, after)`` names
    no region and passes the circle (module docstring); ``(factors, after, the TCP errors
    per machine, axis and sample after)``, or ``None``.

    Parameters
    ----------
    machines : list of Machine
        The model and its draws [SI].
    comp : Compensation
        The compensation [-].
    levels : ndarray of float
        Share per region and axis, shape (regions, axes) [-].
    labels : ndarray of int
        Region per sample [-].
    before : ndarray
        The figures uncompensated (:func:`.robust.judged`) [m].
    check : callable
        ``(before, after, TCP errors after) -> (bad regions, circle vouched)`` [-].
    judge_errors : callable
        The figures of composed errors [m].
    steps : tuple of float
        The shares a region may take, ascending [-].
    plants : dict, optional
        Per axis how it runs a command [-].
    progress : callable, optional
        Called with no argument after each round run, at most :data:`ROUNDS` times [-].
    """
    axes = comp.reference.axes
    levels = levels.copy()
    for _ in range(ROUNDS):
        factors = {a: profile(levels[:, j], labels, comp.reference.period_s)
                   for j, a in enumerate(axes)}
        errors = composed_errors(machines, comp, factors, plants)
        after = judge_errors(errors)
        if progress is not None:
            progress()
        bad, circle_ok = check(before, after, errors)
        if not bad and circle_ok:
            return factors, after, errors
        # a region's error is also the correction of the one before it, still settling;
        # a circle's spike and G are of every region at once
        lower = ({q for b in bad for q in (b - 1, b) if q >= 0} if bad
                 else range(levels.shape[0]))
        for r in lower:
            levels[r] = _lower(levels[r], steps)
        if not levels.any():
            return None
    return None


def _lower(shares: np.ndarray, steps) -> np.ndarray:
    """Each share one step of ``steps`` lower, none below 0 [-]."""
    return np.array([max([0.0, *[v for v in steps if v < s]]) for s in shares])
