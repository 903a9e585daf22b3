"""A chunk's segments handed to the interpolator in parts of about a piece's samples.

A chunk of blocks is sized from the samples the blocks before it gave
(:class:`tcpmm.path.stream.ChunkSize`), which a program whose blocks turn long within a
chunk outruns: 2 000 blocks of 0.01 mm then semicircles of 2 mm radius at F1000 gave a
chunk of 100 000 semicircles, 16 M samples, past the samples a chunk's command may have
(:data:`~tcpmm.path.interpolate.MAX_SAMPLES`). :func:`parts` therefore cuts a chunk's
segments, before they are planned, where the time they take at their programmed feeds
(the least they can take, read off their ends and feeds at little cost) passes some
:data:`~tcpmm.path.stream.CHUNK_SAMPLES` samples. The interpolator gives the same command
whatever the segments it is handed at a time (:mod:`tcpmm.path.stream_plan`), as it does
whatever the chunks, so the cuts change nothing but the pieces' sizes.
"""

from __future__ import annotations

import math
from collections.abc import Iterator

import numpy as np

from .runs import RUNS, ArcRun, LineRun
from .segments import AXIS_INDEX, Arc, Dwell, Line, Rapid, arc_sweep


def parts(segments: list, settings, samples: int) -> Iterator[list]:
    """``segments`` in consecutive parts of about ``samples`` samples each at their feeds.

    Parameters
    ----------
    segments : list
        A chunk's segments, runs among them (:mod:`tcpmm.path.runs`) [-].
    settings : InterpolatorSettings
        Interpolator settings: the sample period and the rapid speeds [-].
    samples : int
        Samples of a part at most, at the blocks' feeds; a block is not cut [-].

    Yields
    ------
    list
        The segments of each part, a run cut between its blocks where a part ends [-].
    """
    t = block_seconds(segments, settings.rapid())
    if t.sum() <= samples * settings.period_s:  # not NaN or infinite either
        yield segments
        return
    n = np.cumsum(np.where(np.isfinite(t), t, samples * settings.period_s))
    n /= settings.period_s
    count = min(math.ceil(n[-1] / samples), n.size)
    # a part ends after the block where the samples pass each ``count``-th of the whole
    ends = np.searchsorted(n, n[-1] * np.arange(1, count) / count) + 1
    done = 0
    for end in np.unique(np.minimum(ends, n.size)).tolist():
        part, segments = split_blocks(segments, end - done)
        done = end
        if part:
            yield part
    if segments:
        yield segments


def split_blocks(segments: list, k: int) -> tuple[list, list]:
    """The first ``k`` blocks of ``segments`` and the rest, a run cut where they end [-]."""
    i = 0
    while k > 0 and i < len(segments):
        s = segments[i]
        n = len(s) if type(s) in RUNS else 1
        if n > k:
            return [*segments[:i], s.cut(0, k)], [s.cut(k, n), *segments[i + 1:]]
        k -= n
        i += 1
    return segments[:i], segments[i:]


def block_seconds(segments: list, rapid_m_per_s) -> np.ndarray:
    """Per block, its length over its programmed feed, the time at the axes' rapid speeds
    of a rapid, that of a dwell: the least time it takes, infinite or NaN where its feed
    is not positive [s].

    Parameters
    ----------
    segments : list
        Segments, runs among them [-].
    rapid_m_per_s : tuple of float
        Rapid speed of X, Y, Z [m/s].
    """
    out, plain = [], []
    with np.errstate(divide="ignore", invalid="ignore"):
        for s in segments:
            t = type(s)
            if t is LineRun or t is ArcRun:
                out.append(np.array(plain))
                plain = []
                out.append(_run_seconds(s))
            else:
                plain.append(_seconds(s, rapid_m_per_s))
        out.append(np.array(plain))
    return np.concatenate(out)


def _run_seconds(run) -> np.ndarray:
    """Per block of a run of lines or arcs, its length over its feed [s]."""
    start = run.starts()
    d = np.asarray(run.end_m, float) - start
    if type(run) is LineRun:
        length = np.sqrt(np.einsum("ij,ij->i", d, d))
    else:
        ia, ib = (AXIS_INDEX[a] for a in run.plane_axes)
        c = np.asarray(run.centre_m, float)
        xs, ys = start[:, ia] - c[:, ia], start[:, ib] - c[:, ib]
        xe, ye = run.end_m[:, ia] - c[:, ia], run.end_m[:, ib] - c[:, ib]
        r = 0.5 * (np.hypot(xs, ys) + np.hypot(xe, ye))
        length = np.hypot(r * arc_sweep(xs, ys, xe, ye, run.ccw), d[:, 3 - ia - ib])
    return length / np.fromiter(run.feed_m_per_s, float, len(run))


def _seconds(s, rapid_m_per_s) -> float:
    """The least time a segment other than a run or a line takes [s]."""
    t = type(s)
    if t is Dwell:
        return float(s.duration_s)
    if t is Rapid:
        return max(abs(b - a) / v for a, b, v in zip(s.start_m, s.end_m, rapid_m_per_s,
                                                         strict=True))
    if t is Line or t is Arc:
        return s.length_m / s.feed_m_per_s if s.feed_m_per_s > 0 else math.inf
    return 0.0
