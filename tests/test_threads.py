"""BLAS on one thread: set before numpy loads where the command line starts, else limited
through threadpoolctl; either way every BLAS pool the process has runs one thread."""

import json
import os
import subprocess
import sys

CHECK = """
import json, sys
import tcpmm.cli
from tcpmm._threads import limit_blas_threads
import numpy as np
np.ones((64, 64)) @ np.ones((64, 64))
limited = limit_blas_threads()
loaded = "threadpoolctl" in sys.modules
from threadpoolctl import threadpool_info
print(json.dumps({"limiter": limited is not None, "threadpoolctl_before": loaded,
                  "threads": sorted({p["num_threads"] for p in threadpool_info()})}))
"""


def run(env_extra):
    env = {k: v for k, v in os.environ.items()
           if k not in ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "BLIS_NUM_THREADS",
                        "VECLIB_MAXIMUM_THREADS", "OMP_NUM_THREADS")}
    out = subprocess.run([sys.executable, "-c", CHECK], env={**env, **env_extra},
                         capture_output=True, text=True, check=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def test_the_command_line_starts_blas_on_one_thread():
    got = run({})
    assert got["threads"] == [1]
    assert not got["limiter"] and not got["threadpoolctl_before"]


def test_a_thread_count_of_the_users_is_kept_and_limited_afterwards():
    got = run({"OPENBLAS_NUM_THREADS": "2"})
    assert got["limiter"] and got["threadpoolctl_before"]
    assert got["threads"] == [1]


def test_the_axes_run_on_the_cores_the_process_may_use(monkeypatch):
    """A process confined to one core (a container's CPU set, taskset) runs the axes one
    after the other, however many cores the machine has."""
    from tcpmm import builtin_machine, paper_circle_command, simulate
    from tcpmm._threads import os as threads_os
    from tcpmm.sim import simulate as sim_module

    def no_pool(*args, **kwargs):
        raise AssertionError("a thread pool on one usable core")

    monkeypatch.setattr(threads_os, "sched_getaffinity", lambda pid: {0}, raising=False)
    monkeypatch.setattr(threads_os, "cpu_count", lambda: 64)
    monkeypatch.setattr(sim_module, "ThreadPoolExecutor", no_pool)
    run = simulate(builtin_machine(), paper_circle_command())
    assert set(run.axes) == {"X", "Y", "Z"}


def _items(n, fail_at=None):
    for i in range(n):
        if i == fail_at:
            raise ValueError(f"bad item {i}")
        yield i


def test_reading_ahead_gives_every_item_in_order():
    from tcpmm._threads import read_ahead

    assert list(read_ahead(_items(50))) == list(range(50))
    assert list(read_ahead(_items(0))) == []


def test_an_error_read_ahead_comes_where_its_item_would_have():
    import pytest

    from tcpmm._threads import read_ahead

    got = []
    with pytest.raises(ValueError, match="bad item 7"):
        for i in read_ahead(_items(20, fail_at=7)):
            got.append(i)
    assert got == list(range(7))


def test_reading_ahead_given_up_early_ends_its_thread():
    import threading

    from tcpmm._threads import read_ahead

    before = threading.active_count()
    it = read_ahead(_items(1000))
    assert [next(it) for _ in range(3)] == [0, 1, 2]
    it.close()
    assert threading.active_count() == before
