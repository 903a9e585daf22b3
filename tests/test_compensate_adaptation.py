"""The friction pulse's adaptation characteristic (tcpmm.compensate.adaptation): its shape
as the Sinumerik function manual defines it, the circle at a feed override, the pulse the
drive fires at each reversal, the choice of characteristic, and the parameter file."""

import math

import numpy as np
import pytest

from tcpmm.compensate.adaptation import (
    Characteristic,
    SpikeCurves,
    best_characteristic,
    time_scaled,
)
from tcpmm.compensate.controller import AxisController, ControllerCompensation
from tcpmm.compensate.controller_file import read_controller_parameters
from tcpmm.compensate.drive import drive_inputs, reversal_pulses
from tcpmm.compensate.turns import reversal_accelerations, reversals
from tcpmm.errors import InputError
from tcpmm.path.circle import circle_command

R, F = 0.02, 4000 / 60e3  # [m], [m/s]


def test_characteristic_has_the_four_ranges():
    """B1 a ramp from 0, B2 the largest, B3 straight to the smallest, B4 the smallest
    (SINUMERIK 840D sl function manual K3, "Friction compensation with adaptation
    characteristic")."""
    ch = Characteristic((0.1, 0.2, 0.6), 0.25)
    a = np.array([0.0, 0.05, 0.1, 0.15, 0.2, 0.4, 0.6, 5.0, -0.05])
    assert ch.factor(a) == pytest.approx([0.0, 0.5, 1.0, 1.0, 1.0, 0.625, 0.25, 0.25, 0.5])


def test_a_circle_at_half_its_feed_reverses_at_a_quarter_of_the_acceleration():
    cmd = circle_command(R, F, accel_limit_m_per_s2=2.0)
    half = time_scaled(cmd, 0.5)
    assert half.period_s == pytest.approx(cmd.period_s)
    assert half.time_s[-1] - half.time_s[0] == pytest.approx(
        2 * (cmd.time_s[-1] - cmd.time_s[0]), abs=cmd.period_s)
    for a in ("X", "Y"):
        t_full, t_half = reversals(cmd, a)[0], reversals(half, a)[0]
        # the same turns, and no ripple at the rests at either end becoming one
        assert t_half.size == t_full.size > 0
        acc, full = (reversal_accelerations(c, a, t) for c, t in ((half, t_half),
                                                                  (cmd, t_full)))
        # v^2 / R on the circle (the second turn); where the feed-in and feed-out arcs
        # (radius R/2) join it, at the first and last, the acceleration jumps there and the
        # reading lies between v^2 / R and 2 v^2 / R
        assert full[1] == pytest.approx(F**2 / R, rel=0.02)
        assert np.all((full[[0, -1]] > F**2 / R) & (full[[0, -1]] < 2 * F**2 / R))
        assert acc == pytest.approx(full / 4, rel=0.02)
        assert np.all(np.isfinite(half.positions[a]))


def test_the_drive_scales_each_pulse_by_the_characteristic():
    cmd = circle_command(R, F, accel_limit_m_per_s2=2.0)
    ch = Characteristic((0.01, 0.05, 0.1), 0.5)
    flat = reversal_pulses(cmd, "X", 1.0, 0.01)
    adapted = reversal_pulses(cmd, "X", 1.0, 0.01, ch)
    turns = reversals(cmd, "X")[0]
    a = reversal_accelerations(cmd, "X", turns)  # 0.22 m/s^2: beyond a3, the smallest
    assert np.all(a > 0.1)
    assert np.abs(adapted[turns]) == pytest.approx(0.5 * np.abs(flat[turns]))
    # the same through the controller's parameters, with a share of them
    c = AxisController(1.0, 0.01, 0.0, 0.0, ch)
    _, pulses = drive_inputs(cmd, {"X": c}, share=0.5)
    assert np.abs(pulses["X"][turns]) == pytest.approx(0.25 * np.abs(flat[turns]))
    assert c.scaled(0.5).characteristic is ch


def _curves(best_amp) -> SpikeCurves:
    """Spikes that grow with the distance from an optimum amplitude per override [um]."""
    accel = np.array([0.0125, 0.05, 0.2])
    amps = np.arange(0.0, 3.01, 0.25)
    spikes = np.array([10.0 + 4.0 * np.abs(amps - b) for b in best_amp])
    return SpikeCurves(accel, amps, spikes)


def test_a_characteristic_is_kept_where_the_best_pulse_depends_on_the_acceleration():
    curves = _curves([0.5, 2.0, 2.0])  # little pulse at the slowest reversal
    ch, top, lost = best_characteristic(curves, 2.0)
    assert ch is not None and lost < 0.5
    got = top * ch.factor(curves.accel_m_per_s2)
    assert got == pytest.approx([0.5, 2.0, 2.0], abs=0.13)


def test_no_characteristic_where_one_amplitude_is_as_good():
    ch, top, lost = best_characteristic(_curves([1.5, 1.5, 1.5]), 1.5)
    assert ch is None and top == 1.5 and lost == pytest.approx(0.0)
    # a gain within the spikes' margin (2 %, at least 0.1 um) is no gain
    ch, _, _ = best_characteristic(_curves([1.5, 1.5, 1.52]), 1.5)
    assert ch is None


def _cc(ch) -> ControllerCompensation:
    return ControllerCompensation({"X": AxisController(0.8, 0.03, 0.8 * 0.01, 2e-6, ch),
                                   "Y": AxisController(0.5, 0.01, 0.5 * 0.01, 0.0)})


def test_the_parameter_file_gives_the_characteristic_with_its_machine_data(tmp_path):
    ch = Characteristic((0.0123, 0.0497, 0.0993), 0.75)
    text = _cc(ch).parameter_text()
    for md in ("MD32510", "MD32520", "MD32530", "MD32540", "MD32550", "MD32560", "MD32570"):
        assert md in text
    path = tmp_path / "p.yaml"
    path.write_text(text)
    got = read_controller_parameters(path, ("X", "Y"))
    assert got["Y"].characteristic is None
    back = got["X"].characteristic
    assert back.accel_m_per_s2 == pytest.approx(ch.accel_m_per_s2, rel=1e-3)
    assert back.low_ratio == pytest.approx(0.75, rel=1e-3)
    assert got["X"].pulse_A == pytest.approx(0.8)


@pytest.mark.parametrize("edit, said", [
    (lambda t: t.replace("  FRICT_COMP_ADAPT_ENABLE: 1  # MD32510\n", ""),
     "without FRICT_COMP_ADAPT_ENABLE"),
    (lambda t: t.replace("FRICT_COMP_ACCEL2_m_per_s2: 0.0497", "FRICT_COMP_ACCEL2_m_per_s2: 0.2"),
     "ACCEL1_m_per_s2 < FRICT_COMP_ACCEL2_m_per_s2 <"),
    (lambda t: t.replace("friction_pulse_min_A: 0.6", "friction_pulse_min_A: 0.4"),
     "are one amplitude and disagree"),
    (lambda t: t.replace("  FRICT_COMP_ADAPT_ENABLE: 1", "  FRICT_COMP_ADAPT_ENABLE: 2"),
     "FRICT_COMP_ADAPT_ENABLE"),
])
def test_a_characteristic_typed_wrong_is_refused(tmp_path, edit, said):
    text = _cc(Characteristic((0.0123, 0.0497, 0.0993), 0.75)).parameter_text()
    path = tmp_path / "p.yaml"
    path.write_text(edit(text))
    assert edit(text) != text
    with pytest.raises(InputError, match=said):
        read_controller_parameters(path, ("X", "Y"))


def test_switched_off_the_characteristic_is_not_applied(tmp_path):
    text = _cc(Characteristic((0.0123, 0.0497, 0.0993), 0.75)).parameter_text()
    path = tmp_path / "p.yaml"
    path.write_text(text.replace("FRICT_COMP_ADAPT_ENABLE: 1", "FRICT_COMP_ADAPT_ENABLE: 0"))
    assert read_controller_parameters(path, ("X", "Y"))["X"].characteristic is None
    assert math.isfinite(read_controller_parameters(path, ("X", "Y"))["X"].pulse_A)


def test_the_command_line_says_the_characteristic():
    from tcpmm.cli._compensate_text import adaptation_lines

    lines = adaptation_lines(_cc(Characteristic((0.0123, 0.0497, 0.0993), 0.75)))
    assert len(lines) == 1 and lines[0].startswith("  X: the pulse adapted")
    assert "0.8 A up to 0.0123 m/s^2" in lines[0] and "0.6 A from 0.0993 m/s^2" in lines[0]
    assert adaptation_lines(_cc(None)) == []


def test_a_minimum_beyond_the_current_limit_or_accelerations_in_mm_are_refused(tmp_path):
    """A unit slip in the minimum fires only beyond ACCEL3, where a quick check at a low
    feed does not look; accelerations in mm/s^2 leave every reversal on the ramp from
    zero, the compensation quietly off."""
    from tcpmm.machines.builtin import builtin_machine

    axes = builtin_machine().axes
    text = _cc(Characteristic((0.0123, 0.0497, 0.0993), 0.75)).parameter_text()
    path = tmp_path / "p.yaml"
    # the current form alone, which the axes convert no velocity form against
    current = "\n".join(line for line in text.splitlines() if "FRICT_COMP_CONST" not in line)
    path.write_text(current.replace("friction_pulse_min_A: 0.6", "friction_pulse_min_A: 600"))
    with pytest.raises(InputError, match="beyond the axis's current limit"):
        read_controller_parameters(path, {a: axes[a] for a in ("X", "Y")})
    path.write_text(text.replace("0.0123", "12.3").replace("0.0497", "49.7")
                    .replace("0.0993", "99.3"))
    with pytest.raises(InputError, match="mm/s\\^2 typed as m/s\\^2"):
        read_controller_parameters(path, ("X", "Y"))


def test_a_pulse_without_a_characteristic_says_it_off():
    text = _cc(None).parameter_text()
    assert text.count("FRICT_COMP_ADAPT_ENABLE: 0  # MD32510") == 2
    zero = ControllerCompensation({"X": AxisController(0.0, 0.03, 0.0, 0.0)})
    assert "FRICT_COMP_ADAPT_ENABLE:" not in zero.parameter_text()


def test_the_quadrant_acceleration_leaves_out_the_reversals_from_rest():
    from tcpmm.compensate.adaptation import quadrant_acceleration

    assert quadrant_acceleration(np.array([0.0004, 0.2, 0.19, 0.3, 0.001])) == 0.2
