"""The table damping that a guideway share from the sweep rests on: its two measures and
how they are combined, against the truth.

On every axis whose share comes from the TCP deflection of the travelling sweep, the
table's viscous force (``C_t`` with the guideway's viscous friction) has two measures:
the slope of the nut deflection over the plateaus of the friction runs, and the FRFs'
``C_t``. This study collects both, with their standard deviations, on the reference
machines and on the package's own unseen machines, and compares four rules of taking the
table damping from them with the truth:

- ``before``: the plateaus' figure where its relative deviation is within 10 %, else the
  FRFs' ``C_t``, at most the steady slope less the FRFs' screw-side damping;
- ``plateaus`` and ``FRFs`` alone;
- ``weighed``: both by their inverse variances, the FRFs' where they determine ``C_t``
  (what identify does, ``tcpmm.ident.friction.table_viscous_estimate``).

The plateau measure is the one identify ended with (its share settled with the weighed
damping), so the other rules are judged on the same plateaus. Run:
``.venv/bin/python -m studies.table_damping [--seeds 0 1] [--n 12] [--json FILE]``.
"""

from __future__ import annotations

import argparse
import json
import math
import tempfile
import warnings
from pathlib import Path

import numpy as np

from tcpmm.ident.pipeline import identify_bundle
from tcpmm.io.bundle import read_bundle
from tcpmm.io.truthfile import machine_from_truth
from tcpmm.machines.virtual import virtual_bundle

from . import DATA
from .unseen import draw_machine

#: The own studies: (label, LuGre fraction, range of the guideway share, pre-sliding of
#: the identified contacts: 0.5 um as the unseen-machine study gives them, or fitted).
STUDIES = (("default", 1 / 3, (0.2, 0.9), 0.5e-6), ("LuGre", 1.0, (0.2, 0.9), None),
           ("share 0.03-0.15", 1 / 3, (0.03, 0.15), 0.5e-6))


def axis_rows(idn, true, tag: str) -> list[dict]:
    """The two measures, what the model took, the truth and what the old rule needs, per
    axis whose share came from the sweep [SI]."""
    rows = []
    for name, a in idn.axes.items():
        sp = a.friction_split
        if sp is None or sp.source != "sweep":
            continue
        t, m = true.axis(name), a.physical.mechanics
        g = t.friction.guideway
        fv = dict(zip(a.friction.names, a.friction.values, strict=True))["Fv"]
        rows.append(dict(
            tag=tag, axis=name, plateaus=sp.estimate.table_viscous,
            plateaus_std=sp.estimate.table_viscous_std, frf=m.C_t,
            frf_std=a.physical.std.get("C_t", math.nan), weighed=sp.viscous_on_table,
            room=fv - (m.B_m + m.B_L) / m.R_L**2,
            true=t.mechanics.C_t + (g.fv_pos if g is not None else 0.0)))
    return rows


def rule_before(r) -> float:
    """The plateaus' where they determine it within 10 %, else the FRFs' capped [N s/m]."""
    p, sd = r["plateaus"], r["plateaus_std"]
    if math.isfinite(p) and math.isfinite(sd) and 0 < sd < 0.1 * p:
        return p
    return min(r["frf"], max(r["room"], 0.0))


RULES = {"before": rule_before,
         "plateaus": lambda r: r["plateaus"] if math.isfinite(r["plateaus"]) else math.nan,
         "FRFs": lambda r: r["frf"],
         "weighed": lambda r: r["weighed"]}


def reference_rows(data: Path) -> list[dict]:
    """Rows of machines C, D and E [-]."""
    rows = []
    for letter in "cde":
        folder = data / f"bench_{letter}"
        idn = identify_bundle(read_bundle(folder / "bundle"))
        rows += axis_rows(idn, machine_from_truth(folder / "truth.yaml"), letter.upper())
    return rows


def own_rows(seeds, n: int) -> list[dict]:
    """Rows of the own unseen machines of every study and seed [-]."""
    rows = []
    for label, lugre, share, presliding in STUDIES:
        for seed in seeds:
            for i in range(n):
                true, _ = draw_machine(seed, i, False, lugre, share)
                with tempfile.TemporaryDirectory() as tmp:
                    virtual_bundle(true, Path(tmp) / "bundle", axes=("X", "Y"))
                    idn = identify_bundle(read_bundle(Path(tmp) / "bundle"),
                                          presliding=presliding)
                rows += axis_rows(idn, true, f"{label}, seed {seed}, machine {i}")
    return rows


def summary(rows: list[dict], title: str) -> None:
    """Relative error of each rule against the truth: median, 90th percentile, count
    above 20 % [-]."""
    print(f"{title}: {len(rows)} axes with the share from the sweep")
    print(f"  {'rule':10s} {'median':>8s} {'p90':>8s} {'largest':>8s} {'above 20 %':>11s}")
    for name, rule in RULES.items():
        e = np.array([abs(rule(r) / r["true"] - 1.0) for r in rows])
        e = np.where(np.isfinite(e), e, np.inf)
        print(f"  {name:10s} {np.median(e):8.3f} {np.quantile(e, 0.9):8.3f} "
              f"{e.max():8.3f} {int(np.sum(e > 0.2)):11d}")


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--data", type=Path,
                   default=DATA)
    p.add_argument("--seeds", type=int, nargs="+", default=[0, 1])
    p.add_argument("--n", type=int, default=12, help="machines per seed")
    p.add_argument("--json", type=Path, help="write the rows to this file")
    a = p.parse_args(argv)
    warnings.simplefilter("ignore")
    ref = reference_rows(a.data)
    own = own_rows(a.seeds, a.n)
    summary(ref, "reference machines C, D, E")
    summary(own, "own unseen machines")
    if a.json:
        a.json.write_text(json.dumps(ref + own, indent=1))


if __name__ == "__main__":
    main()
