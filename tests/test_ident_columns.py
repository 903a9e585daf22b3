"""Gates on the columns of a bundle's records: swapped columns and columns in the wrong
unit are named, with the column and why, before any fit."""

import dataclasses
from types import SimpleNamespace

import numpy as np
import pytest

from conftest import bench_path, run_cli
from tcpmm.cli import main
from tcpmm.ident.gates.columns import column_findings


@pytest.fixture(scope="module")
def records(vmc):
    from tcpmm.machines.virtual import bundle_machine_yaml, virtual_friction, virtual_sweep

    a = vmc.axes["X"]
    return (bundle_machine_yaml(vmc, ["X"]),
            virtual_sweep(a, duration_s=2.0, band_hz=(10.0, 1000.0), name="X"),
            virtual_friction(a, name="X"))


def _bundle(records, sweep=None, friction=None):
    from tcpmm.io.bundle_schema import MachineConfig

    machine, s, f = records
    axes = {"X": SimpleNamespace(sweep=sweep or s, friction=friction or f)}
    return SimpleNamespace(machine=MachineConfig.model_validate(machine), axes=axes)


def _swap(record, a, b):
    return dataclasses.replace(record, **{a: getattr(record, b), b: getattr(record, a)})


def _scaled(record, col, k):
    return dataclasses.replace(record, **{col: getattr(record, col) * k})


def test_the_columns_of_a_sane_bundle_pass(records):
    assert column_findings(_bundle(records)) == []


def test_a_scale_two_percent_off_the_lead_is_said(records):
    """A scale reading 2 % more than the motor angle through lead_mm (a lead or a
    resolution set wrong) passed in silence, and identification blamed a TCP device
    "drifting by 3040 um" over the sweep for the deflection it made; now the friction runs
    say by how much and what to check, and a sane bundle says nothing."""
    import warnings

    from tcpmm.errors import InputWarning

    _, s, f = records
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        assert column_findings(_bundle(records)) == []
        sane = [str(w.message) for w in got if issubclass(w.category, InputWarning)]
        b = _bundle(records, _scaled(s, "scale_m", 1.02), _scaled(f, "scale_m", 1.02))
        assert column_findings(b) == []
    said = [str(w.message) for w in got if issubclass(w.category, InputWarning)][len(sane):]
    assert not sane
    assert len(said) == 1 and "1.0200 times" in said[0] and "lead_mm" in said[0]
    assert said[0].startswith("virtual friction runs of axis X")


def test_a_tcp_device_reading_off_the_scale_is_said(records):
    """A TCP device whose scale factor is 0.2 % off passed as a TCP 'drifting by 304 um'
    over machine D's sweep; now the sweep says the TCP travels 1.0020 times the scale and
    what to check. The scale off the lead is not blamed on the TCP."""
    import warnings

    from tcpmm.errors import InputWarning

    _, s, f = records
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        assert column_findings(_bundle(records, _scaled(s, "tcp_m", 1.002))) == []
        said = [str(w.message) for w in got if issubclass(w.category, InputWarning)]
        assert column_findings(_bundle(records, _scaled(s, "tcp_m", 1.0005))) == []
        b = _bundle(records, _scaled(s, "scale_m", 1.02), _scaled(f, "scale_m", 1.02))
        assert column_findings(b) == []
    assert len(said) == 1 and "TCP travels 1.0020 times" in said[0], said
    assert "columns scale_mm and tcp_mm" in said[0] and "scale factor" in said[0]
    rest = [str(w.message) for w in got if issubclass(w.category, InputWarning)][1:]
    assert len(rest) == 1 and "lead_mm" in rest[0], rest


@pytest.mark.parametrize(("kind", "change", "needles"), [
    ("friction", lambda r: _swap(r, "current_cmd_A", "motor_angle_rad"),
     ["friction.csv column current_cmd_A", "swapped", "do not move together"]),
    ("friction", lambda r: _scaled(r, "current_cmd_A", 1e3),
     ["friction.csv column current_cmd_A", "milliamperes"]),
    ("sweep", lambda r: _scaled(r, "current_cmd_A", 1e3),
     ["sweep.csv column current_cmd_A", "milliamperes"]),
    ("friction", lambda r: _scaled(r, "motor_angle_rad", 180 / np.pi),
     ["friction.csv columns scale_mm / motor_angle_rad", "in degrees"]),
    ("sweep", lambda r: _scaled(r, "motor_angle_rad", 180 / np.pi),
     ["sweep.csv columns scale_mm / motor_angle_rad", "in degrees"]),
    ("sweep", lambda r: _swap(r, "excitation_A", "tcp_m"),
     ["sweep.csv columns tcp_mm / scale_mm", "do not move together"]),
    # the TCP in um read as 'the scale in micrometres (write mm)': a user who did as told
    # would have divided a right scale by 1000
    ("sweep", lambda r: _scaled(r, "tcp_m", 1e3),
     ["sweep.csv columns tcp_mm / scale_mm", "the TCP in micrometres (write mm)"]),
])
def test_a_swapped_or_misscaled_column_is_named(records, kind, change, needles):
    _, s, f = records
    b = _bundle(records, **{kind: change(s if kind == "sweep" else f)})
    text = " ".join(str(x) for x in column_findings(b))
    for n in needles:
        assert n in text


def test_identify_refuses_swapped_friction_columns_before_the_fit(records, tmp_path, capsys):
    from tcpmm.io.bundle import write_bundle

    machine, s, f = records
    bad = _swap(f, "current_cmd_A", "motor_angle_rad")
    path = write_bundle({"machine": machine, "axes": {"X": {"sweep": s, "friction": bad}}},
                        tmp_path / "b")
    model = tmp_path / "m.yaml"
    assert main(["identify", str(path), "-o", str(model)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "column current_cmd_A" in err[0] and "Traceback" not in err[0]
    assert not model.exists()


def test_a_sweep_that_did_not_move_is_refused_by_name(records):
    """A clamped axis (motor, scale and TCP constant in sweep.csv) went on to the physical
    fit, which failed inside its optimiser ('Each lower bound must be strictly less than
    each upper bound'). The sweep is refused first, naming the column and why."""
    from tcpmm.errors import InputError
    from tcpmm.io.bundle_schema import MachineConfig
    from tcpmm.io.checks import check_sweep_plausibility

    machine, s, _ = records
    axis = MachineConfig.model_validate(machine).axes["X"]
    check_sweep_plausibility(s, axis)
    clamped = dataclasses.replace(s, motor_angle_rad=np.full_like(s.motor_angle_rad, 1.5),
                                  scale_m=np.zeros_like(s.scale_m))
    with pytest.raises(InputError, match="did not move") as e:
        check_sweep_plausibility(clamped, axis)
    assert e.value.column == "motor_angle_rad"


def test_a_resolution_coarser_than_the_recorded_steps_is_warned_of(records):
    """scale_resolution_um written 50 for 0.05 passed without a word, and the model's scale
    then rounded to 50 um (on bench C's fast circle, spikes 2.8 and 3.3 um off, called
    firm). The recorded scale moves by a small part of such a step: a warning says so."""
    import warnings

    from tcpmm.errors import InputWarning
    from tcpmm.io.bundle_schema import MachineConfig
    from tcpmm.io.checks import check_sweep_plausibility

    machine, s, _ = records
    good = MachineConfig.model_validate(machine).axes["X"]
    with warnings.catch_warnings():
        warnings.simplefilter("error", InputWarning)
        check_sweep_plausibility(s, good)
    sensors = {**machine["axes"]["X"]["sensors"], "scale_resolution_um": 50.0}
    bad = MachineConfig.model_validate(
        {**machine, "axes": {"X": {**machine["axes"]["X"], "sensors": sensors}}}).axes["X"]
    with pytest.warns(InputWarning, match="under a tenth of a step of the declared "
                                          "scale_resolution_um 50"):
        check_sweep_plausibility(s, bad)


def test_a_lead_a_quarter_off_is_said_as_one_motion_at_another_scale(tmp_path, capsys):
    """Machine C with X's lead declared 16 mm for 20: the scale travels exactly 1.25 times
    what the motor angle does through it, correlated at 1.00, and the refusal read "do not
    move together (correlation 1.00): a column swapped", its ratio "1.25, outside 0.8 to
    1.25". It now says the columns move together at another scale, and the ratio with the
    digits that set it apart from the bound."""
    import shutil

    import yaml

    d = tmp_path / "lead16"
    shutil.copytree(bench_path("c") / "bundle", d)
    y = yaml.safe_load((d / "machine.yaml").read_text())
    y["axes"]["X"]["lead_mm"] = 16.0
    (d / "machine.yaml").write_text(yaml.safe_dump(y, sort_keys=False))
    code, _, err = run_cli(capsys, "identify", d, "-o", tmp_path / "m.yaml")
    text = " ".join(err.split())
    assert code == 2 and "move together (correlation 1.00) but one travels 1.25 times" in text
    assert "do not move together" not in text and "check lead_mm" in text
    assert "= 1.25, outside 0.8 to 1.25" not in text
