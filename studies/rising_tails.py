"""Reversal transients that rise to their peak past the window: could the circles tell
them from the terms?

The fit's tails (:mod:`tcpmm.analysis.circle_reversal_tail`) decay from the window's end.
A loop recovering from the friction's step may still be rising there; the response of a
critically damped loop, ``(t / p) exp(1 - t / p)`` from the reversal, peaks at ``p``. This
study swaps that law into the tails' columns (here only, not in the package) and asks, for
the fit the package chooses: how much better does a rising tail fit, and how far do the
backlash and the spikes after the terms move over the rising tails that fit within 3.84
noise variances of the best of them and the chosen fit (the band the package's own
``spread`` uses)? Were that band adopted as the terms' and spikes' uncertainty, these
moves are what it would add.

1. The circles of ``tests/test_circle_lingering.py`` (a pulse peaking 8 to 30 deg after
   each quadrant point, -5 um after X's reversals, +4 um after Y's, no backlash) and the
   clean circles of its ``test_clean_circles_say_no_tail_and_keep_their_spikes_tight``.
2. The circles of ``../shared/data/bench_*`` at F5000 and F10000 (no play in their truth).

Not a test: ``python -m studies.rising_tails`` (about 2 min).
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

import numpy as np
from scipy.optimize import minimize_scalar

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
import tcpmm.analysis.circle_fit as cf
import tcpmm.analysis.circle_reversal_tail as crt
from tcpmm.analysis.circle_tail_terms import LINGER

#: The peaks searched, as the angle travelled from the reversal [deg]
RISE_DEG = tuple(float(d) for d in np.geomspace(5.0, 50.0, 17))
RISING = " rising"
_columns = crt.tail_columns


def rising_columns(angle, s, ratio, mu, rev, after_deg, tail):
    """The package's tail columns, or for a shape ending in :data:`RISING` the rising
    law from the reversal, zero within the window [m/m]."""
    decay, shape, *turn = tail
    if not shape.endswith(RISING):
        return _columns(angle, s, ratio, mu, rev, after_deg, tail)

    def course(since):
        x = np.radians(since) / (ratio * decay)
        return np.where(since >= after_deg, x * np.exp(1.0 - x), 0.0)

    return _course_columns(course, shape.removesuffix(RISING),
                           crt.axis_reversals(angle, s, ratio, mu, rev, *turn))


def _course_columns(course, shape: str, reversals) -> list:
    """The two columns per axis of a tail whose course is ``course(since)``, one per sign
    of the axis' velocity after the reversal, as the package's tails of ``shape`` [m/m]."""
    out = []
    for since, sign, proj in reversals:
        col = -sign * proj * course(since) if shape == "axis" else course(since)
        out += [np.where(sign > 0, col, 0.0), np.where(sign < 0, col, 0.0)]
    return out


def rising_costs(pb, mu, waves) -> dict:
    """``(peak, shape) -> sum of squares`` of the fit without tails plus a rising tail, on
    the grid and refined at each shape's local least costs [m^2]."""
    own, pb.tail = pb.tail, None
    _, res, basis = pb.solve(mu, waves)
    pb.tail = own
    base, out = float(res @ res), {}

    def cost(log_peak, shape):
        t = (float(np.exp(log_peak)), shape)
        m = crt.tail_matrix(pb, mu, t)
        q, r = np.linalg.qr(m - basis @ (basis.T @ m))
        q = q[:, np.abs(np.diag(r)) > 1e-9 * max(np.abs(r).max(), 1e-300)]
        out[t] = c = base - float(np.sum((q.T @ res) ** 2))
        return c

    grid = np.log(np.radians(RISE_DEG))
    for shape in (s + RISING for s in crt.SHAPES):
        at = np.array([cost(g, shape) for g in grid])
        for j in range(1, grid.size - 1):
            if at[j] <= min(at[j - 1], at[j + 1]):
                minimize_scalar(cost, bounds=(grid[j - 1], grid[j + 1]), args=(shape,),
                                method="bounded", options={"xatol": 0.002})
    return out


def rivals(pb, mu, waves):
    """The rising tails within the band (module docstring) as ``(tail, coef, waves)``,
    and what the chosen fit leaves over the best of them, in noise variances [-]."""
    res = pb.solve(mu, waves)[1]
    costs = rising_costs(pb, mu, waves)
    level = crt.noise_level(res)
    bound = min(float(res @ res), *costs.values()) + crt.AS_WELL * level
    near = sorted((c, t) for t, c in costs.items() if c <= bound)[:crt.MOST_ALIKE]
    out, own = [], pb.tail
    for _, t in near:
        pb.tail = t
        out.append((t, pb.solve(mu, waves)[0], waves))
    pb.tail = own
    return tuple(out), (float(res @ res) - min(costs.values())) / level


def install() -> None:
    """Swap the rising law into the tails' columns, and have each searched fit carry its
    rivals as the fits of a transient lasting past the window, so that the package works
    out the terms' and spikes' moves over them as it does for those (and opens those that
    move by more than the circles' whole radial error); the rivals' cost saved in
    :data:`GAIN` [-]."""
    crt.tail_columns = rising_columns
    searched, widths = cf.search_tail, cf.search_widths

    def search_tail(pb, mu, waves):
        pb.searched = True
        return searched(pb, mu, waves)

    def search_widths(pb, mu, waves, coef):
        if getattr(pb, "searched", False) and not pb.tail_family:
            found, GAIN[0] = rivals(pb, mu, waves)
            n = coef.size - (4 * len(pb.arcs) if pb.tail is not None else 0)
            moves = pb.tail_spread if pb.tail_spread is not None else np.zeros(n)
            for _, c, _ in found:
                d = np.nan_to_num(c[:n] - coef[:n])
                moves = np.where(np.abs(d) > np.abs(moves), d, moves)
            pb.tail_family, pb.tail_spread = found, moves
        return widths(pb, mu, waves, coef)

    cf.search_tail, cf.search_widths = search_tail, search_widths


#: What the chosen fit leaves over the best rising tail, in noise variances
GAIN = [float("nan")]


def figures(d) -> tuple:
    """The backlash's largest move, the largest finite spike's ±95 % and how many spikes
    read n/a, of the diagnostics ``d`` [m, m, -]."""
    spikes = [k for k in d.spike_u95 if k.startswith("spike_")]
    u95 = [d.spike_u95[k] for k in spikes if np.isfinite(d.spike_u95[k])]
    return (max(abs(d.tail_shift.get(f"backlash_{a}", 0.0)) for a in "XY"),
            max(u95) if u95 else float("nan"), sum(bool(np.isnan(d[k])) for k in spikes))


def row(label, chosen, before, after) -> str:
    """One table row, the package's diagnostics ``before`` and with the rivals ``after``
    [-]."""
    (m0, u0, n0), (m1, u1, n1) = figures(before), figures(after)
    return (f"| {label} | {chosen} | {GAIN[0]:.0f} | {m0 * 1e6:.2f} | {m1 * 1e6:.2f} "
            f"| {u0 * 1e6:.2f} | {u1 * 1e6:.2f} | {n0} | {n1} |")


def main() -> None:
    warnings.simplefilter("ignore")
    import test_circle_diagnostics as gen
    from tcpmm.analysis.circular import analyse_circle
    from tcpmm.analysis.diagnostics import circle_diagnostics
    from tcpmm.io.runfile import read_run
    from test_circle_lingering import pair

    cases = [(f"pulse peaking at {p:g} deg", lambda p=p: pair({}, p)) for p in (8, 20, 30)]
    cases.append(("clean circles", lambda: gen.diagnose(
        {"b_x": 3e-6, "b_y": -2e-6, "tau_y": 0.5e-3, "eps_x": 20e-6, "cx": 3e-6,
         "cyc_x": (0.5e-6, 5e-3, 0.0)})))
    root = Path(__file__).resolve().parents[2] / "shared" / "data"
    for m in ("c", "d", "e", "h", "r05", "r17"):
        for fast, feed in (("", "F5000"), ("_fast", "F10000")):
            files = [root / f"bench_{m}" / f"circle_{w}{fast}_meas.csv" for w in ("ccw", "cw")]
            for sensor in ("tcp", "scale"):
                cases.append((f"bench_{m} {feed} {sensor}", lambda f=files, s=sensor:
                              circle_diagnostics(*[analyse_circle(read_run(x), 0.035)
                                                   for x in f], sensor=s)))
    print("| circles | tail chosen | chosen over best rising [noise var.] | backlash "
          "moves [µm] | with the rivals | largest spike ±95 % [µm] | with the rivals "
          "| spikes n/a (of 8) | with the rivals |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|")
    for label, run in cases:
        before = run()
        said = before.undetermined.get("reversal_tail_decay", "")
        chosen = ("lasts past" if said.startswith(LINGER) else "none" if said
                  else f"{before['reversal_tail_decay'] * 1e3:.0f} ms" if np.isfinite(
                      before["reversal_tail_decay"]) else "fitted")
        if said.startswith(LINGER):
            print(f"| {label} | {chosen} | | | | | | | |", flush=True)
            continue
        saved = crt.tail_columns, cf.search_tail, cf.search_widths
        install()
        try:
            print(row(label, chosen, before, run()), flush=True)
        finally:
            crt.tail_columns, cf.search_tail, cf.search_widths = saved
            GAIN[0] = float("nan")


if __name__ == "__main__":
    main()
