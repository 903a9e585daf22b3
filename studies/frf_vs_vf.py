"""tcpmm's FRF fit against scikit-rf's vector fitting on fifteen machine-tool-like responses
it was not built around (docs/validation/frf_fit.md).

Each response is made from known poles and zeros: one to four modes, antiresonances, a real
pole, one or two integrators (velocity and position responses), a drive's delay of 0.1 to
1 ms; 64 to 2000 bins, log- or linearly spaced; 0.3 to 5 % complex noise, with a coherence
that matches it for ten averages, and in three of them the bins around a mode dropped as a
coherence cut does (below 0.5). Both fitters see the bins of coherence >= 0.5;
``fit_frf(poles=n)`` against ``VectorFitting`` with ``n`` poles
(:func:`benchmarks.frf_fit.vf_response`), ``n`` from 4 to 9. The errors against the data
(total ``sum |H - Hhat|^2 / sum |H|^2`` and median per bin ``|H - Hhat| / |H|``) and against
the noise-free truth are printed, with the poles tcpmm kept.

    .venv/bin/python -m pip install -e '.[bench]'
    .venv/bin/python -m studies.frf_vs_vf [--poles 4-9] [--names A_1mode_lin,...] [--json]
"""

from __future__ import annotations

import argparse
import json
import sys
import warnings
from pathlib import Path

import numpy as np

from tcpmm.ident.frf import FRF
from tcpmm.ident.lti import fit_frf

sys.path.insert(0, str(Path(__file__).parents[1] / "benchmarks"))
from frf_fit import errors, orders, skrf_ready, vf_response

#: Seed of the first response's noise; each next one adds one [-].
SEED = 12345


def _pair(fn, z):
    p = 2 * np.pi * fn * (-z + 1j * np.sqrt(1 - z * z))
    return [p, np.conj(p)]


def _modes(*fz):
    return [p for fn, z in fz for p in _pair(fn, z)]


#: name: poles and zeros [rad/s], band [Hz], bins, spacing, delay [s], relative noise [-],
#: integrators, gain, frequencies around which the bins fall below coherence 0.5 [Hz]
RESPONSES = {
    "A_1mode_lin": dict(P=_modes((250, 0.01)), Z=[], band=(1, 1000), bins=500, sp="lin",
                        tau=3e-4, noise=0.01),
    "B_2mode_anti": dict(P=_modes((60, 0.02), (410, 0.005)), Z=_modes((200, 0.01)),
                         band=(5, 2000), bins=800, tau=1e-4, noise=0.005),
    "C_vel_1s": dict(P=_modes((180, 0.03), (700, 0.01)), Z=_modes((140, 0.02), (520, 0.008)),
                     band=(2, 2000), bins=600, tau=2.5e-4, noise=0.01, integ=1, gain=50.0),
    "D_pos_1s2": dict(P=_modes((95, 0.015)), Z=_modes((70, 0.01)), band=(1, 1000), bins=400,
                      tau=5e-4, noise=0.02, integ=2, gain=1e4),
    "E_3mode": dict(P=_modes((45, 0.04), (320, 0.008), (1250, 0.02)),
                    Z=_modes((210, 0.01), (900, 0.015)), band=(5, 3000), bins=1000, tau=2e-4,
                    noise=0.01),
    "F_4mode": dict(P=_modes((40, 0.05), (180, 0.01), (650, 0.004), (1900, 0.02)),
                    Z=_modes((120, 0.015), (450, 0.006), (1400, 0.02)), band=(5, 4000),
                    bins=1500, tau=1e-4, noise=0.01),
    "G_coarse100": dict(P=_modes((85, 0.02), (540, 0.006)), Z=_modes((300, 0.015)),
                        band=(5, 2500), bins=100, tau=2e-4, noise=0.01),
    "H_dropres": dict(P=_modes((130, 0.01), (820, 0.004)), Z=_modes((500, 0.01)),
                      band=(5, 2000), bins=600, tau=3e-4, noise=0.01, drop=(130, 820)),
    "I_noisy5": dict(P=_modes((150, 0.02), (600, 0.01)), Z=_modes((380, 0.015)),
                     band=(5, 2000), bins=400, tau=4e-4, noise=0.05),
    "J_lin2000": dict(P=[*_modes((310, 0.005), (1800, 0.01)), -2 * np.pi * 60.0],
                      Z=_modes((1100, 0.01)), band=(2.5, 5000), bins=2000, sp="lin", tau=1e-3,
                      noise=0.003),
    "K_small64": dict(P=_modes((120, 0.05), (400, 0.02)), Z=_modes((250, 0.03)),
                      band=(10, 1500), bins=64, tau=1e-4, noise=0.01),
    "L_vel_drop": dict(P=_modes((220, 0.008), (950, 0.02)), Z=_modes((160, 0.006)),
                       band=(2, 3000), bins=700, tau=6e-4, noise=0.02, integ=1, gain=30.0,
                       drop=(220,)),
    "M_lightest": dict(P=_modes((75, 0.002), (480, 0.003)), Z=_modes((260, 0.002)),
                       band=(5, 1500), bins=900, tau=2e-4, noise=0.003),
    "N_lin_coarse": dict(P=_modes((140, 0.02), (700, 0.01), (1600, 0.03)),
                         Z=_modes((400, 0.01), (1200, 0.02)), band=(10, 2500), bins=250,
                         sp="lin", tau=5e-4, noise=0.02),
    "O_vel_drop2": dict(P=_modes((55, 0.03), (310, 0.006), (1100, 0.015)),
                        Z=_modes((40, 0.02), (250, 0.005), (900, 0.01)), band=(1, 2500),
                        bins=1200, tau=3.5e-4, noise=0.01, integ=1, gain=80.0,
                        drop=(310, 1100)),
}


def response(name: str):
    """The measured response of ``name`` (an FRF with its coherence) and its truth [-]."""
    c = RESPONSES[name]
    f0, f1 = c["band"]
    f = (np.linspace(f0, f1, c["bins"]) if c.get("sp") == "lin"
         else np.geomspace(f0, f1, c["bins"]))
    s = 2j * np.pi * f
    h = c.get("gain", 1.0) * np.prod([1 - s / z for z in c["Z"]], axis=0) / np.prod(
        [1 - s / p for p in c["P"]], axis=0)
    h = h / s ** c.get("integ", 0) * np.exp(-s * c["tau"])
    rng = np.random.default_rng(SEED + list(RESPONSES).index(name))
    e = (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)) / np.sqrt(2)
    # the coherence of ten averages whose random error is the noise
    coh = np.full(f.size, 1 / (1 + 20 * c["noise"] ** 2))
    for fd in c.get("drop", ()):
        coh[np.abs(f / fd - 1) < 0.03] = 0.3
    rel = np.sqrt((1 - coh) / (20 * coh))
    return FRF(f, h * (1 + c["noise"] * e), coh, 10, rel, name=name), h


def row(name: str, n: int) -> dict:
    """Both fitters at ``n`` poles on ``name``: errors against the data and the truth."""
    frf, truth = response(name)
    res = fit_frf(frf, poles=n)
    f, H = res.tf.freq_hz, res.tf.H
    sel = np.isin(frf.freq_hz, f)
    mine, vf = res.freqresp(f), vf_response(f, H, n)
    return {"response": name, "poles": n, "kept": int(res.tf.n_den),
            "tcpmm": errors(H, mine), "vf": errors(H, vf),
            "tcpmm_truth": errors(truth[sel], mine), "vf_truth": errors(truth[sel], vf)}


def _print(rows):
    print(f"{'response':<14} {'n':>2} {'kept':>4}  {'total, data':>19}  {'median, data':>19}"
          f"  {'total, truth':>19}  {'median, truth':>19}")
    for r in rows:
        cells = [f"{r[a][k]:9.3g} {r[b][k]:9.3g}" for a, b in (("tcpmm", "vf"),
                                                               ("tcpmm_truth", "vf_truth"))
                 for k in ("total_rel", "median_rel")]
        print(f"{r['response']:<14} {r['poles']:>2} {r['kept']:>4}  " + "  ".join(cells))
    print()
    for label, a, b in (("data", "tcpmm", "vf"), ("truth", "tcpmm_truth", "vf_truth")):
        for key, better in (("total_rel", lambda x, y: x <= y), ("median_rel", lambda x, y: x < y)):
            lost = [r for r in rows if not better(r[a][key], r[b][key])]
            fewer = sum(r["kept"] < r["poles"] for r in lost)
            print(f"against the {label}, {key}: tcpmm behind vector fitting in {len(lost)} of "
                  f"{len(rows)} fits ({fewer} of them keeping fewer poles than asked)")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--poles", default="4-9", help="pole counts, N or N0-N1")
    ap.add_argument("--names", default=",".join(RESPONSES))
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args(argv)
    if not skrf_ready():
        return 0
    warnings.simplefilter("ignore")  # the fits' notes are not this table's subject
    rows = [row(name, n) for name in args.names.split(",") for n in orders(args.poles)]
    if args.json:
        print(json.dumps(rows, indent=1))
    else:
        _print(rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
