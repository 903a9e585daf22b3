"""The arithmetic of corner blending (:mod:`tcpmm.path.blend`) on arrays: the blocks of a
path as a table, the tangent length of each corner, and the rows of the blended path.

Every block of a path, a run of G1 blocks counted block by block, is a row of the table;
the points of the trimmed lines and of the blend arcs are worked out for all corners at
once. Sums over the coordinates are taken first to last (:mod:`tcpmm._rows`), angles one
corner at a time with the C library's functions (:mod:`tcpmm.path.blendtrig`) and lengths
with :func:`math.hypot`, so the bits do not depend on the CPU's vector units or a
library's pairing of a sum.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import _compiled
from .._rows import norm_rows
from .runs import LineRun
from .segments import Line
from .speedlimits import BEND_TOL, REVERSAL_TOL

#: blends shorter than this along either line are not worth a segment [m]
MIN_BLEND_M = 1e-9


@dataclass
class BlockTable:
    """The blocks of a path, one row each, a run's block by block.

    Parameters
    ----------
    start, end : ndarray, shape (n, 3)
        Start and end point of each straight feed move, NaN for other blocks [m].
    is_line : ndarray of bool
        The block is a straight feed move (G1) [-].
    exact : ndarray of bool
        It stops exactly at its end (G61, G9) [-].
    tol : ndarray
        Its own contour tolerance, NaN where it has none [m].
    feed : ndarray
        Its programmed feed, 0 for other blocks [m/s].
    line : ndarray of int
        Its source line, -1 for none [-].
    """

    start: np.ndarray
    end: np.ndarray
    is_line: np.ndarray
    exact: np.ndarray
    tol: np.ndarray
    feed: np.ndarray
    line: np.ndarray

    @property
    def n(self) -> int:
        """Blocks [-]."""
        return self.is_line.size


def block_table(segments) -> BlockTable:
    """The table of ``segments`` (Lines, runs of them, and any other segment) [-]."""
    parts, lines = [], []
    for s in [*segments, None]:
        t = type(s)
        if t is Line:
            lines.append(s)
            continue
        if lines:  # a field per column over the Lines, one conversion each
            parts.append(_line_rows(lines))
            lines = []
        if t is LineRun:
            k = len(s)
            parts.append((s.starts(), np.asarray(s.end_m, float), np.ones(k, bool),
                          np.full(k, s.exact_stop), np.full(k, _tol(s.tolerance_m)),
                          np.asarray(s.feed_m_per_s, float), np.arange(s.line, s.line + k)))
        elif s is not None:
            parts.append((np.full((1, 3), np.nan), np.full((1, 3), np.nan), np.zeros(1, bool),
                          np.zeros(1, bool), np.full(1, np.nan), np.zeros(1),
                          np.full(1, -1)))
    if not parts:
        e = np.zeros((0, 3))
        return BlockTable(e, e, np.zeros(0, bool), np.zeros(0, bool), np.zeros(0),
                          np.zeros(0), np.zeros(0, np.int64))
    cols = [np.concatenate(c) for c in zip(*parts, strict=True)]
    cols[-1] = cols[-1].astype(np.int64)
    return BlockTable(*cols)


def _line_rows(lines: list) -> tuple:
    """The table's columns of consecutive Lines [-]."""
    k = len(lines)
    return (np.array([s.start_m for s in lines], float).reshape(k, 3),
            np.array([s.end_m for s in lines], float).reshape(k, 3), np.ones(k, bool),
            np.array([s.exact_stop for s in lines], bool),
            np.array([_tol(s.tolerance_m) for s in lines], float),
            np.array([s.feed_m_per_s for s in lines], float),
            np.array([-1 if s.line is None else s.line for s in lines], np.int64))


def _tol(t) -> float:
    return np.nan if t is None else float(t)


def tangent_lengths(tb: BlockTable, default_tol_m: float) -> np.ndarray:
    """``d[i + 1]``: tangent length of the corner at the end of block ``i`` (``d[0]`` and
    ``d[n]`` zero), 0 where a block is no straight feed move, is an exact stop or has no
    tolerance (:func:`corner_lengths`) [m]."""
    return corner_table(tb, default_tol_m)[0]


def corner_table(tb: BlockTable, default_tol_m: float) -> tuple[np.ndarray, np.ndarray]:
    """:func:`tangent_lengths` ``d`` and, where it is not zero, the half-angle ``h`` of
    the corner's turn (0 elsewhere), both of length ``n + 1`` [m], [rad]."""
    n = tb.n
    d, h = np.zeros(n + 1), np.zeros(n + 1)
    if n < 2:
        return d, h
    tol = np.where(np.isnan(tb.tol[:-1]), default_tol_m, tb.tol[:-1])
    pairs = np.flatnonzero(tb.is_line[:-1] & tb.is_line[1:] & ~tb.exact[:-1] & (tol > 0.0))
    if pairs.size:
        rows = [np.take(x, pairs + k, axis=0) for k in (0, 1) for x in (tb.start, tb.end)]
        d[pairs + 1], h[pairs + 1] = corner_lengths(*rows, tol[pairs])
    return d, h


def corner_lengths(a0, a1, b0, b1, tols) -> tuple[np.ndarray, np.ndarray]:
    """Distance ``d`` from the corner of the line ``a0 -> a1`` into ``b0 -> b1`` (rows),
    of contour tolerance ``tols`` > 0, at which its blend starts and ends; 0 where it
    stays sharp [m]; and the half-angle of each corner's turn, 0 where ``d`` is [rad].
    Only where a corner turns are its angle and length worked out: a long run of short
    blocks is mostly straight on.

    At a corner turning by ``theta`` the blend passes the corner at
    ``rho (1/cos(theta/2) - 1)`` for its radius ``rho = d / tan(theta/2)``; ``d`` is the
    largest that keeps this within the tolerance, and at most half of either line, so
    that the blends at both ends of a line never overlap. A corner whose unit tangent
    changes by less than ``BEND_TOL`` stays sharp (straight on but for rounding), and so
    does a reversal, as the look-ahead takes one (``REVERSAL_TOL``), and a corner whose
    blend arc, ``2 h d / tan(h)`` for its half-angle ``h``, would be shorter than
    :data:`MIN_BLEND_M`."""
    # A turn of the unit tangent below BEND_TOL is a tangent join, as the look-ahead takes
    # it: its blend would pass the corner by d theta / 4, nothing, on a radius
    # 2 d / theta (km) about a centre so far off that its points keep little of their
    # last micrometre. Straight on, or a reversal, is no turn either.
    turns, h, d_tol = _compiled.call("corner_turns", a0, a1, b0, b1, np.asarray(tols, float),
                                     BEND_TOL)
    d, half = np.zeros(len(a0)), np.zeros(len(a0))
    ks = np.flatnonzero(turns)
    h, d_tol = h[ks], d_tol[ks]
    # Python's math.hypot of a line's differences is math.dist of its ends, to the bit
    len_a = np.array(list(map(math.hypot, *(a1[ks] - a0[ks]).T.tolist())))
    len_b = np.array(list(map(math.hypot, *(b1[ks] - b0[ks]).T.tolist())))
    dk = np.minimum(np.minimum(d_tol, 0.5 * len_a), 0.5 * len_b)
    # Near a reversal the tangent points lie d along the lines but next to each other
    # across them, and the arc between, of radius d cos(h) / sin(h), is too short for the
    # look-ahead to give a speed (1 m out and back 0.4 mm aside, under G64 P0.005, an arc
    # of 1.3e-12 m). The look-ahead stops at a reversal, so it stays sharp.
    back = 2.0 * np.cos(h) ** 2 < REVERSAL_TOL  # 1 + cos(2 h): the tangents' dot product + 1
    with np.errstate(divide="ignore", invalid="ignore"):
        arc = 2.0 * h * dk / np.tan(h)
    blended = (dk >= MIN_BLEND_M) & ~back & (arc >= MIN_BLEND_M)
    d[ks] = np.where(blended, dk, 0.0)
    half[ks] = np.where(blended, h, 0.0)
    return d, half


def units(v) -> np.ndarray:
    """Each row of an (n, 3) array over its length [-]."""
    return v / norm_rows(v)[:, None]


@dataclass
class BlendedRows:
    """The blended path of some blocks, a row per segment, in order.

    Parameters
    ----------
    src : ndarray of int
        The block each row comes from (for a blend, the block before its corner) [-].
    kind : ndarray of int
        0 a line, 1 a line trimmed at an end or both, 2 the blend at the end of ``src``,
        -1 a block that is no straight feed move, as it is [-].
    start, end, centre : ndarray, shape (n, 3)
        Points of the lines and blends (a blend's tangent points and centre) [m].
    """

    src: np.ndarray
    kind: np.ndarray
    start: np.ndarray
    end: np.ndarray
    centre: np.ndarray


def blended_rows(tb: BlockTable, corners: tuple, first: int, stop: int) -> BlendedRows:
    """The rows of blocks ``first`` to ``stop - 1``, each trimmed by the tangent lengths
    and followed by the blend at its end (module docstring); ``corners`` is
    :func:`corner_table`'s ``(d, h)`` [-].

    A trimmed line starts where the blend before it ends, ``d`` along it from the
    corner; a line left shorter than 1e-12 of its length (at least of 1 mm) is dropped.
    The blend at a corner ``p`` of half-angle ``h`` runs from ``p - d u1`` to
    ``p + d u2`` about the centre on the bisector at ``d / (tan h cos h)``."""
    d, half = corners
    idx = np.arange(first, stop)
    blk = slice(first, stop)  # every block read: views, not gathers
    d0, d1 = d[blk], d[first + 1:stop + 1]
    line = tb.is_line[blk]
    trim = line & ((d0 != 0) | (d1 != 0))
    with np.errstate(invalid="ignore", divide="ignore"):
        u = units(tb.end[first:stop + 1] - tb.start[first:stop + 1])
    s0, s1 = tb.start[blk].copy(), tb.end[blk].copy()
    t = np.flatnonzero(trim)
    if t.size:
        # the start of a line whose corner before is blended: that corner, d along
        before = np.where((d0[t] != 0)[:, None], tb.end[idx[t] - 1], tb.start[idx[t]])
        s0[t] = before + d0[t][:, None] * u[t]
        s1[t] = tb.end[idx[t]] - d1[t][:, None] * u[t]
    span = norm_rows(tb.end[blk] - tb.start[blk])
    keep = ~trim | (norm_rows(s1 - s0) > 1e-12 * np.maximum(span, 1e-3))
    kind = np.where(line, trim.astype(np.int64), -1)
    c = np.flatnonzero(d1 != 0)
    b0, b1, bc = _blend_points(tb.end[idx[c]], u[c], u[c + 1], d1[c],
                                half[first + 1:stop + 1][c])
    # rows: each block's own (if kept), then the blend at its end (if any)
    per = keep.astype(np.int64) + (d1 != 0)
    at = np.concatenate([[0], np.cumsum(per)])
    n_rows = int(at[-1])
    own = at[:-1][keep]
    blend_at = at[:-1][c] + keep[c]
    src = np.empty(n_rows, np.int64)
    kinds = np.empty(n_rows, np.int64)
    start, end, centre = np.zeros((n_rows, 3)), np.zeros((n_rows, 3)), np.zeros((n_rows, 3))
    src[own], kinds[own], start[own], end[own] = idx[keep], kind[keep], s0[keep], s1[keep]
    src[blend_at], kinds[blend_at] = idx[c], 2
    start[blend_at], end[blend_at], centre[blend_at] = b0, b1, bc
    return BlendedRows(src, kinds, start, end, centre)


def _blend_points(p, u1, u2, dk, h) -> tuple:
    """Start, end and centre of the blends at the corners ``p`` from the directions
    ``u1`` into ``u2``, tangent lengths ``dk``, half-angles ``h`` [m]."""
    reach = _compiled.call("blend_reach", h, dk)
    with np.errstate(invalid="ignore", divide="ignore"):
        bis = units(u2 - u1)
    centre = p + bis * reach.reshape(-1, 1)
    return p - dk[:, None] * u1, p + dk[:, None] * u2, centre
