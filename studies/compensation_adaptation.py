"""The friction pulse's adaptation characteristic on machines tcpmm did not generate: C, D,
E, H, R05, R17 of the independent simulator (docs/validation/compensation.md, "The pulse
over the feed").

For each machine the model is identified from its bundle; the controller-side compensation
is computed on that model for its measured circle twice, with the pulse of one amplitude
and with the adaptation characteristic (:mod:`tcpmm.compensate.adaptation`), each scaled
back over ``--draws`` draws of the model as ``tcpmm compensate --controller-out`` does.
Both are applied to the TRUE machine (its truth.yaml) on the circle run at feed overrides,
including two the characteristic was not tuned at (3/8 and 3/4). Printed per override: the
largest spike on the true machine without compensation, with one amplitude and adapted,
and what the model predicted adapted.

    .venv/bin/python -m studies.compensation_adaptation [--machines c,d,e,h,r05,r17]
        [--cache DIR] [--draws 6] [--programs F5000,F10000]
"""

from __future__ import annotations

import argparse
import warnings
from pathlib import Path

from tcpmm.compensate.adaptation import DRAWS, time_scaled
from tcpmm.compensate.controller import controller_compensation
from tcpmm.compensate.controller_robust import robust_controller
from tcpmm.compensate.drive import controlled_run
from tcpmm.compensate.scores import judge

from .compensation_controller import bench_circles

R = 0.035  # [m]
#: The overrides the circle is run at on the true machine: those tuned at and between [-].
SHOWN = (0.25, 0.375, 0.5, 0.75, 1.0)
HEAD = ("| machine | circle | adapted | override | largest spike on the true machine [µm]: "
        "none / one amplitude / adapted | model, adapted [µm] |\n|---|---|---|---|---|---|")


def spike(machine, cmd, params) -> float:
    """The largest TCP spike of the circle with the parameters applied [um]."""
    return judge(controlled_run(machine, cmd, params), cmd, R)["circle"]["largest_spike_um"]


def rows(name: str, label: str, model, truth, cmd, draws: int) -> list[str]:
    """Markdown rows, one per override in :data:`SHOWN` [-]."""
    ccs = []
    for adapt in (None, DRAWS):
        cc = controller_compensation(model, cmd, R, adapt_draws=adapt)
        if draws:
            robust_controller(model, cc, cmd, R, n_draws=draws)
        ccs.append(cc.axes)
    adapted = ",".join(a for a, c in ccs[1].items()
                       if c.characteristic is not None and c.pulse_A) or "-"
    out = []
    for k in SHOWN:
        c = time_scaled(cmd, k)
        on = [spike(truth, c, p) for p in ({}, *ccs)]
        out.append(f"| {name.upper()} | {label} | {adapted} | {k:g} | "
                   f"{' / '.join(f'{x:.2f}' for x in on)} | {spike(model, c, ccs[1]):.2f} |")
    return out


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--machines", default="c,d,e,h,r05,r17")
    p.add_argument("--cache", type=Path, default=Path("/tmp/compensate"))
    p.add_argument("--draws", type=int, default=6)
    p.add_argument("--programs", default="F5000,F10000")
    args = p.parse_args(argv)
    print(HEAD)
    for name, label, model, truth, cmd in bench_circles(args.machines, args.cache,
                                                        args.programs):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            for line in rows(name, label, model, truth, cmd, args.draws):
                print(line, flush=True)

if __name__ == "__main__":
    main()
