"""Gates on the masses against the FRFs' static gains: below the first mode a free axis is
one body, so a column swapped on a sweep that stands still, where the column gates cannot
judge it, is named from the FRFs; and a fit whose inertia leaves the mass line is named."""

import dataclasses

import numpy as np
import pytest

from tcpmm.ident.frf.response import reduced_frfs
from tcpmm.ident.gates.columns import MIN_TRAVEL_M
from tcpmm.ident.gates.masses import MASS_RANGE, check_mass_line, mass_findings
from tcpmm.ident.options import MIN_COHERENCE


def _sweep(axis, travel_speed_m_per_s):
    from tcpmm.machines.virtual import virtual_sweep

    return virtual_sweep(axis, duration_s=8.0, band_hz=(2.0, 1000.0), amplitude_A=4.0,
                         travel_speed_m_per_s=travel_speed_m_per_s, name="X")


@pytest.fixture(scope="module")
def standing(vmc):
    """A sweep of the built-in machine's X that does not travel: friction holds its low
    band, and its scale moves less than the column gates judge."""
    return vmc.axes["X"], _sweep(vmc.axes["X"], 0.0)


@pytest.fixture(scope="module")
def travelling(vmc):
    """The same sweep while the axis travels at 20 mm/s: the friction slides."""
    return vmc.axes["X"], _sweep(vmc.axes["X"], 0.02)


def _frfs(sweep):
    return reduced_frfs(sweep.excitation_A, sweep.current_cmd_A, sweep.motor_angle_rad,
                        sweep.scale_m, sweep.tcp_m, time_s=sweep.time_s)


@pytest.mark.parametrize("which", ["standing", "travelling"])
def test_the_true_masses_pass_on_their_own_sweep(request, which):
    axis, sweep = request.getfixturevalue(which)
    assert mass_findings("X", _frfs(sweep), axis.mechanics, "X/sweep.csv", MIN_COHERENCE) == []


def test_excitation_swapped_with_the_tcp_on_a_standing_sweep_is_named(standing):
    axis, sweep = standing
    bad = dataclasses.replace(sweep, excitation_A=sweep.tcp_m, tcp_m=sweep.excitation_A)
    assert np.ptp(bad.scale_m) < MIN_TRAVEL_M  # the column gates do not judge this record
    text = " ".join(str(f) for f in mass_findings("X", _frfs(bad), axis.mechanics,
                                                  "X/sweep.csv", MIN_COHERENCE))
    assert "G_tcp" in text and "tcp_mm / scale_mm" in text and "X/sweep.csv" in text


@pytest.mark.parametrize("k", [0.3, 3.0])
def test_an_inertia_off_the_mass_line_is_named(travelling, k):
    axis, sweep = travelling
    m = axis.mechanics
    wrong = m.replace(M_t=m.M_t * k, J_m=m.J_m * k, J_L=m.J_L * k)
    found = check_mass_line("X", _frfs(sweep)["G_M"], wrong, "X/sweep.csv", MIN_COHERENCE)
    assert len(found) == 1 and "table mass" in found[0].data
    assert not MASS_RANGE[0] <= found[0].value <= MASS_RANGE[1]
    assert found[0].value == pytest.approx(1.0 / k, rel=0.2)


def test_a_low_band_held_by_friction_is_not_read_as_mass(standing):
    axis, sweep = standing
    wrong = axis.mechanics.replace(M_t=axis.mechanics.M_t * 10)
    assert check_mass_line("X", _frfs(sweep)["G_M"], wrong, "X/sweep.csv", MIN_COHERENCE) == []


def test_no_low_band_no_verdict(travelling):
    axis, sweep = travelling
    frfs = _frfs(sweep)
    high = {n: dataclasses.replace(f, coherence=np.where(f.freq_hz > 40.0, f.coherence, 0.0))
            for n, f in frfs.items()}
    wrong = axis.mechanics.replace(M_t=axis.mechanics.M_t * 10)
    assert mass_findings("X", high, wrong, "X/sweep.csv", MIN_COHERENCE) == []


def test_identify_refuses_the_swap_in_one_line_naming_the_file(vmc, standing, tmp_path, capsys):
    from tcpmm.cli import main
    from tcpmm.io.bundle import write_bundle
    from tcpmm.machines.virtual import bundle_machine_yaml, virtual_friction

    _, sweep = standing
    bad = dataclasses.replace(sweep, excitation_A=sweep.tcp_m, tcp_m=sweep.excitation_A)
    path = write_bundle({"machine": bundle_machine_yaml(vmc, ["X"]), "axes": {"X": {
        "sweep": bad, "friction": virtual_friction(vmc.axes["X"], name="X")}}}, tmp_path / "b")
    model = tmp_path / "m.yaml"
    assert main(["identify", str(path), "-o", str(model)]) == 2
    err = [x for x in capsys.readouterr().err.strip().splitlines()
           if not x.startswith("warning:")]
    assert len(err) == 1 and "G_tcp" in err[0] and "sweep.csv" in err[0], err
    assert not model.exists()


def test_a_column_with_a_low_first_mode_is_not_read_as_a_swapped_tcp(vmc):
    """A heavy column whose first mode lies at about 6 Hz, lightly damped, bends in the
    lowest octave of the sweep: G_tcp there is far from one, and only the band below the
    mode tells the rigid body (here too narrow to judge)."""
    from tcpmm.ident.gates.masses import check_static_gains, first_mode_hz

    a = vmc.axes["X"]
    r = 6.0 / 50.3  # the head's mode from 50.3 Hz to 6 Hz at the same damping ratio
    soft = a.replace(mechanics=a.mechanics.replace(K_h=a.mechanics.K_h * r**2,
                                                   C_h=a.mechanics.C_h * r))
    assert first_mode_hz(soft.mechanics) == pytest.approx(6.0, rel=0.05)
    frfs = _frfs(_sweep(soft, 0.02))
    whole_octave = check_static_gains("X", frfs, soft.mechanics.R_L, "X/sweep.csv",
                                      MIN_COHERENCE)
    assert whole_octave and "G_tcp" in whole_octave[0].parameter
    assert mass_findings("X", frfs, soft.mechanics, "X/sweep.csv", MIN_COHERENCE) == []


def test_a_step_that_stops_keeps_its_words_and_offers_no_suspect_model(tmp_path, capsys,
                                                                       monkeypatch):
    """Bench C's sweeps cut to start at 150 Hz, and a step of the chain that stops on them:
    the static gains, read over 2-11.5 Hz, a band the sweep no longer excites, could not
    be checked, and that is said before what the step said. No ``--accept-suspect`` is
    offered: no model was made to write."""
    import tcpmm.ident.chain as chain
    from conftest import bench_path, run_cli
    from studies.cut_sweep import cut_bundle
    from tcpmm.errors import InputError

    def stops(run, options):
        raise InputError("a column stiffness of 6e+27 N/m")

    monkeypatch.setattr(chain, "AXIS_STEPS", tuple(
        (name, stops if name == "linear" else step) for name, step in chain.AXIS_STEPS))
    bundle = cut_bundle(bench_path("c") / "bundle", tmp_path / "cut", 150.0)
    code, _, err = run_cli(capsys, "identify", bundle, "-o", tmp_path / "m.yaml",
                           "--accept-suspect", "--jobs", "1")
    line = [x for x in err.strip().splitlines() if x.startswith("error:")]
    assert code == 2 and len(line) == 1, err
    assert "could not be checked" in line[0] and "The step that stopped said: " in line[0]
    assert line[0].index("static gains") < line[0].index("The step that stopped said: ")
    assert "6e+27 N/m" in line[0]
    assert "--accept-suspect" not in line[0] and not (tmp_path / "m.yaml").exists()


def test_a_sweep_cut_above_the_structure_ends_in_a_verdict(tmp_path, capsys):
    """The same cut sweeps through the whole chain: the fit holds the column the band does
    not show within the range of a machine tool (it ran to 6e27 N/m and stopped the chain),
    and the gates judge the model: suspect, naming the band."""
    from conftest import bench_path, run_cli
    from studies.cut_sweep import cut_bundle

    bundle = cut_bundle(bench_path("c") / "bundle", tmp_path / "cut", 150.0)
    code, _, err = run_cli(capsys, "identify", bundle, "-o", tmp_path / "m.yaml",
                           "--jobs", "1")
    line = [x for x in err.strip().splitlines() if x.startswith("error:")]
    assert code == 2 and len(line) == 1, err
    assert "physically suspect" in line[0] and "--band" in line[0], line
    assert not (tmp_path / "m.yaml").exists()
