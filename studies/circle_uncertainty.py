"""The circle terms' uncertainty from what they leave unexplained, against their scatter.

One machine with every error at once (the suite's generator,
``tests/test_circle_diagnostics.py``, ``draw`` with ``--seed``), its CCW and CW circle of
R 35 mm in 7.2 s measured again and again with fresh noise of 0.1 um: white, or alike over
19 samples (AR(1), ``phi`` 0.9), sampled every 1 or 4 ms; and a ballbar's pair of 220 deg
arcs from -20 deg, out and back, with the errors of the suite's arc tests
(``ARC_ERR``, less X's lateral play and bow, which such arcs do not determine). Per
term: the standard deviation
of its value over the draws, the median of its standard uncertainty
(:attr:`tcpmm.analysis.diagnostics.CircleDiagnostics.sigma`), their ratio, how often the
injected value lies within ±2 of them, and how often the term is said uncertain
(:func:`tcpmm.analysis.circle_sigma.noisy_terms`). With ``--spikes``, the reversal spikes
after the pair's terms instead, with every error and without any (no spike: the circle
reads the noise's extreme over the window), against their 95 % uncertainty
(:attr:`tcpmm.analysis.diagnostics.CircleDiagnostics.spike_u95`). Not a test:
``python -m studies.circle_uncertainty [--draws N] [--seed N] [--spikes]``.
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import numpy as np
from scipy.signal import lfilter

from tcpmm.analysis.circle_sigma import noisy_terms
from tcpmm.analysis.diagnostics import diagnose_pair

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
import test_circle_diagnostics as gen  # the suite's generator

TERMS = ("centre_offset_X", "backlash_X", "lateral_play_X", "squareness", "scale_mismatch",
         "servo_mismatch", "straightness_X", "cyclic_amplitude_X", "cyclic_period_X")
CASES = (("1 ms, white", 7200, 0.0, 360), ("4 ms, white", 1800, 0.0, 360),
         ("1 ms, alike over 19", 7200, 0.9, 360), ("4 ms, alike over 19", 1800, 0.9, 360),
         ("220 deg arcs, 1 ms, white", 7200, 0.0, 220))
#: The arcs' start angle [deg]
ARC_FROM = -20.0


def noisy_circle(direction, err, n, phi, rng, span=360, noise=0.1e-6):
    """One turn of ``n`` samples, or the part of it over ``span`` deg from
    :data:`ARC_FROM`, with ``noise`` of correlation ``phi`` on its radius."""
    start = gen.START
    if span < 360:
        step = np.degrees(2 * np.pi / n)
        start = (ARC_FROM if direction == "ccw" else ARC_FROM + span) + 0.5 * step
    a, e = gen.circle(direction, err, noise=0.0, n=n, start_deg=start)
    if span < 360:
        m = round(span / 360 * n)
        a, e = a[:m + 1], e[:m + 1]
    z = lfilter([np.sqrt(1 - phi**2)], [1, -phi], rng.standard_normal(e.size))
    return a, e + noise * z


def case(err, n, phi, span, draws, seed):
    """Per term: scatter, median standard uncertainty, coverage, share said uncertain."""
    rng = np.random.default_rng(seed)
    w = 2 * np.pi / (n * gen.DT)
    want = gen.expected(err, n)
    got = {t: [] for t in TERMS}
    for _ in range(draws):
        d = diagnose_pair(noisy_circle("ccw", err, n, phi, rng, span),
                          noisy_circle("cw", err, n, phi, rng, span), gen.R, (w, w))
        noisy = noisy_terms(d)
        for t in TERMS:
            got[t].append((d[t], d.sigma.get(t, np.nan), t in noisy))
    rows = []
    for t in TERMS:
        v, s, flag = (np.array(c) for c in zip(*got[t], strict=True))
        if np.all(np.isnan(v)):  # a term the arcs do not determine
            continue
        rows.append((t, np.std(v), np.median(s), np.mean(np.abs(v - want[t]) <= 2 * s),
                     np.mean(flag)))
    return rows


def spike_case(err, n, phi, draws, seed):
    """The spikes' coverage by their 95 % uncertainty, its median, and the 95th
    percentile and median of the spikes' distance from the injected ones [-, m, m, m]."""
    rng = np.random.default_rng(seed)
    w = 2 * np.pi / (n * gen.DT)
    want = gen.expected(err, n)
    off, u95 = [], []
    for _ in range(draws):
        d = diagnose_pair(noisy_circle("ccw", err, n, phi, rng),
                          noisy_circle("cw", err, n, phi, rng), gen.R, (w, w))
        off += [abs(d[k] - want[k]) for k in d.spike_u95]
        u95 += list(d.spike_u95.values())
    off, u95 = np.array(off), np.array(u95)
    return np.mean(off <= u95), np.median(u95), np.percentile(off, 95), np.median(off)


def spikes(draws, seed) -> None:
    """The table of :func:`spike_case` over the samplings and noises of :data:`CASES`."""
    full = gen.draw(np.random.default_rng(seed))
    print("| sampling, noise | errors | within ±95 % | median ±95 % [µm] | 95th percentile of "
          "\\|spike − injected\\| [µm] | median of it [µm] |")
    print("|---|---|---:|---:|---:|---:|")
    for label, n, phi, span in CASES:
        if span < 360:
            continue
        for name, err in (("every error, spikes of 8-20 µm", full), ("none, no spike", {})):
            cover, u, p95, med = spike_case(err, n, phi, draws, seed)
            print(f"| {label} | {name} | {100 * cover:.0f} % | {u * 1e6:.3f} | "
                  f"{p95 * 1e6:.3f} | {med * 1e6:.3f} |")


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--draws", type=int, default=30)
    p.add_argument("--seed", type=int, default=2305)
    p.add_argument("--spikes", action="store_true", help="the reversal spikes instead")
    args = p.parse_args(argv)
    warnings.simplefilter("ignore")
    if args.spikes:
        spikes(args.draws, args.seed)
        return
    full = gen.draw(np.random.default_rng(args.seed))
    arcs = {k: v for k, v in gen.ARC_ERR.items() if k not in ("p_x", "str_x")}
    print("| sampling, noise | term | scatter | median σ | σ / scatter | within ±2σ | "
          "said uncertain |")
    print("|---|---|---:|---:|---:|---:|---:|")
    for label, n, phi, span in CASES:
        err = full if span == 360 else arcs
        for t, sd, s, cover, flag in case(err, n, phi, span, args.draws, args.seed):
            k = 1e3 if t == "servo_mismatch" else 1e6
            print(f"| {label} | {t} | {sd * k:.4f} | {s * k:.4f} | {s / sd:.2f} | "
                  f"{100 * cover:.0f} % | {100 * flag:.0f} % |")


if __name__ == "__main__":
    main()
