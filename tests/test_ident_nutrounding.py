"""The steady stretches and the rounding bias of the nut fit, held bit for bit to the plain
per-sample and per-harmonic loops they are computed without."""

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tcpmm.ident.friction import lostmotion
from tcpmm.ident.friction.lostmotion import quantisation_bias_std
from tcpmm.ident.friction.nutrounding import steady_stretches

Q = 1e-6  # scale step [m]


def stretches_reference(idx, v, rel=0.02):
    """The runs of :func:`steady_stretches`, one sample at a time on numpy scalars."""
    out, i0 = [], 0
    for i in range(1, idx.size + 1):
        if (i == idx.size or idx[i] != idx[i - 1] + 1
                or abs(v[idx[i]] - v[idx[i0]]) > rel * abs(v[idx[i0]])):
            out.append((i0, i))
            i0 = i
    return out


def bias_std_reference(t, x, quantum):
    """:func:`quantisation_bias_std` one harmonic at a time, each with its own 1-D mean."""
    if quantum <= 0.0:
        return 0.0
    t = np.asarray(t, dtype=float)
    x = np.asarray(x, dtype=float)
    if x.size < 3:
        return quantum / math.sqrt(12.0)
    tc = t - t.mean()
    slope = float(tc @ (x - x.mean()) / (tc @ tc)) if tc @ tc > 0 else 0.0
    line = x.mean() + slope * tc
    phase = (line - line[0]) / quantum
    n = np.arange(1, 101)
    z = np.exp(2j * np.pi * phase)
    zn = np.ones_like(z)
    c = np.empty(n.size)
    for i in range(n.size):
        zn *= z
        c[i] = abs(zn.mean()) ** 2
    var_phase = float(np.sum(c / (2.0 * np.pi**2 * n**2)))
    var_phase += float(np.mean(c[-10:])) / (2.0 * np.pi**2 * 100)
    return quantum * math.sqrt(min(max(var_phase, 1.0 / (12.0 * x.size)), 1.0 / 12.0))


def ramp(seed, size):
    """A rounded ramp with vibration, as a scale records a steady motion [s], [m]."""
    rng = np.random.default_rng(seed)
    t = np.arange(size) * 1e-3
    x = rng.uniform(-0.1, 0.1) + rng.uniform(-0.05, 0.05) * t + rng.normal(0.0, Q, size)
    return t, np.round(x / Q) * Q


def test_stretches_known_answer():
    v = np.array([1.0, 1.01, 1.03, 1.0, -0.0, 0.0, 5.0, 5.0, 5.0])
    idx = np.array([0, 1, 2, 3, 4, 5, 7, 8])
    assert steady_stretches(idx, v) == [(0, 2), (2, 3), (3, 4), (4, 6), (6, 8)]
    assert steady_stretches(np.array([], dtype=int), v) == []


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.floats(-2.0, 2.0, allow_subnormal=False), min_size=1, max_size=60),
       st.lists(st.integers(1, 3), min_size=60, max_size=60),
       st.sampled_from([0.0, 0.02, 0.5]))
def test_stretches_as_per_sample_loop(speeds, steps, rel):
    v = np.repeat(np.asarray(speeds), 3)  # plateaus of three equal speeds among the changes
    idx = np.cumsum(steps)[: v.size] - 1
    idx = idx[idx < v.size]
    assert steady_stretches(idx, v, rel) == stretches_reference(idx, v, rel)


@pytest.mark.parametrize("seed", range(40))
def test_bias_std_bit_for_bit_on_ramps(seed):
    t, x = ramp(seed, 3 + 37 * seed)
    assert quantisation_bias_std(t, x, Q) == bias_std_reference(t, x, Q)


@settings(max_examples=100, deadline=None)
@given(st.integers(3, 400), st.floats(-1e-3, 1e-3), st.floats(0.1, 30.0), st.integers(0, 2**32 - 1))
def test_bias_std_bit_for_bit_generated(size, speed, steps, seed):
    rng = np.random.default_rng(seed)
    q = Q * steps
    t = np.arange(size) * 1e-3
    x = np.round((speed * t + rng.normal(0.0, q, size)) / q) * q
    assert quantisation_bias_std(t, x, q) == bias_std_reference(t, x, q)


@pytest.mark.parametrize("block", [1, 7 * 50, 7 * 100 - 1])
def test_bias_std_bit_for_bit_in_blocks(monkeypatch, block):
    monkeypatch.setattr(lostmotion, "_BLOCK", block)
    for seed in range(5):
        t, x = ramp(seed, 50)
        assert quantisation_bias_std(t, x, Q) == bias_std_reference(t, x, Q)
