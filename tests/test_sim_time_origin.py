"""A command simulates the same whatever clock time its samples start at.

A controller trace rarely starts at 0 s. Its period read as the difference of two clock
times (5.001 - 5.0 s) rounds a hair over 1 ms, and the velocity-loop step that maps to a
sample fell a hair short of it: with the segment feed-forward (the default) half of every
sample took the velocity of the segment before. Bench C's circle started at 5 s read its
TCP contour error 70.32 for 72.31 um, its Y current up to 0.77 A off.
"""

import dataclasses

import numpy as np
import pytest

from tcpmm import builtin_machine, simulate
from tcpmm.demo import paper_circle_command
from tcpmm.path import read_command_csv, write_command_csv
from tcpmm.sim.simulate import command_steps


@pytest.fixture(scope="module")
def machine():
    return builtin_machine()


def _shifted(cmd, start_s, tmp_path):
    """``cmd`` with its time from ``start_s``, written as text and read back [-]."""
    path = tmp_path / f"cmd_{start_s:g}.csv"
    write_command_csv(dataclasses.replace(cmd, time_s=cmd.time_s + start_s), path)
    return read_command_csv(path)


@pytest.mark.parametrize("start_s", [4.0, 5.0, 100.0])
def test_a_command_started_later_simulates_to_the_same_bits(machine, tmp_path, start_s):
    cmd = _shifted(paper_circle_command(machine), 0.0, tmp_path)
    late = _shifted(cmd, start_s, tmp_path)
    assert late.time_s[1] - late.time_s[0] != cmd.time_s[1] - cmd.time_s[0] or start_s == 4.0
    a, b = simulate(machine, cmd), simulate(machine, late)
    for ax in machine.axes:
        for sig in ("cmd", "motor", "scale", "tcp", "current"):
            assert np.array_equal(getattr(a.axes[ax], sig), getattr(b.axes[ax], sig)), (ax, sig)


def test_a_period_a_whole_number_of_steps_is_taken_as_exactly_that():
    T_v = 62.5e-6
    t = 5.0 + np.arange(11) * 1e-3
    assert t[1] - t[0] > 1e-3  # the rounding the clock time leaves
    assert command_steps(t, T_v) == (16 * T_v, 161)
    # a period that is no whole number of steps is the samples' own
    t = np.arange(11) * 1e-4
    assert command_steps(t, T_v) == (1e-4, 17)
