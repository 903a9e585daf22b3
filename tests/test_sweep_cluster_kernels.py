"""A sweep on a Dask cluster says which workers run other BLAS kernels or numpy loops than
the command: ``dask worker`` loads numpy before tcpmm, so a worker started without the
variables of docs/sweep.md runs the kernels its CPU chose, and its figures differ from a
local run's in their last digits."""

import logging
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

import pytest

import tcpmm
from conftest import run_cli

pytestmark = pytest.mark.skipif(
    platform.machine() != "x86_64" or not sys.platform.startswith("linux"),
    reason="OpenBLAS's core types (OPENBLAS_CORETYPE) are x86-64's")


@pytest.fixture(scope="module")
def scheduler():
    """A real scheduler on 127.0.0.1 with no worker of its own; the tests start
    ``dask worker`` processes on it, as a user does."""
    from distributed import Client, LocalCluster

    with LocalCluster(n_workers=0, protocol="tcp://", host="127.0.0.1",
                      dashboard_address="127.0.0.1:0", silence_logs=logging.ERROR) as cluster, \
            Client(cluster) as client:
        started = []
        yield cluster.scheduler_address, client, started
        for proc in started:
            proc.terminate()
            proc.wait(30)


def _start_worker(scheduler, name: str, **environ) -> str:
    """Start ``dask worker`` (which loads numpy before tcpmm) with this process's
    environment and ``environ``; its address [-]."""
    address, client, started = scheduler
    env = {**os.environ, **environ,
           "PYTHONPATH": os.pathsep.join([str(Path(tcpmm.__file__).parents[1]),
                                          str(Path(__file__).parent)])}
    started.append(subprocess.Popen(
        [sys.executable, "-m", "distributed.cli.dask_worker", address, "--name", name,
         "--nthreads", "1", "--no-nanny", "--host", "127.0.0.1", "--no-dashboard"],
        env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline:
        for w, info in client.scheduler_info(n_workers=-1)["workers"].items():
            if info.get("name") == name:
                return w
        time.sleep(0.2)
    raise AssertionError(f"the worker {name} did not start")


def _sweep(scheduler, tmp_path, capsys) -> str:
    code, _, err = run_cli(capsys, "sweep", "builtin:vmc", "-p", "X.servo.position_gain=30",
                           "-o", tmp_path, "--scheduler", scheduler[0])
    assert code == 0, err
    return " ".join(err.split())


def test_workers_that_run_other_kernels_are_named_with_the_fix(scheduler, tmp_path, capsys):
    """A worker with the command's environment is not warned of; one that OpenBLAS runs
    with other kernels (Sandybridge's, where the command's are Haswell's) is named, with
    what it runs and the variables that fix it, and the sweep still runs."""
    same = _start_worker(scheduler, "same")
    assert "warning" not in _sweep(scheduler, tmp_path / "a", capsys)
    other = _start_worker(scheduler, "other", OPENBLAS_CORETYPE="Sandybridge")
    err = _sweep(scheduler, tmp_path / "b", capsys)
    assert err.count("warning:") == 1
    assert f"Dask workers {other} (openblas Sandybridge" in err
    assert same not in err
    assert "may differ from a local run's in their last digits" in err
    assert "OPENBLAS_CORETYPE=Haswell" in err and "docs/sweep.md" in err


class _Client:
    """A client whose workers say ``said`` (an exception for one that could not), and
    whose scheduler knows the workers ``silent`` too [-]."""

    def __init__(self, said, silent=()):
        self.said, self.silent = said, silent

    def run(self, function, on_error="raise"):
        return self.said

    def scheduler_info(self):
        return {"workers": {w: {} for w in [*self.said, *self.silent]}}


def test_a_worker_that_cannot_say_is_named_as_unknown_and_the_rest_counted():
    """Four workers that differ: the first three are named, the rest counted; a worker
    whose answer is an error, or that the scheduler knows but did not answer, is
    unknown."""
    from tcpmm._blas_kernels import kernels
    from tcpmm.whatif.sweep.cluster import differing_kernels

    here = kernels()
    said = {"tcp://10.0.0.1:1": here, "tcp://10.0.0.2:1": RuntimeError("no tcpmm"),
            "tcp://10.0.0.3:1": [["openblas SkylakeX"], ["X86_V4"]],
            "tcp://10.0.0.4:1": (("openblas Zen",), ()), "tcp://10.0.0.5:1": ((), ())}
    text = differing_kernels(_Client(said, ["tcp://10.0.0.9:1"]), 1.0)
    assert "10.0.0.1" not in text
    assert "tcp://10.0.0.2:1 (unknown" in text
    assert "tcp://10.0.0.3:1 (openblas SkylakeX, numpy's loops with AVX-512 (X86_V4))" in text
    assert "and 2 more" in text
    assert differing_kernels(_Client({"tcp://10.0.0.1:1": here}), 1.0) is None
    assert "tcp://10.0.0.9:1 (unknown" in differing_kernels(
        _Client({"tcp://10.0.0.1:1": here}, ["tcp://10.0.0.9:1"]), 1.0)
