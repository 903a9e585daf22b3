"""The mechanics' reported deviations are the fits' times the scale a drawn population
shows them to need (``python -m studies.fit_deviation``)."""

from types import SimpleNamespace

import pytest

from tcpmm.ident.physical.uncertainty import FIT_DEVIATION_SCALE, axis_uncertainty
from tcpmm.uncertainty.perturb import SENSITIVE


def test_every_quantity_a_circle_follows_has_a_scale_of_at_least_one():
    assert set(SENSITIVE) <= set(FIT_DEVIATION_SCALE)
    assert all(k >= 1.0 for k in FIT_DEVIATION_SCALE.values())


def test_the_reported_deviation_is_the_fits_times_its_scale(vmc):
    m = vmc.axes["X"].mechanics
    std = {"M_t": 0.01 * m.M_t, "K_h": 0.02 * m.K_h, "C_h": 0.001 * m.C_h, "lead": 1e-9}
    phys = SimpleNamespace(names=list(std), std=std, undetermined=["lead"])
    u = axis_uncertainty(phys, m)
    for p in ("M_t", "K_h", "C_h"):
        assert u.mechanics[p] == pytest.approx(std[p] * FIT_DEVIATION_SCALE[p], rel=1e-12)
    assert "lead" not in u.mechanics  # what the data do not determine is not a deviation


def test_the_study_scales_a_deviation_to_its_median_error():
    """Known answer: errors of ln 1.1 against a relative deviation of a third of that give
    |z| = 3 on every axis, a scale of 3 / 0.6745; where the mechanics are open the axis does
    not count."""
    import math

    from studies.fit_deviation import NORMAL_MEDIAN_ABS, scales

    fit = 1.1
    sd = math.log(1.1) / 3.0 * fit
    rows = [{"open": [], "M_t": [1.0, fit, sd]} for _ in range(5)]
    rows.append({"open": ["mechanics"], "M_t": [1.0, 100.0, 1e-6]})
    for r in rows:
        r.update({p: [1.0, 1.0, None] for p in ("J_m", "J_L", "K_L", "C_t", "K_t", "M_b",
                                                   "C_b", "K_b", "M_h", "C_h", "K_h")})
    assert scales(rows)["M_t"] == pytest.approx(round(3.0 / NORMAL_MEDIAN_ABS, 1))
