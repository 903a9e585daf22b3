"""An axis whose command holds still: the records copied from a cycle of its states are
the kernel's, to the bit, whatever pieces the command comes in."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from tcpmm.sim import axishold
from tcpmm.sim.axishold import held
from tcpmm.sim.axisstream import AxisStream
from tcpmm.sim.simulate import simulate_axis

SIGNALS = ("cmd", "motor", "scale", "tcp", "current", "motor_speed", "motor_angle",
           "current_peak")


def command(n_hold: int) -> np.ndarray:
    """Held at 0, a move of 2 mm, held at 2 mm, back to 1 mm, held there [m]."""
    move = 1e-3 * (1 - np.cos(np.linspace(0, np.pi, 400)))
    back = 2e-3 - 0.5e-3 * (1 - np.cos(np.linspace(0, np.pi, 200)))
    return np.concatenate([np.zeros(n_hold), move, np.full(n_hold, 2e-3), back,
                           np.full(n_hold // 2, 1e-3)])


def streamed(axis, cmd, cuts, period=1e-3):
    """The records of ``cmd`` pushed in pieces cut at ``cuts``, and the stream [SI]."""
    s = AxisStream(axis, period)
    edges = [0, *cuts, cmd.size]
    runs = [s.push(cmd[a:b]) for a, b in itertools.pairwise(edges)]
    runs.append(s.push(np.empty(0), True, (cmd.size - 1) * period))
    return {sig: np.concatenate([getattr(r, sig) for r in runs]) for sig in SIGNALS}, s


@pytest.mark.parametrize("axis", ["X", "Z"])
@pytest.mark.parametrize("cuts", [[1, 4700, 4701, 9000], [3333, 6000, 9999, 15000]])
def test_a_held_command_gives_the_kernels_records(vmc, axis, cuts):
    cmd = command(5000)
    ref = simulate_axis(vmc.axes[axis], np.arange(cmd.size) * 1e-3, cmd)
    got, _ = streamed(vmc.axes[axis], cmd, cuts)
    for sig in SIGNALS:
        assert np.array_equal(got[sig], getattr(ref, sig)), sig


def test_the_hunting_z_axis_is_copied_from_its_cycle(vmc, monkeypatch):
    # Z of builtin:vmc hunts about a held position in a cycle of some two seconds
    found = []
    copied = axishold.HeldCommand._copied

    def logged(self, k, stop, *args):
        found.append(self.cycle[2])
        return copied(self, k, stop, *args)

    monkeypatch.setattr(axishold.HeldCommand, "_copied", logged)
    cmd = np.zeros(12000)
    ref = simulate_axis(vmc.axes["Z"], np.arange(cmd.size) * 1e-3, cmd)
    got, _ = streamed(vmc.axes["Z"], cmd, [7000])
    assert found and found[0] > 1
    for sig in SIGNALS:
        assert np.array_equal(got[sig], getattr(ref, sig)), sig


def test_no_cycle_within_the_budget_runs_the_kernel(vmc, monkeypatch):
    monkeypatch.setattr(axishold, "MAX_RECORDS", 50)
    cmd = command(3000)
    ref = simulate_axis(vmc.axes["Z"], np.arange(cmd.size) * 1e-3, cmd)
    got, s = streamed(vmc.axes["Z"], cmd, [1000, 2000, 4000])
    assert s.hold.looked <= 50
    for sig in SIGNALS:
        assert np.array_equal(got[sig], getattr(ref, sig)), sig


def test_a_command_held_at_minus_zero_is_not_one_held_at_zero():
    z = np.zeros(4)
    assert held(z, z) is not None
    assert held(np.array([0.0, -0.0, 0.0]), np.zeros(3)) is None
    assert held(z, z) != held(-z, z)
    assert held(np.array([0.0, 1e-9]), np.zeros(2)) is None
