"""With the friction pulse on the controller, the corrected command turns an axis back
only where the program does: each extra turn would fire a pulse the model's friction
predicts and the machine's may not."""

import math

import numpy as np
import pytest

from tcpmm.compensate.combined import combined_compensation
from tcpmm.compensate.drive import extra_reversals, reversals
from tcpmm.compensate.turns import holds, stretches, without_new_turns
from tcpmm.path.circle import circle_command
from tcpmm.path.command import Command
from test_compensate_combined import R, _pulses, _rough

T = 1e-3


def _out_and_back():
    """Out 10 mm, a rest, back to 0 and a rest: one reversal, at the start of the way
    back [m]."""
    out = 0.01 * (1 - np.cos(np.linspace(0, np.pi, 800))) / 2
    back = 0.01 * (1 + np.cos(np.linspace(0, np.pi, 1000))) / 2
    return np.r_[np.zeros(200), out, np.full(500, 0.01), back, np.zeros(500)]


def _turns(x):
    return reversals(Command(T * np.arange(x.size), {"A": x}), "A")[0].size


def test_the_stretches_are_the_programs_moves_between_its_reversals():
    """The rests belong to the move before them; the first stretch takes the first move's
    direction, and an axis that never moves has one stretch of direction 0."""
    ref = _out_and_back()
    (a0, b0, d0), (a1, b1, d1) = stretches(ref, T)
    assert (a0, d0, a1, b1, d1) == (0, 1.0, b0, ref.size, -1.0)
    assert 1500 <= b0 <= 1502 and _turns(ref) == 1
    assert stretches(np.zeros(50), T) == [(0, 50, 0.0)]


def test_the_holds_are_the_runs_of_equal_positions():
    """The rest before, between and after the moves; two equal samples at a reversal are
    no hold."""
    assert holds(_out_and_back()) == [(0, 201), (999, 1501), (2499, 3000)]
    assert holds(np.array([0.0, 1.0, 1.0, 0.0])) == []


def test_a_settling_swing_in_a_hold_is_held_and_a_monotone_command_kept_to_the_bit():
    """A 1 um swing at 30 Hz in the rest after the move out turns the axis back 26 times;
    projected, the hold moves one way only, and the command turns at most once at each end
    of it besides the program's reversal, within the swing's size. A command that turns
    only where the program does is returned as it is."""
    ref = _out_and_back()
    t = T * np.arange(ref.size)
    swing = 1e-6 * np.sin(2 * np.pi * 30 * t) * np.exp(-((t - 1.25) / 0.1) ** 2)
    got = without_new_turns(ref, ref + swing, T)
    assert _turns(ref + swing) > 20 and _turns(got) <= 3
    d = np.diff(got[999:1500])
    assert np.all(d >= 0) or np.all(d <= 0)
    assert np.max(np.abs(got - ref)) <= np.max(np.abs(swing))
    longer = ref * (1 + 1e-4)  # a scale correction: no turn of its own
    assert np.array_equal(without_new_turns(ref, longer, T, free_s=0.1), longer)


def test_about_a_reversal_the_correction_is_free_for_as_long_as_the_pulse_acts():
    """A swing within 0.1 s after the program's reversal is kept with a pulse of 0.1 s,
    and held to the program's direction without one."""
    ref = _out_and_back()
    t = T * np.arange(ref.size)
    turn = stretches(ref, T)[1][0]
    swing = 1e-5 * np.sin(2 * np.pi * 30 * t) * np.exp(-((t - t[turn] - 0.02) / 0.01) ** 2)
    assert np.array_equal(without_new_turns(ref, ref + swing, T, free_s=0.1), ref + swing)
    got = without_new_turns(ref, ref + swing, T)
    assert _turns(ref + swing) >= 3 and np.all(np.diff(got[turn + 1:turn + 200]) <= 0)


@pytest.mark.filterwarnings("ignore::tcpmm.errors.InputWarning")
def test_the_correction_learned_with_the_pulse_adds_no_turn_but_at_a_hold():
    """Four times the built-in friction, a pulse on each axis: the correction learned
    with it had turned X back 78 times and Y 76 where the circle turns each 4 times. Now
    it turns each where the circle does, once more at most at the ends of the rests
    before and after it, and still lowers the spike by more than half."""
    from tcpmm.compensate import predicted_scores

    m = _rough(4.0)
    circle = circle_command(R, 5000 / 60e3, turns=1.0, start_angle_rad=math.pi / 4)
    both = combined_compensation(m, circle, _pulses(m), iterations=5, n_draws=0)
    for got, want in extra_reversals(both.command, both.reference).values():
        assert got <= want + 2
    scores = predicted_scores(m, both, R)
    assert (scores["after"]["circle"]["largest_spike_um"]
            < 0.5 * scores["before"]["circle"]["largest_spike_um"])
