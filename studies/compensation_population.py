"""Compensation on random machines of the unseen-machine population, each run on its truth.

Each machine is drawn as :mod:`studies.unseen` draws them (mechanics, friction and its
form, servo, sensors, with lost motion), its measurement bundle recorded on it
(:func:`tcpmm.machines.virtual.virtual_bundle`) and a model identified from that alone.
The circle R 35 mm CCW of bench C's command at F5000 and F10000 (1 m/s^2, 20 ms moving
average) is compensated on the model, the correction scaled over ``--draws`` machines
drawn from the model's uncertainty as ``tcpmm compensate`` does, and run on the true
machine; with ``--programs`` also (or instead) the CAM-style spiral and square of
:mod:`studies.compensation` under ``G64``, planned with the headroom ``tcpmm compensate
--gcode`` gives them. Per machine and program: the shares kept, the firm share of the
path and the true machine's largest contour error over it before / after (and the least
of it region by region), the draws' verdict on the largest spike, and the true machine's
contour error, largest spike and G before and after; "worse" names a figure the true
machine made worse by more than the sensors' 0.1 um, each corner's overshoot and each
quadrant point's spike pass by pass among them; a machine whose model
identification refuses as suspect has a line that says so. Not a test:
``python -m studies.compensation_population [--seed N] [--machines 0-9] [--draws N]
[--programs "spiral G64,square G64"] [--circle given|command|none]``.
"""

from __future__ import annotations

import argparse
import tempfile
import warnings
from pathlib import Path

from tcpmm.compensate.headroom import DEFAULT_HEADROOM, program_with_headroom
from tcpmm.compensate.robust import DRAWS
from tcpmm.ident.gates.finding import SuspectModelError
from tcpmm.ident.pipeline import identify_bundle
from tcpmm.io.bundle import read_bundle
from tcpmm.machines.virtual import virtual_bundle
from tcpmm.path import InterpolatorSettings, read_command_csv

from . import DATA
from .compensation import SQUARE, corners_worse, one, spiral
from .unseen import draw_machine

FEEDS = (("F5000", "circle_ccw_cmd.csv"), ("F10000", "circle_ccw_fast_cmd.csv"))
#: the programs of ``--programs``: bench C's circles, and the CAM-style programs of
#: :mod:`studies.compensation` planned as ``tcpmm compensate --gcode`` plans them
PROGRAMS = ("circle F5000", "circle F10000", "spiral G64", "square G64")
#: a figure worse on the true machine by more than this counts [um]
WORSE_UM = 0.1


def identified(seed: int, index: int):
    """The true machine and the model identified from its bundle (without the verdict on
    the reference circles, which leaves the model as it is) [-]."""
    truth, _ = draw_machine(seed, index, backlash=True)
    with tempfile.TemporaryDirectory() as tmp:
        virtual_bundle(truth, Path(tmp) / "bundle", seed=index)
        return truth, identify_bundle(read_bundle(Path(tmp) / "bundle"),
                                      verdict=False).machine


def commands(label: str, model):
    """The command at the full limits, the one the correction is learned on, and the
    circle's radius (None for a CAM program) of a program of :data:`PROGRAMS` [-]."""
    if label.startswith("circle"):
        cmd = read_command_csv(DATA / "bench_c" / dict(FEEDS)[label.split()[1]])
        return cmd, cmd, 0.035
    text = spiral() if label.startswith("spiral") else SQUARE
    settings = InterpolatorSettings.model_validate(model.interpolation or {})
    full, planned = program_with_headroom(text, settings, DEFAULT_HEADROOM)
    return full, planned, None


def _pair(before, after) -> str:
    """``before -> after``, or ``-`` where a figure is not measured [um]."""
    return "-" if before is None else f"{before:.2f} -> {after:.2f}"


def row(index: int, label: str, r: dict) -> str:
    """One line of the table of a result of :func:`studies.compensation.one` [-]."""
    names = {"ce": "contour", "spike": "spike", "g": "G"}
    worse = [names[k] for k in names if r[f"{k}_before"] is not None
             and r[f"{k}_after"] > r[f"{k}_before"] + WORSE_UM]
    if r["co_rises"]:  # in no other column
        worse.append(corners_worse(r["co_rises"]))
    worse += [s for s in r["spikes_grown"] if "spike" not in worse]  # each quadrant point
    f, firm = r["factors"], r["firm_truth"]
    where = "-" if firm is None else f"{firm[0]:.1f}x (least region {firm[1]:.1f}x)"
    return (f"| {index} | {label} | {f['X']:.2g}/{f['Y']:.2g} | {100 * r['firm']:.0f} % | "
            f"{where} | {r['spike_verdict']} | {_pair(r['ce_before'], r['ce_after'])} | "
            f"{_pair(r['spike_before'], r['spike_after'])} | "
            f"{_pair(r['g_before'], r['g_after'])} | "
            f"{', '.join(worse) or '-'} |")


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--seed", type=int, default=91)
    p.add_argument("--machines", default="0-9", help="first-last, or a list a,b,c")
    p.add_argument("--draws", type=int, default=DRAWS, help="as tcpmm compensate's default")
    p.add_argument("--programs", default="circle F5000,circle F10000",
                   help=f"a comma list of {', '.join(PROGRAMS)}")
    p.add_argument("--circle", choices=("given", "command", "none"), default="given",
                   help="the circle the draws judge: R 35 mm about the origin (--radius), "
                        "the one the command runs (tcpmm compensate without --radius), or "
                        "none (the circle judged as a path)")
    a = p.parse_args(argv)
    labels = [x.strip() for x in a.programs.split(",")]
    unknown = [x for x in labels if x not in PROGRAMS]
    if unknown:
        p.error(f"unknown program {', '.join(unknown)}; choose from {', '.join(PROGRAMS)}")
    if "-" in a.machines:
        lo, hi = (int(x) for x in a.machines.split("-"))
        indices = range(lo, hi + 1)
    else:
        indices = [int(x) for x in a.machines.split(",")]
    warnings.simplefilter("ignore")
    print("| machine | program | shares X/Y | firm | true reduction where firm | spike verdict "
          "| contour error [µm] | largest spike [µm] | G [µm] | worse |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for i in indices:
        try:
            truth, model = identified(a.seed, i)
        except SuspectModelError:  # as tcpmm identify refuses it: nothing to compensate
            print(f"| {i} | - | identification refused the model as suspect | | | | | | | |")
            continue
        for label in labels:
            full, planned, radius = commands(label, model)
            r = one(f"m{i}", model, truth, label, (full, planned), radius, a.draws,
                    judged=a.circle)
            print(row(i, label, r), flush=True)


if __name__ == "__main__":
    main()
