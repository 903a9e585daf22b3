"""Which block of the NC program each sample of the command is in: its line, and whether
it is a rapid (G0), through the post-interpolation filter, as the path comes whole or in
pieces.

A filtered sample is made of the unfiltered samples of the filter's window before it: it
is in a rapid when any of them is (the command still moves at rapid traverse, or starts
to), and its line is that of the sample at the middle of the window (the group delay of
the symmetric filters), so that the line names the block whose geometry the filtered
command is at. A dwell is of the kind of the motion before it: it stands where that move
left the tool, in the air after a G0 (a spindle's run-up before plunging), in the part
after a G1 (the bottom of a hole). A segment of no source line (the interpolator's own)
gives line 0.
"""

from __future__ import annotations

import numpy as np

from .geometry import DWELL, PathArrays


class BlockTrack:
    """The NC line and the rapid flag of each filtered command sample, given the
    unfiltered samples a piece at a time (module docstring).

    Parameters
    ----------
    taps : int
        Length of the post-interpolation filter's impulse response [-].
    """

    def __init__(self, taps: int):
        self.m = int(taps)
        self.air = self.line = None  # the last ``m - 1`` unfiltered samples' flags, lines
        self.air_before = False  # the last motion segment so far was a rapid

    def segment_air(self, p: PathArrays) -> np.ndarray:
        """Per segment of ``p``: a rapid, or a dwell after one [-]."""
        motion = p.kind != DWELL
        last = np.maximum.accumulate(np.where(motion, np.arange(p.n), -1)) if p.n else \
            np.zeros(0, np.int64)
        air = np.where(last >= 0, p.rapid[np.maximum(last, 0)], self.air_before)
        if motion.any():
            self.air_before = bool(p.rapid[np.flatnonzero(motion)[-1]])
        return air

    def push(self, p: PathArrays, seg: np.ndarray, last: bool) -> tuple:
        """The line and rapid flag of the filtered samples that the unfiltered samples on
        segments ``seg`` of ``p`` complete, and at the ``last`` the filter's settling
        after them [-].

        Parameters
        ----------
        p : PathArrays
            The segments the samples are on [-].
        seg : ndarray of int
            Segment of each unfiltered sample [-].
        last : bool
            The path ends with them [-].

        Returns
        -------
        line : ndarray of int32
            Source line, 0 where the block has none [-].
        rapid : ndarray of int8
            1 in a rapid, else 0 [-].
        """
        # per segment first: a path has fewer segments than samples
        air = self.segment_air(p)[seg]
        line = np.maximum(p.line, 0).astype(np.int32)[seg]
        k = self.m - 1
        if k == 0:  # no filter: each sample is its own
            return line, air.view(np.int8)
        if self.air is None:
            if not line.size and not last:
                return np.zeros(0, np.int32), np.zeros(0, np.int8)
            self.air = np.zeros(k, bool)
            self.line = np.full(k, line[0] if line.size else 0, np.int32)
        ext_air = np.concatenate([self.air, air])
        ext_line = np.concatenate([self.line, line])
        if last:  # the filter settles at the end point, at rest
            ext_air = np.concatenate([ext_air, np.zeros(k, bool)])
            ext_line = np.concatenate([ext_line, np.full(k, ext_line[-1], np.int32)])
        n = ext_air.size - k
        c = np.concatenate([[0], np.cumsum(ext_air, dtype=np.int64)])
        rapid = (c[k + 1:] > c[:n]).astype(np.int8)
        mid = k - k // 2
        out_line = ext_line[mid:mid + n].copy()
        self.air, self.line = ext_air[ext_air.size - k:], ext_line[ext_line.size - k:]
        return out_line, rapid


def sample_index(time_s, t0: float, period_s: float, n: int) -> np.ndarray:
    """Index of the command sample (of ``n`` from time ``t0`` at ``period_s``) at or before
    each of the times ``time_s``, the last one after the end [s], [-]."""
    return np.clip(((np.asarray(time_s, float) - t0) / period_s + 1e-9).astype(np.int64), 0,
                   n - 1)


def at_times(time_s, t0: float, period_s: float, values: tuple) -> tuple:
    """``values`` (arrays over the command samples from time ``t0`` at ``period_s``) at the
    times ``time_s``: :func:`sample_index`'s sample [-].

    Parameters
    ----------
    time_s : ndarray
        Times of the records [s].
    t0 : float
        Time of the first command sample [s].
    period_s : float
        Command period [s].
    values : tuple of ndarray
        Arrays of one value per command sample [-].
    """
    k = sample_index(time_s, t0, period_s, values[0].size)
    return tuple(v[k] for v in values)


class HeldBlocks:
    """The lines and rapid flags of the command samples given a piece at a time
    (:class:`~tcpmm.path.stream.CommandChunk`), held until the records of their times
    are made: :func:`at_times` of the whole command, for records that come in order.

    Parameters
    ----------
    period_s : float
        Command period; the command starts at time 0 [s].
    """

    def __init__(self, period_s: float):
        self.dt, self.first = period_s, 0
        self.line, self.rapid = np.zeros(0, np.int32), np.zeros(0, np.int8)

    def add(self, line, rapid) -> None:
        """The next command samples' lines and flags [-]."""
        self.line = np.concatenate([self.line, line])
        self.rapid = np.concatenate([self.rapid, rapid])

    def at(self, time_s) -> tuple:
        """Line and flag at the times ``time_s`` (later than those asked before); the
        samples before the last one taken are let go [-]."""
        k = sample_index(time_s, 0.0, self.dt, self.first + self.line.size) - self.first
        out = self.line[k], self.rapid[k]
        if k.size:
            cut = int(k[-1])
            self.line, self.rapid = self.line[cut:], self.rapid[cut:]
            self.first += cut
        return out
