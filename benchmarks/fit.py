"""Transfer-function fit against scikit-rf vector fitting on the same noisy FRFs.

Two cases, each with 2 % complex multiplicative noise on 500 log-spaced bins:

* a 6th-order feed-drive-like response (three lightly damped modes over 20-800 Hz and one
  antiresonance; numerator degree 2),
* a G_tcp-like response (paper eq. 10 with the demonstration machine's X values: a 50 Hz
  structural mode, a 163 Hz bed mode and two antiresonances; 4/4).

Both fitters get the same model order. Vector fitting (``skrf.vectorFitting``) gets the
matched number of complex pole pairs (constant term only where the model is proper), and
also twice as many poles. Errors are against the true, noise-free response: the RMS relative
complex error and, as vector fitting minimises it, the RMS absolute error relative to the RMS
of the response. Times are the median wall time of the fit alone over the noise draws. The
noise floor is the error an efficient estimator leaves, ``noise * sqrt(p / (2 N))`` for ``p``
real parameters and ``N`` complex bins: no fitter can do better on average.

Run: ``.venv/bin/python benchmarks/fit.py``
"""

from __future__ import annotations

import logging
import time
import warnings

import numpy as np

from tcpmm.ident.lti import fit_tf

N_POINTS = 500
NOISE = 0.02
SEEDS = range(5)


def section(f_hz, zeta):
    w = 2 * np.pi * f_hz
    return np.array([1 / w**2, 2 * zeta / w, 1.0])


def feed_drive_case():
    den = np.array([1.0])
    for f, z in [(35.0, 0.03), (180.0, 0.02), (620.0, 0.04)]:
        den = np.polymul(den, section(f, z))
    num = 3e-6 * section(120.0, 0.015)
    return "6th order, 3 modes 35/180/620 Hz", num, den, np.geomspace(10.0, 1500.0, N_POINTS), 2, 6


def gtcp_case():
    Mt, Ct, Mb, Cb, Kb, Mh, Ch, Kh = 150, 500, 800, 8.9e4, 1e9, 400, 7.6e3, 4e7
    num = np.polymul([Mh - Mt, Ch - Ct, Kh], [Mb, Cb, Kb])
    den = np.polymul([Mh, Ch, Kh], [Mt + Mb, Ct + Cb, Kb])
    return "G_tcp-like, modes 50/163 Hz", num, den, np.geomspace(2.0, 1000.0, N_POINTS), 4, 4


def noisy(H, seed):
    rng = np.random.default_rng(seed)
    e = (rng.standard_normal(H.size) + 1j * rng.standard_normal(H.size)) / np.sqrt(2)
    return H * (1 + NOISE * e)


def errors(H_model, H_true):
    rel = np.sqrt(np.mean(np.abs(H_model / H_true - 1) ** 2))
    ab = np.sqrt(np.mean(np.abs(H_model - H_true) ** 2) / np.mean(np.abs(H_true) ** 2))
    return rel, ab


def ours(f, H, n_num, n_den):
    t0 = time.perf_counter()
    fit = fit_tf((f, H), n_num, n_den)
    return fit.freqresp(f), time.perf_counter() - t0


def vector_fitting(f, H, n_cmplx, constant):
    import skrf
    from skrf.vectorFitting import VectorFitting

    ntw = skrf.Network(frequency=skrf.Frequency.from_f(f, unit="hz"), s=H.reshape(-1, 1, 1))
    vf = VectorFitting(ntw)
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        vf.vector_fit(
            n_poles_real=0, n_poles_cmplx=n_cmplx, init_pole_spacing="log", fit_constant=constant
        )
    dt = time.perf_counter() - t0
    return vf.get_model_response(0, 0, f), dt


def run_case(case):
    name, num, den, f, n_num, n_den = case
    s = 2j * np.pi * f
    H_true = np.polyval(num, s) / np.polyval(den, s)
    proper = n_num == n_den
    fitters = {
        f"tcpmm fit_tf {n_num}/{n_den}": lambda H: ours(f, H, n_num, n_den),
        f"skrf VF {n_den // 2} pairs": lambda H: vector_fitting(f, H, n_den // 2, proper),
        f"skrf VF {n_den} pairs": lambda H: vector_fitting(f, H, n_den, True),
    }
    rows = {}
    for label, fitter in fitters.items():
        rel, ab, times = [], [], []
        fitter(noisy(H_true, 99))  # warm-up (imports, caches)
        for seed in SEEDS:
            Hm, dt = fitter(noisy(H_true, seed))
            r, a = errors(Hm, H_true)
            rel.append(r)
            ab.append(a)
            times.append(dt)
        rows[label] = (np.median(rel), np.median(ab), np.median(times))
    print(
        f"\n{name}: {N_POINTS} log-spaced bins, {NOISE:.0%} complex noise, "
        f"median over {len(SEEDS)} noise draws"
    )
    print(f"{'fitter':<24} {'RMS rel. error':>15} {'RMS abs. error':>15} {'time [ms]':>10}")
    for label, (r, a, t) in rows.items():
        print(f"{label:<24} {r:>15.5f} {a:>15.5f} {1e3 * t:>10.1f}")
    n_par = n_num + 1 + n_den
    print(
        f"noise floor (Cramer-Rao, {n_par} parameters): "
        f"{NOISE * np.sqrt(n_par / (2 * N_POINTS)):.5f} RMS rel. error"
    )
    ours_rel, _, ours_t = rows[next(iter(rows))]
    vf_rel, _, vf_t = rows[list(rows)[1]]
    print(
        f"matched order: error ratio ours/VF = {ours_rel / vf_rel:.2e}, "
        f"time ratio ours/VF = {ours_t / vf_t:.2f}"
    )


def main():
    logging.getLogger("skrf").setLevel(logging.ERROR)
    from tcpmm._threads import limit_blas_threads

    limit_blas_threads()
    for case in (feed_drive_case(), gtcp_case()):
        run_case(case)


if __name__ == "__main__":
    main()
