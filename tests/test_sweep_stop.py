"""A sweep stopped (Ctrl-C) while tasks run on workers keeps the rows of the tasks the
workers finish, as the command says."""

import os
import signal
import threading
import time

import pytest

from tcpmm.whatif.sweep import Variant
from tcpmm.whatif.sweep.run import _on_client


def _slow(machine, program, variant, *rest):
    """A variant of 50 ms [-]."""
    time.sleep(0.05)
    return {"x": float(variant.values[0][1])}


def test_rows_of_the_tasks_under_way_at_a_stop_are_kept():
    """Stopped with tasks on the workers, the sweep dropped their rows although their
    variants were computed (and their run files written) and it said them kept."""
    from distributed import Client, LocalCluster

    todo = [Variant((("X.servo.K_pp", float(k)),)) for k in range(40)]
    got = []
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                      dashboard_address=":0") as cluster, Client(cluster) as client:
        client.submit(time.sleep, 0).result()  # the workers up before the clock starts
        stop = threading.Timer(0.25, os.kill, (os.getpid(), signal.SIGINT))
        stop.start()
        with pytest.raises(KeyboardInterrupt):  # four chunks of 0.5 s: none done by then
            _on_client(client, _slow, lambda v: (None, None, v), todo,
                       lambda v, r: got.append(r))
        stop.join()
    assert len(got) == 40 and all(r is not None for r in got)
