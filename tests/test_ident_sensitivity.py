"""How far the spikes move over what the friction runs leave open
(``tcpmm.ident.friction.sensitivity``)."""

import pytest

from conftest import bench_path
from tcpmm.ident.friction import lost_motion_spike_range, spike_range, with_share
from tcpmm.io.truthfile import machine_from_truth


@pytest.fixture(scope="module")
def machine_c():
    return machine_from_truth(bench_path("c") / "truth.yaml")


def test_a_new_share_keeps_the_total_friction(machine_c):
    fr = machine_c.axes["Y"].friction
    new = with_share(fr, 0.3)
    for d in ("fc_pos", "fs_neg"):
        total = getattr(fr.guideway, d) + getattr(fr.screw, d)
        assert getattr(new.guideway, d) + getattr(new.screw, d) == pytest.approx(total)
        assert getattr(new.guideway, d) == pytest.approx(0.3 * total)
    # the bristles keep their displacement: stiffness with the level
    assert new.guideway.sigma0 / new.guideway.fs_pos == pytest.approx(
        fr.guideway.sigma0 / fr.guideway.fs_pos)
    assert with_share(fr, 1.0) is None
    assert with_share(fr.model_copy(update={"screw": None, "guideway": None}), 0.5) is None
    # all on one contact: the other takes its form, the total kept
    alone = fr.model_copy(update={"screw": None})
    half = with_share(alone, 0.5)
    assert half.screw.fc_pos == pytest.approx(0.5 * fr.guideway.fc_pos)
    assert half.guideway.fc_pos == pytest.approx(0.5 * fr.guideway.fc_pos)
    assert type(half.screw) is type(fr.guideway)


def test_the_same_friction_moves_nothing_and_a_play_moves_the_spikes(machine_c):
    fr = machine_c.axes["Y"].friction
    assert spike_range(machine_c, "Y", (fr, fr)) == 0.0
    assert lost_motion_spike_range(machine_c, "Y", (0.0, 3e-6)) > 0.5e-6
    assert spike_range(machine_c.model_copy(update={"axes": {"Y": machine_c.axes["Y"]}}),
                       "Y", (fr, fr)) is None  # no second axis for a circle


def _fitted(machine, lo, hi):
    """An identified axis whose pre-sliding fit left the range ``lo``-``hi`` [m]."""
    from types import SimpleNamespace

    from tcpmm.ident.friction import PreslidingFit

    z = (lo + hi) / 2
    fit = PreslidingFit(z, (hi - lo) / 4, 0.5, 0.05, 6, 1.0, 1.0, True, "", (lo, hi))
    return SimpleNamespace(presliding_fit=fit, presliding_sensitivity=None)


def test_the_presliding_range_is_simulated_and_warned_about_when_it_matters(machine_c):
    import warnings

    from tcpmm.errors import InputWarning
    from tcpmm.ident.friction import presliding_spike_range, warn_presliding_sensitivity

    assert presliding_spike_range(machine_c, "Y", (4e-6, 4e-6), 0.5) == 0.0
    wide, narrow = _fitted(machine_c, 2e-6, 8e-6), _fitted(machine_c, 4.00e-6, 4.02e-6)
    with pytest.warns(InputWarning, match=r"axis Y: .* between 2\.00 and 8\.00 um"):
        warn_presliding_sensitivity("Y", wide, machine_c, None)
    assert wide.presliding_sensitivity.spike_change_m > 1e-6
    with warnings.catch_warnings():
        warnings.simplefilter("error", InputWarning)
        warn_presliding_sensitivity("Y", narrow, machine_c, None)
    assert 0.0 < narrow.presliding_sensitivity.spike_change_m < 1e-6
    assert narrow.presliding_sensitivity.to_dict()["presliding_m"] == [4.00e-6, 4.02e-6]


def test_a_spread_draws_the_presliding_distance(machine_c):
    """The uncertainty's ``presliding`` draws the distance of both contacts (log-normal),
    their damping ratio kept; without it the bristles stay as they are."""
    import math

    import numpy as np

    from tcpmm.model import AxisUncertainty
    from tcpmm.whatif.spread import draw_axis

    a = machine_c.axes["Y"]
    fr = a.friction
    drawn = [draw_axis(a.replace(uncertainty=AxisUncertainty(presliding=0.2)),
                       np.random.default_rng(k)).friction for k in range(64)]
    z = np.array([d.guideway.fs_pos / d.guideway.sigma0 for d in drawn])
    z0 = fr.guideway.fs_pos / fr.guideway.sigma0
    assert np.std(np.log(z / z0)) == pytest.approx(0.2, rel=0.3)
    for d in drawn[:4]:
        k = fr.guideway.sigma0 / d.guideway.sigma0
        assert fr.screw.sigma0 / d.screw.sigma0 == pytest.approx(k)  # one distance for both
        assert d.guideway.sigma1 == pytest.approx(fr.guideway.sigma1 / math.sqrt(k))
    same = draw_axis(a.replace(uncertainty=AxisUncertainty()), np.random.default_rng(0))
    g = same.friction.guideway
    assert g.fs_pos / g.sigma0 == pytest.approx(z0, rel=1e-12)


def test_a_change_that_is_not_a_number_is_said_so():
    """Where the model's run of the circle holds its current at the limit, the spikes'
    change came out NaN and the warning read 'move by up to nan um'."""
    from tcpmm.ident.friction.sensitivity import moved_by

    assert moved_by(1.5e-6) == "by up to 1.50 um"
    assert "nan" not in moved_by(float("nan")) and "cannot tell" in moved_by(float("nan"))
