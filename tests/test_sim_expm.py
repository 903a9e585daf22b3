"""The matrix exponential of the exact discretisation (tcpmm.sim.expm, compiled; entry
point tcpmm._compiled.expm).

Known answers, the group property, and agreement with scipy.linalg.expm (Al-Mohy and
Higham's algorithm, the reference implementation) on the discretisations the simulator
makes of the built-in machine and of the independent simulator's machines C, D and E.
"""

import math

import numpy as np
import pytest
import scipy.linalg

from conftest import bench_path
from tcpmm import builtin_machine
from tcpmm._compiled import expm
from tcpmm.io.truthfile import machine_from_truth
from tcpmm.mechanics.statespace import plant
from tcpmm.sim import expm as numba_expm


def zoh_blocks(machine):
    """The block matrices ``[[A dt, B dt], [0, 0]]`` the simulator exponentiates per axis,
    at the velocity-loop period and at a sixteenth of it."""
    out = []
    for axis in machine.axes.values():
        p = plant(axis.mechanics, axis.servo.current_bandwidth_hz)
        n, m = p.B.shape
        for dt in (axis.servo.T_v, axis.servo.T_v / 16):
            M = np.zeros((n + m, n + m))
            M[:n, :n], M[:n, n:] = p.A * dt, p.B * dt
            out.append(M)
    return out


def test_known_answers():
    assert np.array_equal(expm(np.zeros((3, 3))), np.eye(3))
    t = 2.5
    np.testing.assert_allclose(expm([[0.0, t], [0.0, 0.0]]), [[1.0, t], [0.0, 1.0]],
                               rtol=0, atol=1e-15)
    # rotations, from a degree of 3 to thirteen with halvings
    for w in (1e-3, 0.3, 1.0, 2.0, 50.0, 400.0):
        c, s = math.cos(w), math.sin(w)
        np.testing.assert_allclose(expm([[0.0, w], [-w, 0.0]]), [[c, s], [-s, c]],
                                   rtol=0, atol=4e-15 * max(1.0, w))
    # a stiff diagonal: each entry's own exponential, to its relative precision
    d = np.array([-700.0, -30.0, 0.0, 1e-9, 20.0])
    np.testing.assert_allclose(np.diag(expm(np.diag(d))), np.exp(d), rtol=1e-13)


def test_group_property_and_inverse():
    rng = np.random.default_rng(7)
    A = rng.normal(size=(6, 6))
    E = expm(A)
    np.testing.assert_allclose(E @ E, expm(2 * A), rtol=1e-12, atol=1e-12 * np.abs(E @ E).max())
    np.testing.assert_allclose(E @ expm(-A), np.eye(6), atol=1e-12)


@pytest.mark.parametrize("scale", [1e-3, 0.1, 1.0, 5.0, 30.0])
def test_agrees_with_scipy_on_random_matrices(scale):
    rng = np.random.default_rng(int(scale * 1000))
    A = rng.normal(size=(9, 9)) * scale / 3
    ref = scipy.linalg.expm(A)
    assert np.abs(expm(A) - ref).max() <= 1e-13 * np.abs(ref).max()


@pytest.mark.parametrize("letter", ["builtin", "c", "d", "e"])
def test_agrees_with_scipy_on_the_plants(letter):
    """The plants' blocks are far from normal (1-norms to 5e4 against a spectral radius of
    order 1): the halvings follow the powers' norms, as in scipy, not the 1-norm; and
    badly scaled: balanced first. The compiled module and numba's function agree to the
    bit."""
    machine = (builtin_machine() if letter == "builtin"
               else machine_from_truth(bench_path(letter) / "truth.yaml"))
    for M in zoh_blocks(machine):
        ref = scipy.linalg.expm(M)
        got = expm(M)
        np.testing.assert_allclose(got, ref, rtol=1e-12, atol=0)  # each entry
        assert np.array_equal(got, numba_expm.expm(M))


def test_balancing_is_lapacks():
    """The plants' entries span 20 orders of magnitude; unbalanced, their small entries
    (a force's effect on a position over a sub-step) lost up to 7 digits, enough to move a
    mass identified from runs with play by 30 %. The scales are dgebal's."""
    for M in zoh_blocks(machine_from_truth(bench_path("d") / "truth.yaml")):
        _, T = scipy.linalg.matrix_balance(M, permute=False, separate=False)
        assert np.array_equal(numba_expm._balance(M), np.diag(T))


def test_rejects_what_it_cannot_take():
    with pytest.raises(ValueError, match="square"):
        expm(np.zeros((2, 3)))
    with pytest.raises(ValueError, match="finite"):
        expm([[np.nan, 0.0], [0.0, 1.0]])


def test_balancing_ends_on_entries_beyond_the_range_of_a_norm():
    """An entry over 1e154 makes a row's or column's 2-norm overflow, and halving an
    infinite norm never reached the other: `tcpmm machine show` of a model with a
    stiffness of 1e300 hung, deaf to SIGTERM inside the compiled loop. Numba's function
    runs as Python first, under an alarm, so that the test fails rather than hangs."""
    import signal

    A = np.array([[0.0, 1e200], [-1.0, 0.0]])

    def late(signum, frame):
        raise TimeoutError("the balancing did not end")

    before = signal.signal(signal.SIGALRM, late)
    signal.alarm(5)
    try:
        with np.errstate(over="ignore"):  # the squares of 1e200 overflow, as meant
            d = numba_expm._balance.py_func(A)
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, before)
    assert np.all(np.isfinite(d)) and np.all(d > 0)
    assert np.array_equal(numba_expm._balance(A), d)
    expm(A)  # ends; its value is not meaningful at this scale
