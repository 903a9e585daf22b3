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
from tcpmm.sim.cornerfigs import settle_rows

TOL = 1e-6


def _held(dev, tol):
    q = dev.size // 4 or 1
    tail = dev[-q:]
    if tail.size < 4:
        return 0.0
    level = float(np.median(tail))
    if np.isnan(tail).any() or not level > tol:
        return 0.0
    if float(np.max(np.abs(tail - level))) <= tol:
        return level
    # a ringing about a sag: wholly outside the band, about the level of the quarter before
    before = float(np.median(dev[-2 * q:-q]))
    return level if tail.min() > tol and abs(before - level) <= tol else 0.0


def _shape(t, dist, dev, past, b0, b1, end, tol):
    """Overshoot and rounding as numpy gives them."""
    own = (t >= b0) & (t <= b1)
    if not own.any():
        return [float("nan"), float("nan")]
    if end:  # the level from every sample, the travel from the command's arrival on
        dv = dev[own]
        dv = dev[own & past] - max(float(np.median(dv[-(dv.size // 4 or 1):])), 0.0)
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
    got = settle_rows(rows, np.array(cols, np.int64), TOL)
    quarter = n - n // 4
    level = np.median(rows[quarter:, cols], axis=0)
    for j, col in enumerate(cols):
        out = np.flatnonzero(np.abs(rows[:, col] - level[j]) > TOL)
        # settled only where the whole last quarter lies within the band
        unsettled = out.size and out[-1] >= quarter
        assert got[j] == (-1 if unsettled else (out[-1] + 1 if out.size else 0))


def _batch(rng, d):
    """A command polyline with a rest, and two sensors' samples of it."""
    p = np.cumsum(rng.normal(0, 1e-4, (60, d)), axis=0)
    p[20] = p[19]  # a rest: a segment of no length
    s = np.cumsum(np.concatenate([[0.0], norm_rows(np.diff(p, axis=0))]))
    m, off = 300, 5
    t = np.sort(rng.uniform(0, 0.06, m))
    q = p[rng.integers(0, 59, (2, m))] + rng.normal(0, 2e-5, (2, m, d))
    e, f = rng.normal(0, 1e-6, (2, m)), rng.integers(-3 + off, 59 + off, (2, m))
    return p, s, np.arange(60) * 1e-3, t, q, e, f, off


def _numpys_share(p, s, tc, t, q, e, f, off, c, n, lim, end):
    """A corner's share of the batch as the numpy expressions give it: per sensor the
    times, distances, deviations and past-flags near it, and its settling rows."""
    t_lo, t_hi, t0, s_i, span, s_on, s_first = lim
    w = slice(np.searchsorted(t, t_lo, "left"), np.searchsorted(t, t_hi, "right"))
    after = t[w] >= t0
    rows = [t[w][after], np.interp(t[w][after], tc, s)]
    near_cols = []
    for k in range(2):
        qk, lf = q[k, w], f[k, w] - off
        mine = lf >= 0
        at = s[np.where(mine, lf, 0)]
        near = mine & (at >= s_i - span) & ((at <= s_i + span) | (at <= s_on))
        if end:  # past the end point, closest to a segment wholly before the span
            back = ~mine | (s[np.where(mine, lf + 1, 0)] < s_i - span)
            near |= after & back & (norm_rows(qk - c) <= span)
        qn, foot = qk[near], lf[near]
        rows.append(norm_rows(qk[after] - c) if end else e[k, w][after])
        if end:
            dev, past = dot_rows(qn - c, n), t[w][near] >= t0
        else:
            a, dd = p[foot], p[foot + 1] - p[foot]
            ln2 = dot_rows(dd, dd)
            fr = np.clip(np.divide(dot_rows(qn - a, dd), ln2, out=np.zeros(ln2.shape),
                                   where=ln2 > 0), 0.0, 1.0)
            dev = dot_rows(qn - (a + fr[:, None] * dd), n)
            past = s[foot] + fr * np.sqrt(ln2) >= s_first - 1e-12
        near_cols.append((t[w][near], norm_rows(qn - c), dev, past))
    return near_cols, np.column_stack(rows)


@pytest.mark.parametrize("d", [2, 3])
def test_feed_many_takes_numpys_share_for_each_corner(d):
    """Three corners (one the end of the path) take down their windows of one batch of
    two sensors' samples: those near each corner, their figures, and the settling rows
    from its time on, each as numpy gives them."""
    rng = np.random.default_rng(7 + d)
    p, s, tc, t, q, e, f, off = _batch(rng, d)
    corners = [(30, 0.01, 0.05, 0.03, 40, 29, 0), (45, 0.03, 0.06, 0.045, 50, 44, 0),
               (59, 0.05, np.inf, 0.055, 59, 57, 1)]
    c = np.array([p[k[0]] for k in corners])
    n = rng.normal(size=(3, d))
    lims = np.array([[lo, hi, t0, s[i], 4e-4, s[on], s[first]]
                     for i, lo, hi, t0, on, first, _ in corners])
    end = np.array([k[-1] for k in corners], np.int64)
    cuts, tn, dist, dev, past, rowcut, rows = call("feed_many", t, q, e, f, off, tc, s, p,
                                                   c, n, lims, end)
    for j in range(3):
        near_cols, want_rows = _numpys_share(p, s, tc, t, q, e, f, off, c[j], n[j],
                                             lims[j], end[j])
        assert np.array_equal(rows[rowcut[j]:rowcut[j + 1]], want_rows)
        for k in range(2):
            got = slice(cuts[j, k], cuts[j, k + 1])
            for x, want in zip((tn, dist, dev, past.astype(bool)), near_cols[k],
                               strict=True):
                assert np.array_equal(x[got], want)
    # every corner holds samples of both kinds
    assert (np.diff(cuts[:, [0, -1]], axis=1) > 0).all() and (np.diff(rowcut) > 10).all()


def test_feed_many_interpolates_the_path_as_numpy_does():
    """The command's path length at the settling rows, for samples on vertices, between
    them, two at one time and before and after the command (the vertex of each looked
    for on from the one before): numpy's interpolation."""
    rng = np.random.default_rng(3)
    p, s, tc, *_, off = _batch(rng, 2)
    t = np.sort(np.r_[-0.002, tc[::7], tc[5], rng.uniform(0, 0.059, 200), 0.0595, 0.07])
    m = t.size
    lims = np.array([[t[0], np.inf, t[0], s[10], 4e-4, s[10], s[10]]])
    *_, rowcut, rows = call("feed_many", t, np.zeros((2, m, 2)), np.zeros((2, m)),
                            np.full((2, m), off, np.int64), off, tc, s, p, p[10:11],
                            np.ones((1, 2)), lims, np.zeros(1, np.int64))
    assert rowcut[-1] == m and np.array_equal(rows[:, 1], np.interp(t, tc, s))


@pytest.mark.parametrize("turn", [0.9, np.nan])
def test_corner_frame_is_numpys_geometry(turn):
    """The rest's first vertex, the path length at the corner's time, the outward and
    outgoing directions, with numpy's interpolation."""
    rng = np.random.default_rng(3)
    p = np.cumsum(rng.normal(0, 1e-4, (80, 2)), axis=0)
    p[38:41] = p[41]  # the command rests on the corner point
    s = np.cumsum(np.concatenate([[0.0], norm_rows(np.diff(p, axis=0))]))
    tc = np.arange(80) * 1e-3
    i, span = 41, 3e-4
    # among other corners of one call, each its own frame
    rows = call("corner_frames", p, s, tc, np.array([20, i, 60]), np.array([0.5, turn, 0.7]),
                span)
    got = rows[1]
    for j, k, t in ((0, 20, 0.5), (2, 60, 0.7)):
        one = call("corner_frames", p, s, tc, np.array([k]), np.array([t]), span)[0]
        assert rows[j].tobytes() == one.tobytes()
    assert got[0] == 38
    t0 = tc[38] if np.isnan(turn) else tc[i]
    assert got[1] == np.interp(t0, tc, s)
    back = np.array([np.interp(s[i] - span, s, p[:, k]) for k in range(2)])
    ahead = np.array([np.interp(s[i] + span, s, p[:, k]) for k in range(2)])
    t_in = (p[i] - back) / np.sqrt(dot_rows(p[i] - back, p[i] - back))
    t_out = (ahead - p[i]) / np.sqrt(dot_rows(ahead - p[i], ahead - p[i]))
    nn = t_in - dot_rows(t_in, t_out) * t_out
    want = t_in if np.isnan(turn) else nn / np.sqrt(dot_rows(nn, nn))
    assert np.array_equal(got[2:4], want)
    assert np.array_equal(got[4:], t_in if np.isnan(turn) else t_out)
