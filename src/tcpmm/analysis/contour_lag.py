"""Windows too short for the tool's lag.

The contour seeks each sample's closest command point among the command's samples within
a window of time about it. A tool that lags its command by more than that (a slow position
loop without feed-forward lags by ``1/K_v``: 0.33 s at 3/s) lies closer to the command
before the window than to any of it: its distance to the window's first segment is the
following error, not the contour error. Such a sample is found where the closest point
lies on the window's first (or last) segment and the segment just outside is closer
still. Where the window is the default, the contour widens it until no sample is cut
off; where the user gave it, the contour refuses and says what to do. A sample closer to
the command just *after* its window is no lag (a tool does not lead its command): the
path comes back near it within a little more than the window (a zig-zag's next pass
0.05 mm away), or the command's time line lags the run's; it is said so.
"""

from __future__ import annotations

import numpy as np

from .._rows import dot_rows
from ..errors import InputError

#: the window when none is given [s]
WINDOW_S = 0.2
#: the widest the default window is widened to (five doublings); a tool lagging more
#: than that is not following its command [s]
WIDEST_S = 6.4
#: closer by more than this share of the distance, plus :data:`_ABS`, is closer: two
#: segments meeting at the closest vertex give that vertex's distance to the rounding [-]
_REL = 1e-9
#: [m]
_ABS = 1e-9
#: :func:`outside_closer`'s flags: the command before the window lies closer (a tool
#: lagging), the command after it does (the path coming back near) [-]
BEHIND, AHEAD = 1, 2


def windows(window_s: float | None):
    """The windows to try in turn: ``window_s`` alone where given, else
    :data:`WINDOW_S` doubled up to :data:`WIDEST_S` [s]."""
    if window_s is not None:
        if not (np.isfinite(window_s) and window_s > 0):
            raise InputError(f"window_s must be a positive number, got {window_s}")
        return [float(window_s)]
    out = [WINDOW_S]
    while out[-1] * 2 <= WIDEST_S * (1 + 1e-12):
        out.append(out[-1] * 2)
    return out


def _segment_distance(q, a, b):
    """Distance from each point ``q`` to the segment from ``a`` to ``b`` (rows) [m]."""
    d = b - a
    rel = q - a
    ln2 = dot_rows(d, d)
    f = np.clip(np.divide(dot_rows(rel, d), ln2, out=np.zeros(ln2.shape), where=ln2 > 0),
                0.0, 1.0)
    off = rel - f[:, None] * d
    return np.sqrt(dot_rows(off, off))


def outside_closer(q, p, lo, hi, kept, dist, foot, prev=None) -> np.ndarray:
    """The samples whose closest command point lies on their window's first or last
    segment, with the segment just outside the window closer still.

    Parameters
    ----------
    q : ndarray, shape (n, d)
        The samples [m].
    p : ndarray, shape (m, d)
        The command's vertices [m].
    lo, hi : ndarray of int
        Each sample's window: the segments ``lo .. hi - 1`` (at least ``lo``) [-].
    kept : tuple of ndarray of bool
        Per sample, whether its window's start and end are the time window's, not a
        feed move's end that bounds it on purpose [-].
    dist, foot : ndarray
        The distance found (signed or not) and its segment [m], [-].
    prev : ndarray, shape (d,), optional
        The command's vertex before ``p[0]``, where ``p`` is a piece of a longer command
        [m].

    Returns
    -------
    ndarray of int8
        :data:`BEHIND` where the segment before the window is closer, :data:`AHEAD` where
        the one after it is, both or-ed, 0 elsewhere [-].
    """
    m = p.shape[0]
    last = np.minimum(np.maximum(hi, lo + 1) - 1, m - 2)
    low = kept[0] & (foot == lo) & ((lo > 0) | (prev is not None))
    high = kept[1] & (foot == last) & (last + 1 <= m - 2)
    cut = np.zeros(q.shape[0], np.int8)
    for side, i0, bit in ((low, lo - 1, BEHIND), (high, last + 1, AHEAD)):
        k = np.flatnonzero(side)
        if k.size:
            start = p[np.maximum(i0[k], 0)]
            start[i0[k] < 0] = prev  # the segment from the vertex before the piece
            out = _segment_distance(q[k], start, p[i0[k] + 1])
            held = np.abs(dist[k])
            cut[k] |= np.where(out < held - (held * _REL + _ABS), bit, 0).astype(np.int8)
    return cut


def cut_off(t, cuts: dict, counted=None):
    """The time of the first sample counted that a window cut off its closest command
    point, how many there are, over every sensor, and whether any lies closer to the
    command before its window (:func:`outside_closer`); ``None`` for none [s], [-], [-]."""
    first, n, behind = np.inf, 0, False
    for c in cuts.values():
        c = c if counted is None else np.where(counted, c, 0)
        idx = np.flatnonzero(c)
        if idx.size:
            n = max(n, idx.size)
            first = min(first, float(t[idx[0]]))
            behind = behind or bool(np.any(c[idx] & BEHIND))
    return None if n == 0 else (first, n, behind)


class WindowCut(Exception):
    """A window cuts samples off their closest command point: the first one's time, how
    many of those measured, and whether any lies closer before its window [s], [-], [-]."""

    def __init__(self, first_s: float, n: int, behind: bool = True):
        super().__init__(first_s, n, behind)
        self.first_s, self.n, self.behind = first_s, n, behind


def window_error(window_s: float, given: bool, first_s: float,
                 n: int | None = None, behind: bool = True) -> InputError:
    """What to say where a window cuts samples off their closest command point
    (``given``: the user chose it; ``n`` of them, where all were measured; ``behind``:
    some lie closer to the command before their window, else all after it) [-]."""
    many = "" if n is None else f"{n} samples, "
    where = f"({many}the first at {first_s:.3f} s)"
    what = (f"the run lags its command by more than the window of {window_s:g} s in which "
            f"each sample's closest command point is sought {where}: measured within it, "
            "the contour error would be the following error") if behind else (
        f"samples lie closer to the command just after the window of {window_s:g} s in "
        f"which each one's closest command point is sought than to any of it {where}: "
        "the path comes back near them a little later (another pass), or the command's "
        "time line lags the run's; measured within it, their error would be read to the "
        "window's edge")
    if given:
        return InputError(f"{what}; leave --window-s out (the window is then widened to "
                          "what the run needs) or give a longer one")
    return InputError(f"{what}, even at the widest window tried; the axes do not follow "
                      "the command (check that the command and the actual positions are "
                      "of one run, on one time line)")


def widened(search, t, window_s: float | None, counted=None) -> tuple:
    """``search(w, cuts)``'s result at the first window of :func:`windows` that cuts no
    sample counted (``counted``: all where ``None``) off its closest command point, and
    that window; an error where none does (:func:`window_error`) [-], [s].

    Parameters
    ----------
    search : callable
        Measures at the window ``w`` [s], filling ``cuts`` as
        :func:`~tcpmm.analysis.contour.distances_to_polyline` does [-].
    t : ndarray
        The samples' times [s].
    window_s : float or None
        The window the user gave; ``None`` for the default, widened as needed [s].
    counted : ndarray of bool, optional
        The samples whose figures count [-].
    """
    for w in windows(window_s):
        cuts = {}
        found = search(w, cuts)
        cut = cut_off(t, cuts, counted)
        if cut is None:
            return found, w
    raise window_error(w, window_s is not None, *cut)
