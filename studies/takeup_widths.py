"""The take-up width on circles whose reversals carry a transient.

1. The suite's dead-band circles (``tests/test_circle_takeup.py``: 4 and 6 um of backlash
   taken up as a dead band, 0.05 um of noise) with a spike of the height given 3 deg
   after every quadrant point: the widths read, or why they are open.
2. The circles of ``../shared/data/bench_*`` (no play in their truths) at F5000 and
   F10000, at the TCP and the linear scale: the widths and backlashes read, or why a
   width is open (``transient``: the spikes after the terms stand out; ``lingers``: a
   transient lasts past the window; ``backlash``: the backlash is open; ``samples``: the
   samples do not tell the width).

Not a test: ``python -m studies.takeup_widths`` (about 1 min).
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from . import DATA

#: The start of each reason a width is open, and its short name
WHY = (("the reversals' own transient", "transient"), ("a transient lasts past", "lingers"),
       ("the backlash it takes up is open", "backlash"), ("the samples after", "samples"))


def shown(diag, axis: str) -> str:
    """A width with its ±95 %, or why it is open [-]."""
    k = f"take_up_width_{axis}"
    if np.isfinite(diag[k]):
        return f"{diag[k] * 1e6:.2f} ± {2 * diag.sigma[k] * 1e6:.2f}"
    said = diag.undetermined.get(k, "")
    return next((name for start, name in WHY if said.startswith(start)), "n/a")


def backlash(diag, axis: str) -> str:
    """A backlash, n/a where open [µm]."""
    v = diag[f"backlash_{axis}"]
    return f"{v * 1e6:.2f}" if np.isfinite(v) else "n/a"


def main() -> None:
    warnings.simplefilter("ignore")
    from tcpmm.analysis.circular import analyse_circle
    from tcpmm.analysis.diagnostics import circle_diagnostics
    from tcpmm.io.runfile import read_run
    from test_circle_takeup import diagnose_dead_band

    print("| circles | width X [µm] | width Y [µm] | backlash X, Y [µm] |")
    print("|---|---|---|---|")
    for height in (0.0, 0.2, 1.0, 5.0):
        spike = {(d, q): (height * 1e-6, 3.0) for d in ("ccw", "cw") for q in "ABCD"}
        d = diagnose_dead_band({"b_x": 4e-6, "b_y": 6e-6, "spikes": spike})
        print(f"| dead bands 4, 6 µm, spike {height:g} µm | {shown(d, 'X')} | {shown(d, 'Y')} "
              f"| {backlash(d, 'X')}, {backlash(d, 'Y')} |", flush=True)
    for m in ("c", "d", "e", "h", "r05", "r17"):
        for fast, feed in (("", "F5000"), ("_fast", "F10000")):
            files = [DATA / f"bench_{m}" / f"circle_{w}{fast}_meas.csv" for w in ("ccw", "cw")]
            res = [analyse_circle(read_run(f), 0.035) for f in files]
            for sensor in ("tcp", "scale"):
                d = circle_diagnostics(*res, sensor=sensor)
                print(f"| bench_{m} {feed} {sensor} | {shown(d, 'X')} | {shown(d, 'Y')} "
                      f"| {backlash(d, 'X')}, {backlash(d, 'Y')} |", flush=True)


if __name__ == "__main__":
    main()
