"""The local turns at chosen vertices, as they are over the whole path: the same to the
bit."""

from __future__ import annotations

import numpy as np

from tcpmm.analysis.corners import local_turns


def _path(rng, d, m=400):
    """A random walk of ``m`` vertices that rests here and there (vertices repeated) [m]."""
    p = np.cumsum(rng.normal(0, 1e-4, (m, d)), axis=0)
    for a in rng.integers(1, m - 5, 12):
        p[a:a + rng.integers(1, 5)] = p[a - 1]
    return p


def test_local_turns_at_some_vertices_are_those_of_all():
    """The local turns asked at some vertices (ends and rests among them) are those of
    the whole path at them."""
    rng = np.random.default_rng(5)
    p = _path(rng, 2, 200)
    at = np.r_[0, rng.integers(0, 200, 50), 199]
    assert local_turns(p, at).tobytes() == local_turns(p)[at].tobytes()
