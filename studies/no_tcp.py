"""Machines measured without a TCP device: each bench's bundle with its ``tcp_mm`` columns
and the TCP sensor taken away, identified, and its four measured circles set against the
intervals of the model it gives (the measured TCP, which the model never saw).

As a user runs it: ``tcpmm identify``, and for each measured circle ``tcpmm simulate`` and
``tcpmm compare ... --model --json``. Printed per bench: how many TCP figures lie inside
their 90 % intervals, the verdicts, the median half-width and the largest |measured -
predicted|.

Run: ``.venv/bin/python -m studies.no_tcp OUT [--benches c,d,e,h,r05,r17] [--data DIR]``
"""

from __future__ import annotations

import argparse
import json
import shutil
import statistics
from pathlib import Path

import pandas as pd
import yaml

from . import DATA
from .cut_sweep import FIGURES
from .same_bits import CASES, tcpmm


def without_tcp(source: Path, folder: Path) -> Path:
    """The bundle ``source`` copied to ``folder`` without its TCP device [-]."""
    shutil.copytree(source, folder, dirs_exist_ok=True)
    for f in folder.glob("*/*.csv"):
        d = pd.read_csv(f)
        d.drop(columns=["tcp_mm"], errors="ignore").to_csv(f, index=False,
                                                            float_format="%.9g")
    m = yaml.safe_load((folder / "machine.yaml").read_text())
    for a in m["axes"].values():
        a["sensors"].pop("tcp_resolution_um", None)
    (folder / "machine.yaml").write_text(yaml.safe_dump(m, sort_keys=False))
    return folder


def judged(bench: Path, out: Path) -> list[dict]:
    """The TCP figures of ``bench``'s measured circles against the model identified from
    its bundle without the TCP device: per figure its row of ``compare --json`` [-]."""
    model = out / "model.yaml"
    tcpmm("identify", without_tcp(bench / "bundle", out / "bundle"), "-o", model)
    rows = []
    for case in CASES:
        pred, cmp_ = out / f"pred_{case}.csv", out / f"cmp_{case}.json"
        tcpmm("simulate", model, "--command", bench / f"circle_{case}_cmd.csv", "-o", pred)
        tcpmm("compare", bench / f"circle_{case}_meas.csv", pred, "--radius", "35",
              "--model", model, "--json", stdout=cmp_)
        for row in json.loads(cmp_.read_text())["tcp_judged"]:
            rows += [{"inside": bool(row[f"{f}_inside"]), "verdict": row[f"{f}_verdict"],
                      "half_um": row[f"{f}_90_um"], "off_um": abs(row[f"{f}_um"])}
                     for f in FIGURES]
    return rows


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("out", type=Path, help="folder for the bundles, models and outputs")
    p.add_argument("--benches", default="c,d,e,h,r05,r17")
    p.add_argument("--data", type=Path, default=DATA)
    args = p.parse_args(argv)
    print("| bench | inside | firm / uncertain / undetermined | median half-width [µm] | "
          "largest \\|measured - predicted\\| [µm] |\n|---|---|---|---|---|")
    for b in args.benches.split(","):
        rows = judged(args.data / f"bench_{b}", args.out / b)
        n = {v: sum(r["verdict"] == v for r in rows)
             for v in ("firm", "uncertain", "undetermined")}
        print(f"| {b.upper()} | {sum(r['inside'] for r in rows)} of {len(rows)} | "
              f"{n['firm']} / {n['uncertain']} / {n['undetermined']} | "
              f"{statistics.median(r['half_um'] for r in rows):.1f} | "
              f"{max(r['off_um'] for r in rows):.2f} |")


if __name__ == "__main__":
    main()
