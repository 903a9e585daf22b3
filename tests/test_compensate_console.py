"""What tcpmm compensate says on the console and in its files about the program it was
given."""

import json

import pytest

from tcpmm.cli import main

#: A circle of R 35 mm that starts and ends at quadrant point A (X35 Y0): it never
#: crosses A, so no reversal spike can be reported there.
CIRCLE_AT_A = "G21 G17 G90\nG0 X35 Y0\nG3 X35 Y0 I-35 J0 F3000\nM30\n"


def test_a_circle_starting_at_a_quadrant_point_is_said_once(tmp_path, capsys):
    """Without --report the console says that no spike is reported at A, once over the
    runs and draws judged, and --json stays one JSON document on stdout that carries
    it."""
    prog = tmp_path / "circle_at_a.nc"
    prog.write_text(CIRCLE_AT_A)
    args = ["compensate", "builtin:vmc", "--gcode", str(prog), "-o", str(tmp_path / "c.csv"),
            "--radius", "35", "--draws", "2", "--iterations", "3"]
    assert main(args) == 0
    err = capsys.readouterr().err
    said = [line for line in err.splitlines() if "no reversal spike is reported at A" in line]
    assert len(said) == 1, err
    assert main([*args, "--json"]) == 0
    got = capsys.readouterr()
    d = json.loads(got.out)
    assert any("no reversal spike is reported at A" in w for w in d["warnings"])
    assert got.err.count("no reversal spike is reported at A") == 1


@pytest.fixture(scope="module")
def scurve_model(tmp_path_factory):
    """The built-in machine with an S-curve interpolator of 6 m/s² and 200 m/s³: it plans
    within the jerk limit along the path, not at a junction [-]."""
    from tcpmm import builtin_machine, save_model

    vmc = builtin_machine()
    path = tmp_path_factory.mktemp("model") / "scurve.yaml"
    save_model(vmc.model_copy(update={"interpolation": {
        **(vmc.interpolation or {}), "profile": "scurve", "path_accel_m_per_s2": 6.0,
        "path_jerk_m_per_s3": 200.0}}), path)
    return path


@pytest.mark.parametrize(("moves", "cause"), [
    # a line into an arc and an arc into one turning the other way, tangent: the velocity
    # is continuous, the acceleration steps (X 2 650 m/s³ of the plan at the S-bend)
    ("G0 X0 Y-10\nG1 X0 Y0 F8000\nG2 X20 Y0 I10 J0\nG3 X40 Y0 I10 J0", "step of curvature"),
    # a corner of 90 deg: the velocity steps (X 860 m/s³ of the plan)
    ("G0 X0 Y0\nG1 X20 Y0 F10000\nG1 X20 Y20", "sharp corner's velocity step")])
def test_a_jerk_beyond_the_limit_is_explained_from_the_path(tmp_path, capsys, scurve_model,
                                                            moves, cause):
    """The program's own jerk beyond the limit is a tangent junction's step of curvature
    where the path's direction is continuous, and a sharp corner's velocity step where it
    is not. As programmed (``--headroom 0``: with headroom the plan holds a step of
    curvature within the jerk given, ``tests/test_transition_jerk.py``) the step of
    curvature's warning names the settings that hold it."""
    prog = tmp_path / "p.nc"
    prog.write_text(f"G21 G17 G90 G64\n{moves}\nM30\n")
    assert main(["compensate", str(scurve_model), "--gcode", str(prog), "-o",
                 str(tmp_path / "c.csv"), "--draws", "0", "--iterations", "2",
                 "--headroom", "0"]) == 0
    lines = [s for s in capsys.readouterr().err.splitlines() if "jerk up to" in s]
    assert lines and all(cause in s for s in lines), lines
    fixes = "transition_jerk_m_per_s3" in lines[0] and "--headroom above 0" in lines[0]
    assert fixes is (cause == "step of curvature"), lines


def test_the_contour_rms_is_over_the_program_s_motion(monkeypatch):
    """The hold appended after the program for the TCP to settle is left out of the rms:
    the program's figure before is the same whatever the hold's length (the run up to the
    program's end does not depend on it), where the hold's small errors diluted it."""
    from tcpmm.compensate import compensate, learning, predicted_scores
    from tcpmm.machines.builtin import builtin_machine
    from tcpmm.path.circle import circle_command

    machine = builtin_machine()
    cmd = circle_command(0.01, 0.05)
    rms = {}
    for tail_s in (0.3, 0.6):
        monkeypatch.setattr(learning, "TAIL_S", tail_s)
        comp = compensate(machine, cmd, iterations=1)
        rms[tail_s] = predicted_scores(machine, comp, programmed=cmd)["before"]["path"][
            "contour_rms_um"]
    assert rms[0.3] == pytest.approx(rms[0.6], rel=1e-9)


def test_the_program_as_programmed_and_its_plan_with_headroom_are_told_apart(
        tmp_path, capsys, scurve_model):
    """A corner planned with headroom 0.25: the demands are the program's at the full
    limits (X jerk 3 972 m/s³), the peak beyond the limit the plan's with headroom (764):
    both lines called it "the program", the one "program ->", the next "the program as
    planned". Each now says which plan it means."""
    prog = tmp_path / "corner.nc"
    prog.write_text("G21 G17 G90 G64\nG0 X0 Y0\nG1 X20 Y0 F10000\nG1 X20 Y20\nM30\n")
    assert main(["compensate", str(scurve_model), "--gcode", str(prog), "-o",
                 str(tmp_path / "c.csv"), "--draws", "0", "--iterations", "2"]) == 0
    said = capsys.readouterr()
    out = said.out
    lines = out.splitlines()
    assert "(as programmed)" in lines[1] and "(planned with headroom 0.25, uncorrected)" in lines[2]
    assert "X asks (as programmed -> compensated)" in out
    beyond = [s for s in said.err.splitlines() if "above its limit" in s]  # warnings
    assert beyond and all("the program planned with headroom 0.25 reaches" in s for s in beyond)
    assert "planned with headroom 0.25: 75% of the axes'" in out and "s as programmed" in out
    assert "program ->" not in out and "program as planned" not in out


@pytest.mark.parametrize("settle_s", [0.0, 0.05])
def test_the_dense_program_says_which_lines_are_the_rapids(settle_s):
    """The dense program writes a program's G0 rapids as G1 at the planned speed, so that
    it keeps the command's timing; its header now says so, with the lines they are (one
    per sample; the hold after a program that ends on a rapid is dwells, none of them),
    and a command with no rapids says nothing."""
    import re

    from tcpmm.compensate.gcodeout import dense_program
    from tcpmm.compensate.learning import extended
    from tcpmm.path.program import program_to_command

    cmd = program_to_command("G21 G90 G17 G64\nG0 X5 Y5\nG1 X25 Y5 F4000\nG0 X40 Y40\n"
                             "G1 X50 Y40 F4000\nG0 X60 Y40\nM30\n")
    cmd = extended(cmd, 0, 50)[0]  # held at its end, as compensate holds it
    text = dense_program(cmd, settle_s=settle_s).splitlines()
    assert text[1].startswith("(the program's G0 rapids are written as G1")
    named = set()
    for a, b in re.findall(r"(\d+)(?:-(\d+))?", text[1].split("lines ")[1]):
        named.update(range(int(a), int(b or a) + 1))
    first = 6 if settle_s else 5  # the line of the second sample
    assert text[first - 2].startswith("G4 P" if settle_s else "G0 ")  # the first's, or its dwell
    rapid = {first + k - 1 for k in range(1, cmd.time_s.size) if cmd.meta["rapid"][k]}
    assert named == {n for n in rapid if text[n - 1].startswith("G1 ")}
    assert len(named) > 100 and text[-2].startswith("G4 ") and len(text) - 2 in rapid
    plain = cmd.__class__(cmd.time_s, cmd.positions)
    assert "rapids" not in dense_program(plain)


def _polyline_arc(blocks: int = 60, radius_mm: float = 10.0, blend: str = "") -> str:
    """A half circle posted as ``blocks`` G1 lines, as CAM writes a curve [mm]."""
    import math

    pts = [(radius_mm * math.cos(math.pi * k / blocks), radius_mm * math.sin(math.pi * k / blocks))
           for k in range(blocks + 1)]
    lines = [f"G21 G17 G90 G64{blend}", f"G0 X{pts[0][0]:.4f} Y{pts[0][1]:.4f}"]
    lines += [f"G1 X{x:.4f} Y{y:.4f} F3000" for x, y in pts[1:]]
    return "\n".join([*lines, "M30", ""])


@pytest.mark.parametrize("blend, said", [("", True), (" P0.01", False)])
def test_a_polyline_slowed_by_its_sharp_corners_is_told_why(tmp_path, capsys, blend, said):
    """Planned with headroom, each junction of a curve posted as lines is a sharp corner
    taken with a third of the velocity step: the plan's extra time is mostly there, and
    the console says so; rounded by G64 P, the corners add nothing and nothing is said."""
    prog = tmp_path / "arc.nc"
    prog.write_text(_polyline_arc(blend=blend))
    args = ["compensate", "builtin:vmc", "--gcode", str(prog), "-o", str(tmp_path / "c.csv"),
            "--draws", "0", "--iterations", "3"]
    assert main(args) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert ("at sharp corners between blocks, each taken with a velocity step of 33% of the "
            "axes' acceleration" in out) is said, out
    assert main([*args, "--json"]) == 0
    settings = json.loads(capsys.readouterr().out)["settings"]
    added = settings["planned_duration_s"] - settings["programmed_duration_s"]
    assert (settings["corner_steps_s"] >= 0.1 * added) is said


def test_a_lower_acceleration_given_is_not_taken_for_sharp_corners(tmp_path, capsys):
    """The same curve rounded by G64 P0.01, its axes given 0.5 m/s² on a 1 m/s²
    interpolator: the plan with the headroom is slower on every ramp for the lower limit,
    not at corners, and nothing is said of corners; measured against a plan at the
    interpolator's own limits, the lower limit's ramps were put at the corners and a P the
    program has was asked for. The plan with the corners'
    step at the machine's share differs from it by a few samples at most (1 ms each), far
    below a tenth of the time the headroom and the lower limit add."""
    prog = tmp_path / "arc.nc"
    prog.write_text(_polyline_arc(blend=" P0.01"))
    args = ["compensate", "builtin:vmc", "--gcode", str(prog), "-o", str(tmp_path / "c.csv"),
            "--draws", "0", "--iterations", "3", "--accel-m-per-s2", "0.5"]
    assert main(args) == 0
    assert "sharp corners" not in " ".join(capsys.readouterr().out.split())
    assert main([*args, "--json"]) == 0
    settings = json.loads(capsys.readouterr().out)["settings"]
    added = settings["planned_duration_s"] - settings["programmed_duration_s"]
    assert added > 0.1 and settings["corner_steps_s"] < 0.01 * added


@pytest.mark.parametrize("as_json", [False, True])
def test_a_corner_the_correction_overshoots_is_said(tmp_path, capsys, as_json):
    """A square with dwells at F6000 on the built-in machine: the correction takes the
    contour error from 64.6 to 9.4 µm, and the TCP from 7.0 to 9.4 µm outside the path
    past a corner, which the figures did not tell from the rounding they took away (on
    bench H's model 5.2 -> 22.2 µm, which its true machine ran at 23.2). The figures
    before and after give the corners' overshoot, and a warning says where it grew."""
    prog = tmp_path / "dwell.nc"
    prog.write_text("G90 G17 G21 G64 P0.02 F6000\nG1 X30 Y0\nG1 X30 Y15\nG4 P0.2\n"
                    "G1 X30 Y30\nG1 X0 Y30\nG4 P0.3\n")
    args = ["compensate", "builtin:vmc", "--gcode", str(prog), "-o", str(tmp_path / "c.csv"),
            "--draws", "0"]
    if not as_json:
        assert main(args) == 0
        got = capsys.readouterr()
        assert "corner overshoot" in got.out and "outside the path past a corner" in got.err
        return
    assert main([*args, "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    b, a = (d["scores"][k]["path"] for k in ("before", "after"))
    assert a["corner_overshoot_um"] > b["corner_overshoot_um"] + 1.0, (b, a)
    assert len(a["corner_overshoot_at_mm"]) == 2
    said = [w for w in d["warnings"] if "outside the path past a corner" in w]
    assert len(said) == 1 and f"{a['corner_overshoot_um']:.2f} µm after" in said[0], said
