"""Pairs of partial arcs on random machines: which terms read off, and which are open.

Each case is a ballbar's partial-arc test, out along an arc CCW and back CW over the same
angles, from the generator of the suite's circle diagnostics
(``tests/test_circle_diagnostics.py``: every error injected as the position error it is,
each axis lagging its command by its own time and reversing where its own velocity turns,
0.05 um of noise on each axis), drawn at random:

- an arc of 210-330 deg from a random start angle;
- radius 20-100 mm, feed 2 000-10 000 mm/min, sampled every 1, 2 or 4 ms;
- Y lagging X by up to +-1.5 ms;
- backlash of each axis up to +-6 um, lateral play up to +-3 um, bows up to +-5 um,
  centre offset up to +-5 um;
- scale mismatch up to +-80 ppm, squareness up to +-80 um/m.

Every error is present, also those an arc cannot tell apart from others (the lateral play
and bow of an axis whose two ends the arc does not both reach): a machine has them all.
The pair is diagnosed (:func:`tcpmm.analysis.diagnostics.diagnose_pair`), and each term is
compared with what was injected. A term is *open* where it is NaN, with its reason under
``undetermined``; *conditional* where the diagnostics say it rests on a term the arcs do
not determine, and how much it moves per unit of that term (``aliases``); *off* where it
is neither and misses the injected value by more than 2 % of it and by more than 0.1 um of
the radial error it makes (the tolerance of the suite's tests). Not a test:
``python -m studies.arcs [--seed N] [--cases N]``.
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

import numpy as np

from tcpmm.analysis.diagnostics import diagnose_pair

from . import one_direction

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
import test_circle_diagnostics as gen  # the suite's generator

#: Term -> the generator's key and the radial error per unit of the term, of a circle of
#: radius R turning at w [-, m/unit]; the servo mismatch is ``tau_y - tau_x``.
TERMS = {"backlash_X": ("b_x", lambda R, w: 0.5), "backlash_Y": ("b_y", lambda R, w: 0.5),
         "lateral_play_X": ("p_x", lambda R, w: 0.5),
         "lateral_play_Y": ("p_y", lambda R, w: 0.5),
         "straightness_X": ("str_x", lambda R, w: 1.0),
         "straightness_Y": ("str_y", lambda R, w: 1.0),
         "centre_offset_X": ("cx", lambda R, w: 1.0),
         "centre_offset_Y": ("cy", lambda R, w: 1.0),
         "squareness": ("alpha", lambda R, w: R / 2),
         "scale_mismatch": ("eps_x", lambda R, w: R / 2),
         "servo_mismatch": ("tau_y", lambda R, w: R * w / 2)}


def draw(rng) -> tuple:
    """One case: radius [m], sample period [s], feed [mm/min], errors [SI], start and
    span of the arc [deg]; the circle's errors and its start drawn as
    :func:`studies.one_direction.draw` draws them, with a lateral play of each axis."""
    radius, dt, feed, err, _, lo = one_direction.draw(rng)
    err.update(p_x=rng.uniform(-3e-6, 3e-6), p_y=rng.uniform(-3e-6, 3e-6))
    return radius, dt, feed, err, lo, rng.uniform(210, 330)


def arc(direction, err, lo, span, n_turn, seed) -> tuple:
    """The part of a turn of ``n_turn`` samples from ``lo`` over ``span`` deg, run in
    ``direction``, half a sample off the reversals [rad, m]."""
    w = 2 * np.pi / (n_turn * gen.DT)
    start = (lo if direction == "ccw" else lo + span) + 0.5 * np.degrees(w * gen.DT)
    a, e = gen.circle(direction, err, seed, start_deg=start, n=n_turn)
    m = round(span / 360 * n_turn)
    return a[:m + 1], e[:m + 1]


def judge(case: int, rng) -> tuple[list, int, list]:
    """The terms off (``(case, term, found, injected, R mm, dt s, F, lag ms, start deg,
    span deg)``, found and injected in millionths of the term's SI unit), the number open,
    and per conditional term whether it is off too, of one case [-]."""
    radius, dt, feed, err, lo, span = draw(rng)
    gen.R, gen.DT = radius, dt
    n = round(2 * np.pi * radius / (feed / 60e3 * dt))
    w = 2 * np.pi / (n * dt)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        diag = diagnose_pair(arc("ccw", err, lo, span, n, 2 * case),
                             arc("cw", err, lo, span, n, 2 * case + 1), radius, (w, w))
    off, opened, held = [], 0, []
    # said to rest on a term the arcs do not determine, and by how much per unit of it
    conditional = {t for moves in diag.aliases.values() for t in moves}
    for term, (key, per_unit) in TERMS.items():
        true, found = err[key], diag[term]
        miss = abs(found - true) > max(0.02 * abs(true), 0.1e-6 / per_unit(radius, w))
        if not np.isfinite(found):
            opened += 1
        elif term in conditional:
            held.append(bool(miss))
        elif miss:
            off.append((case, term, round(found * 1e6, 2), round(true * 1e6, 2),
                        round(radius * 1e3), dt, round(feed), round(err["tau_y"] * 1e3, 2),
                        round(lo), round(span)))
    return off, opened, held


def main(argv=None) -> dict:
    args, results = one_direction.run_cases(argv, __doc__, judge)
    off = [row for o, _, _ in results for row in o]
    opened = sum(n for _, n, _ in results)
    held = [x for _, _, h in results for x in h]
    print(f"seed {args.seed}: {args.cases} pairs of arcs, {len(off)} terms off, neither "
          f"open nor conditional; {opened} open, {len(held)} conditional ({sum(held)} of "
          "them off)")
    for row in off:
        print("  case {}: {} {} for {} (R {} mm, every {} s, F{}, lag {} ms, "
              "from {} deg over {} deg)".format(*row))
    return {"cases": args.cases, "off": off, "open": opened, "conditional": len(held),
            "conditional_off": sum(held)}


if __name__ == "__main__":
    main()
