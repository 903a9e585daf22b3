"""The TCP device's gain against the fitted model on machines heavier and softer than the
reference ones: a true TCP device is not blamed, a mis-scaled one still is.

Bench C with its table mass and friction doubled (its Y's first mode at 24 Hz) and bench
H's X with a table 2.3 times and a head half as heavy on a softer column (17 Hz) were
refused with their TCP devices true: the gate read the bins at the sweep's start, which
the start lifts above the model (bench H's X by 11 % at 4.4 Hz), and extrapolated them to
zero frequency (1.033 and 1.19).
"""

import dataclasses
import warnings

import pytest
import yaml

from conftest import bench_path
from tcpmm.ident.gates.finding import SuspectModelError
from tcpmm.ident.gates.masses import TCP_GAIN_RANGE
from tcpmm.ident.pipeline import identify_bundle

#: The machines: bench, axis, and the factors on the table's and head's masses, the head's
#: stiffness and the friction [-].
MACHINES = {"c_heavy_Y": ("c", "Y", 2.0, 1.0, 1.0, 2.0),
            "h_soft_X": ("h", "X", 2.29, 0.5, 0.74, 0.77)}


def _bundle(tmp_path, key):
    """The machine's one-axis bundle, simulated by :func:`virtual_bundle` [-]."""
    from tcpmm.io.bundle import read_bundle
    from tcpmm.io.truthfile import machine_from_truth
    from tcpmm.machines.virtual import virtual_bundle

    letter, axis, table, head, column, friction = MACHINES[key]
    truth = yaml.safe_load((bench_path(letter) / "truth.yaml").read_text())
    a = truth["axes"][axis]
    a["mechanics"]["Mt_kg"] *= table
    a["mechanics"]["Mh_kg"] *= head
    a["mechanics"]["Kh_N_per_m"] *= column
    for k in ("guide_Fc_N", "guide_Fs_N", "screw_Tc_Nm", "screw_Ts_Nm"):
        a["friction"][k] *= friction
    truth["axes"] = {axis: a}
    (tmp_path / "truth.yaml").write_text(yaml.safe_dump(truth, sort_keys=False))
    machine = machine_from_truth(tmp_path / "truth.yaml")
    return read_bundle(virtual_bundle(machine, tmp_path / "bundle", axes=(axis,), seed=8))


def _scaled(bundle, factor):
    """``bundle`` with its TCP device reading ``factor`` times the motion [-]."""
    (name, x), = bundle.axes.items()
    sweep = dataclasses.replace(x.sweep, tcp_m=factor * x.sweep.tcp_m)
    return dataclasses.replace(bundle, axes={name: dataclasses.replace(x, sweep=sweep)})


def _tcp_findings(bundle):
    """The findings on the TCP device's gain identifying ``bundle`` gives [-]."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            identify_bundle(bundle, verdict=False)
        except SuspectModelError as e:
            return [f for f in e.findings if "TCP device" in f.parameter or "G_tcp" in f.parameter]
    return []


@pytest.fixture(scope="module", params=sorted(MACHINES))
def bundle(request, tmp_path_factory):
    return _bundle(tmp_path_factory.mktemp(request.param), request.param)


def test_a_true_tcp_device_on_a_heavy_or_soft_machine_is_not_blamed(bundle):
    """Their TCP devices read the motion in full, as the simulator's do: nothing about
    ``G_tcp`` may be found."""
    assert _tcp_findings(bundle) == []


@pytest.mark.parametrize("factor", [1.04, 0.96])
def test_a_tcp_device_four_per_cent_off_is_still_refused(bundle, factor):
    """A TCP device reading 4 % more or less of the motion (its scaling, or a cosine error
    of 16 deg for the less) is refused with its gain, on the side it lies. Read within
    0.015 of it: where the band below the first mode is short (bench H's X: 6.8-11 Hz) the
    fitted mode takes up part of the scaling, and 0.96 read 0.973 (the 16 edited bench
    machines of docs/validation/identification_findings.md read 0.960-0.973 and
    1.037-1.044)."""
    (gain,) = _tcp_findings(_scaled(bundle, factor))
    assert gain.value == pytest.approx(factor, abs=0.015), str(gain)
    assert (gain.value - 1.0) * (factor - 1.0) > 0.0
    assert not TCP_GAIN_RANGE[0] <= gain.value <= TCP_GAIN_RANGE[1]
    assert f"scale tcp_mm by {1.0 / gain.value:.4g}" in gain.remedy


@pytest.mark.parametrize("top_hz", [7.5, 20.0])
def test_a_gain_left_unjudged_is_said_with_the_sweep_that_judges_it(top_hz):
    """A first mode so low (11 Hz; judged up to 7.5 Hz) that fewer than three bins lie
    between 1.5 times the sweep's start (4.4 Hz) and the mode over 1.5: the gain went
    unjudged without a word, and a device that reads a share of the motion passed as the
    structure's dynamics. It is said, with a sweep start that lets it be judged; where
    the band holds bins enough, nothing is said."""
    import numpy as np

    from tcpmm.errors import InputWarning
    from tcpmm.ident.frf import FRF
    from tcpmm.ident.gates.masses import check_tcp_gain

    f = np.arange(4.4, 40.0, 0.732)
    frf = FRF(f, np.ones(f.size, complex), np.ones(f.size), 10, np.zeros(f.size), name="G_tcp")
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        found = check_tcp_gain("X", frf, lambda x: np.ones(x.size), "X/sweep.csv", 0.5, top_hz)
    text = [str(w.message) for w in said if issubclass(w.category, InputWarning)]
    assert found == []
    if top_hz > 10:
        assert text == []
        return
    assert len(text) == 1 and "X/sweep.csv: axis X: the TCP device's gain against the " \
        "scale is not judged: the FRF holds fewer than 3 coherent bins from 6.6 Hz" in text[0]
    assert "up to 7.5 Hz" in text[0] and "a sweep from 2.5 Hz or lower" in text[0]
