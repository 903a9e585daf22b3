"""Runs and sweeps meeting faults: a full disk under a sweep, an axis that runs away from
its command or saturates its current, an unstable model; each said, none taken for a
result."""

import errno
import json

import pytest

from tcpmm.cli import main
from tcpmm.whatif.sweep import read_results

ARGS = ["sweep", "builtin:vmc", "-p", "X.servo.position_gain=30,40", "--circle", "5,4000",
        "--workers", "1", "--json"]


def test_a_run_that_cannot_be_written_fails_its_variant_and_is_retried(tmp_path,
                                                                      monkeypatch, capsys):
    from tcpmm.io import runwrite

    write = runwrite.write_run_csv

    def full(run, path):
        raise OSError(errno.ENOSPC, "No space left on device")

    args = [*ARGS, "-o", str(tmp_path / "o"), "--keep-runs", str(tmp_path / "runs")]
    monkeypatch.setattr(runwrite, "write_run_csv", full)
    assert main(args) != 0
    got = json.loads(capsys.readouterr().out)
    assert (got["computed"], len(got["failed"])) == (0, 2)
    assert "No space left on device" in got["failed"][0]["reason"]
    assert len(read_results(tmp_path / "o")) == 0
    monkeypatch.setattr(runwrite, "write_run_csv", write)
    assert main(args) == 0
    got = json.loads(capsys.readouterr().out)
    assert (got["computed"], got["reused"], got["failed"]) == (2, 0, [])
    assert len(list((tmp_path / "runs").glob("*.csv"))) == 2
    assert read_results(tmp_path / "o")["spike_max_um"].notna().all()


def test_a_row_whose_run_file_is_gone_is_computed_again(tmp_path, capsys):
    args = [*ARGS, "-o", str(tmp_path / "o"), "--keep-runs", str(tmp_path / "runs")]
    assert main(args) == 0
    capsys.readouterr()
    next((tmp_path / "runs").glob("*.csv")).unlink()
    assert main(args) == 0
    got = json.loads(capsys.readouterr().out)
    assert (got["computed"], got["reused"]) == (1, 1)


def _runaway(vmc, force_n=-20000.0):
    """The machine with a load on Z its drive cannot hold [N]."""
    z = vmc.axes["Z"]
    return vmc.with_axis("Z", z.replace(mechanics=z.mechanics.model_copy(
        update={"load_force": force_n})))


def test_a_runaway_axis_is_said_in_the_run_and_on_stderr(vmc, capsys):
    import warnings

    from tcpmm.errors import RunFaultWarning
    from tcpmm.sim.simulate import simulate
    from tcpmm.whatif.sweep.task import _circle_command

    cmd = _circle_command(5e-3, 0.1)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ok = simulate(vmc, cmd)
        run = simulate(_runaway(vmc), cmd)
    said = [str(w.message) for w in caught if issubclass(w.category, RunFaultWarning)]
    assert ok.to_dict()["faults"] == [] and len(said) == 1
    assert said[0].startswith("axis Z: leaves the command from t = ")
    fault = run.to_dict()["faults"][0]
    assert fault["axis"] == "Z" and fault["deviation_m"] > 0.1 and fault["saturated_s"] > 0.1


def test_a_saturating_axis_is_said(vmc):
    from tcpmm.analysis.runaway import run_faults
    from tcpmm.errors import RunFaultWarning
    from tcpmm.sim.simulate import simulate
    from tcpmm.whatif.sweep.task import _circle_command

    x = vmc.axes["X"]
    weak = vmc.with_axis("X", x.replace(servo=x.servo.model_copy(update={"current_limit": 0.5})))
    with pytest.warns(RunFaultWarning, match="axis X: holds its current"):
        faults = run_faults(weak, simulate(weak, _circle_command(5e-3, 0.1)))
    assert [f.axis for f in faults][:1] == ["X"] and faults[0].saturated_from_s is not None
    assert "holds its current at the limit of 0.5 A" in faults[0].text()


def test_a_sweep_says_its_runaway_variants(tmp_path, capsys):
    args = ["sweep", "builtin:vmc", "-p", "Z.mechanics.load_force=-2000,-20000",
            "--circle", "5,4000", "--workers", "1", "-o", str(tmp_path / "o")]
    assert main(args) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "axis Z: leaves the command" in err[0]
    summary = read_results(tmp_path / "o").set_index("Z.mechanics.load_force")
    assert summary.loc[-20000.0, "fault"].startswith("axis Z: leaves the command")
    assert summary.loc[-2000.0, "fault"] == ""


def test_bode_and_sweep_warn_of_an_unstable_model(tmp_path, capsys):
    from tcpmm.io.modelfile import write_machine
    from tcpmm.machines.builtin import builtin_machine

    vmc = builtin_machine("vmc")
    x = vmc.axes["X"]
    bad = vmc.with_axis("X", x.replace(servo=x.servo.model_copy(update={"K_vp": 50.0})))
    write_machine(bad, tmp_path / "m.yaml")
    assert main(["bode", str(tmp_path / "m.yaml"), "--axis", "X", "--tf", "cmd_to_tcp",
                 "--freq-hz", "10"]) == 0
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "axis X of model" in err and "unstable" in err


def test_the_report_says_a_runaway_run(vmc, tmp_path, capsys):
    from tcpmm.io.modelfile import write_machine
    from tcpmm.sim.simulate import simulate
    from tcpmm.whatif.sweep.task import _circle_command

    bad = _runaway(vmc)
    write_machine(bad, tmp_path / "m.yaml")
    with pytest.warns(Warning):
        simulate(bad, _circle_command(5e-3, 0.1)).write(tmp_path / "run.csv")
    assert main(["report", "-o", str(tmp_path / "r.html"), "--model", str(tmp_path / "m.yaml"),
                 "--run", str(tmp_path / "run.csv"), "--radius", "5"]) == 0
    err = capsys.readouterr().err
    assert "run.csv: axis Z: leaves the command" in err
    page = (tmp_path / "r.html").read_text(encoding="utf-8")
    assert "Runaway and saturation" in page and "axis Z: leaves the command" in page


def test_a_lost_scheduler_is_one_line_and_a_rerun_resumes(tmp_path, monkeypatch, capsys):
    import contextlib
    import logging
    import time

    from distributed import Client, LocalCluster

    from tcpmm.cli import sweep as sweep_cli

    cluster = LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                           dashboard_address=":0", silence_logs=logging.ERROR)
    client = Client(cluster, timeout="1s")  # its reconnection gives up at once
    monkeypatch.setattr(sweep_cli, "_client", lambda address: client)

    @contextlib.contextmanager
    def stopping(description):  # the scheduler stops after the second variant
        yield lambda done, total: done == 2 and cluster.sync(cluster.scheduler.close)

    monkeypatch.setattr(sweep_cli, "_bar", stopping)
    args = ["sweep", "builtin:vmc", "-p", "X.servo.position_gain=20:40:1", "--circle",
            "5,4000", "-o", str(tmp_path / "o"), "--scheduler", "tcp://example:8786"]
    t0 = time.monotonic()
    try:
        assert main(args) == 2
        assert time.monotonic() - t0 < 20
    finally:
        with contextlib.suppress(Exception):
            client.close(timeout=1)
            cluster.close(timeout=1)
    cap = capsys.readouterr()
    err = cap.err.strip().splitlines()
    assert len(err) == 1 and "the Dask scheduler at " in err[0] and "rerun to resume" in err[0]
    assert "failed" not in cap.out
    kept = len(read_results(tmp_path / "o"))
    assert 2 <= kept < 21
