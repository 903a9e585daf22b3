"""The verdict's 90 % intervals on a drawn population of machines whose truth is known.

Each machine is drawn about one of the independent simulator's machines (the truth of
``../shared/data/bench_{c,d,e,h,r05,r17}``, loaded into tcpmm), over wide ranges: masses,
stiffnesses and damping x0.5-2, friction level x0.5-2, guideway share 0.05-0.95, velocity
feed-forward 0-1, position loop 0.5, 1 or 2 ms, scales of 0.05-1 um; the velocity loop's
gains follow the drive's inertia. It is measured virtually as the bench protocol does (a
15 s log sweep of 2-1000 Hz at a quarter of the current limit while the axis travels at
10 mm/s, and the friction runs), identified from that bundle alone, and its reference
circles (R 35 mm, F5000 and F10000, CCW and CW) predicted with the verdict and simulated on
the true machine.

The machines are split in two: the even ones calibrate the factor (split-conformal over
machines: the per-machine largest score at rank ceil(0.9 (n + 1))), the odd ones check it.
Printed: coverage of the 90 % intervals, their median half-width, the firm figures and the
firm figures that miss their target, with the shipped factor and with the one the even
half gives.

Run: ``.venv/bin/python -m studies.population --n 24 [--seed 0] [--json FILE]``;
``--rows FILE [FILE ...]`` summarises saved rows (of several seeds) without running.
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import tempfile
import warnings
from pathlib import Path

import numpy as np

from tcpmm.ident.friction.sensitivity import with_share
from tcpmm.ident.pipeline import identify_bundle
from tcpmm.io.bundle import read_bundle, write_bundle
from tcpmm.io.truthfile import machine_from_truth
from tcpmm.machines.virtual import bundle_machine_yaml, virtual_friction, virtual_sweep
from tcpmm.uncertainty import CALIBRATION, figures, prediction_verdict, reference_tests

from . import DATA
from .unseen import axis_stable

TEMPLATES = ("c", "d", "e", "h", "r05", "r17")
SCALES_M = (0.05e-6, 0.1e-6, 0.5e-6, 1e-6)
POSITION_PERIODS_S = (0.5e-3, 1e-3, 2e-3)
GROUPS = {"mass": ("J_m", "J_L", "M_t", "M_b", "M_h"), "stiffness": ("K_L", "K_t", "K_b", "K_h"),
          "damping": ("B_m", "B_L", "C_t", "C_b", "C_h")}


def _log_uniform(rng, lo: float, hi: float) -> float:
    return float(math.exp(rng.uniform(math.log(lo), math.log(hi))))


def _draw_axis(rng, axis):
    """One axis drawn about a template axis; ``None`` when its sampled loop is unstable."""
    m = axis.mechanics
    upd = {p: getattr(m, p) * _log_uniform(rng, 0.5, 2.0)
           for names in GROUPS.values() for p in names}
    mech = m.replace(**upd)
    j_old = m.J_m + m.J_L + m.M_t * m.R_L ** 2
    j_new = mech.J_m + mech.J_L + mech.M_t * mech.R_L ** 2
    t_v = axis.servo.T_v
    t_p = max(t_v, round(float(rng.choice(POSITION_PERIODS_S)) / t_v) * t_v)
    servo = axis.servo.model_copy(update={
        "K_vp": axis.servo.K_vp * j_new / j_old, "K_vi": axis.servo.K_vi * j_new / j_old,
        "k_ff": float(rng.uniform(0.0, 1.0)), "T_p": t_p})
    fr = axis.friction
    if fr is not None:
        from tcpmm.whatif.spread import scaled_contact

        k = _log_uniform(rng, 0.5, 2.0)
        fr = fr.model_copy(update={"guideway": scaled_contact(fr.guideway, k),
                                   "screw": scaled_contact(fr.screw, k)})
        fr = with_share(fr, float(rng.uniform(0.05, 0.95))) or fr
    sensors = axis.sensors.model_copy(
        update={"scale_resolution": float(rng.choice(SCALES_M))})
    drawn = axis.replace(mechanics=mech, servo=servo, friction=fr, sensors=sensors)
    return drawn if axis_stable(drawn) else None


def draw(seed: int, index: int):
    """Machine ``index`` of population ``seed`` and the template it was drawn about."""
    rng = np.random.default_rng([seed, index])
    letter = TEMPLATES[index % len(TEMPLATES)]
    base = machine_from_truth(DATA / f"bench_{letter}" / "truth.yaml")
    axes = {}
    for name, a in base.axes.items():
        for _ in range(30):
            drawn = _draw_axis(rng, a)
            if drawn is not None:
                axes[name] = drawn
                break
        else:
            axes[name] = a
    return base.model_copy(update={"axes": axes, "name": f"drawn {seed}-{index}"}), letter


def measure(machine, folder: Path, seed: int) -> Path:
    """The bench protocol on a machine, as a bundle in ``folder``."""
    recs = {}
    for k, (name, a) in enumerate(machine.axes.items()):
        sweep = virtual_sweep(a, duration_s=15.0, band_hz=(2.0, 1000.0),
                              amplitude_A=0.25 * a.servo.current_limit,
                              travel_speed_m_per_s=0.01, seed=seed + k, name=name)
        recs[name] = {"sweep": sweep, "friction": virtual_friction(a, name=name)}
    return write_bundle({"machine": bundle_machine_yaml(machine, tuple(machine.axes)),
                         "axes": recs}, folder)


def identified(seed: int, index: int):
    """Machine ``index`` of population ``seed``, its template, and its identification from
    the bench protocol's bundle alone (the exception, where identification refused it)."""
    truth, letter = draw(seed, index)
    with tempfile.TemporaryDirectory() as tmp, warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            return truth, letter, identify_bundle(
                read_bundle(measure(truth, Path(tmp) / "b", index)), accept_suspect=True,
                verdict=False)
        except Exception as exc:  # a refusal is a result of the study, not its end
            return truth, letter, exc


def judge(seed: int, index: int) -> list[dict]:
    """One row per reference figure of machine ``index``: predicted, true, interval."""
    truth, letter, idn = identified(seed, index)
    if isinstance(idn, Exception):
        return [{"machine": index, "template": letter, "refused": str(idn)[:200]}]
    tests = reference_tests(idn.machine)
    true = figures(truth, tests)
    rows = []
    for f in prediction_verdict(idn.machine, tests).figures:
        key = (f.test, f.direction, f.figure)
        if key not in true:
            continue
        raw = (f.half_width - CALIBRATION["floor_m"]) / CALIBRATION["factor"]
        err = abs(true[key] - f.nominal)
        rows.append({"machine": index, "template": letter, "figure": f.figure,
                     "verdict": f.verdict, "error_m": err, "raw_m": raw,
                     "target_m": f.target, "suspect": bool(idn.findings)})
    return rows


def summary(rows: list[dict], factor: float) -> dict:
    """Coverage, median half-width and firm figures with a calibration factor."""
    hw = [factor * r["raw_m"] + CALIBRATION["floor_m"] for r in rows]
    inside = [r["error_m"] <= h for r, h in zip(rows, hw, strict=True)]
    firm = [h <= r["target_m"] for r, h in zip(rows, hw, strict=True)]
    miss = [f and r["error_m"] > r["target_m"] for r, f in zip(rows, firm, strict=True)]
    return {"figures": len(rows), "coverage": sum(inside) / max(len(rows), 1),
            "median_half_width_um": statistics.median(hw) * 1e6 if hw else math.nan,
            "firm": sum(firm), "firm_off_target": sum(miss)}


def conformal_factor(rows: list[dict]) -> float:
    """The split-conformal factor over machines: per machine the largest score, at rank
    ceil(0.9 (n + 1)) of n (the largest where n is too small) [-]."""
    per = {}
    for r in rows:
        s = r["error_m"] / r["raw_m"] if r["raw_m"] > 0 else math.inf
        per[r["machine"]] = max(per.get(r["machine"], 0.0), s)
    scores = sorted(per.values())
    rank = min(math.ceil(0.9 * (len(scores) + 1)), len(scores))
    return scores[rank - 1] if scores else math.nan


def _run(n: int, seed: int) -> list[dict]:
    """Judge machines ``0..n-1`` of population ``seed``, printing one line per machine."""
    rows = []
    for i in range(n):
        got = judge(seed, i)
        rows += [{**r, "seed": seed} for r in got]
        ok = [r for r in got if "refused" not in r]
        worst = max((r["error_m"] / r["raw_m"] for r in ok if r["raw_m"] > 0), default=0.0)
        print(f"machine {i:3d} ({got[0]['template']}): "
              + (f"refused: {got[0]['refused']}" if not ok else
                 f"{sum(r['verdict'] == 'firm' for r in ok)} of {len(ok)} firm, "
                 f"largest score {worst:.2f}"), flush=True)
    return rows


def report(rows: list[dict]) -> None:
    """The factor the even machines give, its check on the odd ones, and per template the
    coverage and widths with the shipped factor."""
    ok = [{**r, "machine": (r.get("seed", 0), r["machine"])} for r in rows
          if "refused" not in r]
    calib = [r for r in ok if r["machine"][1] % 2 == 0]
    check = [r for r in ok if r["machine"][1] % 2 == 1]
    k = conformal_factor(calib)
    machines = {(r.get("seed", 0), r["machine"]) for r in rows}
    print(f"refused: {sum('refused' in r for r in rows)} of {len(machines)} machines")
    print(f"factor from the even machines: {k:.2f}; from all: {conformal_factor(ok):.2f}")
    for name, part in (("odd machines", check), ("all machines", ok)):
        for label, f in (("shipped", CALIBRATION["factor"]), ("even half's", k)):
            print(f"{name}, {label} factor {f:.2f}: {summary(part, f)}")
    for letter in TEMPLATES:
        part = [r for r in ok if r["template"] == letter]
        if part:
            print(f"about {letter}: {summary(part, CALIBRATION['factor'])}")


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--n", type=int, default=24)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--json", type=Path)
    p.add_argument("--rows", type=Path, nargs="+")
    args = p.parse_args(argv)
    if args.rows:
        rows = [r for f in args.rows for r in json.loads(f.read_text())]
    else:
        rows = _run(args.n, args.seed)
        if args.json:
            args.json.write_text(json.dumps(rows, indent=1))
    report(rows)


if __name__ == "__main__":
    main()
