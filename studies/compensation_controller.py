"""Controller-side compensation on machines tcpmm did not generate: C, D, E, H, R05, R17 of
the independent simulator (docs/validation/compensation.md).

For each machine the model is identified from its bundle; friction pulses and cross-talk
feed-forward are computed on that model for its measured circles
(:func:`tcpmm.compensate.controller.controller_compensation`), and then applied to the TRUE
machine (its truth.yaml) as a drive applies them: the pulses added to the current command,
the feed-forward to the position setpoint. With ``--draws N`` the parameters are first
scaled back over N draws of the model (:mod:`tcpmm.compensate.controller_robust`), as
``tcpmm compensate --controller-out`` does. Printed: the TCP figures on the true machine
before and after, what the model predicted, the share kept and the draws' spike verdict.

    .venv/bin/python -m studies.compensation_controller [--machines c,d,e,h,r05,r17]
        [--cache DIR] [--draws 6] [--combined] [--programs F5000,F10000]

With ``--combined`` each circle is compensated three ways on the model, each scaled back
over the draws, and run on the true machine: the command correction alone
(:func:`tcpmm.compensate.robust_factors`), the parameters alone, and the correction learned
with the parameters on the controller (:mod:`tcpmm.compensate.combined`).
"""

from __future__ import annotations

import argparse
import warnings
from pathlib import Path

from tcpmm.compensate import compensate, robust_factors
from tcpmm.compensate.combined import combined_compensation
from tcpmm.compensate.controller import controller_compensation
from tcpmm.compensate.controller_robust import robust_controller
from tcpmm.compensate.drive import controlled_run
from tcpmm.compensate.scores import judge, judged_path, runs_before_after
from tcpmm.io.truthfile import machine_from_truth
from tcpmm.path import read_command_csv
from tcpmm.sim.simulate import simulate

from . import DATA
from .compensation import model_of

R = 0.035  # [m]


def on_truth(truth, command, cc) -> dict:
    """The true machine's TCP figures with the controller-side compensation applied [-]."""
    return judge(controlled_run(truth, command, cc.axes), command, R)


def row(name: str, label: str, before: dict, after: dict, cc) -> str:
    """One Markdown row: contour, largest spike and G before -> after on the true machine,
    the model's prediction of the after [um], the share kept and the spike's verdict."""
    def figs(d):
        return (d["path"]["contour_error_um"], d["circle"]["largest_spike_um"],
                d["circle"]["circular_deviation_um"])

    b, a, m = figs(before), figs(after), figs(cc.scores["after"])
    cells = " | ".join(f"{x:.2f} -> {y:.2f} ({z:.2f})" for x, y, z in zip(b, a, m, strict=True))
    rob = cc.robustness
    kept = f"{rob['share']:g} | {rob['spike']['verdict']}" if "spike" in rob else "- | -"
    return f"| {name.upper()} | {label} | {cells} | {kept} |"


def figs(d: dict) -> str:
    """Contour error / largest spike / G of :func:`judge`'s figures [um]."""
    return (f"{d['path']['contour_error_um']:.2f} / {d['circle']['largest_spike_um']:.2f} / "
            f"{d['circle']['circular_deviation_um']:.2f}")


def verdicts(circle: dict) -> str:
    """The draws' verdict on the spike and on G [-]."""
    return "/".join(circle.get(k, {}).get("verdict", "-") for k in ("spike",
                                                                    "circular_deviation"))


def combined_row(name: str, label: str, model, truth, cmd, draws: int) -> str:
    """One Markdown row: on the true machine before, with the command correction alone,
    the parameters alone and both; the shares kept and the draws' verdicts on the spike
    and G of each [-]."""
    before = judge(simulate(truth, cmd), cmd, R)
    alone = compensate(model, cmd)
    robust_factors(model, alone, n_draws=draws, radius_m=R)
    cc = controller_compensation(model, cmd, R)
    tuned = dict(cc.axes)
    robust_controller(model, cc, cmd, R, n_draws=draws)
    both = combined_compensation(model, cmd, tuned, n_draws=draws, radius_m=R)
    cells = [figs(before)]
    for comp in (alone, both):
        if comp is both:
            cells.append(figs(on_truth(truth, cmd, cc)))
        cells.append(figs(judge(runs_before_after(truth, comp)[1], judged_path(comp), R)))
    rob, rc, ra = both.robustness, cc.robustness, alone.robustness
    shares = (f"{'/'.join(f'{v:g}' for v in ra['factors'].values())} | {rc['share']:g} | "
              f"{rob['parameter_share']:g}, {'/'.join(f'{v:g}' for v in rob['factors'].values())}")
    ver = " | ".join([verdicts(ra.get("circle", {})),
                      verdicts({k: rc[k] for k in ("spike", "circular_deviation") if k in rc}),
                      verdicts(rob.get("circle", {}))])
    return f"| {name.upper()} | {label} | {' | '.join(cells)} | {shares} | {ver} |"


COMBINED_HEAD = ("| machine | circle | before | command only | pulse only | both | shares command "
                 "X/Y | share pulse | shares both: parameters, command X/Y | verdict command "
                 "spike/G | verdict pulse | verdict both |\n|---|---|---|---|---|---|---|---|---"
                 "|---|---|---|")


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--machines", default="c,d,e,h,r05,r17")
    p.add_argument("--cache", type=Path, default=Path("/tmp/compensate"))
    p.add_argument("--draws", type=int, default=0)
    p.add_argument("--combined", action="store_true")
    p.add_argument("--programs", default="F5000,F10000")
    args = p.parse_args(argv)
    print(COMBINED_HEAD if args.combined else
          "| machine | circle | contour error [µm] | largest spike [µm] | G [µm] "
          "| share kept | spike verdict |\n|---|---|---|---|---|---|---|")
    for name, label, model, truth, cmd in bench_circles(args.machines, args.cache,
                                                        args.programs):
        if args.combined:
            print(combined_row(name, label, model, truth, cmd, args.draws), flush=True)
            continue
        cc = controller_compensation(model, cmd, R)
        if args.draws:
            robust_controller(model, cc, cmd, R, n_draws=args.draws)
        before = judge(simulate(truth, cmd), cmd, R)
        print(row(name, label, before, on_truth(truth, cmd, cc), cc), flush=True)


def bench_circles(machines: str, cache: Path, programs: str):
    """Per machine of ``machines`` (comma-separated) and circle of ``programs``: its name,
    the circle's label, the model identified from its bundle, the true machine's X and Y
    axes and the circle's command; warnings kept quiet [-]."""
    for name in machines.split(","):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            model = model_of(name, cache)
            truth = machine_from_truth(DATA / f"bench_{name}" / "truth.yaml")
            truth = truth.model_copy(update={"axes": {a: truth.axes[a] for a in ("X", "Y")}})
            for label, file in (("F5000", "circle_ccw_cmd.csv"),
                                ("F10000", "circle_ccw_fast_cmd.csv")):
                if label in programs.split(","):
                    yield name, label, model, truth, read_command_csv(
                        DATA / f"bench_{name}" / file)

if __name__ == "__main__":
    main()
