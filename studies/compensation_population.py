"""Compensation on random machines of the unseen-machine population, each run on its truth.

Each machine is drawn as :mod:`studies.unseen` draws them (mechanics, friction and its
form, servo, sensors, with lost motion), its measurement bundle recorded on it
(:func:`tcpmm.machines.virtual.virtual_bundle`) and a model identified from that alone.
The circle R 35 mm CCW of bench C's command at F5000 and F10000 (1 m/s^2, 20 ms moving
average) is compensated on the model, the correction scaled over ``--draws`` machines drawn
from the model's uncertainty as ``tcpmm compensate`` does, and run on the true machine.
Per machine and feed: the shares kept, the firm share of the path and the true machine's
largest contour error over it before / after (and the least of it region by region), the
draws' verdict on the largest spike, and the true machine's contour error, largest spike
and G before and after; "worse" names a figure the true machine made worse by more than the
sensors' 0.1 um; a machine whose model identification refuses as suspect has a line that
says so. Not a test:
``python -m studies.compensation_population [--seed N] [--machines 0-9] [--draws N]``.
"""

from __future__ import annotations

import argparse
import tempfile
import warnings
from pathlib import Path

from tcpmm.compensate.robust import DRAWS
from tcpmm.ident.gates.finding import SuspectModelError
from tcpmm.ident.pipeline import identify_bundle
from tcpmm.io.bundle import read_bundle
from tcpmm.machines.virtual import virtual_bundle
from tcpmm.path import read_command_csv

from . import DATA
from .compensation import one
from .unseen import draw_machine

FEEDS = (("F5000", "circle_ccw_cmd.csv"), ("F10000", "circle_ccw_fast_cmd.csv"))
#: a figure worse on the true machine by more than this counts [um]
WORSE_UM = 0.1


def identified(seed: int, index: int):
    """The true machine and the model identified from its bundle [-]."""
    truth, _ = draw_machine(seed, index, backlash=True)
    with tempfile.TemporaryDirectory() as tmp:
        virtual_bundle(truth, Path(tmp) / "bundle", seed=index)
        return truth, identify_bundle(read_bundle(Path(tmp) / "bundle")).machine


def row(index: int, feed: str, r: dict) -> str:
    """One line of the table of a result of :func:`studies.compensation.one` [-]."""
    names = {"ce": "contour", "spike": "spike", "g": "G"}
    worse = [k for k in names if r[f"{k}_after"] > r[f"{k}_before"] + WORSE_UM]
    f, firm = r["factors"], r["firm_truth"]
    where = "-" if firm is None else f"{firm[0]:.1f}x (least region {firm[1]:.1f}x)"
    return (f"| {index} | {feed} | {f['X']:.2g}/{f['Y']:.2g} | {100 * r['firm']:.0f} % | "
            f"{where} | {r['spike_verdict']} | {r['ce_before']:.2f} -> {r['ce_after']:.2f} | "
            f"{r['spike_before']:.2f} -> {r['spike_after']:.2f} | "
            f"{r['g_before']:.2f} -> {r['g_after']:.2f} | "
            f"{', '.join(names[k] for k in worse) or '-'} |")


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--seed", type=int, default=91)
    p.add_argument("--machines", default="0-9", help="first-last, or a list a,b,c")
    p.add_argument("--draws", type=int, default=DRAWS, help="as tcpmm compensate's default")
    a = p.parse_args(argv)
    if "-" in a.machines:
        lo, hi = (int(x) for x in a.machines.split("-"))
        indices = range(lo, hi + 1)
    else:
        indices = [int(x) for x in a.machines.split(",")]
    warnings.simplefilter("ignore")
    print("| machine | circle | shares X/Y | firm | true reduction where firm | spike verdict "
          "| contour error [µm] | largest spike [µm] | G [µm] | worse |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for i in indices:
        try:
            truth, model = identified(a.seed, i)
        except SuspectModelError:  # as tcpmm identify refuses it: nothing to compensate
            print(f"| {i} | - | identification refused the model as suspect | | | | | | | |")
            continue
        for feed, file in FEEDS:
            cmd = read_command_csv(DATA / "bench_c" / file)
            r = one(f"m{i}", model, truth, feed, (cmd, cmd), 0.035, a.draws)
            print(row(i, feed, r), flush=True)


if __name__ == "__main__":
    main()
