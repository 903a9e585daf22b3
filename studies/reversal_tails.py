"""The reversals' tails past the window the circle fit leaves out: injected, and on the
independent simulator's machines.

1. The suite's circles (``tests/test_circle_diagnostics.py``: every error as the position
   error it is, R 35 mm in 7.2 s, 0.05 um of noise on each axis) with backlash, lateral
   play, squareness, scale and servo mismatch, a bow and a centre offset
   (``tests/test_reversal_tail.py``, ``BASE``), and after every quadrant point a tail of
   ``--height`` at the point decaying over a number of degrees, each reversal its own share
   (1, 0.3, -0.5, 0.8) or all alike: the reversing axis' position error (``axis``) or a
   radial error (``radial``). Per case: the time constant found with its ±95 %, and of the
   terms the one
   furthest from its injected value, as radial error, with what the diagnostics say of
   it (``~``: uncertain by the reversals' tails, by the move given).
2. The circles of ``../shared/data/bench_*`` at F5000 and F10000: the tails' time constant
   found against the position loop's ``1 / K_pp`` (``truth.yaml``, X axis), and the
   backlash.

With ``--without-tails`` the fit has no tail columns, as before it modelled them. Not a
test: ``python -m studies.reversal_tails [--height UM] [--without-tails]``.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import yaml

from tcpmm.analysis.circle_tails import moving_terms, radial_size
from tcpmm.analysis.circular import analyse_circle
from tcpmm.analysis.diagnostics import circle_diagnostics
from tcpmm.io.runfile import read_run

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
import test_circle_diagnostics as gen
from test_reversal_tail import BASE, SHARES, pair

TERMS = ("backlash_X", "backlash_Y", "lateral_play_X", "squareness", "scale_mismatch",
         "servo_mismatch", "straightness_Y", "centre_offset_X")
DATA = Path(__file__).resolve().parents[2] / "shared" / "data"


def worst(d, want):
    """The term furthest from its injected value as radial error: ``(name, off [m],
    flagged move or None [m])``."""
    per_unit = dict(gen.PER_UNIT)
    out = []
    for t in TERMS:
        off = abs(d[t] - want[t]) * per_unit.get(t, 1.0)
        moved = moving_terms(d).get(t)
        move = None if moved is None else radial_size(t, moved[1] - moved[0], gen.R)
        out.append((off, t, move))
    off, t, move = max(out)
    return t, off, move


def injected(height) -> None:
    want = gen.expected(BASE)
    print("| shape | shares | decay [deg] | found ±95 % [deg] | furthest term | off [µm] "
          "| said |")
    print("|---|---|---:|---:|---|---:|---|")
    for shape in ("axis", "radial"):
        for alike in (False, True):
            for decay in (8.0, 16.0, 30.0, 45.0):
                d = pair(height, decay, shape, shares=(1.0,) * 4 if alike else SHARES)
                t, off, move = worst(d, want)
                found = d.terms.get("reversal_tail_decay", (np.nan,))[0] * gen.W
                u95 = 2 * d.sigma.get("reversal_tail_decay", np.nan) * gen.W
                said = "firm" if move is None else f"~ {move * 1e6:.2f} µm"
                print(f"| {shape} | {'alike' if alike else 'own'} | {decay:.0f} | "
                      f"{np.degrees(found):.1f} ± {np.degrees(u95):.1f} | {t} "
                      f"| {off * 1e6:.2f} | {said} |")


def benches() -> None:
    print("\n| machine | feed | 1/K_pp X [ms] | tails' time constant [ms] | backlash X, Y [µm] |")
    print("|---|---|---:|---:|---|")
    for d in sorted(DATA.glob("bench_*")):
        truth = yaml.safe_load((d / "truth.yaml").read_text())
        kpp = _kpp(truth)
        for fast, feed in (("", "F5000"), ("_fast", "F10000")):
            files = [d / f"circle_{w}{fast}_meas.csv" for w in ("ccw", "cw")]
            if not all(f.exists() for f in files):
                continue
            res = [analyse_circle(read_run(f), 0.035) for f in files]
            diag = circle_diagnostics(*res)
            tau = diag.terms.get("reversal_tail_decay", (np.nan,))[0]
            ranked = moving_terms(diag)
            bx = f"{diag['backlash_X'] * 1e6:.2f}{'~' if 'backlash_X' in ranked else ''}"
            by = f"{diag['backlash_Y'] * 1e6:.2f}{'~' if 'backlash_Y' in ranked else ''}"
            u95 = 2 * diag.sigma.get("reversal_tail_decay", np.nan)
            shown = "none" if not np.isfinite(tau) else f"{tau * 1e3:.0f} ± {u95 * 1e3:.0f}"
            print(f"| {d.name} | {feed} | {1e3 / kpp:.0f} | {shown} | {bx}, {by} |")


def _kpp(truth) -> float:
    """The X axis' position loop gain from a bench's truth [1/s]."""
    def find(node):
        if isinstance(node, dict):
            if "Kpp_1_per_s" in node:
                return float(node["Kpp_1_per_s"])
            for v in node.values():
                got = find(v)
                if got is not None:
                    return got
        return None
    return find(truth) or float("nan")


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--height", type=float, default=3.0, help="tail at the point [um]")
    p.add_argument("--without-tails", action="store_true", help="fit no tail columns")
    a = p.parse_args(argv)
    if a.without_tails:
        import tcpmm.analysis.circle_fit as fit
        fit.search_tail = lambda pb, mu, waves: None
    injected(a.height * 1e-6)
    benches()


if __name__ == "__main__":
    main()
