"""A sweep stopped (Ctrl-C) while tasks run on workers keeps the rows of the tasks the
workers finish, as the command says."""

import time

import pytest

from tcpmm.whatif.sweep import Variant
from tcpmm.whatif.sweep.run import _on_client


def _slow(machine, program, variant, *rest):
    """A variant of 50 ms [-]."""
    time.sleep(0.05)
    return {"x": float(variant.values[0][1])}


def test_rows_of_the_tasks_under_way_at_a_stop_are_kept():
    """Stopped (a Ctrl-C, raised here as the first row is taken, so that the stop falls
    while the other chunks run on the workers whatever the machine's load), the sweep
    dropped the rows of the chunks under way although their variants were computed (and
    their run files written) and it said them kept."""
    from distributed import Client, LocalCluster

    todo = [Variant((("X.servo.K_pp", float(k)),)) for k in range(40)]
    got = []

    def sink(variant, row):
        got.append(row)
        if len(got) == 1:
            raise KeyboardInterrupt

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                      dashboard_address=":0") as cluster, Client(cluster) as client:
        with pytest.raises(KeyboardInterrupt):
            _on_client(client, _slow, lambda v: (None, None, v), todo, sink)
    # the rest of the chunk being taken at the stop is lost; the chunks on the workers not
    assert len(got) > 10 and all(r is not None for r in got), len(got)
