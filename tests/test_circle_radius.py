"""The radial deviation is the mean radius of the samples about the nominal centre, less the
nominal, with a servo mismatch on a full turn.
"""

import numpy as np
import pytest

from tcpmm.analysis.diagnostics import diagnose_pair
from test_circle_diagnostics import DT, R, circle


def _pair(err, n):
    w = 2 * np.pi / (n * DT)
    return diagnose_pair(circle("ccw", err, 1, n=n), circle("cw", err, 2, n=n), R, (w, w))


@pytest.mark.parametrize("n, tau", [(1320, 4e-3), (7200, 2e-3), (754, -2e-3)],
                         ids=["F10000-4ms", "F1800-2ms", "F17500-2ms"])
@pytest.mark.parametrize("others", [{}, {"cx": 3e-6, "cy": -2e-6, "eps_x": 10e-6,
                                         "alpha": 15e-6, "b_x": 4e-6, "b_y": -3e-6}],
                         ids=["alone", "with-others"])
def test_a_servo_mismatch_moves_the_radial_deviation_by_what_it_moves_the_samples(
        n, tau, others):
    """Each lagging axis stays on its own sine, of the full radius: over the samples of a
    turn the tool's radius is ``R sqrt(1 - sin mu sin(2u - mu))``, whose mean is
    ``-R mu^2 / 16`` off R. The mean over the tool's angle, which the lag moves along the
    ellipse, weighs its inside more and is ``-5 R mu^2 / 16`` off: with Y 4 ms behind at
    F10000 on R 35 mm, -3.97 um for -0.79 um."""
    err = {"tau_y": tau, **others}
    d = _pair(err, n)
    mu = 2 * np.pi / (n * DT) * tau
    for direction in ("ccw", "cw"):
        e = circle(direction, err, noise=0.0, n=n)[1][:-1]
        true = float(np.mean(e))
        if not others:
            assert true == pytest.approx(-R * mu**2 / 16, rel=0.02)
        assert d[f"radial_deviation_{direction}"] == pytest.approx(
            true, abs=max(0.1e-6, 0.02 * abs(true))), direction
    assert d["servo_mismatch"] == pytest.approx(tau, rel=0.01)
