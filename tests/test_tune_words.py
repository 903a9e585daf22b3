"""What ``tcpmm tune`` and ``tcpmm machine show`` say of loops at the ends of the range: a
machine with no path to run, a velocity loop slowed from an unstable one, a position loop
slower than a millihertz."""

import json
import re

from conftest import run_cli
from tcpmm import save_model
from tcpmm.servo.margins import axis_margins


def _x_changed(vmc, **servo):
    x = vmc.axes["X"]
    return vmc.model_copy(update={"axes": {**vmc.axes, "X": x.replace(
        servo=x.servo.model_copy(update=servo))}})


def test_a_one_axis_machine_is_not_said_to_be_moved_by_a_path(vmc, tmp_path, capsys):
    """X alone has no circle to run, and no program was given: its line read "moved by the
    path; ... k_ff kept, chosen on the path" and the JSON listed X as moved, of a path that
    was never predicted."""
    save_model(vmc.model_copy(update={"axes": {"X": vmc.axes["X"]}}), tmp_path / "x.yaml")
    code, out, err = run_cli(capsys, "tune", tmp_path / "x.yaml")
    assert code == 0, err
    [line] = [s for s in out.splitlines() if s.strip().startswith("X: ")]
    assert "no path predicted" in line and "k_ff kept (no path predicted" in line, line
    assert "moved by the path" not in out and "chosen on the path" not in out
    assert "no circle predicted: the machine has no Y axis" in out
    code, out, err = run_cli(capsys, "tune", tmp_path / "x.yaml", "--json")
    assert code == 0, err
    got = json.loads(out)
    assert got["moved_axes"] == [] and got["matched_axes"] == ["X"]


def test_a_slowed_loop_reads_as_the_table_gives_it(vmc, tmp_path, capsys):
    """X's velocity gain 15 times the built-in's: the loop is unstable as given and the
    proposal slows it from 378 to 119.5 Hz, which the verdict wrote "from 378 to 1.2e+02
    Hz". Verdict and warning now give the table's figures."""
    save_model(_x_changed(vmc, K_vp=15 * vmc.axes["X"].servo.K_vp), tmp_path / "m.yaml")
    code, out, err = run_cli(capsys, "tune", tmp_path / "m.yaml")
    assert code == 0, err
    assert "e+" not in out + err
    cells = re.search(r"velocity bandwidth \[Hz\] +([\d.]+)\* +([\d.]+)\n", out)
    assert cells, out
    b, a = cells.groups()
    assert float(a) < 0.5 * float(b)
    assert f"met only with the velocity loop slowed from {b} to {a} Hz" in out
    assert f"the velocity loop's bandwidth cut from {b} to {a} Hz" in err


def test_a_position_loop_slower_than_a_millihertz_has_its_crossover(vmc, tmp_path, capsys):
    """K_pp 0.005 1/s crosses over at K_pp / 2 pi = 0.8 mHz, below the 1 mHz the search
    started at: the phase margin read "infinite (no crossing)" and the bandwidth none; then,
    found, "at 0.0 Hz". A slow position loop is a real one (a ballbar test at a tiny gain)."""
    for k_pp in (0.005, 5e-5):
        pos = axis_margins(vmc.axes["X"].mechanics,
                           _x_changed(vmc, K_pp=k_pp).axes["X"].servo)["position"]
        assert abs(pos.bandwidth_hz / (k_pp / (2 * 3.141592653589793)) - 1) < 1e-3
        assert 89.0 < pos.phase_margin_deg < 90.0
    save_model(_x_changed(vmc, K_pp=0.005), tmp_path / "m.yaml")
    code, out, err = run_cli(capsys, "machine", "show", tmp_path / "m.yaml")
    assert code == 0, err
    [line] = [s for s in out.splitlines() if "position loop" in s][:1]
    assert "phase margin 90.0 deg at 0.0008 Hz, bandwidth 0.0008 Hz" in line, line


def _r05_x():
    """Bench r05's X as ``tcpmm tune`` proposes it: the identified mechanics, the
    proposal's low-pass and PI and position gain [SI]."""
    from tcpmm.mechanics.lumped import AxisMechanics
    from tcpmm.servo.params import ServoParams

    mech = AxisMechanics(
        J_m=9.532122957876765e-05, B_m=0.0, J_L=0.0001395091164620126,
        B_L=0.003541533400593328, K_L=2152.6510987962847, lead=0.008,
        M_t=54.62061767481668, C_t=165.9133528270798, K_t=40572901.72138592,
        M_b=150.01401625760926, C_b=13658.672042569091, K_b=99259210.15459697,
        M_h=57.94372813135238, C_h=988.374545124414, K_h=2612324.137051301, K_tc=1.454)
    servo = ServoParams.create(
        K_pp=58.738082583518576, K_vp=0.05269228340013278, K_vi=3.1209588409446183,
        k_ff=0.0, T_p=0.002, T_v=6.25e-05, current_limit=12.0,
        current_bandwidth_hz=1296.422591616291, delay_samples=1,
        velocity_feedback="difference",
        filters=[{"type": "lowpass", "f_hz": 122.97753845479284, "zeta": 0.7}])
    return mech, servo


def test_a_loop_just_unstable_does_not_read_a_spectral_radius_of_one():
    """Bench r05's X as tuned: its velocity gain is limited by the stability with the
    modes shifted, and the note quoted the loop just above that gain as "unstable ...
    (spectral radius 1.0000)", a radius that reads as stable. A radius within 5e-5 of 1
    is given as its distance from 1."""
    from tcpmm.servo.tune import velocity_limit

    text = velocity_limit(*_r05_x(), 6.0, 45.0)
    assert "unstable" in text, text
    (rho,) = re.findall(r"spectral radius ([^)]*)\)", text)
    assert rho != "1.0000" and rho.startswith("1 + "), text


def test_settings_tuned_again_are_kept(vmc):
    """Bench r05's model as tune wrote it, tuned again: its K_vp and K_pp came back a bit
    or two off (0.052692283400132774 for ...278), so the axis's sentence said "K_pp
    lowered to 58.74 1/s" beside a table of 58.74 -> 58.74, and the path's figures moved
    by 1e-10 um, which the draws' note listed as "not smaller on every one: ... +0.00 um".
    A gain the tuning finds within rounding of the one it had is the one it had."""
    from tcpmm.whatif.tuning_axes import axis_reasons, tune_axes

    mech, servo = _r05_x()
    x = vmc.axes["X"].replace(mechanics=mech, servo=servo)
    axes = tune_axes(vmc.model_copy(update={"axes": {"X": x}}), 6.0, 45.0, ["X"], jobs=1)
    assert axes["X"].after == servo
    (said,) = axis_reasons(axes, ["X"], ["X"], False).values()
    assert "K_pp kept" in said, said
