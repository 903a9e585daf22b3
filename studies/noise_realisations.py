"""Identify the reference machines again with more sensor noise, and compare their circles.

Three machines of an independent simulator are few. A method that holds on machines it has
not seen should at least hold on the same machines measured again. This study does the
nearest thing it can: it adds a second noise realisation to the recorded positions of each
``bundle/`` (motor angle, scale and TCP of the sweep and the friction runs). Each sample
gets normal noise of ``--sigma`` sensor steps (default 0.5: the encoder noise of that
simulator). Then each bundle is identified again and its four measured circles are
predicted. Seed 0 is the bundle as recorded.

Per machine and seed it prints the largest |measured - predicted| TCP reversal spike at
B-D / TCP contour-error difference of each circle, in um (as ``reference_machines.py``),
and the parameters that moved most: the current-loop bandwidth, the motor inertia against
the screw's, and the pre-sliding distance of each axis.

Run: ``.venv/bin/python -m studies.noise_realisations [--seeds 0,1,2,3]
[--machines cde] [--sigma 0.5]``.
"""

from __future__ import annotations

import argparse
import shutil
import tempfile
import warnings
from pathlib import Path

import numpy as np
import pandas as pd

from tcpmm.ident.pipeline import identify_bundle
from tcpmm.io.bundle import read_bundle

from . import DATA
from .reference_machines import CASES, misfit

#: Recorded position columns that get the extra noise.
COLUMNS = ("motor_angle_rad", "scale_mm", "tcp_mm")


def _step(x: np.ndarray) -> float:
    """Smallest nonzero step of a rounded signal [as x]."""
    d = np.abs(np.diff(x))
    d = d[d > 0]
    return float(d.min()) if d.size else 0.0


def noisy_bundle(bundle: Path, out: Path, seed: int, sigma: float) -> Path:
    """A copy of ``bundle`` with normal noise of ``sigma`` steps on its position columns
    (none for seed 0) [-]."""
    shutil.copytree(bundle, out)
    if seed == 0:
        return out
    rng = np.random.default_rng(seed)
    for f in sorted(out.glob("*/*.csv")):
        table = pd.read_csv(f)
        for c in COLUMNS:
            if c in table:
                x = table[c].to_numpy(float)
                table[c] = x + rng.normal(0.0, sigma * _step(x), x.size)
        table.to_csv(f, index=False, float_format="%.15g")
    return out


def _parameters(idn) -> str:
    cells = []
    for name, a in idn.axes.items():
        m = a.axis.mechanics
        fit = a.presliding_fit
        z = fit.presliding * 1e6 if fit is not None and fit.determined else float("nan")
        cells.append(f"{name}: f_cl {a.axis.servo.current_bandwidth_hz:5.0f} Hz, "
                     f"J_m/J_L {m.J_m / m.J_L:.3f}, z {z:4.2f} um")
    return "; ".join(cells)


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--data", type=Path,
                   default=DATA)
    p.add_argument("--machines", default="cde")
    p.add_argument("--seeds", default="0,1,2,3")
    p.add_argument("--sigma", type=float, default=0.5, help="noise [sensor steps]")
    args = p.parse_args(argv)
    print("machine seed " + "  ".join(f"{c:>13s}" for c in CASES) + "   (spike / contour, um)")
    for letter in args.machines:
        folder = args.data / f"bench_{letter}"
        for seed in (int(s) for s in args.seeds.split(",")):
            with tempfile.TemporaryDirectory() as tmp, warnings.catch_warnings():
                warnings.simplefilter("ignore")
                b = noisy_bundle(folder / "bundle", Path(tmp) / "bundle", seed, args.sigma)
                idn = identify_bundle(read_bundle(b))
            cells = [misfit(idn.machine, folder, c) for c in CASES]
            print(f"{letter.upper():7s} {seed:4d} "
                  + "  ".join(f"{s:5.2f} / {c:4.2f}" for s, c in cells), flush=True)
            print(f"             {_parameters(idn)}", flush=True)


if __name__ == "__main__":
    main()
