"""A corrected command that turns an axis back only where the program does.

A drive fires its friction pulse at every reversal of the commanded velocity
(:func:`.drive.reversal_pulses`). A correction learned with the pulse on the controller
may turn the axis back where the program does not: where the program holds an axis, or
ends a move, it asks for a command that swings as a mode settles (bench R05 at F3000 on
R 35 mm: X turned 26 times where the program turns 3). Each swing fires a pulse into an
axis its friction holds, and on friction the model has wrong that pulse pushes the axis
where nothing else moves it: the TCP at rest ended 44.8 um off, against 23.1 um
uncompensated, where the model predicted 14.8 um.

So with the pulse on, each learning step projects the corrected command, stretch by
stretch between the program's reversals, onto the commands that do not turn there:

- about each reversal of the program, for as long as the pulse acts, the correction is
  free: it shapes the reversal with the pulse, and the turns it adds fire while the
  friction turns anyway (held to the program's direction there too, the correction lost
  half its gain on bench R05's spike);
- where the program holds the axis (:func:`holds`), onto the nearer of the commands that
  move one way only, free to turn at its ends: a move ahead of the start or a pull-back
  at the end stays;
- where it moves, onto the commands that move in its direction, within the ends of the
  free windows and holds beside them.

Each is the least-squares monotone sequence (isotonic regression), clipped between its
neighbours' ends where it has them, which is the least-squares monotone sequence that
joins them; a command already so is left as it is.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import isotonic_regression

from ..path.command import Command

#: The shortest hold: shorter runs of equal positions are a reversal's or a corner's
#: samples [samples]
MIN_HOLD = 3


def reversals(command: Command, axis: str) -> tuple:
    """The samples at which an axis's commanded velocity reverses, where a drive fires its
    friction pulse, and the sign of the velocity per sample [-]."""
    x = command.positions[axis]
    if x.size < 3:
        return np.zeros(0, np.int64), np.zeros(x.size)
    v = np.gradient(x, command.period_s)
    s = np.sign(np.where(np.abs(v) > 1e-9, v, 0.0))
    moving = np.flatnonzero(s)
    return moving[1:][s[moving[1:]] != s[moving[:-1]]], s


#: Half the span over which the acceleration at a reversal is read: the velocity's change
#: across it, which one sample's second difference would read with the command's rounding
#: and interpolation jitter [s].
ACCEL_HALF_SPAN_S = 0.005


def reversal_accelerations(command: Command, axis: str, turns: np.ndarray) -> np.ndarray:
    """The magnitude of the axis's commanded acceleration at each of its reversals
    ``turns`` (samples), what a quadrant-error compensation's adaptation characteristic
    is a function of: the velocity's change across :data:`ACCEL_HALF_SPAN_S` either side
    over that time [m/s^2]."""
    x, T = command.positions[axis], command.period_s
    v = np.gradient(x, T)
    w = max(1, round(ACCEL_HALF_SPAN_S / T))
    lo, hi = np.maximum(turns - w, 0), np.minimum(turns + w, x.size - 1)
    return np.abs(v[hi] - v[lo]) / np.maximum((hi - lo) * T, T)


def stretches(reference, period_s: float) -> list[tuple[int, int, float]]:
    """The program's stretches between its reversals: ``(start, stop, direction)``, the
    direction +1 or -1 of the axis's motion there, 0 for an axis the program never moves
    [-, -, -].

    Parameters
    ----------
    reference : ndarray
        The programmed position of one axis [m].
    period_s : float
        Its sample period [s].
    """
    n = np.size(reference)
    time_s = period_s * np.arange(n)
    turns, s = reversals(Command(time_s, {"A": np.asarray(reference, float)}), "A")
    moving = np.flatnonzero(s)
    if moving.size == 0:
        return [(0, n, 0.0)]
    edges = [0, *turns.tolist(), n]
    first = [float(s[moving[0]])] + [float(s[i]) for i in turns]
    return [(a, b, d) for a, b, d in zip(edges[:-1], edges[1:], first, strict=True) if b > a]


def holds(reference) -> list[tuple[int, int]]:
    """The stretches ``[start, stop)`` over which the program holds the axis: runs of at
    least :data:`MIN_HOLD` equal positions [-].

    Parameters
    ----------
    reference : ndarray
        The programmed position of one axis [m].
    """
    same = np.diff(np.asarray(reference, float)) == 0.0
    edges = np.flatnonzero(np.diff(np.r_[0, same.astype(np.int8), 0]))
    return [(int(a), int(b) + 1) for a, b in zip(edges[::2], edges[1::2], strict=True)
            if b + 1 - a >= MIN_HOLD]


def pieces(reference, period_s: float, free_s: float) -> list[tuple[int, int, float]]:
    """The pieces the projection holds to one direction, in order: ``(start, stop,
    direction)``, direction 0 for a hold (either way) (module docstring) [-].

    Parameters
    ----------
    reference : ndarray
        The programmed position of one axis [m].
    period_s : float
        Its sample period [s].
    free_s : float
        Half the window about each reversal of the program left free [s].
    """
    n, k = np.size(reference), round(free_s / period_s)
    held = np.zeros(n, bool)
    for a, b in holds(reference):
        held[a:b] = True
    out = []
    for a, b, d in stretches(reference, period_s):
        lo, hi = a + (k if a > 0 else 0), b - (k if b < n else 0)
        if hi <= lo:
            continue
        cuts = lo + np.flatnonzero(np.diff(held[lo:hi].astype(np.int8))) + 1
        for u, v in zip([lo, *cuts], [*cuts, hi], strict=True):
            out.append((int(u), int(v), 0.0 if held[u] else d))
    return out


def without_new_turns(reference, position, period_s: float, free_s: float = 0.0):
    """``position`` projected onto the commands that turn the axis back only where the
    program does, or within ``free_s`` of it (module docstring) [m].

    Parameters
    ----------
    reference : ndarray
        The programmed position of the axis [m].
    position : ndarray
        The corrected command of the axis [m].
    period_s : float
        The sample period [s].
    free_s : float
        Half the window about each reversal of the program left free [s].
    """
    return held_to(pieces(reference, period_s, free_s), position)


def held_to(parts, position) -> np.ndarray:
    """``position`` projected piece by piece onto the commands that do not turn within
    the pieces ``parts`` of :func:`pieces` (module docstring) [m]."""
    out = np.array(position, float)
    for a, b, d in parts:
        y = out[a:b]
        if b - a < 2:
            continue
        if d == 0.0:  # a hold may turn at its ends: it is not joined to its neighbours
            if not (np.all(np.diff(y) >= 0.0) or np.all(np.diff(y) <= 0.0)):
                out[a:b] = _nearer(y)
        elif not (np.all(d * np.diff(y) >= 0.0) and _joins(out, a, b, d)):
            z = isotonic_regression(y, increasing=d > 0).x
            out[a:b] = np.clip(z, *_bounds(out, a, b, d))
    return out


def _nearer(y) -> np.ndarray:
    """The nearer to ``y`` of its least-squares monotone sequences, up or down [m]."""
    up, down = (isotonic_regression(y, increasing=u).x for u in (True, False))
    return up if np.sum((up - y) ** 2) <= np.sum((down - y) ** 2) else down


def _bounds(out, a: int, b: int, d: float) -> tuple[float, float]:
    """The values a piece ``[a, b)`` of direction ``d`` may take to join its neighbours'
    ends without a turn [m]."""
    before = out[a - 1] if a > 0 else (-np.inf if d > 0 else np.inf)
    after = out[b] if b < out.size else (np.inf if d > 0 else -np.inf)
    return (before, after) if d > 0 else (after, before)


def _joins(out, a: int, b: int, d: float) -> bool:
    """Whether the piece ``[a, b)`` lies between its neighbours' ends [-]."""
    low, high = _bounds(out, a, b, d)
    return bool(low <= out[a:b].min() and out[a:b].max() <= high)
