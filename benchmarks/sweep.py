"""Sweep throughput: N variants of the paper's circle (R35 mm, F5000, CCW and CW) on the
built-in machine, a Latin hypercube over the X and Y position gains, on the local cores.

Prints the time per variant in one process, the wall time of the sweep on a local Dask
cluster of one single-threaded worker per core (start-up apart, and with it), the
variants per second and the parallel efficiency, serial time per variant x N / (cores x
wall). Not a test: ``python benchmarks/sweep.py --n 500``; ``--json`` for the figures as
JSON.
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
import time

from tcpmm.builtin import builtin_machine
from tcpmm.sweep import CircleProgram, evaluate_variant, lhs_design, parse_param, run_sweep

SERIAL_SAMPLE = 20


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
    sample = variants[:min(SERIAL_SAMPLE, a.n)]
    t0 = time.perf_counter()
    for v in sample:
        evaluate_variant(m, program, v)
    per = (time.perf_counter() - t0) / len(sample)
    with tempfile.TemporaryDirectory() as out:
        t0 = time.perf_counter()
        with local_cluster(a.workers) as cluster, Client(cluster) as client:
            client.run(evaluate_variant, m, program, variants[0])  # load the kernels
            t1 = time.perf_counter()
            res = run_sweep(m, program, variants, out, client=client)
            t2 = time.perf_counter()
    wall, total = t2 - t1, t2 - t0
    fig = {"variants": a.n, "workers": a.workers, "cores": os.cpu_count(),
           "serial_s_per_variant": per, "wall_s": wall, "wall_with_startup_s": total,
           "variants_per_s": a.n / wall, "failed": len(res.failed),
           "efficiency": per * a.n / (a.workers * wall),
           "efficiency_with_startup": per * a.n / (a.workers * total)}
    if a.json:
        print(json.dumps(fig, indent=2))
    else:
        print(f"{a.n} variants of the paper's circle on {a.workers} workers "
              f"({fig['cores']} cores)")
        print(f"  serial: {per * 1e3:.1f} ms per variant")
        print(f"  sweep:  {wall:.1f} s ({total:.1f} s with the cluster's start-up), "
              f"{fig['variants_per_s']:.1f} variants/s")
        print(f"  parallel efficiency {fig['efficiency']:.2f} "
              f"({fig['efficiency_with_startup']:.2f} with start-up)")
    return fig


if __name__ == "__main__":
    main()
