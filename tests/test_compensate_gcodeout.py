"""The dense program of ``tcpmm compensate --gcode-out`` against the command it is written
from, sample by sample, as a controller set as the model's interpolator plans it."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest

from tcpmm import builtin_machine
from tcpmm.cli import main
from tcpmm.compensate.gcodeout import REPLAY_TOL_M, dense_program
from tcpmm.path import Command, circle_command, write_command_csv


def _slow_line() -> Command:
    """A 10 mm move in XY over 2 s with a cosine speed: far inside the interpolator's
    acceleration, so that it plans each 1 ms block in its period [m]."""
    t = np.arange(2000) * 1e-3
    x = 0.01 * (1.0 - np.cos(np.pi * t / t[-1])) / 2.0
    return Command(t, {"X": x, "Y": 0.5 * x})


def test_a_program_the_interpolator_retimes_is_said_with_its_largest_departure(capsys):
    """Only the whole run's time was compared (within 2 %): the dense program of bench C's
    compensated circle ran 4436 mm/min at its reversals, where the command file runs 5000,
    up to 551 µm from it at the same time, with no word, and the figures after were taken
    for the program's. A circle that speeds up at the interpolator's full acceleration
    already shows it: each 1 ms block, its feed the mean speed over it, starts at the
    slower feed before it, and the program falls behind."""
    from tcpmm.cli._compensate_dense import warn_replanned

    cmd = circle_command(0.035, 5000 / 60e3)
    text = dense_program(cmd, settle_s=0.25)
    rep = warn_replanned(builtin_machine(), cmd, text, Path("c.nc"), 0.25, "c.csv")
    err = " ".join(capsys.readouterr().err.split())
    assert rep["departure_m"] > 100e-6 and rep["share_beyond"] > 0.5
    said = re.search(r"c\.nc: a controller set as the model's interpolator \(trapezoid, 1 "
                     r"m/s\^2 on the path\) does not replay c\.csv: planned so, its command "
                     r"departs from the file's by up to ([\d.]+) µm at ([\d.]+) s \(line "
                     r"(\d+) of c\.nc", err)
    assert said, err
    assert float(said[1]) == pytest.approx(rep["departure_m"] * 1e6, abs=0.1)
    k = round((float(said[2]) - cmd.time_s[0]) / cmd.period_s)
    line = text.splitlines()[int(said[3]) - 1]  # the line written for that sample
    assert line.startswith("G1 X") and float(line.split()[1][1:]) == pytest.approx(
        cmd.positions["X"][k] * 1e3, abs=1e-6)
    assert "the figures after are c.csv's, not the program's" in err


def test_a_program_the_interpolator_replays_is_not_said(capsys):
    """A command well inside the interpolator's limits replays within the tolerance, and
    nothing is said."""
    from tcpmm.cli._compensate_dense import warn_replanned

    cmd = _slow_line()
    rep = warn_replanned(builtin_machine(), cmd, dense_program(cmd, settle_s=0.1),
                         Path("c.nc"), 0.1)
    assert rep["departure_m"] < REPLAY_TOL_M and rep["share_beyond"] == 0.0
    assert capsys.readouterr().err == ""


def test_the_dense_program_is_said_written_and_its_replay_is_in_the_json(tmp_path, capsys,
                                                                         monkeypatch):
    """--gcode-out wrote its program without a word on stdout. It says so, with whether a
    controller set as the model replays it, and --json carries the comparison."""
    monkeypatch.chdir(tmp_path)  # names short of the temporary folder's, as printed
    write_command_csv(_slow_line(), tmp_path / "line.csv")
    args = ["compensate", "builtin:vmc", "--command", "line.csv", "-o", "line_comp.csv",
            "--draws", "0", "--iterations", "2", "--gcode-out", "line_comp.nc"]
    assert main(args) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert "wrote line_comp.nc: line_comp.csv as a dense G1 program" in out
    assert "a controller set as the model's interpolator replays it within" in out
    assert main([*args, "--json"]) == 0
    said = json.loads(capsys.readouterr().out)["settings"]["gcode_out"]
    assert said["file"] == "line_comp.nc" and said["replay"]["tolerance_m"] == REPLAY_TOL_M
    assert said["replay"]["departure_m"] < REPLAY_TOL_M
