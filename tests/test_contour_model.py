"""The contour error of any program predicted with its 90 % interval (``tcpmm contour
--model``, :class:`tcpmm.uncertainty.ProgramTest`): judged on machines of the independent
simulator whose truth is known, and refused where the run is not the model's prediction."""

import json
import warnings

import pytest

from conftest import bench_path
from studies.program_intervals import PROGRAMS, rows_of
from tcpmm.cli import main
from tcpmm.ident.pipeline import identify_bundle
from tcpmm.io.bundle import read_bundle
from tcpmm.io.truthfile import machine_from_truth
from tcpmm.path import program_to_command
from tcpmm.sim.simulate import simulate
from tcpmm.uncertainty import ProgramTest, prediction_verdict, program_figures

#: a 40 mm square under G64 P0.01 at F5000, at rest at its end
SQUARE = "G21 G90 G17 G64 P0.01\nG1 X40 F5000\nY40\nX0\nY0\nG4 P0.3\nM30\n"


def _xy(machine):
    return machine.model_copy(update={"axes": {n: machine.axes[n] for n in ("X", "Y")}})


@pytest.mark.parametrize("letter", ["c", "d"])
def test_the_true_machines_contour_error_lies_in_the_predicted_interval(letter, once):
    """Machines C and D identified from their bundles predict the largest and RMS TCP
    contour error (3-200 um) of a square at F5000 and F10000 and of a spiral
    (docs/validation/program_intervals.md); run on their true parameters (``truth.yaml``)
    the figures lie within the intervals, and those called firm within their targets
    (1 % or 0.5 um). The intervals are the circles' calibration; the programs were none of
    the shapes it was made on."""
    def make():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return identify_bundle(read_bundle(bench_path(letter) / "bundle"), verdict=False)

    model = once(f"bench_{letter}", make).machine
    truth = _xy(machine_from_truth(bench_path(letter) / "truth.yaml"))
    rows = rows_of(letter, model, truth)
    assert len(rows) == 2 * len(PROGRAMS)
    for r in rows:
        assert r["inside"], r
        assert r["verdict"] != "firm" or r["within_target"], r


def test_a_program_test_judges_the_figures_of_its_own_run(vmc):
    """The figures of a :class:`ProgramTest` are those of the contour error measured on
    the model's run of its command, with the rapids left out as ``contour`` leaves them."""
    cmd = program_to_command("G21 G90 G17\nG0 X5 Y5\n" + SQUARE.split("\n", 1)[1])
    test = ProgramTest("square", cmd, ("X", "Y"))
    run = simulate(_xy(vmc), cmd)
    got = program_figures(run, test)
    from tcpmm.analysis.contour import contour_error

    want = contour_error(run, plane=("X", "Y")).summary()["tcp"]
    assert got == {("square", "path", "contour error"): want["max_abs_m"],
                   ("square", "path", "contour rms"): want["rms_m"]}
    with_rapids = program_figures(run, ProgramTest("square", cmd, ("X", "Y"), rapids=True))
    assert with_rapids[("square", "path", "contour rms")] != want["rms_m"]
    verdict = prediction_verdict(_xy(vmc), [test], "tcp")
    assert [(f.figure, f.nominal) for f in verdict.figures] == [
        ("contour error", want["max_abs_m"]), ("contour rms", want["rms_m"])]


@pytest.fixture(scope="module")
def square_run(tmp_path_factory):
    """The square simulated on the built-in machine, as a run file [-]."""
    folder = tmp_path_factory.mktemp("square")
    (folder / "sq.nc").write_text(SQUARE)
    assert main(["simulate", "builtin:vmc", "--gcode", str(folder / "sq.nc"),
                 "-o", str(folder / "run.csv")]) == 0
    return folder / "run.csv"


def test_cli_contour_with_the_model_gives_each_figure_its_interval(square_run, capsys):
    capsys.readouterr()
    assert main(["contour", str(square_run), "--model", "builtin:vmc", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    judged = {f["figure"]: f for f in d["tcp_verdict"]}
    assert set(judged) == {"contour error", "contour rms"}
    # the model's figures on the run's command read back from the file are the run's own
    assert judged["contour error"]["nominal_um"] == pytest.approx(
        d["sensors"]["tcp"]["max_abs_um"], rel=1e-4)
    assert judged["contour rms"]["nominal_um"] == pytest.approx(
        d["sensors"]["tcp"]["rms_um"], rel=1e-4)
    assert all(f["half_width_um"] > 0 for f in judged.values())
    assert main(["contour", str(square_run), "--model", "builtin:vmc"]) == 0
    cap = capsys.readouterr()
    text = cap.out
    # the built-in machine was never identified: its intervals are the floors alone
    assert "builtin:vmc carries no uncertainty of identification" in " ".join(cap.err.split())
    assert "tcp, 90 % interval over what identification leaves uncertain:" in text
    # one unit on the line: 'µm: firm (+- 0.78 um)' mixed the two spellings
    line = next(ln for ln in text.splitlines() if ln.strip().startswith("max |e| "))
    assert f"max |e| {judged['contour error']['nominal_um']:.2f} um: " in line
    assert "µ" not in line


def test_cli_contour_refuses_to_judge_what_the_model_did_not_predict(square_run, tmp_path,
                                                                     capsys):
    """Another model (a lower position gain on X) would have given the intervals of its
    own prediction to the built-in machine's run; a run without a TCP, a given command
    and a run streamed are refused as well, each saying why."""
    from tcpmm.io.modelfile import write_machine
    from tcpmm.machines.builtin import builtin_machine

    m = builtin_machine()
    x = m.axes["X"]
    write_machine(m.with_axis("X", x.replace(servo=x.servo.model_copy(
        update={"K_pp": 0.8 * x.servo.K_pp}))), tmp_path / "other.yaml")
    capsys.readouterr()
    assert main(["contour", str(square_run), "--model", str(tmp_path / "other.yaml")]) == 2
    assert "is not this model's prediction" in " ".join(capsys.readouterr().err.split())
    import pandas as pd

    table = pd.read_csv(square_run)
    table.drop(columns=[c for c in table if c.endswith("_tcp_mm")]).to_csv(
        tmp_path / "no_tcp.csv", index=False)
    assert main(["contour", str(tmp_path / "no_tcp.csv"), "--model", "builtin:vmc"]) == 2
    assert "the run has no tcp signals" in " ".join(capsys.readouterr().err.split())
    assert main(["contour", str(square_run), "--model", "builtin:vmc", "--command",
                 str(square_run)]) == 2
    assert "leave out --command" in " ".join(capsys.readouterr().err.split())
    table.to_parquet(tmp_path / "run.parquet")
    assert main(["contour", str(tmp_path / "run.parquet"), "--model", "builtin:vmc",
                 "--chunk-rows", "500"]) == 2
    assert "--model takes a run read whole" in " ".join(capsys.readouterr().err.split())


@pytest.mark.parametrize("period_s", ["0.005", "0.05"])
def test_cli_contour_refuses_a_run_recorded_coarser_than_its_command(square_run, tmp_path,
                                                                    capsys, period_s):
    """The model's own run of the square recorded every 50 ms was refused as another
    model's, and every 5 ms gave intervals about figures other than the table's: the
    command it is run again on is then the run's coarse samples of it."""
    run = tmp_path / "coarse.csv"
    assert main(["simulate", "builtin:vmc", "--gcode", str(square_run.parent / "sq.nc"),
                 "-o", str(run), "--record-period-s", period_s]) == 0
    capsys.readouterr()
    assert main(["contour", str(run), "--model", "builtin:vmc"]) == 2
    err = " ".join(capsys.readouterr().err.split())
    assert f"is recorded every {float(period_s) * 1e3:.4g} ms" in err
    assert "without --record-period-s" in err and "not this model's prediction" not in err


def test_cli_contour_judges_the_run_of_a_command_file_at_its_own_period(tmp_path, capsys):
    """A command file every 2 ms is run and recorded at its own period: the run holds the
    whole command, and is judged (it was refused as a run recorded coarsely)."""
    from tcpmm.path import write_command_csv
    from tcpmm.path.circle import circle_command
    from tcpmm.path.command import Command

    c = circle_command(0.01, 3000.0 / 6e4, turns=1.0)
    write_command_csv(Command(c.time_s[::2], {a: p[::2] for a, p in c.positions.items()}),
                      cmd := tmp_path / "cmd2ms.csv")
    run = tmp_path / "run.csv"
    assert main(["simulate", "builtin:vmc", "--command", str(cmd), "-o", str(run)]) == 0
    capsys.readouterr()
    assert main(["contour", str(run), "--model", "builtin:vmc", "--json"]) == 0, \
        capsys.readouterr().err
    assert {f["figure"] for f in json.loads(capsys.readouterr().out)["tcp_verdict"]} == {
        "contour error", "contour rms"}


def test_the_verdict_counts_its_runs_on_a_bar(square_run, tmp_path, monkeypatch, capsys):
    """Each uncertain quantity runs the whole program again at both ends of its range: the
    bar is told how many runs and advanced once by each."""
    from contextlib import contextmanager

    from tcpmm.cli import _contour_model
    from tcpmm.io.modelfile import write_machine
    from tcpmm.machines.builtin import builtin_machine
    from tcpmm.model import AxisUncertainty

    m = builtin_machine()
    x = m.axes["X"]
    write_machine(m.with_axis("X", x.replace(uncertainty=AxisUncertainty(
        mechanics={"M_t": 0.02 * x.mechanics.M_t, "K_t": 0.05 * x.mechanics.K_t}))),
        tmp_path / "m.yaml")
    seen = {}

    @contextmanager
    def bar(total, description):
        seen.update(total=total, done=0)

        def advance(*_):
            seen["done"] += 1

        yield advance

    monkeypatch.setattr(_contour_model, "progress_bar", bar)
    (tmp_path / "sq.nc").write_text(SQUARE)
    assert main(["simulate", str(tmp_path / "m.yaml"), "--gcode", str(tmp_path / "sq.nc"),
                 "-o", str(tmp_path / "run.csv")]) == 0
    capsys.readouterr()
    assert main(["contour", str(tmp_path / "run.csv"), "--model", str(tmp_path / "m.yaml")]) == 0
    assert seen == {"total": 4, "done": 4}  # two quantities, each at both ends
    assert "carries no uncertainty" not in capsys.readouterr().err
