"""One direction of a circle on random machines: which terms read off, and which are open.

Each case is one circle, CCW or CW, from the generator of the suite's circle diagnostics
(``tests/test_circle_diagnostics.py``: every error injected as the position error it is,
each axis lagging its command by its own time and reversing where its own velocity turns,
0.05 um of noise on each axis), drawn at random:

- radius 20-100 mm, feed 2 000-10 000 mm/min, sampled every 1, 2 or 4 ms;
- Y lagging X by up to +-1.5 ms;
- backlash of each axis up to +-6 um, bows up to +-5 um, centre offset up to +-5 um;
- scale mismatch up to +-80 ppm, squareness up to +-80 um/m;
- a random start angle.

The circle is diagnosed alone (:func:`tcpmm.analysis.circle_single.diagnose_single`), and
each backlash, bow, centre offset and the scale mismatch is compared with what was
injected. A term is *off* where it is given (not NaN) and misses the injected value by more
than 2 % of it and by more than 0.1 um of the radial error it makes (the tolerance of the
suite's tests); *open* where it is NaN, with its reason under ``undetermined``. Not a test:
``python -m studies.one_direction [--seed N] [--cases N]``.
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import numpy as np

from tcpmm.analysis.circle_single import diagnose_single

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
import test_circle_diagnostics as gen  # the suite's generator

#: Term -> the generator's key and the radial error per unit of the term at radius ``r``
#: [-, m/unit].
TERMS = {"backlash_X": ("b_x", lambda r: 0.5), "backlash_Y": ("b_y", lambda r: 0.5),
         "straightness_X": ("str_x", lambda r: 1.0), "straightness_Y": ("str_y", lambda r: 1.0),
         "centre_offset_X": ("cx", lambda r: 1.0), "centre_offset_Y": ("cy", lambda r: 1.0),
         "scale_mismatch": ("eps_x", lambda r: r / 2)}


def draw(rng) -> tuple:
    """One case: radius [m], sample period [s], feed [mm/min], errors [SI], direction,
    start angle [deg]."""
    radius, dt, feed = rng.uniform(0.02, 0.1), rng.choice([1e-3, 2e-3, 4e-3]), \
        rng.uniform(2000, 10000)
    err = {"tau_y": rng.uniform(-1.5e-3, 1.5e-3), "b_x": rng.uniform(-6e-6, 6e-6),
           "b_y": rng.uniform(-6e-6, 6e-6), "str_x": rng.uniform(-5e-6, 5e-6),
           "str_y": rng.uniform(-5e-6, 5e-6), "cx": rng.uniform(-5e-6, 5e-6),
           "cy": rng.uniform(-5e-6, 5e-6), "eps_x": rng.uniform(-80e-6, 80e-6),
           "alpha": rng.uniform(-80e-6, 80e-6)}
    direction = "ccw" if rng.random() < 0.5 else "cw"
    return radius, float(dt), feed, err, direction, rng.uniform(0, 360)


def judge(case: int, rng) -> tuple[list, int]:
    """The terms off (``(case, term, found um, injected um, R mm, dt s, F, lag ms)``) and
    the number open of one case [-]."""
    radius, dt, feed, err, direction, start = draw(rng)
    gen.R, gen.DT = radius, dt
    n = round(2 * np.pi * radius / (feed / 60e3 * dt))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        diag = diagnose_single(*gen.circle(direction, err, case, start_deg=start, n=n),
                               direction, radius)
    off, opened = [], 0
    for term, (key, per_unit) in TERMS.items():
        true, found = err[key], diag[term]
        if not np.isfinite(found):
            opened += 1
        elif abs(found - true) > max(0.02 * abs(true), 0.1e-6 / per_unit(radius)):
            off.append((case, term, round(found * 1e6, 2), round(true * 1e6, 2),
                        round(radius * 1e3), dt, round(feed), round(err["tau_y"] * 1e3, 2)))
    return off, opened


def run_cases(argv, doc: str, judge) -> tuple:
    """The command line of a study of random cases (``--seed``, ``--cases``) and
    ``judge(case, rng)`` of each case, in order, from one generator: ``(args, results)``."""
    p = argparse.ArgumentParser(description=doc.splitlines()[0])
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--cases", type=int, default=120)
    args = p.parse_args(argv)
    rng = np.random.default_rng(args.seed)
    return args, [judge(case, rng) for case in range(args.cases)]


def main(argv=None) -> dict:
    args, results = run_cases(argv, __doc__, judge)
    off = [row for o, _ in results for row in o]
    opened = sum(n for _, n in results)
    print(f"seed {args.seed}: {args.cases} circles, {len(off)} terms off and not open, "
          f"{opened} open")
    for row in off:
        print("  case {}: {} {} um for {} (R {} mm, every {} s, F{}, lag {} ms)".format(*row))
    return {"cases": args.cases, "off": off, "open": opened}


if __name__ == "__main__":
    main()
