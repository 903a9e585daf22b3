"""The row-wise reductions of :mod:`tcpmm._rows` against numpy's along the rows."""

import numpy as np

from tcpmm._rows import any_rows, min_rows


def test_the_smallest_of_each_row_is_numpys_with_infinities_and_nans():
    rng = np.random.default_rng(5)
    for d in (1, 2, 3, 5):
        a = rng.normal(size=(500, d)) * 10.0 ** rng.integers(-300, 300, (500, d))
        a[rng.random((500, d)) < 0.1] = np.inf
        a[rng.random((500, d)) < 0.05] = -np.inf
        a[rng.random((500, d)) < 0.05] = np.nan
        want = np.min(a, axis=1)
        got = min_rows(a)
        assert np.array_equal(got.view(np.int64), want.view(np.int64))
        assert np.shares_memory(got, a) is False
    assert min_rows(np.empty((0, 3))).shape == (0,)


def test_whether_any_of_each_row_is_numpys():
    rng = np.random.default_rng(6)
    for d in (1, 2, 3):
        a = rng.random((400, d)) < 0.3
        assert np.array_equal(any_rows(a), np.any(a, axis=1))
        before = a.copy()
        any_rows(a)
        assert np.array_equal(a, before)
