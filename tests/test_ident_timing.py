"""Computation delay and velocity estimate read from the sweep
(``tcpmm.ident.physical.loop_timing``).

Known answers through the simulator: the built-in X axis with each stable timing, recorded
in step with the drive; and the independent reference machines, whose drives apply the
current one velocity period late and difference the encoder, recorded at 10 kHz against a
16 kHz loop.
"""

import pytest

from conftest import bench_path
from tcpmm.ident.physical import identify_loop_timing
from tcpmm.io.bundle import read_bundle
from tcpmm.machines.virtual import axis_config, virtual_sweep
from tcpmm.servo.sampled import sampled_spectral_radius


@pytest.mark.parametrize("delay, kind", [(0, "state"), (0, "difference"), (1, "state"),
                                         (1, "difference")])
def test_the_drive_timing_is_read_from_its_sweep(vmc, delay, kind):
    a = vmc.axes["X"]
    a = a.replace(servo=a.servo.model_copy(update={"delay_samples": delay,
                                                   "velocity_feedback": kind}))
    assert sampled_spectral_radius(a.mechanics, a.servo) < 1.0
    m = vmc.with_axis("X", a)
    got = identify_loop_timing(virtual_sweep(a, name="X"), axis_config(m, "X"))
    assert got.determined
    assert (got.delay_samples, got.velocity_feedback) == (delay, kind)
    # half a period for the difference, in step with the drive: no hold delay
    assert got.tau_periods == pytest.approx(delay + 0.5 * (kind == "difference"), abs=0.1)
    assert got.gain == pytest.approx(1.0, abs=0.05)


def test_wrong_gains_leave_the_timing_undetermined(vmc):
    a = vmc.axes["X"]
    cfg = axis_config(vmc, "X")
    sweep = virtual_sweep(a, name="X")
    wrong = cfg.model_copy(update={"servo": cfg.servo.model_copy(update={
        "velocity_gain_A_s_per_rad": 2.0 * cfg.servo.velocity_gain_A_s_per_rad,
        "velocity_integral_gain_A_per_rad": 2.0 * cfg.servo.velocity_integral_gain_A_per_rad})})
    got = identify_loop_timing(sweep, wrong)
    assert not got.determined and got.gain == pytest.approx(0.5, abs=0.05)


@pytest.mark.parametrize("letter", ["c", "d", "e"])
def test_reference_drives_apply_one_period_late_and_difference_the_encoder(letter):
    b = read_bundle(bench_path(letter) / "bundle")
    for name, rec in b.axes.items():
        got = identify_loop_timing(rec.sweep, b.machine.axes[name])
        assert got.determined, (name, got)
        assert (got.delay_samples, got.velocity_feedback) == (1, "difference")
        # 1 delay + 1/2 difference + 1/2 for a held current read out of step: 2 periods
        assert got.tau_periods == pytest.approx(2.0, abs=0.05)


def test_a_torque_mode_sweep_says_nothing_of_the_loop():
    b = read_bundle(bench_path("c") / "bundle_openloop")
    rec = b.axes["X"]
    assert identify_loop_timing(rec.sweep, b.machine.axes["X"]) is None


def test_a_record_in_step_with_the_ticks_is_told_from_a_daq_on_its_own_clock():
    from tcpmm.ident.physical import sampled_in_step

    assert sampled_in_step(8000.0, 125e-6)  # one sample per velocity period
    assert sampled_in_step(1000.0, 125e-6)  # every eighth tick
    assert not sampled_in_step(10_000.0, 125e-6)  # the reference machines' DAQ
    assert not sampled_in_step(16_000.0, 125e-6)  # faster than the loop: reads the hold
    assert not sampled_in_step(3000.0, 125e-6)  # 2.67 periods per sample


def test_a_time_base_a_quarter_off_is_warned_about():
    """A sweep sampled at 10 kHz stamped as 8 kHz fits a gain factor of 1.24, inside the
    range read as the declared controller: identify went on without a word and every mass
    came out 57 % heavy. The reference drives fit within 0.7 % of 1 and are not warned."""
    import warnings

    from tcpmm.errors import InputWarning
    from tcpmm.ident.physical.loop_warnings import sweep_timing
    from tcpmm.io.records import SweepRecord

    b = read_bundle(bench_path("c") / "bundle")
    rec, cfg = b.axes["X"].sweep, b.machine.axes["X"]
    with warnings.catch_warnings():
        warnings.simplefilter("error", InputWarning)
        assert sweep_timing("X", rec, cfg).determined
    slow = SweepRecord.from_arrays(rec.time_s * 1.25, rec.excitation_A, rec.current_cmd_A,
                                   rec.motor_angle_rad, rec.scale_m, rec.tcp_m)
    with pytest.warns(InputWarning, match=r"1\.2\d times .* time base \(its sample rate, "
                                          r"8000 Hz\)"):
        got = sweep_timing("X", slow, cfg)
    assert got.determined and got.gain == pytest.approx(1.24, abs=0.02)


def _swapped(cfg):
    other = "encoder" if cfg.servo.position_feedback == "scale" else "scale"
    return cfg.model_copy(update={"servo": cfg.servo.model_copy(update={
        "position_feedback": other})})


@pytest.mark.parametrize("source", ["vmc-scale", "vmc-encoder", "c", "r05"])
def test_a_position_loop_declared_on_the_wrong_sensor_is_said(vmc, source):
    """A machine.yaml declaring the position loop on the motor encoder where the drive
    closes it on the scale (or the other way round) was identified without a word, and
    the model then closed its loop on the wrong sensor. Above the axial mode the two part,
    and the controller output in the sweep tells which one the drive reads. Declared
    right: no warning; swapped: a warning naming both sensors."""
    import warnings

    from tcpmm.errors import InputWarning
    from tcpmm.ident.physical.loop_warnings import sweep_timing

    if source.startswith("vmc"):
        fb = source.split("-")[1]
        a = vmc.axes["X"]
        a = a.replace(servo=a.servo.model_copy(update={"position_feedback": fb}))
        rec, cfg = virtual_sweep(a, name="X"), axis_config(vmc.with_axis("X", a), "X")
    else:
        b = read_bundle(bench_path(source) / "bundle")
        rec, cfg = b.axes["X"].sweep, b.machine.axes["X"]
    with warnings.catch_warnings():
        warnings.simplefilter("error", InputWarning)
        sweep_timing("X", rec, cfg)
    wrong = _swapped(cfg)
    said = {"scale": "linear scale", "encoder": "motor encoder"}
    with pytest.warns(InputWarning, match="reads as a position loop closed on the "
                      f"{said[cfg.servo.position_feedback]}, not on the "
                      f"{said[wrong.servo.position_feedback]} machine.yaml declares"):
        sweep_timing("X", rec, wrong)


@pytest.mark.parametrize("letter", ["c", "r05"])
def test_an_excitation_recorded_with_its_sign_reversed_is_said_so(letter):
    """An excitation_A of the opposite sign left current_cmd_A - excitation_A no controller
    output: identify warned that the gains and the lead were not the drive's and left the
    loop's timing, and with it every figure, undetermined, while the mechanics were
    unchanged. The sign is now said, and the timing read with the column negated."""
    import dataclasses
    import warnings

    from tcpmm.errors import InputWarning
    from tcpmm.ident.physical import sweep_timing

    b = read_bundle(bench_path(letter) / "bundle")
    rec, cfg = b.axes["X"].sweep, b.machine.axes["X"]
    with warnings.catch_warnings():
        warnings.simplefilter("error", InputWarning)
        right = sweep_timing("X", rec, cfg)
    flipped = dataclasses.replace(rec, excitation_A=-rec.excitation_A)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        got = sweep_timing("X", flipped, cfg)
    said = [str(w.message) for w in caught]
    assert any("the excitation's sign is reversed" in m and "Negate excitation_A" in m
               for m in said), said
    assert not any("check the gains" in m for m in said)
    assert got.determined and got == right
