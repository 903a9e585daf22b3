"""Gates of identification: each check on constructed inputs with a known answer, and the
command line refusing (and, when told, marking) a physically suspect model."""

import math
import warnings
from types import SimpleNamespace

import numpy as np
import pytest

from tcpmm.cli import main
from tcpmm.ident import gates
from tcpmm.mechanics.friction import StribeckFriction
from tcpmm.model import AxisFriction


def _record(dt, n=2001, speed=0.01):
    """A record with time step ``dt`` [s] and a scale moving at ``speed`` [m/s]."""
    t = np.arange(n) * dt
    return SimpleNamespace(time_s=t, scale_m=speed * t, source="X/sweep.csv")


def _with_friction(axis, fc, fs, vs, share=0.5):
    """``axis`` with Stribeck friction of levels ``fc``, ``fs`` [N] and Stribeck speed ``vs``
    [m/s], ``share`` of it on the guideway."""

    def part(k):
        return StribeckFriction(fc_pos=k * fc, fc_neg=k * fc, fs_pos=k * fs, fs_neg=k * fs,
                                vs=vs)

    return axis.replace(friction=AxisFriction(screw=part(1 - share), guideway=part(share)))


def test_a_finding_names_axis_parameter_value_bound_data_and_remedy():
    f = gates.Finding("X", "friction.guideway.fs_pos", 26284.0, "N", "above 3 x 373 N",
                      "X/friction.csv", "add slower runs")
    assert str(f) == ("axis X: friction.guideway.fs_pos = 2.628e+04 N, above 3 x 373 N "
                      "(from X/friction.csv); add slower runs")
    with pytest.raises(AttributeError):
        f.value = 1.0  # frozen


def test_time_base_in_seconds_passes():
    assert gates.check_time_base("X", _record(1e-4), "sweep.csv") == []
    assert gates.check_time_base("X", _record(1e-3, speed=0.1), "friction.csv") == []


def test_time_in_milliseconds_is_found():
    """10 kHz written in ms: a sample period of 0.1 s, outside 1e-5 to 1e-2 s."""
    (f,) = gates.check_time_base("X", _record(0.1, speed=1e-5), "sweep.csv")
    assert f.axis == "X" and f.unit == "s" and f.value == pytest.approx(0.1)
    assert "sample period" in f.parameter and "time_s" in f.data and "seconds" in f.remedy


def test_impossible_feed_speed_is_found():
    """A 10 kHz record whose time is 1000 times too short: the scale moves at 10 m/s."""
    (f,) = gates.check_time_base("Y", _record(2e-5, speed=10.0), "sweep.csv")
    assert "feed speed" in f.parameter and f.value == pytest.approx(10.0)
    assert f.unit == "m/s" and f.axis == "Y"


def test_drive_force_at_the_current_limit(vmc):
    a = vmc.axes["X"]
    m = a.mechanics
    limit = gates.drive_force_limit(a)
    assert limit == pytest.approx(a.servo.current_limit * m.K_tc * 2 * math.pi / m.lead)
    assert gates.check_static_friction_vs_drive("X", _with_friction(a, 100.0, 150.0, 1e-3)) == []
    (f,) = gates.check_static_friction_vs_drive(
        "X", _with_friction(a, 0.3 * limit, 1.2 * limit, 1e-3), "X/friction.csv")[:1]
    assert f.value == pytest.approx(1.2 * limit) and f.unit == "N"
    assert "current limit" in f.bound and f.data == "X/friction.csv"
    assert "torque_constant_Nm_per_A" in f.remedy
    assert len(gates.check_static_friction_vs_drive(
        "X", _with_friction(a, 0.3 * limit, 1.2 * limit, 1e-3))) == 2  # both directions


def test_static_far_above_coulomb_unseen_by_the_runs(vmc):
    """The case that motivated the gate: 26 284 N static against 373 N Coulomb on the
    guideway with a Stribeck speed of 0.2 mm/s, the slowest run at 0.5 mm/s."""
    a = _with_friction(vmc.axes["X"], 373.0, 26284.0, 0.2e-3, share=1.0)
    found = gates.check_static_over_coulomb("X", a, 0.5e-3, "X/friction.csv")
    assert [f.parameter for f in found] == ["friction.guideway.fs_pos",
                                            "friction.guideway.fs_neg"]
    assert found[0].value == pytest.approx(26284.0) and "slower" in found[0].remedy
    # the runs saw the hump: Stribeck speed above the slowest run
    assert gates.check_static_over_coulomb("X", a, 0.1e-3) == []
    # a usual ratio, however slow the Stribeck speed
    usual = _with_friction(vmc.axes["X"], 373.0, 2.5 * 373.0, 0.2e-3)
    assert gates.check_static_over_coulomb("X", usual, 0.5e-3) == []


def _friction_runs(speeds, plateau_s=0.5, dt=1e-3):
    """Back-and-forth runs at ``speeds`` [m/s] with Coulomb and viscous current [A]."""
    from tcpmm.io.records import FrictionRecord

    v = np.concatenate([np.full(round(plateau_s / dt), sv) for s in speeds for sv in (s, -s)])
    v = np.convolve(v, np.ones(20) / 20, mode="same")  # 20 ms ramps between plateaus
    t = np.arange(v.size) * dt
    x = np.cumsum(v) * dt
    current = np.tanh(v / 1e-4) * 1.0 + 20.0 * v
    return FrictionRecord.from_arrays(t, current, x * 2 * np.pi / 0.01, x, axis="X")


def test_slowest_plateau_of_the_friction_runs(vmc):
    from tcpmm.machines.virtual import axis_config

    rec = _friction_runs((0.002, 0.005, 0.01, 0.02))
    v = gates.slowest_plateau_speed(rec, axis_config(vmc, "X"), "X")
    assert v == pytest.approx(0.002, rel=0.02)


def test_negative_fit_is_found_and_one_bad_bin_is_not():
    f = np.linspace(1.0, 100.0, 200)
    H = 1.0 / (1j * f)
    assert gates.check_fit_percent("X", "G_M", H, H * 1.05) == []
    (bad,) = gates.check_fit_percent("X", "G_T", H, -H, "X/sweep.csv")  # wrong sign
    assert bad.parameter == "fit of the physical model to log G_T" and bad.unit == "%"
    assert bad.value < -50 and "the mean of the data" in bad.bound and bad.data == "X/sweep.csv"
    # a sharp model peak in one bin makes the plain fit negative, not the trimmed one
    peak = H.copy()
    peak[150] = 1000.0
    from tcpmm.ident.lti import fit_percent

    assert fit_percent(H, peak) < 0 and gates.check_fit_percent("X", "G_M", H, peak) == []
    assert gates.trimmed_fit_percent(H, peak) == pytest.approx(100.0)
    (none,) = gates.check_fit_percent("X", "G_M", H[:0], H[:0])
    assert math.isnan(none.value) and "coherent" in none.bound


def test_a_resonance_a_little_off_is_not_a_negative_fit():
    """A lightly damped mode 2 % off in frequency makes the complex fit strongly negative,
    though the model is right everywhere but at the peak; on the logarithm it is not."""
    from tcpmm.ident.lti import fit_percent

    f = np.linspace(100.0, 400.0, 600)
    s = 2j * np.pi * f

    def mode(fn):
        wn = 2 * np.pi * fn
        return 1.0 / (s**2 / wn**2 + 2 * 0.002 * s / wn + 1)

    H, model = mode(200.0), mode(204.0)
    assert fit_percent(H, model) < -30
    assert gates.trimmed_fit_percent(H, model) > 80
    assert gates.check_fit_percent("X", "G_M", H, model) == []


def test_unstable_sampled_loop_is_found(vmc):
    a = vmc.axes["X"]
    assert gates.check_sampled_loop("X", a) == []
    bad = a.replace(mechanics=a.mechanics.replace(J_m=a.mechanics.J_m / 100))
    (f,) = gates.check_sampled_loop("X", bad, "X/sweep.csv")
    assert f.value > 1.0 and "unstable" in f.bound and "machine.yaml" in f.remedy


def test_suspect_model_error_is_an_input_error():
    from tcpmm.errors import InputError

    f = gates.Finding("X", "p", 1.0, "N", "above 0 N", "d", "fix it")
    err = gates.SuspectModelError([f], file="bundle")
    assert isinstance(err, InputError) and err.findings == [f]
    assert "axis X: p = 1 N" in str(err) and "--accept-suspect" in str(err)


@pytest.fixture(scope="module")
def ms_bundle(tmp_path_factory, vmc):
    """A one-axis bundle whose 8 kHz sweep has its time column in milliseconds."""
    from tcpmm.io.bundle import write_bundle
    from tcpmm.io.records import SweepRecord
    from tcpmm.machines.virtual import bundle_machine_yaml, virtual_sweep

    s = virtual_sweep(vmc.axes["X"], duration_s=3.0, band_hz=(10.0, 1000.0), name="X")
    ms = SweepRecord.from_arrays(s.time_s * 1e3, s.excitation_A, s.current_cmd_A,
                                 s.motor_angle_rad, s.scale_m, s.tcp_m, axis="X")
    path = tmp_path_factory.mktemp("gates") / "b"
    return write_bundle({"machine": bundle_machine_yaml(vmc, ["X"]), "axes": {"X": ms}}, path)


def test_cli_refuses_a_millisecond_time_column_and_marks_when_accepted(capsys, ms_bundle,
                                                                         tmp_path):
    from tcpmm.io.modelfile import read_machine

    model = tmp_path / "m.yaml"
    code = main(["identify", str(ms_bundle), "-o", str(model)])
    err = " ".join(capsys.readouterr().err.split())
    assert code == 2 and not model.exists()
    assert "axis X: sweep.csv sample period = 0.125 s" in err and "--accept-suspect" in err
    assert "Traceback" not in err
    with warnings.catch_warnings():  # the broken sweep warns on the way
        warnings.simplefilter("ignore")
        code = main(["identify", str(ms_bundle), "-o", str(model), "--accept-suspect"])
    assert code == 0 and model.is_file()
    marks = read_machine(model).suspect
    assert any("sample period = 0.125 s" in s for s in marks)
    assert "suspect:" in model.read_text()
    capsys.readouterr()
    assert main(["machine", "show", str(model)]) == 0
    assert "WARNING" in capsys.readouterr().err


def test_friction_runs_of_an_axis_without_friction(vmc_linear):
    """The runs show no friction: the Stribeck fit to noise is not taken for a static
    level, identification ends with a warning and the model simulates."""
    from tcpmm.ident.pipeline import identify_axis
    from tcpmm.machines.virtual import axis_config, virtual_friction, virtual_sweep

    a = vmc_linear.axes["X"]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        idn = identify_axis("X", virtual_sweep(a, name="X", seed=0),
                            axis_config(vmc_linear, "X"),
                            friction=virtual_friction(a, name="X"))
    assert any("no sliding friction" in str(w.message) for w in caught)
    for c in (idn.axis.friction.screw, idn.axis.friction.guideway):
        if c is not None:
            assert c.fs_pos == c.fc_pos and c.fs_neg == c.fc_neg
            assert c.fc_pos < 1.0 and c.fc_neg < 1.0  # [N], noise


@pytest.fixture(scope="module")
def sweep_x(vmc):
    from tcpmm.machines.virtual import virtual_sweep

    return virtual_sweep(vmc.axes["X"], duration_s=3.0, band_hz=(10.0, 1000.0), name="X")


@pytest.mark.parametrize(("current", "angle", "column", "needle"), [
    (1e3, 1.0, "current_cmd_A", "is the column in mA?"),
    (1.0, 180 / math.pi, "motor_angle_rad", "the motor angle looks like degrees"),
])
def test_a_column_in_the_wrong_unit_is_named(vmc, sweep_x, tmp_path, capsys, current, angle,
                                             column, needle):
    """A current in mA or a motor angle in degrees overflowed identification's fits into
    an OverflowError traceback, with or without --accept-suspect."""
    from tcpmm.io.bundle import write_bundle
    from tcpmm.io.records import SweepRecord
    from tcpmm.machines.virtual import bundle_machine_yaml

    s = sweep_x
    bad = SweepRecord.from_arrays(s.time_s, s.excitation_A * current, s.current_cmd_A * current,
                                  s.motor_angle_rad * angle, s.scale_m, s.tcp_m, axis="X")
    root = write_bundle({"machine": bundle_machine_yaml(vmc, ["X"]), "axes": {"X": bad}},
                        tmp_path / "b")
    model = tmp_path / "m.yaml"
    with warnings.catch_warnings():  # reading warns of the same columns
        warnings.simplefilter("ignore")
        code = main(["identify", str(root), "-o", str(model), "--accept-suspect"])
    err = capsys.readouterr().err
    assert code == 2 and not model.exists() and err.count("\n") == 1
    assert err.startswith(f"error: {root / 'X' / 'sweep.csv'}, column '{column}': ")
    assert needle in err
