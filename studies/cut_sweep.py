"""A sweep that misses the structure's modes: bench C's bundle with the excitation cut to
its upper half, identified, and its four measured circles set against the intervals of the
model it gives.

The bench's sweep is a log sweep of 2-1000 Hz over 15 s (``bench_c/README.md``); the rows
before it reaches ``--low`` Hz are dropped, the rest kept as recorded (time from zero).
Then, as a user runs it: ``tcpmm identify``, and for each measured circle ``tcpmm simulate``
and ``tcpmm compare ... --model --json``. Printed per circle and TCP figure: measured minus
predicted, the 90 % half-width, inside or not and the verdict; then how many lie inside.

Run: ``.venv/bin/python -m studies.cut_sweep OUT [--low 45] [--data DIR]``
"""

from __future__ import annotations

import argparse
import json
import math
import shutil
from pathlib import Path

import pandas as pd

from . import DATA
from .same_bits import CASES, tcpmm

#: The bench protocol's sweep: lowest and highest frequency [Hz] and duration [s].
SWEEP_HZ, SWEEP_S = (2.0, 1000.0), 15.0
FIGURES = ("spike_A", "spike_B", "spike_C", "spike_D", "contour_error")


def cut_bundle(source: Path, folder: Path, low_hz: float) -> Path:
    """The bundle ``source`` copied to ``folder`` with each sweep from ``low_hz`` on [-]."""
    shutil.copytree(source, folder, dirs_exist_ok=True)
    t0 = SWEEP_S * math.log(low_hz / SWEEP_HZ[0]) / math.log(SWEEP_HZ[1] / SWEEP_HZ[0])
    for sweep in folder.glob("*/sweep.csv"):
        d = pd.read_csv(sweep)
        kept = d[d.time_s >= t0].copy()
        kept["time_s"] -= kept.time_s.iloc[0]
        kept.to_csv(sweep, index=False, float_format="%.9g")
    return folder


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("out", type=Path, help="folder for the bundle, model and outputs")
    p.add_argument("--low", type=float, default=45.0, help="lowest frequency kept [Hz]")
    p.add_argument("--data", type=Path, default=DATA)
    args = p.parse_args(argv)
    bench = args.data / "bench_c"
    bundle = cut_bundle(bench / "bundle", args.out / "bundle", args.low)
    model = args.out / "model.yaml"
    tcpmm("identify", bundle, "-o", model)
    inside = total = 0
    for case in CASES:
        pred, cmp_ = args.out / f"pred_{case}.csv", args.out / f"cmp_{case}.json"
        tcpmm("simulate", model, "--command", bench / f"circle_{case}_cmd.csv", "-o", pred)
        tcpmm("compare", bench / f"circle_{case}_meas.csv", pred, "--radius", "35",
              "--model", model, "--json", stdout=cmp_)
        for row in json.loads(cmp_.read_text())["tcp_judged"]:
            for f in FIGURES:
                ok = bool(row[f"{f}_inside"])
                inside, total = inside + ok, total + 1
                print(f"{case:9s} {f:14s} {row[f'{f}_um']:8.2f} +- {row[f'{f}_90_um']:7.2f} "
                      f"{'inside' if ok else 'OUTSIDE':8s}{row[f'{f}_verdict']}")
    print(f"{inside} of {total} inside their 90 % intervals")


if __name__ == "__main__":
    main()
