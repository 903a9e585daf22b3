"""Sweep throughput: N variants of the paper's circle (R35 mm, F5000, CCW and CW) on the
built-in machine, a Latin hypercube over the X and Y position gains, on the local cores.

Prints the time per variant in one process pinned to one core (best of three), the wall
time of the sweep on a local Dask cluster of one single-threaded worker per core (start-up
apart, and with it), the variants per second and the parallel efficiency, serial time per
variant x N / (cores x wall). Not a test: ``python benchmarks/sweep.py --n 500``;
``--json`` for the figures as JSON.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import tempfile
import time

from tcpmm.builtin import builtin_machine
from tcpmm.sweep import CircleProgram, evaluate_variant, lhs_design, parse_param, run_sweep

SERIAL_SAMPLE = 100
#: Repeats of the serial sample; the fastest counts, as for every timing here.
SERIAL_REPEATS = 3


def _serial_time(m, program, sample) -> float:
    """Seconds per variant of ``sample`` evaluated one after another [s]."""
    t0 = time.perf_counter()
    for v in sample:
        evaluate_variant(m, program, v)
    return (time.perf_counter() - t0) / len(sample)


@contextlib.contextmanager
def one_core():
    """Pin this process to one core while the serial time is taken: the simulator runs
    the axes of a variant in threads, and a serial time on all cores would make the
    efficiency a lower bound. Yields the number of cores the serial time ran on (all of
    them where the platform cannot pin) [-]."""
    if not hasattr(os, "sched_setaffinity"):
        yield os.cpu_count() or 1
        return
    before = os.sched_getaffinity(0)
    os.sched_setaffinity(0, {min(before)})
    try:
        yield 1
    finally:
        os.sched_setaffinity(0, before)


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=10_000, help="variants [-]")
    ap.add_argument("--workers", type=int, default=os.cpu_count() or 1,
                    help="local worker processes [-]")
    ap.add_argument("--json", action="store_true", help="print the figures as JSON")
    a = ap.parse_args(argv)
    from distributed import Client

    from tcpmm.sweep import local_cluster

    m, program = builtin_machine(), CircleProgram()
    specs = [parse_param(t) for t in ("X.servo.K_pp=20:60", "Y.servo.K_pp=20:60")]
    variants = lhs_design(specs, a.n, seed=0)
    evaluate_variant(m, program, variants[0])  # compile and build the command
    sample = variants[::max(1, a.n // SERIAL_SAMPLE)][:SERIAL_SAMPLE]  # across the design
    with one_core() as serial_cores:
        per = min(_serial_time(m, program, sample) for _ in range(SERIAL_REPEATS))
    with tempfile.TemporaryDirectory() as out:
        t0 = time.perf_counter()
        with local_cluster(a.workers) as cluster, Client(cluster) as client:
            client.run(evaluate_variant, m, program, variants[0])  # load the kernels
            t1, c1 = time.perf_counter(), time.process_time()
            res = run_sweep(m, program, variants, out, client=client)
            t2, c2 = time.perf_counter(), time.process_time()
    wall, total = t2 - t1, t2 - t0
    fig = {"variants": a.n, "workers": a.workers, "cores": os.cpu_count(),
           "serial_cores": serial_cores, "serial_s_per_variant": per, "wall_s": wall,
           "wall_with_startup_s": total, "client_cpu_s": c2 - c1,
           "variants_per_s": a.n / wall, "failed": len(res.failed),
           "efficiency": per * a.n / (a.workers * wall),
           "efficiency_with_startup": per * a.n / (a.workers * total)}
    if a.json:
        print(json.dumps(fig, indent=2))
    else:
        print(f"{a.n} variants of the paper's circle on {a.workers} workers "
              f"({fig['cores']} cores)")
        print(f"  serial: {per * 1e3:.1f} ms per variant on {serial_cores} core(s)")
        print(f"  sweep:  {wall:.1f} s ({total:.1f} s with the cluster's start-up), "
              f"{fig['variants_per_s']:.1f} variants/s")
        print(f"  parallel efficiency {fig['efficiency']:.2f} "
              f"({fig['efficiency_with_startup']:.2f} with start-up)")
    return fig


if __name__ == "__main__":
    main()
