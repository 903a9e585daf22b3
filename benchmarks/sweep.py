"""Sweep throughput: N variants of the paper's circle (R35 mm, F5000, CCW and CW) on the
built-in machine, a Latin hypercube over the X and Y position gains, on the local cores.

The machine's speed drifts from minute to minute on a shared host (the time per variant
alone has moved by 15-25 % between runs a minute apart), so the serial time and the sweep
are taken in turn: the design is swept in ``--rounds`` blocks on one local Dask cluster
of one single-threaded worker per core, and before every block and after the last one
a sample of the design runs in this process pinned to one core. A block's serial time
is the mean of the samples on either side of it. Prints the variants per second, the
parallel efficiency (serial time per variant x variants / (workers x wall), summed over
the blocks), the share of the wall time the workers spent computing variants (Dask's
task stream) and the CPU time of this process (scheduler, rows, files). Not a test:
``python benchmarks/sweep.py --n 500``; ``--json`` for the figures as JSON.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import statistics
import tempfile
import time

from tcpmm._heap import keep_freed_memory
from tcpmm.machines.builtin import builtin_machine
from tcpmm.whatif.sweep import CircleProgram, evaluate_variant, lhs_design, parse_param, run_sweep

#: Variants of a serial sample, spread over the design.
SERIAL_SAMPLE = 60


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


def _busy_s(stream) -> float:
    """Seconds the workers spent computing, from Dask's task stream [s]."""
    return sum(s["stop"] - s["start"] for task in stream for s in task["startstops"]
               if s["action"] == "compute")


def _blocks(client, m, program, variants, rounds, serial):
    """Sweep ``variants`` in ``rounds`` blocks with a serial sample before each block and
    after the last; per block: variants, serial time per variant, wall, workers' busy
    time and this process's CPU time while it ran [-, s]."""
    from distributed import get_task_stream

    size = -(-len(variants) // rounds)
    sample = variants[::max(1, len(variants) // SERIAL_SAMPLE)][:SERIAL_SAMPLE]
    before, out = serial(sample), []
    for k in range(0, len(variants), size):
        block = variants[k:k + size]
        with tempfile.TemporaryDirectory() as folder, get_task_stream(client) as ts:
            t0, c0 = time.perf_counter(), time.process_time()
            res = run_sweep(m, program, block, folder, client=client)
            wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        after = serial(sample)
        out.append({"variants": len(block), "serial_s": (before + after) / 2, "wall_s": wall,
                    "busy_s": _busy_s(ts.data), "cpu_s": cpu, "failed": len(res.failed)})
        before = after
    return out


def _figures(blocks, workers, startup_s, serial_cores) -> dict:
    n = sum(b["variants"] for b in blocks)
    wall = sum(b["wall_s"] for b in blocks)
    work = sum(b["serial_s"] * b["variants"] for b in blocks)
    effs = [b["serial_s"] * b["variants"] / (workers * b["wall_s"]) for b in blocks]
    return {"variants": n, "workers": workers, "cores": os.cpu_count(),
            "serial_cores": serial_cores, "rounds": len(blocks),
            "serial_s_per_variant": work / n,
            "serial_s_per_variant_range": [min(b["serial_s"] for b in blocks),
                                           max(b["serial_s"] for b in blocks)],
            "wall_s": wall, "startup_s": startup_s,
            "client_cpu_s": sum(b["cpu_s"] for b in blocks),
            "variants_per_s": n / wall, "failed": sum(b["failed"] for b in blocks),
            "efficiency": work / (workers * wall),
            "efficiency_min_median_of_rounds": [min(effs), statistics.median(effs)],
            "efficiency_with_startup": work / (workers * (wall + startup_s)),
            "workers_busy": sum(b["busy_s"] for b in blocks) / (workers * wall)}


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=10_000, help="variants [-]")
    ap.add_argument("--rounds", type=int, default=5,
                    help="blocks of the design, each between two serial samples [-]")
    ap.add_argument("--workers", type=int, default=os.cpu_count() or 1,
                    help="local worker processes [-]")
    ap.add_argument("--json", action="store_true", help="print the figures as JSON")
    a = ap.parse_args(argv)
    from distributed import Client

    from tcpmm.whatif.sweep import local_cluster

    m, program = builtin_machine(), CircleProgram()
    specs = [parse_param(t) for t in ("X.servo.K_pp=20:60", "Y.servo.K_pp=20:60")]
    variants = lhs_design(specs, a.n, seed=0)
    keep_freed_memory()  # as the sweep's workers do: the serial time with the same heap
    evaluate_variant(m, program, variants[0])  # compile and build the command
    cores = []

    def serial(sample):
        with one_core() as n_cores:
            cores.append(n_cores)
            return _serial_time(m, program, sample)

    t0 = time.perf_counter()
    with local_cluster(a.workers) as cluster, Client(cluster) as client:
        client.run(evaluate_variant, m, program, variants[0])  # load the kernels
        startup = time.perf_counter() - t0
        blocks = _blocks(client, m, program, variants, max(1, a.rounds), serial)
    fig = _figures(blocks, a.workers, startup, max(cores))
    if a.json:
        print(json.dumps(fig, indent=2))
    else:
        _print(fig)
    return fig


def _print(fig) -> None:
    lo, hi = fig["serial_s_per_variant_range"]
    print(f"{fig['variants']} variants of the paper's circle on {fig['workers']} workers "
          f"({fig['cores']} cores), in {fig['rounds']} rounds")
    print(f"  serial: {fig['serial_s_per_variant'] * 1e3:.1f} ms per variant on "
          f"{fig['serial_cores']} core(s) (rounds {lo * 1e3:.1f}-{hi * 1e3:.1f} ms)")
    print(f"  sweep:  {fig['wall_s']:.1f} s (+{fig['startup_s']:.1f} s the cluster's "
          f"start-up), {fig['variants_per_s']:.1f} variants/s; workers computing "
          f"{fig['workers_busy']:.0%} of the time; this process {fig['client_cpu_s']:.1f} s CPU")
    emin, emed = fig["efficiency_min_median_of_rounds"]
    print(f"  parallel efficiency {fig['efficiency']:.2f} (rounds: min {emin:.2f}, median "
          f"{emed:.2f}; {fig['efficiency_with_startup']:.2f} with start-up)")


if __name__ == "__main__":
    main()
