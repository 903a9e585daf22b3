"""Describing function of the nut's lost motion (tcpmm.ident.friction.playdf)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tcpmm.ident.friction import dead_zone_gain, play_gain


def classical(r):
    """Dead zone of half-width 1, input amplitude r >= 1, no bias (Gelb & Vander Velde)."""
    return 1.0 - (2.0 / np.pi) * (np.arcsin(1.0 / r) + np.sqrt(1.0 - 1.0 / r**2) / r)


def test_without_bias_it_is_the_classical_dead_zone():
    r = np.array([1.5, 2.0, 3.0, 5.0, 10.0, 30.0])
    # a play of 4 um is a dead zone of half-width 2 um
    assert dead_zone_gain(r * 2e-6, 4e-6, 0.0) == pytest.approx(classical(r), abs=2e-3)
    # inside the play the nut never touches a flank
    assert dead_zone_gain([1e-6], 4e-6, 0.0)[0] == pytest.approx(0.0, abs=1e-9)


def test_a_bias_keeps_the_nut_on_its_flank_for_small_vibration():
    play, bias = 4e-6, 1e-6
    assert dead_zone_gain([0.5e-6, 0.99e-6], play, bias) == pytest.approx(1.0, abs=1e-6)
    # once the vibration lifts the nut off, it softens, and stiffens again when large
    g = dead_zone_gain([2e-6, 4e-6, 40e-6, 400e-6], play, bias)
    assert g[0] < 1.0 and g[1] < 1.0
    assert g[2] < g[3] and g[3] > 0.99
    # without play the element is the linear spring
    assert dead_zone_gain([1e-6, 1e-5], 0.0, 0.0) == pytest.approx(1.0, abs=1e-9)


@settings(max_examples=60, deadline=None)
@given(a=st.floats(1e-8, 1e-3), play=st.one_of(st.just(0.0), st.floats(2e-9, 2e-5)),
       bias=st.floats(-1e-5, 1e-5))
def test_the_gain_is_a_softening_between_zero_and_one(a, play, bias):
    g = dead_zone_gain([a], play, bias)[0]
    assert 0.0 <= g <= 1.0
    assert g == pytest.approx(dead_zone_gain([a], play, -bias)[0], abs=1e-9)  # symmetric
    # a bias holds the nut on a flank for longer: never softer than without one
    assert g >= dead_zone_gain([a], play, 0.0)[0] - 2e-3
    half = play / 2  # the dead zone's half-width
    if half > 0 and a > half:  # the classical value, to the quadrature's accuracy
        assert dead_zone_gain([a], play, 0.0)[0] == pytest.approx(classical(a / half), abs=2e-3)


def test_play_gain_interpolates_and_is_one_outside_the_record():
    f = np.array([10.0, 100.0, 1000.0])
    gain = play_gain(f, [0.1e-6, 5e-6, 0.1e-6], 4e-6, 50.0, 1e8)
    assert gain(f)[[0, 2]] == pytest.approx(1.0)  # 0.5 um bias: small vibration stays on
    assert gain(f)[1] < 0.9
    assert gain(np.array([1.0, 1e4])) == pytest.approx(1.0)
