"""The contour error of CAM-style programs predicted with its 90 % interval
(``tcpmm contour --model``), against the true machines C, D, E, H, R05 and R17 of the
independent simulator (docs/validation/program_intervals.md).

For each machine the model is identified from its bundle (cached, as
:mod:`studies.compensation` caches it); each program is interpolated, its largest and RMS
TCP contour error predicted on the model with the verdict over what identification leaves
uncertain (:class:`tcpmm.uncertainty.ProgramTest`), and run on the machine's true
parameters (``truth.yaml``) in tcpmm's simulator.

    .venv/bin/python -m studies.program_intervals [--machines c,d,e,h,r05,r17]
        [--cache DIR] [--out docs/validation/program_intervals_table.md]
"""

from __future__ import annotations

import argparse
from pathlib import Path

from tcpmm.io.truthfile import machine_from_truth
from tcpmm.path import program_to_command
from tcpmm.path.command import Command
from tcpmm.sim.simulate import simulate
from tcpmm.uncertainty import ProgramTest, prediction_verdict, program_figures

from . import DATA
from .compensation import SQUARE, model_of, spiral

#: The programs, each ending at rest (a dwell); the spiral's blended corners hold it below
#: 4400 mm/min, so that a higher feed gives the same command [-].
PROGRAMS = {"square F5000": SQUARE + "G4 P0.3\n",
            "square F10000": SQUARE.replace("F5000", "F10000") + "G4 P0.3\n",
            "spiral F5000": spiral() + "G4 P0.3\n"}


def _xy(machine):
    return machine.model_copy(update={"axes": {n: machine.axes[n] for n in ("X", "Y")}})


def rows_of(name: str, model, truth) -> list:
    """Per program and figure: predicted, true, the interval's half-width, the verdict and
    its cause [um], [-]."""
    import warnings

    out = []
    for label, text in PROGRAMS.items():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # the spiral's first point is where it starts
            cmd = program_to_command(text)
        cmd = Command(cmd.time_s, {n: cmd.positions[n] for n in ("X", "Y")}, cmd.meta)
        test = ProgramTest(label, cmd, ("X", "Y"))
        verdict = prediction_verdict(model, [test], "tcp", jobs=0)
        true = program_figures(simulate(truth, cmd), test)
        for f in verdict.figures:
            x = true[(f.test, f.direction, f.figure)]
            out.append({"machine": name.upper(), "program": label, "figure": f.figure,
                        "predicted_um": f.nominal * 1e6, "true_um": x * 1e6,
                        "half_width_um": f.half_width * 1e6, "verdict": f.verdict,
                        "cause": f.cause, "inside": abs(x - f.nominal) <= f.half_width,
                        "within_target": abs(x - f.nominal) <= f.target})
    return out


def _row(r: dict) -> str:
    verdict = r["verdict"] + (f" ({r['cause']})" if r["cause"] else "")
    return (f"| {r['machine']} | {r['program']} | {r['figure'].replace('contour ', '')} | "
            f"{r['predicted_um']:.2f} | {r['true_um']:.2f} | "
            f"{r['true_um'] - r['predicted_um']:+.2f} | {r['half_width_um']:.2f} | "
            f"{verdict} | {'yes' if r['inside'] else '**no**'} |\n")


def table(rows: list) -> str:
    """Markdown: a row per machine, program and figure [-]."""
    head = ("| machine | program | figure | predicted [µm] | true [µm] | error [µm] | "
            "90 % half-width [µm] | verdict (cause) | inside |\n"
            "|---|---|---|---|---|---|---|---|---|\n")
    body = "".join(_row(r) for r in rows)
    firm = [r for r in rows if r["verdict"] == "firm"]
    tail = (f"\n{sum(r['inside'] for r in rows)} of {len(rows)} figures inside their "
            f"interval; {len(firm)} called firm, {sum(r['within_target'] for r in firm)} of "
            "them within their target.\n")
    return head + body + tail


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--machines", default="c,d,e,h,r05,r17")
    p.add_argument("--cache", type=Path, default=Path("/tmp/compensate"))
    p.add_argument("--out", type=Path)
    args = p.parse_args(argv)
    rows = []
    for name in args.machines.split(","):
        truth = _xy(machine_from_truth(DATA / f"bench_{name}" / "truth.yaml"))
        rows += rows_of(name, model_of(name, args.cache), truth)
    text = table(rows)
    if args.out is not None:
        from tcpmm.io.atomic import write_text_atomic

        write_text_atomic(args.out, text)
    print(text)


if __name__ == "__main__":
    main()
