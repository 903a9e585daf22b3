"""Benchmark: the diagnostics of a CCW and a CW circle, and their cyclic-error scan.

Circles as a ballbar records them, at 1 kHz with every error of the suite's circles at
once (``tests/test_circle_diagnostics.draw``, seed 100, without spikes): R 35 mm at F5000
(2 600 samples a turn), the suite's R 35 mm over 7.2 s (7 200), a ballbar's standard R
100 mm at F1000 (37 700) and R 150 mm at F500 (113 000). For each: the wall time of
``diagnose_pair`` (min of ``--runs``), and the scan's grid of wavenumbers over the first
fit's residual, by the non-uniform FFT the scan uses (``circle_cyclic._grid_power``) and,
as its peer in the same run, by the products of every sample with every wavenumber
(``circle_cyclic._power_of``), with their ratio and the largest difference between the
two relative to the grid's largest power.

Run: ``.venv/bin/python benchmarks/circle.py [--runs 3] [--json]``
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

from tcpmm._threads import limit_blas_threads
from tcpmm.analysis import circle_cyclic as cc
from tcpmm.analysis.diagnostics import diagnose_pair

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
import test_circle_diagnostics as gen

#: (name, radius [m], feed [mm/min])
CASES = (("R 35 mm F5000", 0.035, 5000.0), ("R 35 mm, 7.2 s a turn", 0.035, 1832.6),
         ("R 100 mm F1000", 0.1, 1000.0), ("R 150 mm F500", 0.15, 500.0))


def _pair(radius, feed_mm_per_min):
    """A CCW and a CW circle with every error at once, and their angular speed [rad/s]."""
    gen.R = radius
    w = feed_mm_per_min / 60000.0 / radius
    n = round(2 * np.pi / (w * gen.DT))
    err = {k: v for k, v in gen.draw(np.random.default_rng(100)).items() if k != "spikes"}
    return gen.circle("ccw", err, 1, n=n), gen.circle("cw", err, 2, n=n), w, n


def _best(fn, runs):
    """The least wall time of ``runs`` calls of ``fn`` and its last result [s]."""
    times, out = [], None
    for _ in range(runs):
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    return min(times), out


def _grids(ccw, cw, radius, w, runs):
    """The scan's first grid (the stronger axis', over the fit without cyclic errors) by
    the FFT and by the products: its size, times [s] and the largest difference relative
    to the largest power [-]."""
    seen, grid = [], cc._grid_power

    def keep(*args):
        seen.append(args)
        return grid(*args)

    cc._grid_power = keep
    try:
        diagnose_pair(ccw, cw, radius, (w, w))
    finally:
        cc._grid_power = grid
    pos, wt, res, basis, ks = seen[0][:5]  # and the weighted columns, worked out again
    power = cc._power_of(pos, wt, res, basis)
    t_fft, fast = _best(lambda: grid(pos, wt, res, basis, ks), runs)
    t_sum, slow = _best(lambda: np.concatenate(
        [power(ks[j:j + 64]) for j in range(0, ks.size, 64)]), runs)
    return ks.size, t_fft, t_sum, float(np.max(np.abs(fast - slow)) / np.max(slow))


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args(argv)
    rows = []
    with limit_blas_threads():
        for name, radius, feed in CASES:
            ccw, cw, w, n = _pair(radius, feed)
            t_diag, _ = _best(lambda a=ccw, b=cw, r=radius, w=w: diagnose_pair(a, b, r, (w, w)),
                              args.runs)
            count, t_fft, t_sum, diff = _grids(ccw, cw, radius, w, args.runs)
            rows.append({"case": name, "samples_a_turn": n, "diagnose_pair_s": t_diag,
                         "wavenumbers": count, "grid_fft_s": t_fft, "grid_products_s": t_sum,
                         "ratio": t_sum / t_fft, "largest_difference": diff})
    if args.json:
        print(json.dumps(rows, indent=2))
        return
    print("| case | samples a turn | diagnose_pair [s] | wavenumbers | grid by FFT [s] "
          "| grid by products [s] | ratio | largest difference |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        print(f"| {r['case']} | {r['samples_a_turn']} | {r['diagnose_pair_s']:.2f} | "
              f"{r['wavenumbers']} | {r['grid_fft_s']:.3f} | {r['grid_products_s']:.3f} | "
              f"{r['ratio']:.0f}x | {r['largest_difference']:.1e} |")


if __name__ == "__main__":
    main()
