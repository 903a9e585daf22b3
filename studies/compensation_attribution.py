"""Which part of the model makes a compensated program run past a corner on a random
machine's truth and not on the model: the truth with the model's mechanics, friction,
servo or sensors in turn, then with each of the model's mechanics parameters alone.

One machine of :mod:`studies.compensation_population` (drawn with lost motion, its model
identified from its bundle alone) and one of its programs, compensated as ``tcpmm
compensate`` does with the default draws. Each line gives the largest corner overshoot,
the path's end included, before (the program at the full limits) and after the
correction [um]; the mechanics lines only the parameters where the model is more than 3 %
off the truth, with the model's ratio to the truth and its reported relative deviation.
Not a test: ``python -m studies.compensation_attribution --seed 91 --machine 4
--program "spiral G64"``.
"""

from __future__ import annotations

import argparse
import warnings

from tcpmm.compensate.robust import DRAWS
from tcpmm.compensate.scores import judge, judged_path, programmed_path, runs_before_after

from .compensation import compensation_of
from .compensation_population import PROGRAMS, commands, identified

#: The parts of an axis swapped between the truth and the model [-].
PARTS = ("mechanics", "friction", "servo", "sensors")
#: A parameter of the model is listed where it is this far off the truth [-].
OFF = 0.03


def overshoots(machine, comp, full, radius) -> tuple:
    """The largest corner overshoot before and after the correction on ``machine`` [um]."""
    before, after = runs_before_after(machine, comp, programmed=full)
    b = judge(before, programmed_path(comp, full), radius)["path"]
    a = judge(after, judged_path(comp), radius)["path"]
    return b["corner_overshoot_um"], a["corner_overshoot_um"]


def with_part(base, source, part: str, axis=None, value=None):
    """``base`` with ``part`` of every axis taken from ``source``; with ``axis`` and
    ``value`` (a mechanics parameter's name) that one parameter of that axis only [-]."""
    axes = dict(base.axes)
    for name, a in base.axes.items():
        if name not in source.axes or (axis is not None and name != axis):
            continue
        if value is None:
            axes[name] = a.replace(**{part: getattr(source.axes[name], part)})
        else:
            mech = a.mechanics.replace(**{value: getattr(source.axes[name].mechanics, value)})
            axes[name] = a.replace(mechanics=mech)
    return base.model_copy(update={"axes": axes})


def off_parameters(truth, model):
    """``(axis, parameter, model / truth, reported relative deviation)`` of the model's
    mechanics more than :data:`OFF` off the truth [-]."""
    out = []
    for ax, a in model.axes.items():
        true = truth.axes[ax].mechanics.model_dump()
        sd = a.uncertainty.mechanics if a.uncertainty is not None else {}
        for p, v in a.mechanics.model_dump().items():
            if isinstance(v, float) and true.get(p) and v and abs(v / true[p] - 1) > OFF:
                out.append((ax, p, v / true[p], sd.get(p, float("nan")) / v))
    return out


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seed", type=int, default=91)
    ap.add_argument("--machine", type=int, default=4)
    ap.add_argument("--program", default="spiral G64", choices=PROGRAMS)
    ap.add_argument("--draws", type=int, default=DRAWS)
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    truth, model = identified(args.seed, args.machine)
    full, planned, radius = commands(args.program, model)
    comp, _ = compensation_of(model, (full, planned), radius, draws=args.draws)
    print(f"shares kept: {comp.robustness['factors']}")

    def line(label, machine):
        b, a = overshoots(machine, comp, full, radius)
        print(f"{label:<44} {b:8.2f} -> {a:8.2f} um")

    line("truth", truth)
    line("model", model)
    for part in PARTS:
        line(f"truth with the model's {part}", with_part(truth, model, part))
    for ax, p, ratio, rel in off_parameters(truth, model):
        line(f"truth with the model's {ax} {p} ({ratio:.3f}, sd {rel:.0%})",
             with_part(truth, model, "mechanics", ax, p))


if __name__ == "__main__":
    main()
