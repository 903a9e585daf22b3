"""How much a small parameter error moves the reversal spikes of a circular test.

The random machines of ``studies/unseen_machines.py`` are taken as they are drawn (no
identification, no measurement noise): each one's circle (R35 mm, F5000 mm/min, CCW then
CW) is simulated, then simulated again with one parameter of both axes changed by a small
step up and down, and the TCP figures of the two are compared as ``unseen_machines.py``
compares measured and predicted ones. Each step is at most what identification gets wrong
on machines it has not seen (:data:`tcpmm.whatif.spread.MODEL_ERROR`); those of the share and
the mechanics are a third to a half of it:

``level``
    Friction of both contacts times ``1 +- 0.02``.
``share``
    Guideway share of the friction ``+- 0.03``, the total kept.
``play``
    Lost motion of the screw-nut ``+- 0.04 um`` (only with ``--backlash``).
``C_t``
    Table damping times ``1 +- 0.05``.
``K_t``
    Nut stiffness times ``1 +- 0.02``.
``M_t``
    Table mass times ``1 +- 0.02``.

For each machine and step the script prints the largest change of a spike over the
quadrant points and directions, and after the slash the largest change of its rise or
fall (which does not jump where a spike changes sign between two lobes of similar size).
The summary counts the machines where a step moves a spike by more than the paper's
largest difference, 4.1 um: where it does, no identification whose errors are that size
can predict that spike within 4.1 um.

Usage::

    python -m studies.spike_sensitivity [--seeds 0 1 2 3] [--n 12] [--backlash]
                                         [--only 2 5] [--json FILE]
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

from tcpmm.demo import paper_circle_command
from tcpmm.model import Axis

from .unseen import (
    AXES,
    DIRECTIONS,
    PAPER_MAX,
    QUADRANTS,
    differences,
    draw_machine,
    friction_split,
    max_abs_spike,
    predicted_figures,
    resplit,
    scale_friction,
    with_axes,
)

#: Steps of the parameters: relative, apart from the share [-] and the lost motion [m].
STEPS = {"level": 0.02, "share": 0.03, "play": 0.04e-6, "C_t": 0.05, "K_t": 0.02, "M_t": 0.02}


def stepped(axis: Axis, name: str, sign: int) -> Axis:
    """``axis`` with parameter ``name`` moved by its step in direction ``sign`` [-]."""
    h = sign * STEPS[name]
    fr = axis.friction
    if name in ("C_t", "K_t", "M_t"):
        m = axis.mechanics
        return axis.replace(mechanics=m.replace(**{name: getattr(m, name) * (1 + h)}))
    if fr is None:
        return axis
    if name == "level":
        return axis.replace(friction=fr.model_copy(update={
            "guideway": scale_friction(fr.guideway, 1 + h),
            "screw": scale_friction(fr.screw, 1 + h)}))
    if name == "share":
        return axis.replace(friction=resplit(fr, friction_split(fr)[0] + h))
    if name == "play":
        return axis.replace(friction=fr.model_copy(update={"backlash": max(fr.backlash + h, 0.0)}))
    raise KeyError(name)


def largest_lobe(diff) -> float:
    """Largest ``|rise or fall difference|`` over directions and quadrants [m]."""
    return max(abs(diff[d]["lobes"][q]) for d in DIRECTIONS for q in QUADRANTS)


def sensitivity(machine, cmd, names) -> dict:
    """Largest spike and lobe changes per parameter step, both signs [m].

    Parameters
    ----------
    machine : Machine
        The machine [SI].
    cmd : Command
        The circle command [m].
    names : iterable of str
        Keys of :data:`STEPS` [-].

    Returns
    -------
    dict
        ``{name: {"spike": m, "lobe": m}}`` [-].
    """
    base = predicted_figures(machine, cmd)
    out = {}
    for name in names:
        spike = lobe = 0.0
        for sign in (1, -1):
            moved = with_axes(machine, lambda n, s=sign, k=name: stepped(machine.axes[n], k, s))
            d = differences(base, predicted_figures(moved, cmd))
            spike, lobe = max(spike, max_abs_spike(d)), max(lobe, largest_lobe(d))
        out[name] = {"spike": spike, "lobe": lobe}
    return out


def summary(rows: list, names) -> dict:
    """Per step, and for the largest of all steps per machine: machines above 4.1 um
    (spike, lobe), median and largest spike change [m]."""
    def largest(keys, what):
        return np.array([max(r["steps"][k][what] for k in keys) for r in rows])

    s = {}
    for name, keys in [*((k, [k]) for k in names), ("any", names)]:
        sp, lo = largest(keys, "spike"), largest(keys, "lobe")
        s[name] = {"spike_above": int(np.sum(sp > PAPER_MAX)),
                   "lobe_above": int(np.sum(lo > PAPER_MAX)),
                   "spike_median": float(np.median(sp)), "lobe_median": float(np.median(lo)),
                   "spike_max": float(np.max(sp))}
    return s


def main(argv=None) -> int:
    """Command line entry point."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", type=int, nargs="+", default=[0], help="study seeds")
    ap.add_argument("--n", type=int, default=12, help="machines per seed")
    ap.add_argument("--only", type=int, nargs="+", help="only these machine numbers")
    ap.add_argument("--backlash", action="store_true", help="machines with 0-8 um lost motion")
    ap.add_argument("--json", type=Path, help="write the numbers (SI) to this file")
    args = ap.parse_args(argv)
    names = [k for k in STEPS if args.backlash or k != "play"]
    cmd = paper_circle_command()
    rows, t0 = [], time.perf_counter()
    print("seed machine  " + "  ".join(f"{k:>13s}" for k in names)
          + "   lost motion X/Y [um]   (spike/lobe change [um])")
    for seed in args.seeds:
        for i in (args.only if args.only else range(args.n)):
            true, _ = draw_machine(seed, i, args.backlash)
            steps = sensitivity(true, cmd, names)
            play = [true.axes[n].friction.backlash * 1e6 if true.axes[n].friction else 0.0
                    for n in AXES]
            rows.append({"seed": seed, "machine": i, "backlash": play, "steps": steps})
            print(f"{seed:4d} {i:7d}  " + "  ".join(
                f"{steps[k]['spike'] * 1e6:6.2f}/{steps[k]['lobe'] * 1e6:6.2f}" for k in names)
                + f"   {play[0]:5.2f} / {play[1]:5.2f}", flush=True)
    s = summary(rows, names)
    print(f"\n=== {len(rows)} machines: a step moves a spike by more than 4.1 um on")
    for name, v in s.items():
        step = ("any one step" if name == "any" else
                f"{name} {STEPS[name] * (1e6 if name == 'play' else 1):g}")
        print(f"  {step:14s} {v['spike_above']:3d} machines ({v['lobe_above']} lobe by lobe); "
              f"median change {v['spike_median'] * 1e6:.2f} um, largest "
              f"{v['spike_max'] * 1e6:.2f} um")
    print(f"  total time {time.perf_counter() - t0:.0f} s")
    if args.json:
        args.json.write_text(json.dumps({"backlash": args.backlash, "steps": STEPS,
                                         "units": "SI (m)", "machines": rows, "summary": s},
                                        indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
