"""Calibration of the predicted figures' 90 % intervals on machines of an independent
simulator (``../shared/data/bench_*``).

Each machine is identified from its ``bundle/`` alone; its measured circles (R 35 mm,
F5000 and F10000, CCW and CW; those the analysis finds whole) are predicted with the
verdict of :func:`tcpmm.uncertainty.prediction_verdict`. Per figure (TCP spikes A-D,
contour error, G) it prints the score ``|measured - predicted| / sum`` (``sum``: the
quadrature sum of the changes the uncertain quantities make, the interval before its
calibration factor) and, with the factor in force, whether the measurement lies inside the
interval and whether a figure called firm misses its target. The split-conformal factor over
machines is the largest per-machine score: with six machines, the 90 % level of the
conformal rule (rank ceil(0.9 (n + 1)) of n) needs the largest.

Run: ``.venv/bin/python -m studies.calibration [--data DIR] [--machines c,d,...]``
"""

from __future__ import annotations

import argparse
import math
import statistics
import warnings
from pathlib import Path

from tcpmm.analysis.circular import analyse_circle
from tcpmm.errors import InputError
from tcpmm.ident.pipeline import identify_bundle
from tcpmm.io.bundle import read_bundle
from tcpmm.io.runfile import read_run_csv
from tcpmm.path.commandfile import read_command_csv
from tcpmm.uncertainty import CALIBRATION, CircleTest, circle_figures, prediction_verdict

from . import DATA

CASES = ("ccw", "cw", "ccw_fast", "cw_fast")
R = 0.035  # [m]


def measured(folder: Path):
    """The circles the analysis finds whole, as tests, and their measured TCP figures."""
    tests, meas = [], {}
    for case in CASES:
        try:
            res = analyse_circle(read_run_csv(folder / f"circle_{case}_meas.csv"), R)
        except InputError:
            continue
        tests.append(CircleTest(case, read_command_csv(folder / f"circle_{case}_cmd.csv"), R))
        meas.update(circle_figures(res, case))
    return tests, meas


def judge(letter: str, data: Path) -> list[dict]:
    """One row per measured figure of machine ``letter``."""
    folder = data / f"bench_{letter}"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        machine = identify_bundle(read_bundle(folder / "bundle"), verdict=False).machine
    tests, meas = measured(folder)
    rows = []
    for f in prediction_verdict(machine, tests).figures:
        key = (f.test, f.direction, f.figure)
        if key not in meas:
            continue
        err = abs(meas[key] - f.nominal)
        raw = (f.half_width - CALIBRATION["floor_m"]) / CALIBRATION["factor"]
        rows.append({"machine": letter, "figure": f.figure, "verdict": f.verdict,
                     "error_um": err * 1e6, "half_width_um": f.half_width * 1e6,
                     "score": err / raw if raw > 0 else math.inf,
                     "inside": err <= f.half_width,
                     "unflagged_miss": f.verdict == "firm" and err > f.target})
    return rows


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--data", type=Path,
                   default=DATA)
    p.add_argument("--machines", default="c,d,e,h,r05,r17")
    args = p.parse_args(argv)
    rows = []
    print("machine  figures  firm  inside  unflagged misses  max score  median width um")
    for letter in args.machines.split(","):
        r = judge(letter, args.data)
        rows += r
        print(f"{letter:8s} {len(r):7d} {sum(x['verdict'] == 'firm' for x in r):5d} "
              f"{sum(x['inside'] for x in r):7d} {sum(x['unflagged_miss'] for x in r):17d} "
              f"{max(x['score'] for x in r):10.2f} "
              f"{statistics.median(x['half_width_um'] for x in r):16.2f}")
    n = len(rows)
    print(f"all      {n:7d} {sum(x['verdict'] == 'firm' for x in rows):5d} "
          f"{sum(x['inside'] for x in rows):7d} {sum(x['unflagged_miss'] for x in rows):17d} "
          f"{max(x['score'] for x in rows):10.2f} "
          f"{statistics.median(x['half_width_um'] for x in rows):16.2f}")
    print(f"coverage {sum(x['inside'] for x in rows) / n:.3f} with factor "
          f"{CALIBRATION['factor']:g}, floor {CALIBRATION['floor_m'] * 1e6:g} um")


if __name__ == "__main__":
    main()
