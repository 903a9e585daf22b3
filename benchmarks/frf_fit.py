"""tcpmm's FRF fit against scikit-rf vector fitting on the real Sinumerik speed-loop trace.

Both fit the same bins of ``freq_trace.XML`` (coherence >= 0.5 over the band, default
3.9-4000 Hz). tcpmm chooses its order itself (``fit_frf``, delay fitted); vector fitting
(``skrf.vectorFitting``) gets as many complex pole pairs as tcpmm's model has poles in
total halved and rounded up, plus a constant term, and then twice as many; tcpmm is also
timed at its chosen order alone (no order search). The error is the
relative RMS of the complex residual, ``sqrt(mean |H_model / H - 1|^2)``, and the RMS
absolute residual relative to the RMS of the data, over the same bins. Each fitter runs
``--runs`` times, interleaved; min and median wall times of the fit alone are reported.

Run: ``.venv/bin/python benchmarks/frf_fit.py [--runs 5] [--json]``
"""

from __future__ import annotations

import argparse
import json
import logging
import time
import warnings
from pathlib import Path

import numpy as np

from tcpmm.ident.lti import fit_frf
from tcpmm.io.sinumerik import read_sinumerik_frf

TRACE = Path(__file__).parents[1] / ".." / "shared" / "data" / "sinumerik" / "freq_trace.XML"


def errors(f, H, h):
    return {"rel_rms": float(np.sqrt(np.mean(np.abs(h / H - 1) ** 2))),
            "abs_rel_rms": float(np.sqrt(np.mean(np.abs(h - H) ** 2) / np.mean(np.abs(H) ** 2)))}


def tcpmm_fit(frf, poles="auto"):
    res = fit_frf(frf, poles=poles)
    return res, lambda f: res.freqresp(f)


def vf_fit(f, H, n_pairs):
    import skrf
    from skrf.vectorFitting import VectorFitting

    ntw = skrf.Network(frequency=skrf.Frequency.from_f(f, unit="hz"), s=H.reshape(-1, 1, 1))
    vf = VectorFitting(ntw)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        vf.vector_fit(n_poles_real=0, n_poles_cmplx=n_pairs, init_pole_spacing="log",
                      fit_constant=True)
    return vf, lambda ff: vf.get_model_response(0, 0, ff)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--file", default=str(TRACE))
    args = ap.parse_args(argv)
    logging.getLogger("skrf").setLevel(logging.ERROR)
    from tcpmm._threads import limit_blas_threads

    limit_blas_threads()
    frf = read_sinumerik_frf(args.file)
    res, _ = tcpmm_fit(frf)  # warm-up, and the bins and order both fitters use
    f, H = res.tf.freq_hz, res.tf.H
    n = -(-res.tf.n_den // 2)
    fitters = {
        f"tcpmm fit_frf auto ({res.tf.n_den} poles)": lambda: tcpmm_fit(frf)[1],
        f"tcpmm fit_frf {res.tf.n_den} poles": lambda: tcpmm_fit(frf, res.tf.n_den)[1],
        f"skrf VF {n} pairs": lambda: vf_fit(f, H, n)[1],
        f"skrf VF {2 * n} pairs": lambda: vf_fit(f, H, 2 * n)[1],
    }
    for fit in fitters.values():  # warm-up (imports, caches)
        fit()
    times = {k: [] for k in fitters}
    models = {}
    for _ in range(max(1, args.runs)):
        for k, fit in fitters.items():
            t0 = time.perf_counter()
            models[k] = fit()
            times[k].append(time.perf_counter() - t0)
    rows = {k: {**errors(f, H, models[k](f)), "time_min_s": min(t),
                "time_median_s": float(np.median(t))} for k, t in times.items()}
    out = {"file": args.file, "bins": int(f.size), "band_hz": [float(f[0]), float(f[-1])],
           "noise_rms": res.noise_rms, "runs": args.runs, "fitters": rows}
    if args.json:
        print(json.dumps(out, indent=1))
        return
    print(f"{Path(args.file).name}: {f.size} bins, {f[0]:.4g}-{f[-1]:.4g} Hz; noise level "
          f"(relative RMS) {res.noise_rms:.3f}; {args.runs} interleaved runs")
    print(f"{'fitter':<30} {'rel. RMS':>9} {'abs. RMS':>9} {'min [ms]':>9} {'median [ms]':>12}")
    for k, r in rows.items():
        print(f"{k:<30} {r['rel_rms']:>9.4f} {r['abs_rel_rms']:>9.4f} "
              f"{1e3 * r['time_min_s']:>9.1f} {1e3 * r['time_median_s']:>12.1f}")


if __name__ == "__main__":
    main()
