"""What a sweep on a Dask cluster says when the cluster is not what it should be."""

import socket
import threading
import time

import pytest

from conftest import run_cli


def test_an_address_that_takes_the_connection_but_answers_nothing_is_said(capsys, tmp_path,
                                                                          monkeypatch):
    """The dashboard's port given for the scheduler's (or any port that takes connections
    and says nothing) kept the sweep waiting with no word until it was killed."""
    import tcpmm.cli.sweep as sweep

    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(4)
    held = []
    threading.Thread(target=lambda: held.extend(server.accept() for _ in range(4)),
                     daemon=True).start()
    monkeypatch.setattr(sweep, "ANSWER_S", 2.0)
    t0 = time.perf_counter()
    code, _, err = run_cli(capsys, "sweep", "builtin:vmc", "-p", "X.servo.position_gain=30",
                           "-o", tmp_path / "o", "--scheduler",
                           f"tcp://127.0.0.1:{server.getsockname()[1]}")
    assert code == 2 and time.perf_counter() - t0 < 10.0
    assert "no Dask scheduler answered in 2 s" in " ".join(err.split())
    assert not (tmp_path / "o").exists()
    server.close()


def test_a_scheduler_lost_in_a_study_of_programs_is_not_said_to_resume():
    from tcpmm.whatif.sweep.cluster import SchedulerLost

    assert "rerun to resume" in str(SchedulerLost(None))
    said = str(SchedulerLost(None, resumed=False))
    assert "is not resumed" in said and "kept" not in said


def test_two_studies_of_programs_into_one_folder_at_once_are_refused(tmp_path):
    """The second study ran beside the first, and the table of the one written last
    replaced the other's with no word."""
    from tcpmm.errors import InputError
    from tcpmm.whatif.sweep.programs import run_programs
    from tcpmm.whatif.sweep.store import writing

    with writing(tmp_path), pytest.raises(InputError, match="another sweep is writing"):
        run_programs({}, [], tmp_path, workers=1)


def test_a_program_a_worker_cannot_read_is_said_of_the_worker(tmp_path):
    """A worker that could not read a program (started elsewhere, or without the shared
    folder) said "NC program not found; check the path" of a path that is right on the
    command's machine. Outside a worker, the reader's own message stands."""
    from distributed import Client, LocalCluster

    from tcpmm.machines.builtin import builtin_machine
    from tcpmm.whatif.sweep.programs import program_task

    gone = str(tmp_path / "gone.nc")
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                      dashboard_address=":0") as cluster, Client(cluster) as client:
        row = client.submit(program_task, "m", builtin_machine("vmc"), gone, 1000).result()
    assert row["status"] == "failed"
    assert "Dask worker at" in row["error"] and "cannot read" in row["error"]
    here = program_task("m", builtin_machine("vmc"), gone, 1000)
    assert "Dask worker" not in here["error"] and "not found" in here["error"]
