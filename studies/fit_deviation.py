"""How far the mechanics' reported standard deviations are from their real errors, on a
drawn population of machines whose truth is known.

Every machine of :mod:`studies.population` is measured with the bench protocol and
identified from that bundle alone; per axis and mechanical quantity the study records the
identified value, the true one and the reported standard deviation. The true table damping
is compared with its steady equivalent, ``C_t`` plus the guideway's viscous friction: the
friction runs place the whole viscous force the table side carries into ``C_t``.

The statistic is ``z = |ln(identified / true)| / (sd / identified)`` on the axes whose
mechanics the data determine (no ``mechanics`` open range), and ``z = |share - true| / sd``
for the guideway share the friction runs' plateaus read on an axis whose sweep friction
held, where it bounds that axis' share (:func:`tcpmm.uncertainty.ranges.open_ranges`);
for a deviation that matches
its error, the median of ``|z|`` is 0.674 (the normal's). The scale a quantity's deviation
needs is its median ``|z|`` over 0.674, at least one. Printed per quantity: the median and
90th percentile of ``|z|`` with the deviations as reported (with the shipped scales of
``tcpmm/data/fit_deviation.json``) and as the fits give them (without), and the scale.

Run: ``.venv/bin/python -m studies.fit_deviation --seeds 0 1 [--json FILE]``; ``--write``
stores the scales the seeds give in ``src/tcpmm/data/fit_deviation.json``; ``--rows FILE``
summarises saved rows without running.
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
from pathlib import Path

from tcpmm.ident.friction.sensitivity import coulomb_share
from tcpmm.ident.physical.uncertainty import FIT_DEVIATION_SCALE
from tcpmm.uncertainty.ranges import PLATEAU_SHARE_REL_SD

from .population import identified

MECHANICS = ("J_m", "J_L", "K_L", "M_t", "C_t", "K_t", "M_b", "C_b", "K_b", "M_h", "C_h", "K_h")
QUANTITIES = (*MECHANICS, "plateau_share")
#: Median of |z| of a standard normal [-].
NORMAL_MEDIAN_ABS = 0.6745
DATA_FILE = Path(__file__).resolve().parents[1] / "src" / "tcpmm" / "data" / "fit_deviation.json"


def _true_value(axis, p: str) -> float:
    """The true value the identified one estimates [SI]."""
    v = getattr(axis.mechanics, p)
    g = axis.friction.guideway if axis.friction is not None else None
    if p == "C_t" and g is not None:
        v += 0.5 * (g.fv_pos + g.fv_neg)
    return float(v)


def _plateau_row(truth_axis, ident_axis):
    """True share, the plateaus' own share and its deviation, on an axis whose sweep
    friction held; ``None`` elsewhere."""
    sp = ident_axis.friction_split
    if ident_axis.friction_hold is None or sp is None or truth_axis.friction is None:
        return None
    if not (math.isfinite(sp.plateau_share) and math.isfinite(sp.plateau_share_std)):
        return None
    return [coulomb_share(truth_axis.friction), float(sp.plateau_share),
            float(sp.plateau_share_std)]


def axis_rows(seed: int, index: int) -> list[dict]:
    """One row per axis of machine ``index`` of population ``seed``."""
    truth, letter, idn = identified(seed, index)
    if isinstance(idn, Exception):  # a refused machine has no deviations to judge
        return []
    rows = []
    for name, a in truth.axes.items():
        b = idn.machine.axes[name]
        u = b.uncertainty
        row = {"seed": seed, "machine": index, "template": letter, "axis": name,
               "open": sorted({r.quantity for r in u.open})}
        row["plateau_share"] = _plateau_row(a, idn.axes[name])
        for p in MECHANICS:
            sd = u.mechanics.get(p)
            row[p] = [_true_value(a, p), float(getattr(b.mechanics, p)),
                      None if sd is None else sd / FIT_DEVIATION_SCALE.get(p, 1.0)]
        rows.append(row)
    return rows


def z_scores(rows: list[dict], p: str, shipped: bool) -> list[float]:
    """|z| of quantity ``p`` over the axes whose mechanics the data determine, with the
    fits' deviations (rows hold them unscaled) times the shipped scale or as they are [-]."""
    k = FIT_DEVIATION_SCALE.get(p, 1.0) if shipped else 1.0
    out = []
    for r in rows:
        if p == "plateau_share":  # absolute, where the plateaus bound a held sweep's share
            if r.get(p) is not None and r[p][2] <= PLATEAU_SHARE_REL_SD * r[p][1]:
                out.append(abs(r[p][1] - r[p][0]) / (k * r[p][2]))
            continue
        true, fit, sd = r[p]
        if "mechanics" in r["open"] or not (true > 0 and fit > 0 and sd):
            continue
        out.append(abs(math.log(fit / true)) / (k * sd / fit))
    return out


def scales(rows: list[dict]) -> dict:
    """Per quantity the factor the fits' deviations need, at least one [-]."""
    out = {}
    for p in QUANTITIES:
        z = z_scores(rows, p, shipped=False)
        if z:
            out[p] = round(max(1.0, statistics.median(z) / NORMAL_MEDIAN_ABS), 1)
    return out


def report(rows: list[dict]) -> None:
    """Median and 90th percentile of |z| as reported and as fitted, and the scale."""
    need = scales(rows)
    print(f"{len(rows)} axes, {sum('mechanics' not in r['open'] for r in rows)} whose "
          "mechanics the data determine")
    print("quantity  reported: median |z|  90 %  |  fitted: median |z|  90 %  | scale")
    for p in QUANTITIES:
        line = [p]
        for shipped in (True, False):
            z = sorted(z_scores(rows, p, shipped))
            line += [statistics.median(z), z[int(0.9 * (len(z) - 1))]] if z else [math.nan] * 2
        print("{:8s}  {:19.2f}  {:4.1f}  |  {:17.2f}  {:4.1f}  | {}".format(
            *line, need.get(p, "-")))


def write_scales(rows: list[dict], seeds: list[int]) -> None:
    """Store the scales in the package's data file, with their provenance."""
    text = json.dumps({
        "what": "Factors on the standard deviations the mechanics' fits report, and on the "
                "friction runs' plateaus' own guideway share ('plateau_share'): the median "
                "|ln(identified/true)| / (sd/identified) (|share - true| / sd) over 0.6745, "
                "at least 1, on the axes whose mechanics the data determine (whose sweep "
                "friction held).",
        "provenance": "python -m studies.fit_deviation --seeds "
                      + " ".join(str(s) for s in seeds) + " --write "
                      f"({len(rows)} axes of the drawn population of studies.population).",
        "scale": scales(rows)}, indent=1)
    DATA_FILE.write_text(text + "\n", encoding="utf-8")


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--seeds", type=int, nargs="+", default=[0, 1])
    p.add_argument("--n", type=int, default=24)
    p.add_argument("--json", type=Path)
    p.add_argument("--rows", type=Path, nargs="+")
    p.add_argument("--write", action="store_true")
    args = p.parse_args(argv)
    if args.rows:
        rows = [r for f in args.rows for r in json.loads(f.read_text())]
    else:
        rows = []
        for seed in args.seeds:
            for i in range(args.n):
                rows += axis_rows(seed, i)
                print(f"seed {seed} machine {i}", flush=True)
        if args.json:
            args.json.write_text(json.dumps(rows, indent=1))
    report(rows)
    if args.write:
        write_scales(rows, args.seeds)


if __name__ == "__main__":
    main()
