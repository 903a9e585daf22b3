"""Errors of one axis' position beside a servo mismatch: each axis runs on its own sine,
and a squareness, a scale mismatch or a bow is taken where that axis is, not where the
tool is. Read where the tool is, a squareness of 300 um/m beside a 2 ms mismatch at
F10000 on R 20 mm made 0.15 um of lateral play, and a scale mismatch of 300 ppm 0.03 um
of backlash, that were not there."""

import numpy as np
import pytest

import test_circle_diagnostics as gen
from tcpmm.analysis.diagnostics import diagnose_pair

R = 0.020
#: F10000 on R 20 mm [rad/s]
W = 10000 / 60e3 / R


@pytest.mark.parametrize("err", [
    {"alpha": 300e-6, "tau_y": 2e-3}, {"alpha": -300e-6, "tau_x": 1e-3, "tau_y": -1e-3},
    {"eps_x": 300e-6, "tau_y": 2e-3}, {"str_x": 3e-6, "str_y": -2e-6, "tau_y": 2e-3},
    {"alpha": 150e-6, "eps_x": -200e-6, "b_x": 2e-6, "p_y": 1e-6, "tau_y": -2e-3}])
def test_an_axis_error_beside_a_servo_mismatch_makes_no_other_term(err, monkeypatch):
    monkeypatch.setattr(gen, "R", R)
    n = round(2 * np.pi / (W * gen.DT))
    w = 2 * np.pi / (n * gen.DT)
    diag = diagnose_pair(gen.circle("ccw", err, 1, noise=0.0, n=n),
                         gen.circle("cw", err, 2, noise=0.0, n=n), R, (w, w))
    want = gen.expected(err, n=n)
    for term in ("lateral_play_X", "lateral_play_Y", "backlash_X", "backlash_Y"):
        assert abs(diag[term] - want[term]) < 0.02e-6, (term, diag[term], want[term])
    monkeypatch.setattr(gen, "PER_UNIT", {**gen.PER_UNIT, "squareness": R / 2,
                                          "scale_mismatch": R / 2})
    gen.assert_recovered(diag, {k: v for k, v in want.items()
                                if not k.startswith(("spike", "radial", "cyclic"))}, w)
