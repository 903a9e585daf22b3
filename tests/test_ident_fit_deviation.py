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
