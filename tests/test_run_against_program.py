"""A run measured against the program it was to follow (--command of contour and circle),
where it ran a command tcpmm compensate wrote."""

import json

import numpy as np
import pytest

from tcpmm.path.circle import circle_command


def test_a_run_of_the_compensated_command_is_measured_against_the_program(tmp_path, capsys):
    """contour and circle measured a run of the compensated command against its own
    command signals, the compensated command: bench C's circle read 78.5 um and three
    arcs where compensate had said 18.35 um. With --command the program is the path."""
    from tcpmm.cli import main
    from tcpmm.path import write_command_csv

    prog = tmp_path / "prog.csv"
    write_command_csv(circle_command(0.02, 5000 / 60e3, start_angle_rad=np.pi / 4), prog)
    comp, run = tmp_path / "comp.csv", tmp_path / "run.csv"
    assert main(["compensate", "builtin:vmc", "--command", str(prog), "-o", str(comp),
                 "--draws", "0", "--iterations", "5", "--radius", "20", "--json"]) == 0
    after = json.loads(capsys.readouterr().out)["scores"]["after"]
    assert main(["simulate", "builtin:vmc", "--command", str(comp), "-o", str(run)]) == 0
    capsys.readouterr()
    assert main(["contour", str(run), "--command", str(prog), "--json"]) == 0
    got = json.loads(capsys.readouterr().out)["sensors"]["tcp"]["max_abs_um"]
    assert got == pytest.approx(after["path"]["contour_error_um"], rel=0.02)
    assert main(["circle", str(run), "--radius", "20", "--command", str(prog), "--json"]) == 0
    passes = json.loads(capsys.readouterr().out)["passes"]
    assert len(passes) == 1
    assert main(["contour", str(run), "--command", str(tmp_path / "none.csv")]) == 2



def test_a_command_on_another_time_line_is_refused_and_the_reference_is_written(
        tmp_path, capsys):
    """A program planned with 90 % of the axes' limits left to the correction runs 16.2 s,
    where tcpmm path plans it in 8.15 s. Measured against the latter, the run's samples were
    paired with points of the path seconds away (51 mm of contour error, G 16 mm, exit 0).
    It is refused, naming when each has covered the share of its path where they differ
    most; --reference-out writes the command the run is to be measured against, and against
    it contour gives compensate's own figure."""
    from conftest import run_cli

    nc = tmp_path / "circle.nc"
    nc.write_text("G21 G90 G17\nG0 X35 Y0\nG1 F5000\nG3 X35 Y0 I-35 J0\nM30\n")
    prog, comp, ref, run = (tmp_path / f"{n}.csv" for n in ("prog", "comp", "ref", "run"))
    assert run_cli(capsys, "path", nc, "--model", "builtin:vmc", "-o", prog)[0] == 0
    code, out, _ = run_cli(capsys, "compensate", "builtin:vmc", "--gcode", nc, "-o", comp,
                           "--reference-out", ref, "--draws", "0", "--headroom", "0.9",
                           "--iterations", "3", "--json")
    assert code == 0
    after = json.loads(out)["scores"]["after"]["path"]["contour_error_um"]
    assert run_cli(capsys, "simulate", "builtin:vmc", "--command", comp, "-o", run)[0] == 0
    code, _, err = run_cli(capsys, "contour", run, "--command", prog)
    assert code == 2 and "another time line" in err and "--reference-out" in err
    code, _, err = run_cli(capsys, "circle", run, "--radius", 35, "--command", prog)
    assert code == 2 and "another time line" in err
    code, out, _ = run_cli(capsys, "contour", run, "--command", ref, "--json")
    assert code == 0
    assert json.loads(out)["sensors"]["tcp"]["max_abs_um"] == pytest.approx(after, rel=0.02)


def test_another_programs_command_is_refused(tmp_path, capsys):
    """A 50 mm square measured against the command of a helix of about the same duration:
    the time lines alike, the paths not. It was measured against it, with a contour error
    of 60 mm, exit 0."""
    from conftest import run_cli

    sq, hx = tmp_path / "sq.nc", tmp_path / "hx.nc"
    sq.write_text("G21 G90 G17\nG0 X0 Y0\nG1 X50 Y0 F3000\nG1 X50 Y50\nG1 X0 Y50\n"
                  "G1 X0 Y0\nG4 P0.5\nM30\n")
    hx.write_text("G21 G90 G17\nG0 X10 Y0 Z0\nG3 X10 Y0 Z-5 I-10 J0 F2000\n"
                  "G3 X-10 Y0 Z-7.5 I-10 J0\nG4 P0.2\nM30\n")
    cmd, run = tmp_path / "hx.csv", tmp_path / "sq_run.csv"
    assert run_cli(capsys, "path", hx, "-o", cmd)[0] == 0
    assert run_cli(capsys, "simulate", "builtin:vmc", "--gcode", sq, "-o", run)[0] == 0
    code, out, err = run_cli(capsys, "contour", run, "--command", cmd)
    assert code == 2 and "not the run's path" in err and "51.7 mm" in err and not out


def test_a_dwell_s_correction_and_a_shifted_start_are_told_apart(tmp_path, capsys):
    """A program with a dwell: the compensated command still corrects the tool while the
    program dwells, and the check counted that as motion, so the run of it was refused
    against the very reference compensate wrote ("90 % of its path after 0.587 s of
    motion, the run's own after 0.856 s"). A run of the compensated G-code, which starts
    with a dwell of its own, passed the check against the same reference and read 33 mm of
    contour error: contour takes the command at the run's clock, and the check compared
    times of motion only. Now the first is measured and the second refused."""
    from conftest import run_cli

    nc = tmp_path / "dwell.nc"
    nc.write_text("G90 G17 G64 F5000\nG1 X20 Y0\nG4 P0.5\nG1 X20 Y20\nM30\n")
    comp, ref, run = (tmp_path / f"{n}.csv" for n in ("comp", "ref", "run"))
    code, out, err = run_cli(capsys, "compensate", "builtin:vmc", "--gcode", nc, "-o", comp,
                             "--reference-out", ref, "--gcode-out", tmp_path / "comp.nc",
                             "--draws", "0", "--iterations", "5", "--json")
    assert code == 0, err
    after = json.loads(out)["scores"]["after"]["path"]["contour_error_um"]
    assert run_cli(capsys, "simulate", "builtin:vmc", "--command", comp, "-o", run)[0] == 0
    code, out, err = run_cli(capsys, "contour", run, "--command", ref, "--json")
    assert code == 0, err
    assert json.loads(out)["sensors"]["tcp"]["max_abs_um"] == pytest.approx(after, rel=0.05)
    assert run_cli(capsys, "simulate", "builtin:vmc", "--gcode", tmp_path / "comp.nc", "-o",
                   tmp_path / "run_nc.csv")[0] == 0
    code, _, err = run_cli(capsys, "contour", tmp_path / "run_nc.csv", "--command", ref)
    assert code == 2 and "another time line" in err and "starts to move at" in err
