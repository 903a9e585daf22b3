"""What holds the feed back: per block, the limit that keeps it below the programmed feed.

A feed block (not a rapid, not a dwell) is held back when the highest speed it reaches is
below ``HELD_SHARE`` of its programmed feed. The cause is the block's own speed limit when
that is below the feed (axis velocity, the centripetal acceleration of its curvature, the
filter's tolerance on arcs) and the block reaches it; else the corner at its start or end
when that corner's own limit sets the speed there (a velocity step the axes' acceleration
allows within the filter's spread, the filter's tolerance at the corner, an exact stop);
else the block beyond its slower end where the speed there is that block's own limit
(the arcs of a blend between the short lines of a curve posted as G1 blocks);
else, where the speed falls from its slower end to a junction of a chain of short blocks
whose curvature sets the speed there, that curvature (the blocks between such corners
are too short to speed up and slow down again: the curve as a whole holds them back);
else the path acceleration (the path jerk for the S-curve): the block is too short to
reach the feed from a slower place before or after it. The look-ahead spans the whole
program, so its depth never limits.

The share at the feed is taken from the samples, not the blocks: the path length of the
feed blocks along which the commanded path speed is within 1 % (``HELD_SHARE``) of the
programmed feed. A block that reaches its feed in the middle still slows down at its
corners; counted whole it made a square "at the feed on 100 % of the path".
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._rows import norm_rows
from .geometry import DWELL
from .speedlimits import CHAIN, JUNCTION_CAUSES, SEGMENT_CAUSES

#: Share by which a command's peak must exceed a limit to be said to go beyond it: a
#: command file's rounding alone moves a sample's acceleration that much (7 decimals of a
#: mm at 1 ms: 1e-4 m/s^2), and a figure printed to three digits cannot show less [-].
OVER_SHARE = 1e-3

def derivative(x: np.ndarray, order: int, period_s: float,
               from_rest: bool = False) -> np.ndarray:
    """Backward difference of an order, on the samples' time line: the first ones 0, or
    with ``from_rest`` of a command the axis stands still on before its first sample, as a
    run of it starts (``tcpmm simulate --command``, a dense program's dwell after its
    rapid): the first sample's value held before it, so that a command that leaves its
    first sample at once steps its velocity from rest [m/s^n]."""
    if from_rest:
        return np.diff(np.concatenate([np.full(order, x[0]), x]), order) / period_s ** order
    d = np.zeros_like(x)
    d[order:] = np.diff(x, order) / period_s ** order
    return d


def peak(x: np.ndarray, order: int, period_s: float, from_rest: bool = False) -> float:
    """The largest magnitude of :func:`derivative`: what the samples ask of an axis (with
    ``from_rest``, of one that stands still before them) [m/s^n]."""
    return float(np.max(np.abs(derivative(x, order, period_s, from_rest))))


class RunningPeak:
    """:func:`peak` per axis over a command that comes in pieces, the same numbers as over
    the whole: each piece is differenced after the last ``order`` samples of the one
    before it.

    Parameters
    ----------
    order : int
        Order of the difference [-].
    period_s : float
        Sample period [s].
    """

    def __init__(self, order: int, period_s: float):
        self.order, self.period_s = order, period_s
        self.tail: dict = {}
        self.most: dict = {}

    @classmethod
    def of(cls, positions: dict, order: int, period_s: float) -> dict:
        """The peak per axis of a whole command's ``positions`` [m/s^order]."""
        rp = cls(order, period_s)
        rp.add(positions)
        return rp.most

    def add(self, positions: dict) -> None:
        """Take the next samples of each axis [m]."""
        for a, x in positions.items():
            if a in self.tail:
                x = np.concatenate([self.tail[a], x])
            if x.size > self.order:
                self.most[a] = max(self.most.get(a, 0.0), peak(x, self.order, self.period_s))
            self.tail[a] = x[-self.order:]


#: a block reaching less than this share of its feed is held back [-]
HELD_SHARE = 0.99


@dataclass
class FeedLimits:
    """Per block: programmed feed, the speed reached, and what holds it back.

    Parameters
    ----------
    line : ndarray of int
        Source line of each block, -1 where unknown [-].
    length_m : ndarray
        Block length [m].
    feed_m_per_s : ndarray
        Programmed feed (rapid speed for G0) [m/s].
    limit_m_per_s : ndarray
        Highest speed the block reaches [m/s].
    held : ndarray of bool
        Below ``HELD_SHARE`` of the feed [-].
    cause : ndarray of str
        What holds it back ("" where nothing does) [-].
    feed_length_m : float
        Path length of the feed blocks (no rapids, no dwells) [m].
    length_at_feed_m : float
        Of that, the path length along which the commanded path speed is within
        ``1 - HELD_SHARE`` of the programmed feed, from the samples [m].
    """

    CAUSES = tuple(dict.fromkeys((*SEGMENT_CAUSES[1:], *JUNCTION_CAUSES[1:],
                                  "path acceleration", "path jerk")))

    line: np.ndarray
    length_m: np.ndarray
    feed_m_per_s: np.ndarray
    limit_m_per_s: np.ndarray
    held: np.ndarray
    cause: np.ndarray
    feed_length_m: float
    length_at_feed_m: float

    def summary(self) -> list[dict]:
        """Per cause: path length held back, blocks, lines, lowest speed reached [SI]."""
        rows = []
        for c in dict.fromkeys(self.cause[self.held]):
            k = self.held & (self.cause == c)
            lines = self.line[k][self.line[k] >= 0]
            # NC blocks, not the pieces blending cuts them into (a line and its blend)
            blocks = np.unique(lines).size + int(np.count_nonzero(self.line[k] < 0))
            rows.append({"cause": str(c), "length_m": float(self.length_m[k].sum()),
                         "blocks": blocks,
                         "first_line": int(lines.min()) if lines.size else None,
                         "last_line": int(lines.max()) if lines.size else None,
                         "lowest_m_per_s": float(self.limit_m_per_s[k].min())})
        return sorted(rows, key=lambda r: -r["length_m"])

    def share_at_feed(self) -> float:
        """Share of the feed blocks' path length along which the commanded path speed is
        within 1 % of the programmed feed (module docstring); NaN for a program without
        feed moves [-]."""
        if self.feed_length_m <= 0:
            return float("nan")
        return self.length_at_feed_m / self.feed_length_m

    def ramp_length_m(self) -> float:
        """Path length below the feed in the blocks that reach it: speeding up and slowing
        down at their ends [m]."""
        below = self.feed_length_m - self.length_at_feed_m
        return float(max(below - self.length_m[self.held].sum(), 0.0))

    def to_pandas(self):
        """Per block: line, length [mm], feed and speed reached [mm/min], cause."""
        import pandas as pd

        return pd.DataFrame({"line": self.line, "length_mm": self.length_m * 1e3,
                             "feed_mm_per_min": self.feed_m_per_s * 6e4,
                             "reached_mm_per_min": self.limit_m_per_s * 6e4,
                             "held": self.held, "cause": self.cause})

    def plot(self, ax=None, path=None):
        """Programmed feed and speed reached per block, coloured by the cause; the figure.

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Where to draw; a new figure when omitted [-].
        path : str or Path, optional
            Also save it there (PNG/PDF/SVG) [-].
        """
        from ..plot.path import plot_feed_limits

        return plot_feed_limits(self, ax=ax, path=path)

    def to_dict(self) -> dict:
        """JSON-ready: share at the feed and the causes (mm, mm/min)."""
        return {"share_at_feed": self.share_at_feed(),
                "feed_length_mm": self.feed_length_m * 1e3,
                "length_at_feed_mm": self.length_at_feed_m * 1e3,
                "held_back": [{"cause": r["cause"], "length_mm": r["length_m"] * 1e3,
                               "blocks": r["blocks"], "first_line": r["first_line"],
                               "last_line": r["last_line"],
                               "lowest_mm_per_min": r["lowest_m_per_s"] * 6e4}
                              for r in self.summary()]}


def feed_limits(interp) -> FeedLimits:
    """What holds each block of an interpolated path below its feed (module docstring).

    Parameters
    ----------
    interp : Interpolation
        The result of :func:`tcpmm.path.interpolate_detailed` [-].
    """
    p = interp.path
    feed, vmax = p.feed, interp.segment_vmax_m_per_s
    peak = interp.segment_peak_m_per_s
    v, vj = interp.junction_speed_m_per_s, interp.junction_limit_m_per_s
    motion = (p.kind != DWELL) & ~p.rapid  # rapids position; they have no feed to reach
    held = motion & (peak < HELD_SHARE * feed)
    cause = np.full(p.n, "", dtype=object)
    ramp = "path jerk" if interp.jerk_limited else "path acceleration"
    left, right = _valleys(v)
    for i in np.flatnonzero(held):
        # its own limit where the block reaches it: one that starts from rest short of
        # it (or slows to a tighter block) is held back by what keeps it lower
        if vmax[i] < HELD_SHARE * feed[i] and peak[i] >= HELD_SHARE * vmax[i]:
            cause[i] = SEGMENT_CAUSES[interp.segment_cause[i]]
            continue
        # the slower end, if its corner's own limit sets the speed there
        j = i if v[i] <= v[i + 1] else i + 1
        jc = interp.junction_cause[j]
        own = jc != 0 and v[j] >= vj[j] * (1 - 1e-9) and vj[j] < HELD_SHARE * feed[i]
        if not own and (near := _bounding_neighbour(i, j, v, (vmax, peak), motion, feed)) >= 0:
            cause[i] = SEGMENT_CAUSES[interp.segment_cause[near]]
            continue
        # else the chain of short blocks the speed falls to from there
        k = left[i] if j == i else right[j]
        chain = (interp.junction_cause[k] == CHAIN and v[k] >= vj[k] * (1 - 1e-9)
                 and vj[k] < HELD_SHARE * feed[i])
        cause[i] = JUNCTION_CAUSES[jc] if own else JUNCTION_CAUSES[CHAIN] if chain else ramp
    return FeedLimits(p.line.copy(), p.length.copy(), feed.copy(), np.where(motion, peak, 0.0),
                      held, cause.astype(str), *_length_at_feed(interp, motion))


def _bounding_neighbour(i: int, j: int, v, speeds, motion, feed) -> int:
    """The block beyond block ``i``'s slower end ``j`` where the speed there is that
    block's own limit, below the feed, and block ``i`` runs no faster than it (within
    ``1 - HELD_SHARE``): the arc of a blend between the short lines a curve posted as G1
    blocks is cut into holds the lines between its arcs to its own speed (they were said
    too short to reach the feed, and the path acceleration to blame); a block that speeds
    up well above it on its way is too short for the feed. ``speeds``: each block's limit
    and the highest speed it reaches; -1 for none [-]."""
    vmax, peak = speeds
    n = i - 1 if j == i else i + 1
    if not 0 <= n < vmax.size or not motion[n]:
        return -1
    bound = vmax[n] < HELD_SHARE * feed[i] and v[j] >= vmax[n] * (1 - 1e-9)
    return n if bound and peak[i] <= vmax[n] / HELD_SHARE else -1


def _valleys(v) -> tuple[np.ndarray, np.ndarray]:
    """Per junction, the junction where the speed stops falling: going back (``left``) and
    going on (``right``) from it, itself where the speed does not fall that way [-]."""
    idx = np.arange(v.size)
    back = np.ones(v.size, bool)
    back[1:] = v[:-1] >= v[1:]
    on = np.ones(v.size, bool)
    on[:-1] = v[1:] >= v[:-1]
    left = np.maximum.accumulate(np.where(back, idx, 0))
    right = np.minimum.accumulate(np.where(on, idx, v.size - 1)[::-1])[::-1]
    return left, right


def _length_at_feed(interp, motion) -> tuple[float, float]:
    """Path length of the feed blocks, and the part of it that the command runs within
    ``1 - HELD_SHARE`` of the programmed feed: both of the command as it is written, after
    the interpolation filter (which slows the path and cuts it short where its direction
    turns or its speed changes), each sample against the block the samples before the
    filter were on a filter delay earlier [m]."""
    p, cmd = interp.path, interp.command
    s = np.asarray(cmd.meta["path_s_m"], float)
    ds = np.diff(s)
    cum = np.concatenate([[0.0], np.cumsum(p.length)])
    seg = np.clip(np.searchsorted(cum, s[:-1] + 0.5 * ds, side="right") - 1, 0, p.n - 1)
    if interp.filter is not None and interp.filter.kernel.size > 1:
        lag = round(interp.filter.delay_s / cmd.period_s)
        seg = seg[np.clip(np.arange(ds.size) - lag, 0, ds.size - 1)]
        ds = norm_rows(np.diff(np.column_stack(list(cmd.positions.values())), axis=0))
    feed = motion[seg] & (ds > 0)
    at = feed & (ds >= HELD_SHARE * p.feed[seg] * cmd.period_s)
    return float(ds[feed].sum()), float(ds[at].sum())
