"""Identify the reference machines of an independent simulator and compare their circles.

For each of ../shared/data/bench_{c,d,e}: identify a model from ``bundle/`` alone, predict
the four measured circles (R35, F5000 and F10000, CCW and CW) and print, per circle, the
largest |measured - predicted| TCP reversal spike at B-D (A lies on the feed-in) and the
TCP contour-error difference, in um. ``--truth`` does the same with the true parameters
written into a model (``tcpmm.io.truthfile``): the floor of any identified model.

Run: ``.venv/bin/python -m studies.reference_machines [--truth] [--data DIR]``
"""

from __future__ import annotations

import argparse
import warnings
from pathlib import Path

from tcpmm.analysis.circular import analyse_circle
from tcpmm.analysis.compare import compare_circles
from tcpmm.ident.pipeline import identify_bundle
from tcpmm.io.bundle import read_bundle
from tcpmm.io.runfile import read_run_csv
from tcpmm.io.truthfile import machine_from_truth
from tcpmm.path.commandfile import read_command_csv
from tcpmm.sim.simulate import simulate

from . import DATA

CASES = ("ccw", "cw", "ccw_fast", "cw_fast")
R = 0.035  # [m]


def misfit(machine, folder: Path, case: str) -> tuple[float, float]:
    """Largest TCP spike difference at B-D and contour-error difference [um]."""
    run = simulate(machine, read_command_csv(folder / f"circle_{case}_cmd.csv"))
    meas = analyse_circle(read_run_csv(folder / f"circle_{case}_meas.csv"), R)
    row = next(r for r in compare_circles(meas, analyse_circle(run, R)).rows
               if r["sensor"] == "tcp")
    return max(abs(row[f"spike_{q}_um"]) for q in "BCD"), abs(row["contour_error_um"])


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--data", type=Path,
                   default=DATA)
    p.add_argument("--truth", action="store_true", help="the true parameters, not identified")
    args = p.parse_args(argv)
    print("machine  " + "  ".join(f"{c:>17s}" for c in CASES) + "   (spike / contour, um)")
    for letter in "cde":
        folder = args.data / f"bench_{letter}"
        if args.truth:
            machine = machine_from_truth(folder / "truth.yaml")
        else:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                machine = identify_bundle(read_bundle(folder / "bundle")).machine
        cells = [misfit(machine, folder, c) for c in CASES]
        print(f"{letter.upper():8s} " + "  ".join(f"{s:8.2f} / {c:6.2f}" for s, c in cells))


if __name__ == "__main__":
    main()
