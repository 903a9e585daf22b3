"""The controller parameter file read back (:mod:`tcpmm.compensate.controller_file`): its
two forms of the friction pulse made one, values no drive means refused, and the file's
head and the axes it leaves out said."""

from __future__ import annotations

from pathlib import Path

import pytest

from tcpmm.compensate.controller_file import read_controller_parameters
from tcpmm.errors import InputError

PROGRAM = Path(__file__).resolve().parents[1] / "examples" / "circle_r35_f5000.nc"


def _file(tmp_path, text: str) -> Path:
    path = tmp_path / "p.yaml"
    path.write_text(text)
    return path


def test_the_velocity_form_alone_is_the_pulse(tmp_path, vmc):
    """``FRICT_COMP_CONST_MAX_mm_per_min`` alone ran as no pulse at all, and with
    ``FRICT_COMP_TIME_s`` was refused for a ``friction_pulse_decay_ms`` never given."""
    x = vmc.axes["X"]
    amp = 50 / 6e4 / x.mechanics.R_L * x.servo.K_vp
    p = read_controller_parameters(_file(tmp_path, "X:\n  FRICT_COMP_CONST_MAX_mm_per_min: "
                                         "50\n  FRICT_COMP_TIME_s: 0.02\n"), vmc.axes)
    assert p["X"].pulse_A == pytest.approx(amp) and p["X"].decay_s == pytest.approx(0.02)
    assert p["X"].velocity_pulse_m_per_s == pytest.approx(50 / 6e4)
    with pytest.raises(InputError, match="needs its decay time"):
        read_controller_parameters(_file(tmp_path, "X:\n  FRICT_COMP_CONST_MAX_mm_per_min: "
                                         "500\n"), vmc.axes)
    # names alone cannot convert it
    with pytest.raises(InputError, match="model's K_vp and R_L; read it with the model's"):
        read_controller_parameters(_file(tmp_path, "X:\n  FRICT_COMP_CONST_MAX_mm_per_min: "
                                         "50\n  FRICT_COMP_TIME_s: 0.02\n"), ["X", "Y"])


def test_the_two_forms_of_the_pulse_must_agree(tmp_path, vmc):
    """``FRICT_COMP_CONST_MAX_mm_per_min: 9999`` beside 0.3 A ran as 0.3 A unsaid; the
    file as written (4 significant digits of each) still reads."""
    with pytest.raises(InputError, match=r"friction_pulse_A 0.3 A and FRICT_COMP_CONST_MAX"
                                         r"_mm_per_min 9999 are one pulse and disagree: the "
                                         r"latter is 9999 mm/min / 60000 / R_L .* \* K_vp"):
        read_controller_parameters(_file(tmp_path, "X:\n  friction_pulse_A: 0.3\n"
                                         "  friction_pulse_decay_ms: 20\n"
                                         "  FRICT_COMP_CONST_MAX_mm_per_min: 9999\n"), vmc.axes)
    x = vmc.axes["X"]
    v = 0.7 / x.servo.K_vp * x.mechanics.R_L * 6e4
    p = read_controller_parameters(_file(tmp_path, f"X:\n  friction_pulse_A: 0.7\n"
                                         f"  friction_pulse_decay_ms: 20\n"
                                         f"  FRICT_COMP_CONST_MAX_mm_per_min: {v:.4g}\n"
                                         f"  FRICT_COMP_TIME_s: 0.02\n"), vmc.axes)
    assert p["X"].pulse_A == 0.7


@pytest.mark.parametrize("body, said", [
    ("friction_pulse_A: -500\n  friction_pulse_decay_ms: 20",
     r"-500 A is beyond the axis's current limit of 20 A; .*mA typed as A"),
    ("friction_pulse_A: 0.3\n  friction_pulse_decay_ms: 20000",
     r"20000 ms is a friction pulse decay longer than 10 s.*us typed as ms"),
    ("friction_pulse_A: 0.3\n  FRICT_COMP_TIME_s: 20",
     r"FRICT_COMP_TIME_s 20 s is .* longer than 10 s.*ms typed as s\? \(20 ms is 0.02 s\)"),
    ("friction_pulse_A: 0.3\n  friction_pulse_decay_ms: 0.02",
     r"shorter than one velocity-loop period \(T_v 0.125 ms\).*\(0.02 s is 20 ms\)"),
    ("cross_talk_um_per_m_per_s2: 1e6", r"1000 mm per m/s\^2.*below 5 Hz.*nm typed as um"),
])
def test_values_no_drive_means_are_refused(tmp_path, vmc, body, said):
    """A pulse beyond the current limit, a decay of 20 s or of 20 us and a cross-talk of a
    metre per m/s^2 ran, and the run's warning blamed the command's units."""
    with pytest.raises(InputError, match=said):
        read_controller_parameters(_file(tmp_path, f"X:\n  {body}\n"), vmc.axes)


def test_the_head_says_what_holds(tmp_path):
    """Share 0 said the command was learned with the parameters and is right only with
    them, then that all are 0; ``--draws 0`` said share 1 as if draws had kept it."""
    from tcpmm.cli.compensate import _parameter_note

    none = _parameter_note("c.csv", 0.0, 16)
    assert "kept none" in none and "learned with them" not in none and "off (0)" in none
    untested = _parameter_note("c.csv", 1.0, 0)
    assert "not tested on draws" in untested and "share" not in untested
    half = _parameter_note("c.csv", 0.5, 16)
    assert "tested on 16 draws" in half and "kept: 0.5" in half
    assert all(line.startswith("# ") for line in (none + untested + half).splitlines())


def test_an_axis_the_file_leaves_out_is_said(tmp_path, capsys):
    """A file with X only left Y of an XY circle uncompensated, unsaid."""
    from tcpmm.cli import main

    params = _file(tmp_path, "X:\n  friction_pulse_A: 0.3\n  friction_pulse_decay_ms: 20\n")
    assert main(["simulate", "builtin:vmc", "--gcode", str(PROGRAM), "--controller",
                 str(params), "-o", str(tmp_path / "run.csv")]) == 0
    err = " ".join(capsys.readouterr().err.split())
    assert f"{params} has no parameters for Y: it runs without controller-side" in err


def test_a_file_computed_on_another_model_says_so(tmp_path):
    """The file names the model it was computed on; applied on another, the pulses answer
    the other's friction: a warning names both, and the same model reads quietly."""
    import warnings

    from tcpmm.compensate.controller import AxisController, ControllerCompensation
    from tcpmm.errors import InputWarning

    mine = {"name": "bench d", "digest": "0123456789abcdef"}
    cc = ControllerCompensation({"X": AxisController(0.5, 0.02, 0.0, 0.0)})
    path = tmp_path / "p.yaml"
    path.write_text(cc.parameter_text(mine))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert read_controller_parameters(path, ("X",), mine)["X"].pulse_A == 0.5
        assert read_controller_parameters(path, ("X",))["X"].pulse_A == 0.5  # none to check
    other = {"name": "bench e", "digest": "fedcba9876543210"}
    with pytest.warns(InputWarning, match="computed on the model 'bench d' \\(digest "
                      "0123456789abcdef\\), not on this one \\('bench e', digest "
                      "fedcba9876543210\\)"):
        read_controller_parameters(path, ("X",), other)
    # a file without the model's name, as typed by hand, is read as before
    path.write_text(cc.parameter_text())
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        read_controller_parameters(path, ("X",), other)
