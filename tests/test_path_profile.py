"""Feed profile and look-ahead: speed changes, reachable speeds, segment profiles."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from tcpmm.path.lookahead import lookahead
from tcpmm.path.profile import (
    change,
    change_position,
    distance,
    peak,
    reach,
    segment_position,
    segment_profiles,
)

speeds = st.one_of(st.just(0.0), st.floats(1e-6, 1.0))  # [m/s]
accels = st.floats(0.1, 10.0)
jerks = st.one_of(st.just(math.inf), st.floats(1.0, 1000.0))
lengths = st.floats(1e-5, 0.5)


def _samples(f, T):
    """f on a grid over [0, T], no finer than 1 us (finer steps only amplify rounding)."""
    n = int(min(500, max(4, T / 1e-6))) + 1
    t = np.linspace(0.0, T, n)
    return t, np.array([f(x) for x in t])


def _max_derivs(t, s, braking=0.0):
    """Differences of s and the rounding noise they carry [m/s, m/s^2, m/s^3]; ``braking``
    is the largest ``v^2/a`` of the motion [m]."""
    h = t[1] - t[0]
    v = np.diff(s) / h
    a = np.diff(s, 2) / h**2
    j = np.diff(s, 3) / h**3
    # rounding of s. A position sums several pieces of about its own size (v0 t, a t^2/2,
    # the lengths of earlier phases), each rounded: 0.625 m/s for 12.5 ms, say, came out
    # 70 eps off, and a second difference combines three such positions. Phase lengths
    # from speed differences, (v0^2 - v1^2)/(2 a), are rounded relative to v^2/a: from
    # 0.93751 to 0.9375 m/s in 10 um at 0.96 m/s^2, 0.9 eps of it.
    eps = np.finfo(float).eps
    noise = max(256 * eps * np.abs(s).max(), 16 * eps * braking, 1e-16)
    return v, a, j, noise / h**2, noise / h**3


@settings(max_examples=60, deadline=None)
@given(va=speeds, vb=speeds, a=accels, j=jerks)
def test_speed_change_meets_limits_and_ends(va, vb, a, j):
    T, tj, ap = change(va, vb, a, j)
    d = distance(va, vb, a, j)
    assert ap <= a * (1 + 1e-12)
    if va == vb:
        assert T == 0.0
        return
    assert change_position(T, va, vb, T, tj, ap) == d
    t, s = _samples(lambda x: change_position(x, va, vb, T, tj, ap), T)
    v, acc, jerk, acc_noise, jerk_noise = _max_derivs(t, s, max(va, vb) ** 2 / a)
    h = t[1] - t[0]
    assert np.all(np.diff(s) >= -1e-15)
    # speed stays between the end speeds; starts and ends at them
    assert v.min() >= min(va, vb) - 1e-9 and v.max() <= max(va, vb) + 1e-9
    assert abs(v[0] - va) <= a * h + 1e-9 and abs(v[-1] - vb) <= a * h + 1e-9
    # second/third differences are averages of acceleration/jerk over the stencil
    assert np.abs(acc).max() <= a * (1 + 1e-9) + acc_noise
    if math.isfinite(j):
        assert np.abs(jerk).max() <= j * (1 + 1e-9) + jerk_noise


@settings(max_examples=80, deadline=None)
@given(va=speeds, length=lengths, a=accels, j=jerks, cap=st.floats(0.0, 2.0))
def test_reach_is_the_highest_feasible_speed(va, length, a, j, cap):
    vb = reach(va, length, a, j, cap)
    assert vb <= cap
    if cap <= va:
        return
    assert vb >= va
    assert distance(va, vb, a, j) <= length * (1 + 1e-9)
    if vb < cap:  # limited by the distance: a little more speed would not fit
        assert distance(va, vb * (1 + 1e-6) + 1e-9, a, j) > length


@settings(max_examples=60, deadline=None)
@given(v0=speeds, v1=speeds, vmax=st.floats(0.01, 1.0), length=lengths, a=accels, j=jerks)
def test_segment_profile_covers_its_length(v0, v1, vmax, length, a, j):
    v0, v1 = min(v0, vmax), min(v1, vmax)
    # make the end speeds connectable as the look-ahead would
    v1 = min(v1, reach(v0, length, a, j, vmax))
    v0 = min(v0, reach(v1, length, a, j, vmax))
    vp = peak(v0, v1, vmax, length, a, j)
    assert max(v0, v1) <= vp <= vmax
    prof = segment_profiles(
        np.array([length]), np.array([v0, v1]), np.array([vmax]), np.array([a]), j
    )[0]
    T = prof[1] + prof[4] + prof[5]
    assert segment_position(T, v0, v1, length, prof) == length
    t, s = _samples(lambda x: segment_position(x, v0, v1, length, prof), T)
    v, acc, jerk, acc_noise, jerk_noise = _max_derivs(t, s, vp**2 / a)
    assert abs(s[-1] - length) <= 1e-12 * length + 1e-15
    assert v.max() <= vmax * (1 + 1e-9) + 1e-12
    assert np.abs(acc).max() <= a * (1 + 1e-9) + acc_noise
    if math.isfinite(j):
        assert np.abs(jerk).max() <= j * (1 + 1e-9) + jerk_noise


@settings(max_examples=40, deadline=None)
@given(
    data=st.lists(st.tuples(lengths, st.floats(0.0, 1.0)), min_size=1, max_size=30),
    a=accels,
    j=jerks,
)
def test_lookahead_gives_connectable_junction_speeds(data, a, j):
    length = np.array([d[0] for d in data])
    vj = np.array([0.0] + [d[1] for d in data[:-1]] + [0.0])
    acc = np.full(length.size, a)
    v = lookahead(length, vj, acc, j)
    assert v[0] == 0.0 and v[-1] == 0.0
    assert np.all(v <= vj + 1e-15)
    for i in range(length.size):
        assert distance(v[i], v[i + 1], a, j) <= length[i] * (1 + 1e-9) + 1e-15
