"""Friction pulses with decays beyond the grid's longest, on machines tcpmm did not
generate (docs/validation/compensation.md, "Decays beyond 300 ms").

Each bench circle's pulses are tuned on the model identified from its bundle
(:func:`tcpmm.compensate.controller.controller_compensation`, one amplitude, no draws) with
the shipped decays and with decays of 1 and 3 s added, and applied to the true machine.
Printed per circle: the true machine's largest TCP spike and contour error before and with
each grid's pulses, and the amplitude and decay tuned per axis.

    .venv/bin/python -m studies.pulse_decay [--machines c,d,e,h,r05,r17] [--cache DIR]
"""

from __future__ import annotations

import argparse
import importlib
from pathlib import Path

from tcpmm.compensate.scores import judge
from tcpmm.sim.simulate import simulate

from .compensation_controller import R, bench_circles, on_truth

# the subpackage, not the function of the same name the flat API exports
controller = importlib.import_module("tcpmm.compensate.controller")
pulse_tuning = importlib.import_module("tcpmm.compensate.pulse_tuning")

LONGER_DECAYS_S = (1.0, 3.0)


def cell(fig: dict) -> str:
    """Largest spike / contour error of :func:`judge`'s figures [um]."""
    return f"{fig['circle']['largest_spike_um']:.2f} / {fig['path']['contour_error_um']:.2f}"


def tuned(model, truth, cmd, decays) -> str:
    """The true machine's figures with the pulses tuned on ``model`` over ``decays``, and
    each axis's amplitude [A] and decay [ms] [-]."""
    shipped = pulse_tuning.PULSE_DECAYS_S
    pulse_tuning.PULSE_DECAYS_S = decays
    try:
        cc = controller.controller_compensation(model, cmd, R, adapt_draws=None)
    finally:
        pulse_tuning.PULSE_DECAYS_S = shipped
    pulses = ", ".join(f"{a} {c.pulse_A:.2f} A {c.decay_s * 1e3:g} ms"
                       for a, c in cc.axes.items() if c.pulse_A)
    return f"{cell(on_truth(truth, cmd, cc))} | {pulses or '-'}"


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--machines", default="c,d,e,h,r05,r17")
    p.add_argument("--cache", type=Path, default=Path("/tmp/compensate"))
    args = p.parse_args(argv)
    print("| machine | circle | before: spike / contour error [µm] | decays to 300 ms | pulses "
          "| decays to 3 s | pulses |\n|---|---|---|---|---|---|---|")
    longer = controller.PULSE_DECAYS_S + LONGER_DECAYS_S
    for name, label, model, truth, cmd in bench_circles(args.machines, args.cache,
                                                        "F5000,F10000"):
        before = judge(simulate(truth, cmd), cmd, R)
        print(f"| {name.upper()} | {label} | {cell(before)} | "
              f"{tuned(model, truth, cmd, controller.PULSE_DECAYS_S)} | "
              f"{tuned(model, truth, cmd, longer)} |", flush=True)


if __name__ == "__main__":
    main()
