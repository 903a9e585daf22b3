"""Identification speed: seconds per axis of ``identify_bundle`` on measurement bundles.

Each bundle is read once, identified once as a warm-up (it fills the numba cache and the
imports), then ``--repeat`` times; per axis the minimum and the median wall time are
printed. An axis's time runs from the previous axis's end (the first: from the call, so it
includes the check of every friction record that ``identify_bundle`` does first).

Not a test: run ``.venv/bin/python benchmarks/identify.py`` (the bundles ``bench_c``,
``bench_d``, ``bench_e`` under ``--data``), or give bundle folders; ``--json`` prints the
times as JSON.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
import warnings
from pathlib import Path

from tcpmm.ident.pipeline import identify_bundle
from tcpmm.io.bundle import read_bundle

BENCHES = ("bench_c", "bench_d", "bench_e")


def axis_times(bundle) -> dict:
    """Wall time per axis of one identification [s]."""
    from tcpmm.ident.friction import nutrounding

    nutrounding.stretch_bias_std.cache_clear()  # each run as a first identification
    marks = []
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        identify_bundle(bundle, progress=lambda name: marks.append((name, time.perf_counter())))
    out, prev = {}, t0
    for name, t in marks:
        out[name], prev = t - prev, t
    return out


def bench(path: Path, repeat: int) -> dict:
    """Minimum and median seconds per axis over ``repeat`` runs after a warm-up [s]."""
    bundle = read_bundle(path)
    axis_times(bundle)  # warm-up
    runs = [axis_times(bundle) for _ in range(repeat)]
    return {name: {"min_s": min(r[name] for r in runs),
                   "median_s": statistics.median(r[name] for r in runs)}
            for name in runs[0]}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("bundles", nargs="*", type=Path, help="bundle folders")
    ap.add_argument("--data", type=Path, default=Path("/work/shared/data"),
                    help="folder holding bench_c/bundle, bench_d/bundle, bench_e/bundle")
    ap.add_argument("--repeat", type=int, default=3, help="timed runs after the warm-up")
    ap.add_argument("--json", action="store_true", help="print JSON")
    args = ap.parse_args(argv)
    paths = args.bundles or [args.data / b / "bundle" for b in BENCHES]
    result = {}
    for p in paths:
        if not p.is_dir():
            print(f"no bundle at {p}: skipped", file=sys.stderr)
            continue
        label = p.parent.name if p.name == "bundle" else p.name
        result[label] = bench(p, max(1, args.repeat))
    if args.json:
        print(json.dumps(result, indent=2))
        return
    print(f"{'bundle':10s} {'axis':5s} {'min [s]':>8s} {'median [s]':>11s}")
    for label, axes in result.items():
        for name, t in axes.items():
            print(f"{label:10s} {name:5s} {t['min_s']:8.2f} {t['median_s']:11.2f}")


if __name__ == "__main__":
    main()
