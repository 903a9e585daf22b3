"""The largest current between two records, which a drive's clamp meets.

A record every millisecond samples the current of one velocity-loop step in sixteen:
the compensated command of bench C's model read 2.58 A at its records against a limit of
2.9 A, while the drive sat at the limit for 44 steps between them, and the program's own
peak of 3.14 A read 2.67 A. Each record carries the largest size of the current over the
steps since the record before (``AxisRun.current_peak``).
"""

import numpy as np
import pytest

from tcpmm import builtin_machine, simulate
from tcpmm.demo import paper_circle_command
from tcpmm.result import AxisRun


@pytest.fixture(scope="module")
def runs():
    m = builtin_machine()
    cmd = paper_circle_command(m)
    every = m.axes["X"].servo.T_v
    return m, simulate(m, cmd), simulate(m, cmd, record_period_s=every)


def test_each_record_holds_the_largest_current_since_the_record_before(runs):
    m, coarse, fine = runs
    per = round(1e-3 / m.axes["X"].servo.T_v)
    for a in m.axes:
        steps = np.abs(fine.axes[a].current)
        peak = coarse.axes[a].current_peak
        assert peak[0] == steps[0]
        n = peak.size - 1
        between = steps[1:1 + n * per].reshape(n, per).max(axis=1)
        assert np.array_equal(peak[1:], between), a
        # recorded every step, the peak is the step's own current
        assert np.array_equal(fine.axes[a].current_peak, steps), a
    # between the records the current goes past what they show on this circle's Y or Z
    assert any(np.max(coarse.axes[a].current_peak) > np.max(np.abs(coarse.axes[a].current))
               for a in m.axes)


def test_a_run_read_from_a_file_takes_its_sampled_current():
    run = AxisRun(cmd=np.zeros(3), current=np.array([1.0, -2.0, 0.5]))
    assert np.array_equal(run.peak_current(), [1.0, 2.0, 0.5])
