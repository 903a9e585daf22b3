"""Servo tuning proposals on machines tcpmm did not generate: C, D, E, H, R05, R17 of the
independent simulator (docs/validation/tuning.md).

For each machine the model is identified from its bundle and tuned (``tune_machine``, 6 dB /
45 deg) with the modes judged up to 0, 5 and 10 % off the model's frequencies; each
proposal is put on the TRUE machine (its truth.yaml) and the sampled loop's spectral radius
taken with the truth's modes moved by a common factor within +-10 % and with its screw
(``K_L``) or nut (``K_t``) stiffness alone 20 % off. A radius of 1 or more is a loop that
oscillates on that machine.

    .venv/bin/python -m studies.tuning [--machines c,d,e,h,r05,r17] [--cache DIR]
"""

from __future__ import annotations

import argparse
import warnings
from pathlib import Path

import numpy as np

from tcpmm.io.truthfile import machine_from_truth
from tcpmm.servo.modeshift import mode_tolerance, shifted
from tcpmm.servo.sampled import sampled_spectral_radius
from tcpmm.servo.tune import tune_machine

from . import DATA
from .compensation import model_of

#: Mode tolerances the proposals are made with [-].
TOLERANCES = (0.0, 0.05, 0.10)
#: Common factors on the truth's mode frequencies the proposals are run with [-].
SHIFTS = np.linspace(0.90, 1.10, 41)


def on_truth(truth, name: str, servo) -> tuple[float, float, float]:
    """Largest spectral radius of ``servo`` on the true axis: unshifted, over the modes'
    common shifts within 5 % and 10 %, and with the screw or the nut alone 20 % off [-]."""
    mech = truth.axes[name].mechanics
    radius = {float(s): sampled_spectral_radius(shifted(mech, float(s)), servo)
              for s in SHIFTS}
    alone = max(sampled_spectral_radius(mech.scaled(**{k: f}), servo)
                for k in ("K_L", "K_t") for f in (0.8, 1.2))
    near = max(r for s, r in radius.items() if abs(s - 1.0) <= 0.05 + 1e-9)
    return near, max(radius.values()), alone


def _filter(f) -> str:
    """A filter of the proposal in a few words, for a table cell (the long form is
    :func:`tcpmm.servo.currentfilters.filter_text`) [-]."""
    if f.type == "notch":
        return f"{f.f_hz:.0f} Hz {f.depth_db:g} dB"
    return f"low-pass {f.f_hz:.0f} Hz, damping {f.zeta:g}"


def rows_of(name: str, model, truth) -> list[str]:
    """Markdown rows of one machine: per tolerance and axis, the proposal and its spectral
    radius on the truth [-]."""
    out = []
    for tol in TOLERANCES:
        with mode_tolerance(tol):
            proposals = tune_machine(model, 6.0, 45.0)
        for axis, t in proposals.items():
            filters = ", ".join(_filter(f) for f in t.after.filters) or "-"
            bw = (t.margins_before["velocity"].bandwidth_hz,
                  t.margins_after["velocity"].bandwidth_hz)
            near, wide, alone = on_truth(truth, axis, t.after)
            out.append(f"| {name.upper()} | {axis} | {100 * tol:g} % | "
                       f"{'met' if t.met else 'NOT MET'} | {t.after.K_vp:.3g} | {filters} | "
                       f"{bw[0]:.3g} -> {bw[1]:.3g} | {near:.4f} | {wide:.4f} | "
                       f"{alone:.4f} |")
    return out


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--machines", default="c,d,e,h,r05,r17")
    p.add_argument("--cache", type=Path, default=Path("/tmp/tcpmm-tuning"))
    args = p.parse_args(argv)
    warnings.simplefilter("ignore")
    print("| machine | axis | mode tolerance | verdict | K_vp [A s/rad] | filter | "
          "velocity bandwidth [Hz] | truth, modes +-5 % | truth, modes +-10 % | "
          "truth, screw or nut +-20 % |")
    print("|---|---|---:|---|---:|---|---|---:|---:|---:|")
    for name in args.machines.split(","):
        model = model_of(name, args.cache)
        truth = machine_from_truth(DATA / f"bench_{name}" / "truth.yaml")
        for row in rows_of(name, model, truth):
            print(row, flush=True)


if __name__ == "__main__":
    main()
