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

