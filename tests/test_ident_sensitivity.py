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
    assert with_share(fr.model_copy(update={"screw": None}), 0.5) is None


def test_the_same_friction_moves_nothing_and_a_play_moves_the_spikes(machine_c):
    fr = machine_c.axes["Y"].friction
    assert spike_range(machine_c, "Y", (fr, fr)) == 0.0
    assert lost_motion_spike_range(machine_c, "Y", (0.0, 3e-6)) > 0.5e-6
    assert spike_range(machine_c.model_copy(update={"axes": {"Y": machine_c.axes["Y"]}}),
                       "Y", (fr, fr)) is None  # no second axis for a circle
