"""The compiled corner arithmetic (:mod:`tcpmm.sim.cornerfigs`) against the numpy expressions
that define it: the same figures to the bit, on random samples of every size, with ties,
signed zeros and NaN among them."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tcpmm._compiled import call
from tcpmm._rows import dot_rows, norm_rows

TOL = 1e-6


def _held(dev, tol):
    tail = dev[-(dev.size // 4 or 1):]
    if tail.size < 4:
        return 0.0
    level = float(np.median(tail))
    return level if level > tol and float(np.max(np.abs(tail - level))) <= tol else 0.0


def _shape(t, dist, dev, past, b0, b1, end, tol):
    """Overshoot and rounding as numpy gives them."""
    own = (t >= b0) & (t <= b1)
    if not own.any():
        return [float("nan"), float("nan")]
    if end:
        dv = dev[own]
        dv = dv - max(float(np.median(dv[-(dv.size // 4 or 1):])), 0.0)
    else:
        dv = dev[own & past]
        dv = dv - _held(dv, tol)
    return [float(max(np.max(dv), 0.0)) if dv.size else 0.0, float(np.min(dist[own]))]


def _values(draw, n):
    """Samples of a few microns, many of them equal (a point at rest), some NaN."""
    pool = draw(st.lists(st.floats(-5e-6, 5e-6, allow_subnormal=False), min_size=1,
                         max_size=6))
    pool += [0.0, -0.0]
    idx = draw(st.lists(st.integers(0, len(pool) - 1), min_size=n, max_size=n))
    return np.array([pool[i] for i in idx])


@settings(max_examples=300, deadline=None)
@given(st.data())
def test_corner_shapes_are_numpys_figures(data):
    sensors = data.draw(st.integers(1, 3))
    cols, expected, cut = [[], [], [], []], [], [0]
    end = data.draw(st.integers(0, 1))
    b0, b1 = 0.25, data.draw(st.sampled_from([0.75, 1.0]))
    for _ in range(sensors):
        n = data.draw(st.integers(0, 40))
        t = np.sort(np.array(data.draw(st.lists(st.sampled_from([0.0, 0.25, 0.5, 0.8, 1.0]),
                                                min_size=n, max_size=n)), float))
        dist = np.abs(_values(data.draw, n)) if n else np.empty(0)
        dev = _values(data.draw, n) if n else np.empty(0)
        if n and data.draw(st.booleans()):
            dev[data.draw(st.integers(0, n - 1))] = np.nan
        past = np.array(data.draw(st.lists(st.booleans(), min_size=n, max_size=n)), bool)
        expected.append(_shape(t, dist, dev, past, b0, b1, end, TOL) if n else
                        [float("nan")] * 2)
        for col, v in zip(cols, (t, dist, dev, past.astype(np.uint8)), strict=True):
            col.append(v)
        cut.append(cut[-1] + n)
    got = call("corner_shapes", *(np.concatenate(c) for c in cols),
               np.array(cut, np.int64), b0, b1, end, TOL)
    # the same bits, up to the sign of a zero overshoot (max of -0.0 and 0.0 either way)
    assert np.array_equal(got + 0.0, np.array(expected) + 0.0, equal_nan=True)


@settings(max_examples=200, deadline=None)
@given(st.data())
def test_settle_rows_finds_where_numpy_does(data):
    n = data.draw(st.integers(4, 60))
    rows = np.column_stack([np.arange(n, dtype=float), np.arange(n) * 1e-4] +
                           [_values(data.draw, n) * 2 for _ in range(3)])
    cols = [2, 3, 4]
    got = call("settle_rows", rows, np.array(cols, np.int64), TOL)
    level = np.median(rows[n - n // 4:, cols], axis=0)
    for j, col in enumerate(cols):
        out = np.flatnonzero(np.abs(rows[:, col] - level[j]) > TOL)
        last_out = abs(rows[-1, col] - level[j]) > TOL
        assert got[j] == (-1 if last_out else (out[-1] + 1 if out.size else 0))


@pytest.mark.parametrize("end", [0, 1])
@pytest.mark.parametrize("d", [2, 3])
def test_near_rows_are_numpys_rows(end, d):
    rng = np.random.default_rng(7 + d + 10 * end)
    p = np.cumsum(rng.normal(0, 1e-4, (60, d)), axis=0)
    p[20] = p[19]  # a rest: a segment of no length
    s = np.cumsum(np.concatenate([[0.0], norm_rows(np.diff(p, axis=0))]))
    q = p[rng.integers(0, 59, 300)] + rng.normal(0, 2e-5, (300, d))
    lf = rng.integers(-3, 59, 300)
    c, n = p[30].copy(), rng.normal(size=d)
    s_i, span, s_on, s_first = float(s[30]), 4e-4, float(s[40]), float(s[29])
    rows, dist, dev, past = call("near_rows", q, lf, s, p, c, n, s_i, span, s_on, s_first,
                                 end)
    mine = lf >= 0
    at = s[np.where(mine, lf, 0)]
    near = mine & (at >= s_i - span) & ((at <= s_i + span) | (at <= s_on))
    assert np.array_equal(rows, np.flatnonzero(near))
    qn, foot = q[near], lf[near]
    assert np.array_equal(dist, norm_rows(qn - c))
    if end:
        assert np.array_equal(dev, dot_rows(qn - c, n)) and past.all()
        return
    a, dd = p[foot], p[foot + 1] - p[foot]
    ln2 = dot_rows(dd, dd)
    f = np.clip(np.divide(dot_rows(qn - a, dd), ln2, out=np.zeros(ln2.shape),
                          where=ln2 > 0), 0.0, 1.0)
    assert np.array_equal(dev, dot_rows(qn - (a + f[:, None] * dd), n))
    assert np.array_equal(past.astype(bool), s[foot] + f * np.sqrt(ln2) >= s_first - 1e-12)
