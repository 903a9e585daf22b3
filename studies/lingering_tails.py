"""Reversal transients that last past the window the circle fit leaves out.

The suite's circles (``tests/test_circle_diagnostics.py``: R 35 mm in 7.2 s, 0.05 um of
noise on each axis) with a pulse ``h (u / p) exp(1 - u / p)`` of radial error after each
quadrant point (``tests/test_circle_lingering.py``, ``pulsed``: -5 um after X's reversals,
+4 um after Y's), peaking ``p`` degrees after the point, with and without 3 um of
backlash on each axis. Per case: what the tail check says, the backlash X read with its
uncertainty by the reversals' tails, and the spikes after the terms whose ±95 % misses
the pulse's height. Not a test: ``python -m studies.lingering_tails``.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from test_circle_lingering import HEIGHTS, pair

PEAKS_DEG = (4.0, 8.0, 14.0, 20.0)
PLAY = ({}, {"b_x": 3e-6, "b_y": 3e-6})


def main() -> None:
    print("| peak [deg] | backlash [µm] | tail check | backlash X ± tails [µm] "
          "| spike A CCW ±95 % [µm] | spikes n/a | spikes missed |")
    print("|---:|---:|---|---|---|---:|---:|")
    for peak in PEAKS_DEG:
        for err in PLAY:
            d = pair(err, peak)
            said = d.undetermined.get("reversal_tail_decay", "")
            check = ("lasts past" if said.startswith("a transient lasts") else
                     "none" if said else "tail fitted")
            keys = [(f"spike_{q}_{w}", h) for q, h in HEIGHTS.items() for w in ("ccw", "cw")]
            shut = sum(bool(np.isnan(d[k])) for k, _ in keys)
            missed = sum(bool(abs(d[k] - h) > d.spike_u95[k]) for k, h in keys)
            moved = abs(d.tail_shift.get("backlash_X", 0.0))
            print(f"| {peak:g} | {err.get('b_x', 0.0) * 1e6:g} | {check} "
                  f"| {d['backlash_X'] * 1e6:.2f} ± {moved * 1e6:.2f} "
                  f"| {d['spike_A_ccw'] * 1e6:.2f} ± {d.spike_u95['spike_A_ccw'] * 1e6:.2f} "
                  f"| {shut} | {missed} |", flush=True)


if __name__ == "__main__":
    main()
