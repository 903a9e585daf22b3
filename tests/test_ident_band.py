"""A band that misses the axis's dynamics, named as the cause: ``--band`` leaving out the
frequencies where the fitted mechanics put their modes, or a sweep that excites nothing
where the static gains are read. Bench C's modes lie at 24-746 Hz (``truth.yaml``); its
sweep excites 2-1000 Hz, so a band of 2-40 Hz misses the axial modes, one of 100-400 Hz
the structure's, and the sweep cut to start at 150 Hz both the structure and the static
gains."""

import dataclasses
import math
import shutil
import warnings

import pandas as pd
import pytest

from conftest import SWEEP_SAMPLES, bench_path, bench_x_alone, refusal
from studies.cut_sweep import cut_bundle
from tcpmm.errors import InputError
from tcpmm.ident import gates
from tcpmm.ident.chain import identify_bundle
from tcpmm.ident.frf.excited import BandCover, mode_frequencies_hz
from tcpmm.ident.gates.finding import SuspectModelError
from tcpmm.io.bundle import read_bundle
from tcpmm.io.modelfile import read_machine, write_machine


def _identify(bundle, band):
    """``(error text or None, warning texts)`` of identifying ``bundle`` in ``band`` [Hz]."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            identify_bundle(read_bundle(bundle), *band, verdict=False)
            error = None
        except InputError as exc:
            error = exc
    return error, [str(w.message) for w in caught]


@pytest.fixture(scope="module")
def up_to_40_hz():
    """Bench C in 2-40 Hz: below the axial modes, whose fit makes X's sampled loop
    unstable."""
    return _identify(bench_path("c") / "bundle", (2.0, 40.0))


@pytest.fixture(scope="module")
def up_to_40_hz_accepted():
    """Bench C in 2-40 Hz with ``accept_suspect``, judged: the identification and what
    it warned."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        idn = identify_bundle(read_bundle(bench_path("c") / "bundle"), 2.0, 40.0,
                              accept_suspect=True)
    return idn, [str(w.message) for w in caught]


@pytest.fixture(scope="module")
def from_100_hz():
    """Bench C in 100-400 Hz: above the structure's modes, whose fit makes Y's sweep
    deflection read a guideway share far outside 0 to 1."""
    return _identify(bench_path("c") / "bundle", (100.0, 400.0))


@pytest.fixture(scope="module")
def first_third(tmp_path_factory):
    """Bench C with each sweep cut to its first third: its log sweep then stops at about
    15 Hz, below the velocity loop's crossover."""
    bundle = tmp_path_factory.mktemp("third")
    shutil.copytree(bench_path("c") / "bundle", bundle, dirs_exist_ok=True)
    for sweep in bundle.glob("*/sweep.csv"):
        d = pd.read_csv(sweep)
        d.iloc[: len(d) // 3].to_csv(sweep, index=False, float_format="%.9g")
    return _identify(bundle, (None, None))


@pytest.fixture(scope="module")
def cut_at_150_hz(tmp_path_factory):
    """Bench C with each sweep cut to start at 150 Hz, identified in the default band."""
    bundle = cut_bundle(bench_path("c") / "bundle", tmp_path_factory.mktemp("cut150"), 150.0)
    return _identify(bundle, (None, None))


def test_an_unstable_loop_of_a_band_below_the_modes_names_the_band(up_to_40_hz):
    error, said = up_to_40_hz
    assert isinstance(error, SuspectModelError)
    (loop,) = [f for f in error.findings if "spectral radius" in f.parameter]
    assert loop.axis == "X" and loop.value > 1.0
    assert "band 2.136-39.98 Hz (--band) leaves out 39.98-" in loop.remedy
    assert loop.remedy.index("widen --band") < loop.remedy.index("check the servo settings")
    (warned,) = [w for w in said if "position loop is unstable" in w]
    assert warned.index("leaves out 39.98-") < warned.index("check the servo settings")


def test_a_sweep_stopping_below_the_crossover_is_named_before_the_servo(first_third):
    """A sweep cut short reaches 15 Hz: what its fit makes of the modes is a guess, and
    the unstable loop and the failed fit blame the sweep's reach before the servo
    settings or the record's columns."""
    error, said = first_third
    assert isinstance(error, SuspectModelError)
    loops = [f for f in error.findings if "spectral radius" in f.parameter]
    assert loops
    for f in loops:
        assert "excitation reaches only 15 Hz, below the velocity loop's crossover" in f.remedy
        assert f.remedy.index("reaches only") < f.remedy.index("check the servo settings")
    assert all("reaches only 15 Hz" in f.remedy for f in error.findings
               if f.parameter.startswith("fit of the physical model"))
    (warned,) = [w for w in said if "position loop is unstable" in w]
    assert warned.index("reaches only") < warned.index("check the servo settings")


def test_a_sweep_stopping_below_the_axial_mode_is_named_before_the_servo():
    """Bench D's X with its sweep cut to its first three quarters: the log sweep reaches
    179 Hz, past the velocity loop's crossover but not the axial mode at 867 Hz, which the
    fit then puts at some 4 kHz, and the sampled loop is unstable. The sweep's reach and
    the mode beyond it are named before the servo settings."""
    refused = refusal(bench_x_alone("d", lambda sw: dataclasses.replace(sw, **{
        f: getattr(sw, f)[:3 * sw.time_s.size // 4] for f in SWEEP_SAMPLES})))
    (loop,) = [f for f in refused.findings if "spectral radius" in f.parameter]
    assert "excitation reaches only 178.8 Hz, and the fitted mechanics put a mode at" in (
        loop.remedy)
    assert loop.remedy.index("far above it") < loop.remedy.index("check the servo settings")


def test_an_accepted_unstable_model_is_returned_without_blaming_the_columns(
        up_to_40_hz_accepted, tmp_path):
    """The model's runs of a circle diverge: the sensitivities that simulate them are left
    out, one warning per axis, and no circle check of those runs names a file's column."""
    idn, said = up_to_40_hz_accepted
    assert any("spectral radius" in s for s in idn.machine.suspect)
    assert not [w for w in said if "_mm" in w or "opposite sign" in w]
    skipped = [w for w in said if "sensitivities of the TCP spikes" in w]
    assert [w.split(":")[0] for w in skipped] == ["axis X", "axis Y"]
    assert all("axis X: its sampled position loop is unstable" in w for w in skipped)
    assert all(a.presliding_sensitivity is None for a in idn.axes.values())
    write_machine(idn.machine, tmp_path / "m.yaml")
    assert read_machine(tmp_path / "m.yaml").suspect == idn.machine.suspect


def test_the_figures_of_an_accepted_unstable_model_are_not_predicted(up_to_40_hz_accepted):
    verdict = up_to_40_hz_accepted[0].verdict
    assert verdict.figures and not verdict.firm
    for f in verdict.figures:
        assert math.isnan(f.nominal) and f.verdict == "undetermined" and f.axes == ("X",)
        assert f.cause.startswith("no prediction: axis X: its sampled position loop")
        assert f.to_dict()["nominal_um"] is None
    assert verdict.axes["X"]["verdict"] == "undetermined"
    assert {f.test for f in verdict.figures} == set(verdict.tests)


def test_a_share_outside_0_to_1_of_a_band_above_the_structure_names_the_band(from_100_hz):
    error, said = from_100_hz
    assert error is None
    outside = [w for w in said if "outside 0 to 1" in w]
    assert outside and all(w.startswith("axis Y:") for w in outside)
    for w in outside:
        assert "band 100.1-399.8 Hz (--band) leaves out 2-100.1 Hz" in w
        assert w.index("widen --band") < w.index("is the TCP device zeroed")


def test_static_gains_of_a_sweep_that_excites_none_are_not_judged(cut_at_150_hz):
    """The fit holds the structure the cut sweep does not show within a machine's range
    and the chain runs to the gates; their verdict reads no static gain from the noise
    below the sweep."""
    error, _ = cut_at_150_hz
    text = str(error)
    assert isinstance(error, SuspectModelError)
    assert "static gain of G_T" not in text  # no reading of the noise below the sweep
    assert "--band" in text


def test_a_band_that_covers_the_modes_leaves_the_servo_to_blame(vmc):
    a = vmc.axes["X"]
    bad = a.replace(mechanics=a.mechanics.replace(J_m=a.mechanics.J_m / 100))
    modes = mode_frequencies_hz(bad.mechanics)
    wide = BandCover((1.0, 2.0 * modes[-1]), (1.0, 2.0 * modes[-1]))
    (f,) = gates.check_sampled_loop("X", bad, "X/sweep.csv", wide)
    assert f.remedy.startswith("check the servo settings")
    narrow = BandCover((1.0, 0.5 * modes[0]), (1.0, 2.0 * modes[-1]))
    (g,) = gates.check_sampled_loop("X", bad, "X/sweep.csv", narrow)
    assert g.remedy.index("widen --band") < g.remedy.index("check the servo settings")
    unasked = BandCover((1.0, 0.5 * modes[0]), (1.0, 2.0 * modes[-1]), asked=(True, False))
    assert unasked.words(bad.mechanics) is None  # an end the user did not set cuts nothing
