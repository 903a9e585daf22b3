"""The sampler's segment and distance at every sample, compiled (and from the module built
ahead of time), as the loop in Python gives them: the same to the bit."""

from __future__ import annotations

import numpy as np
import pytest

from tcpmm import _compiled
from tcpmm.path.lookahead import lookahead
from tcpmm.path.profile import segment_profiles
from tcpmm.path.sampling import _positions


def _pythons(k0, off, dur, length, v, prof, n_samples, period_s):
    """The segment and the distance along it at each sample, the sampler's loop run by
    Python rather than compiled [-], [m]."""
    seg, s = np.zeros(n_samples, np.int64), np.zeros(n_samples)
    _positions.py_func(k0, off, dur, length, v, prof, period_s, seg, s)
    return seg, s


@pytest.mark.parametrize("seed", [1, 2])
def test_the_compiled_sampler_is_the_python_loop(seed):
    """Segments of random lengths (some of none) and speeds, with a rest between: every
    sample's segment and distance as the loop in Python gives them."""
    rng = np.random.default_rng(seed)
    n, dt, acc, jerk = 40, 1e-3, 2.0, 50.0
    length = rng.uniform(1e-4, 5e-3, n)
    length[rng.integers(0, n, 4)] = 0.0
    vmax = rng.uniform(0.01, 0.08, n)
    vj = np.r_[0.0, np.minimum(vmax[:-1], vmax[1:]), 0.0]
    vj[n // 2] = 0.0  # a rest between two moves
    v = lookahead(length, vj, np.full(n, acc), jerk)
    prof = segment_profiles(length, v, vmax, np.full(n, acc), jerk)
    dur = prof[:, 1] + prof[:, 4] + prof[:, 5]
    k_off = np.concatenate([[0.0], np.cumsum(dur)[:-1]]) / dt
    k0 = np.floor(k_off).astype(np.int64)
    off = (k_off - k0) * dt
    n_samples = int(np.ceil(dur.sum() / dt)) + 3
    got = _compiled.sample(k0, off, dur, length, v, prof, n_samples, dt)
    want = _pythons(k0, off, dur, length, v, prof, n_samples, dt)
    assert np.array_equal(got[0], want[0]) and got[1].tobytes() == want[1].tobytes()
    assert np.unique(got[0]).size > n // 2  # the samples run through the segments
