"""Command-line start-up and whole commands, timed from outside by the wall clock.

1. A warm ``tcpmm simulate`` of the paper's circle on the built-in machine
   (``examples/circle_r35_f5000.nc`` to a CSV run): target 0.3 s.
2. ``tcpmm identify`` on a shipped bench bundle (``/work/shared/data/bench_*/bundle`` or
   ``--bundle``), per axis: target 5 s.
3. ``tcpmm --help`` (imports every command's module) and ``tcpmm --version``.

Each command runs as a new process (``python -m tcpmm.cli``, this interpreter, this
source) once unmeasured (compiled kernels cached, files in the page cache), then
``--runs`` times; min and median of the wall clock (``time.perf_counter`` around the
child's whole life). Not a test:
``python benchmarks/cli.py [--runs N] [--bundle DIR] [--skip-identify] [--json]``.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
PROGRAM = ROOT / "examples" / "circle_r35_f5000.nc"
BUNDLES = sorted(Path("/work/shared/data").glob("bench_*/bundle"))
TARGETS_S = {"simulate_circle": 0.3, "identify_per_axis": 5.0}


def wall(args: list[str], runs: int) -> tuple[float, float]:
    """Min and median wall time [s] of ``tcpmm ARGS`` as a new process, after one
    unmeasured run."""
    cmd = [sys.executable, "-c",
           "import sys; from tcpmm.cli import run; sys.exit(run())", *args]
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"))
    times = []
    for k in range(runs + 1):
        t0 = time.perf_counter()
        done = subprocess.run(cmd, env=env, capture_output=True, text=True)
        if k:
            times.append(time.perf_counter() - t0)
        if done.returncode not in (0, 3):  # 3: identify's "not every figure firm"
            raise SystemExit(f"{' '.join(args)} failed:\n{done.stderr}")
    return min(times), float(np.median(times))


def axes_of(bundle: Path) -> int:
    """The number of axes of a bundle (its sub-folders) [-]."""
    return sum(1 for p in bundle.iterdir() if p.is_dir())


def main(argv=None) -> dict:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--runs", type=int, default=7, help="timed runs per command (>= 3)")
    p.add_argument("--bundle", type=Path, default=BUNDLES[0] if BUNDLES else None,
                   help="the bundle identify runs on")
    p.add_argument("--identify-runs", type=int, default=3, help="timed runs of identify")
    p.add_argument("--skip-identify", action="store_true")
    p.add_argument("--json", action="store_true", help="print the figures as JSON only")
    args = p.parse_args(argv)
    runs = max(3, args.runs)
    out: dict = {"runs": runs, "clock": "wall"}
    with tempfile.TemporaryDirectory() as tmp:
        run_csv = str(Path(tmp) / "run.csv")
        for name, cmd in {"version": ["--version"], "help": ["--help"],
                          "simulate_circle": ["simulate", "builtin:vmc", "--gcode",
                                              str(PROGRAM), "-o", run_csv]}.items():
            out[f"{name}_s"], out[f"{name}_median_s"] = wall(cmd, runs)
        if not args.skip_identify and args.bundle is not None:
            n = axes_of(args.bundle)
            lo, med = wall(["identify", str(args.bundle), "-o", str(Path(tmp) / "m.yaml")],
                           max(1, args.identify_runs))
            out |= {"identify_bundle": str(args.bundle), "identify_axes": n,
                    "identify_per_axis_s": lo / n, "identify_per_axis_median_s": med / n}
    out["targets_s"] = TARGETS_S
    if args.json:
        print(json.dumps(out, indent=1))
        return out
    print(f"Whole commands, new process each, wall clock, min / median of {runs}:")
    for key in ("version", "help", "simulate_circle"):
        print(f"  {key:18s} {out[f'{key}_s']:6.2f} / {out[f'{key}_median_s']:6.2f} s")
    if "identify_per_axis_s" in out:
        print(f"  identify per axis  {out['identify_per_axis_s']:6.2f} / "
              f"{out['identify_per_axis_median_s']:6.2f} s ({out['identify_bundle']}, "
              f"{out['identify_axes']} axes)")
    print(f"  targets: {TARGETS_S}")
    return out


if __name__ == "__main__":
    main()
