"""The compiled response behind every margin and tuning (tcpmm.sim.hessenberg): a dense
solve's answer, numba's bits, one frequency's bits alone as in a grid, and no exception on
an eigenvalue."""

import numpy as np
import pytest

from tcpmm import _compiled as compiled
from tcpmm.servo.freqresp import loop_response
from test_compiled import built_or_skip


def case(seed, n=12):
    """A discrete system whose matrix entries span ten decades, as a sampled loop's do
    before balancing, its input and output vectors, and frequencies up to Nyquist at
    1 kHz [-]."""
    rng = np.random.default_rng(seed)
    scale = 10.0 ** rng.uniform(-5, 5, n)
    Phi = 0.3 * rng.normal(size=(n, n)) * scale[:, None] / scale[None, :]
    return Phi, rng.normal(size=(n, 1)), rng.normal(size=(1, n)), rng.uniform(0.0, 500.0, 300)


def dense(Phi, Gam, C, D, dt, f):
    """``C (zI - Phi)^-1 Gam + D`` by one dense solve per frequency [-]."""
    z = np.exp(2j * np.pi * f * dt)
    x = np.linalg.solve(z[:, None, None] * np.eye(Phi.shape[0]) - Phi, Gam[:, 0])
    return x @ C[0] + D[0, 0]


@pytest.mark.parametrize("seed", range(5))
def test_the_response_is_a_dense_solves(seed):
    Phi, Gam, C, f = case(seed)
    D = np.array([[0.25]])
    np.testing.assert_allclose(loop_response(Phi, Gam, C, D, 1e-3)(f),
                               dense(Phi, Gam, C, D, 1e-3, f), rtol=1e-8)


def test_a_zero_pivot_is_swapped_away():
    """``zI - H`` with a zero in its first diagonal place at the shift ``z = 1``:
    elimination without a row exchange would divide by it."""
    H = np.array([[1.0, 2.0, 0.25], [3.0, 0.0, 1.0], [0.0, 4.0, 2.0]])
    re, im = compiled.hessenberg_response(H, np.ones(1), np.zeros(1), np.array([1.0, 2.0, 3.0]),
                                          np.eye(3)[0])
    x = np.linalg.solve(np.eye(3) - H, [1.0, 2.0, 3.0])
    assert im[0] == 0.0 and re[0] == pytest.approx(x[0], rel=1e-14)


def test_a_shift_on_an_eigenvalue_gives_no_number_and_no_exception():
    H = np.array([[0.5, 1.0], [0.0, 0.25]])
    re, im = compiled.hessenberg_response(H, np.array([0.5, 0.9]), np.zeros(2), np.ones(2),
                                          np.ones(2))
    assert not np.isfinite(re[0]) and np.isfinite([re[1], im[1]]).all()


def test_one_frequency_alone_gives_its_bits_in_a_grid():
    """Brent's method refines a crossing one frequency at a time on the grid's response."""
    Phi, Gam, C, f = case(7)
    response = loop_response(Phi, Gam, C, np.zeros((1, 1)), 1e-3)
    grid = response(f)
    alone = np.array([response(v)[0] for v in f])
    assert np.array_equal(grid.view(np.int64), alone.view(np.int64))
    assert response(3.0).shape == (1,) and response(np.ones((2, 3))).shape == (2, 3)


def test_compiled_as_numbas_to_the_bit(monkeypatch):
    built_or_skip()
    Phi, Gam, C, f = case(3)
    ours = loop_response(Phi, Gam, C, np.zeros((1, 1)), 1e-3)(f)
    monkeypatch.setattr(compiled, "_chosen", [None, "numba's kernels (forced)"])
    theirs = loop_response(Phi, Gam, C, np.zeros((1, 1)), 1e-3)(f)
    assert np.array_equal(ours.view(np.int64), theirs.view(np.int64))
