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
        [--cache DIR] [--draws 6]
"""

from __future__ import annotations

import argparse
import warnings
from pathlib import Path

from tcpmm.compensate.controller import (
    controller_compensation,
    reversal_pulses,
    with_cross_talk,
)
from tcpmm.compensate.controller_robust import robust_controller
from tcpmm.compensate.scores import judge
from tcpmm.io.truthfile import machine_from_truth
from tcpmm.path import read_command_csv
from tcpmm.sim.simulate import simulate

from . import DATA
from .compensation import model_of

R = 0.035  # [m]


def on_truth(truth, command, cc) -> dict:
    """The true machine's TCP figures with the controller-side compensation applied [-]."""
    gains = {a: c.cross_talk_s2 for a, c in cc.axes.items()}
    ctc = with_cross_talk(command, gains)
    pulses = {a: reversal_pulses(ctc, a, c.pulse_A, c.decay_s) for a, c in cc.axes.items()}
    return judge(simulate(truth, ctc, current_feedforward_A=pulses), command, R)


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


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--machines", default="c,d,e,h,r05,r17")
    p.add_argument("--cache", type=Path, default=Path("/tmp/compensate"))
    p.add_argument("--draws", type=int, default=0)
    args = p.parse_args(argv)
    print("| machine | circle | contour error [µm] | largest spike [µm] | G [µm] "
          "| share kept | spike verdict |")
    print("|---|---|---|---|---|---|---|")
    for name in args.machines.split(","):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            model = model_of(name, args.cache)
            truth = machine_from_truth(DATA / f"bench_{name}" / "truth.yaml")
            truth = truth.model_copy(update={"axes": {a: truth.axes[a] for a in ("X", "Y")}})
            for label, file in (("F5000", "circle_ccw_cmd.csv"),
                                ("F10000", "circle_ccw_fast_cmd.csv")):
                cmd = read_command_csv(DATA / f"bench_{name}" / file)
                cc = controller_compensation(model, cmd, R)
                if args.draws:
                    robust_controller(model, cc, cmd, R, n_draws=args.draws)
                before = judge(simulate(truth, cmd), cmd, R)
                print(row(name, label, before, on_truth(truth, cmd, cc), cc), flush=True)


if __name__ == "__main__":
    main()
