"""The TCP device's gain gate on a population of heavy and soft machines: bench machines of
the independent simulator with one axis's table and head masses (x0.5-3), head stiffness
(x0.3-2), head damping ratio (x0.5-2) and friction (x0.5-3) drawn log-uniform, each
recorded by :func:`tcpmm.virtual_bundle` with its TCP device true and with its ``tcp_mm``
column scaled (a device reading a share of the motion).

Per machine: the bench and axis, the factors drawn, the model's first mode, and for each
bundle what identification found about ``G_tcp`` (the gain against the model, the static
gain), or ``-``. The true device found is a false alarm, the scaled one not found a miss.

Run: ``.venv/bin/python -m studies.tcp_gain_population [--count 16] [--scale 1.04]``.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import tempfile
import warnings
from pathlib import Path

import numpy as np
import yaml

from tcpmm.ident.gates.masses import first_mode_hz
from tcpmm.ident.pipeline import identify_bundle
from tcpmm.io.bundle import read_bundle
from tcpmm.io.truthfile import machine_from_truth
from tcpmm.machines.virtual import virtual_bundle

DATA = Path(__file__).resolve().parents[1] / ".." / "shared" / "data"
BENCHES = ("c", "d", "e", "h", "r05", "r17")
FRICTION_KEYS = ("guide_Fc_N", "guide_Fs_N", "screw_Tc_Nm", "screw_Ts_Nm")


def draw_truth(index: int, data: Path) -> tuple[str, str, dict, dict]:
    """``(bench, axis, factors, truth)``: machine ``index`` of the population, its truth
    file's content with the one axis left [-]."""
    rng = np.random.default_rng([11, index])
    bench = BENCHES[index % len(BENCHES)]
    truth = yaml.safe_load((data / f"bench_{bench}" / "truth.yaml").read_text())
    axis = list(truth["axes"])[int(rng.integers(len(truth["axes"])))]
    a, m = truth["axes"][axis], truth["axes"][axis]["mechanics"]

    def draw(lo, hi):
        return float(math.exp(rng.uniform(math.log(lo), math.log(hi))))

    e = {"Mt": draw(0.5, 3), "Mh": draw(0.5, 3), "Kh": draw(0.3, 2), "zeta": draw(0.5, 2),
         "friction": draw(0.5, 3)}
    m["Mt_kg"] *= e["Mt"]
    m["Mh_kg"] *= e["Mh"]
    m["Kh_N_per_m"] *= e["Kh"]
    m["Ch_Ns_per_m"] *= e["zeta"] * math.sqrt(e["Kh"] * e["Mh"])
    for k in FRICTION_KEYS:
        if k in a["friction"]:
            a["friction"][k] *= e["friction"]
    truth["axes"] = {axis: a}
    return bench, axis, e, truth


def tcp_findings(bundle) -> tuple[str, float]:
    """``(found, first mode)``: what identifying ``bundle`` found about ``G_tcp`` [-, Hz]."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        idn = identify_bundle(bundle, verdict=False, accept_suspect=True)
    (a,) = idn.axes.values()
    found = [s.split(": ", 1)[1].split(", ")[0] for s in idn.machine.suspect
             if "TCP device" in s or "G_tcp" in s]
    found = [f.replace("gain of the TCP device against the scale", "TCP gain")
             .replace("static gain of G_tcp over its rigid-body value", "static G_tcp")
             for f in found]
    return "; ".join(found) or "-", first_mode_hz(a.axis.mechanics)


def row(index: int, scale: float, data: Path) -> str:
    """The table row of machine ``index`` [-]."""
    bench, axis, e, truth = draw_truth(index, data)
    with tempfile.TemporaryDirectory() as tmp:
        (Path(tmp) / "truth.yaml").write_text(yaml.safe_dump(truth, sort_keys=False))
        machine = machine_from_truth(Path(tmp) / "truth.yaml")
        true = read_bundle(virtual_bundle(machine, Path(tmp) / "bundle", axes=(axis,), seed=7))
    x = true.axes[axis]
    off = dataclasses.replace(true, axes={axis: dataclasses.replace(
        x, sweep=dataclasses.replace(x.sweep, tcp_m=scale * x.sweep.tcp_m))})
    (got, mode), (bad, _) = tcp_findings(true), tcp_findings(off)
    drawn = ", ".join(f"{k} {v:.2f}" for k, v in e.items())
    return f"| {index} | {bench.upper()} {axis} | {drawn} | {mode:.1f} | {got} | {bad} |"


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", default=str(DATA), help="folder holding bench_*/truth.yaml")
    ap.add_argument("--count", type=int, default=16, help="machines")
    ap.add_argument("--scale", type=float, default=1.04, help="the scaled TCP's factor")
    args = ap.parse_args(argv)
    print(f"| # | axis | factors | first mode [Hz] | TCP true | TCP x {args.scale:g} |")
    print("|---|---|---|---|---|---|")
    for index in range(args.count):
        print(row(index, args.scale, Path(args.data)), flush=True)


if __name__ == "__main__":
    main()
