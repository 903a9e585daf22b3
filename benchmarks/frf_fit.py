"""tcpmm's FRF fit against scikit-rf's vector fitting, at 4 to 9 poles.

Four frequency responses: the real Sinumerik speed-loop trace
(``shared/data/sinumerik/freq_trace.XML``, bins of coherence >= 0.5 over 3.9-4000 Hz) and
three that the script makes from known poles with 1 % complex noise on log-spaced bins,
400 unless said (``two modes``: 4 poles and an antiresonance, 5-2000 Hz; ``three
modes``: 6 poles, two antiresonances and a real pole, 5-3000 Hz, with a 0.2 ms delay as a
drive has; ``coarse, 128 bins``: 4 poles and an antiresonance on 128 bins 4.8 % apart, as
an exported FRF has, its 600 Hz mode of damping 0.008 narrower than one bin). Both
fitters see the same bins. tcpmm (``fit_frf(poles=n)``, numerator degree n or n - 1, delay
fitted) against ``skrf.vectorFitting.VectorFitting`` with n poles (n // 2 complex pairs
and n % 2 real poles, log-spaced starts, constant term, no delay: vector fitting has
none). Two errors against the data fitted, side by side:

* total relative error ``sum |H - Hhat|^2 / sum |H|^2`` (the large part of the response
  dominates, what vector fitting minimises);
* median per-bin relative error ``median |H - Hhat| / |H|`` (every bin alike).

For the made responses the same two errors against the noise-free truth are also given.
``--bundle DIR`` (repeatable) adds the G_M and G_T of the X sweep of a measurement bundle,
estimated as ``tcpmm identify`` does: e.g. ``--bundle ../shared/data/bench_d/bundle``;
with a ``truth.yaml`` beside the bundle, both errors against the true response as well.
``--file PATH`` (repeatable) fits measured responses in any file ``tcpmm frf`` reads in
place of the trace; ``--no-made`` leaves out the made responses.

``--holdout`` judges both fitters on bins they did not fit, which needs no truth: each
response's bins are split into two interleaved halves (even and odd bins of the whole
response, before the coherence cut); each fitter is fitted on one half (vector fitting
on the bins tcpmm kept of it) and both errors are measured on the bins of the other half
that tcpmm fits on the whole response, beside the same errors on the half fitted. The
table gives the mean over both ways round, ``--json`` each (``split`` 0: fitted on the
even bins) and their mean (``split`` "mean"), with the poles tcpmm kept (``kept``) and,
where it refuses a half, why (``refused``). Where the true response is known (the made
responses, a bundle with its ``truth.yaml``), both errors against it on the held-out bins
too, and the truth's own against the data there: a bin at the peak of a mode narrower
than a bin is measured low, and a fit that follows the measured peak wins on it.

Install scikit-rf (the ``bench`` extra) and run::

    .venv/bin/python -m pip install -e '.[bench]'
    .venv/bin/python benchmarks/frf_fit.py [--poles 4-9] [--json] [--holdout]

Without scikit-rf the script prints how to install it and exits with 0.
"""

from __future__ import annotations

import argparse
import json
import logging
import sys
import warnings
from dataclasses import replace
from pathlib import Path

import numpy as np

from tcpmm.ident.frf import FRF
from tcpmm.ident.lti import fit_frf

TRACE = Path(__file__).parents[1] / ".." / "shared" / "data" / "sinumerik" / "freq_trace.XML"
#: Largest chi2 ratio of a bundle's truth against its data for rows against the truth [-].
TRUTH_CHI2 = 2.0
INSTALL = "pip install -e '.[bench]'  (or: pip install scikit-rf)"


def _pair(fn, zeta):
    p = 2 * np.pi * fn * (-zeta + 1j * np.sqrt(1 - zeta**2))
    return [p, np.conj(p)]


#: Made responses: (poles [rad/s], zeros [rad/s], band [Hz], delay [s], log-spaced bins [-]).
MADE = {
    "two modes": ([*_pair(120, 0.03), *_pair(450, 0.05)], _pair(300, 0.02), (5.0, 2000.0), 0.0,
                  400),
    "three modes": ([*_pair(80, 0.04), *_pair(520, 0.02), *_pair(1400, 0.06),
                     -2 * np.pi * 900.0], [*_pair(350, 0.03), *_pair(1100, 0.05)],
                    (5.0, 3000.0), 2e-4, 400),
    "coarse, 128 bins": ([*_pair(80, 0.03), *_pair(600, 0.008)], _pair(300, 0.02),
                         (5.0, 2000.0), 0.0, 128),
}


def made_frf(name, noise=0.01, seed=0):
    """A response of known poles and zeros (unit gain at s = 0) with complex noise."""
    poles, zeros, (f0, f1), tau, bins = MADE[name]
    f = np.geomspace(f0, f1, bins)
    s = 2j * np.pi * f
    h = np.prod([1 - s / z for z in zeros], axis=0) / np.prod([1 - s / p for p in poles],
                                                              axis=0)
    h = h * np.exp(-s * tau)
    rng = np.random.default_rng(seed)
    e = (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)) / np.sqrt(2)
    frf = FRF(f, h * (1 + noise * e), np.ones(f.size), 10, np.zeros(f.size), name=name)
    return frf, h


def errors(H, h):
    """Total relative error and median per-bin relative error of ``h`` against ``H``."""
    return {"total_rel": float(np.sum(np.abs(H - h) ** 2) / np.sum(np.abs(H) ** 2)),
            "median_rel": float(np.median(np.abs(H - h) / np.abs(H)))}


def vf_response(f, H, n_poles):
    """Vector fitting of ``n_poles`` poles; its response at ``f`` [Hz]."""
    return vf_model(f, H, n_poles)(f)


def vf_model(f, H, n_poles):
    """Vector fitting of ``n_poles`` poles to ``H`` at ``f`` [Hz]; its response as a
    function of the frequency [Hz]."""
    import skrf
    from skrf.vectorFitting import VectorFitting

    ntw = skrf.Network(frequency=skrf.Frequency.from_f(f, unit="hz"), s=H.reshape(-1, 1, 1))
    vf = VectorFitting(ntw)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        vf.vector_fit(n_poles_real=n_poles % 2, n_poles_cmplx=n_poles // 2,
                      init_pole_spacing="log", fit_constant=True)
    return lambda freq_hz: vf.get_model_response(0, 0, freq_hz)


def compare(frf, truth, counts):
    """Rows of both fitters at each pole count on the bins tcpmm fits."""
    rows = []
    for n in counts:
        res = fit_frf(frf, poles=n)
        f, H = res.tf.freq_hz, res.tf.H
        sel = np.isin(frf.freq_hz, f)
        for fitter, h in (("tcpmm", res.freqresp(f)), ("skrf VF", vf_response(f, H, n))):
            row = {"response": frf.name, "poles": n, "fitter": fitter, **errors(H, h)}
            if truth is not None:
                t = errors(truth[sel], h)
                row |= {"truth_total_rel": t["total_rel"], "truth_median_rel": t["median_rel"]}
            rows.append(row)
    return rows


def half_frf(frf, parity: int):
    """Every other bin of ``frf`` from bin ``parity`` (0 even, 1 odd) [-]."""
    return replace(frf, freq_hz=frf.freq_hz[parity::2], H=frf.H[parity::2],
                   coherence=frf.coherence[parity::2], rel_std=frf.rel_std[parity::2],
                   name=f"{frf.name} ({'even' if parity == 0 else 'odd'} bins)")


def holdout_rows(frf, n, used_hz, truth=None):
    """Both fitters fitted to each half of ``frf`` at ``n`` poles, with both errors on the
    bins they fitted (``fit_*``) and on the other half's bins among ``used_hz`` [Hz], those
    tcpmm fits on the whole response (``held_*``); a half tcpmm refuses gives a row with
    its reason. With the true response at the bins of ``frf``, both errors against it on
    the held-out bins (``held_truth_*``), and the truth's own against the data there
    (``truth_held_*``): what a model without error leaves on them [-]."""
    from tcpmm.errors import InputError

    rows = []
    for parity in (0, 1):
        base = {"response": frf.name, "poles": n, "split": parity}
        try:
            res = fit_frf(half_frf(frf, parity), poles=n)
        except InputError as exc:
            rows += [{**base, "fitter": fitter, "refused": str(exc)}
                     for fitter in ("tcpmm", "skrf VF")]
            continue
        f, H = res.tf.freq_hz, res.tf.H
        held = np.isin(frf.freq_hz, used_hz) & (np.arange(frf.freq_hz.size) % 2 != parity)
        fv, Hv = frf.freq_hz[held], frf.H[held]
        vf = vf_model(f, H, n)
        if truth is not None:
            base |= {f"truth_held_{k}": v for k, v in errors(Hv, truth[held]).items()}
        for fitter, model, kept in (("tcpmm", res.freqresp, int(res.tf.n_den)),
                                    ("skrf VF", vf, n)):
            fit_e, held_e = errors(H, model(f)), errors(Hv, model(fv))
            row = {**base, "fitter": fitter, "kept": kept,
                   **{f"fit_{k}": v for k, v in fit_e.items()},
                   **{f"held_{k}": v for k, v in held_e.items()}}
            if truth is not None:
                got = errors(truth[held], model(fv)).items()
                row |= {f"held_truth_{k}": v for k, v in got}
            rows.append(row)
    return rows + _mean_rows(rows)


def _mean_rows(rows):
    """The mean of both splits' errors, per fitter, where neither half was refused [-]."""
    out = []
    for fitter in ("tcpmm", "skrf VF"):
        two = [r for r in rows if r["fitter"] == fitter]
        if len(two) < 2 or any("refused" in r for r in two):
            continue
        keys = [k for k in two[0] if k.startswith(("fit_", "held_", "truth_"))]
        out.append({**two[0], "split": "mean", "kept": [r["kept"] for r in two],
                    **{k: float(np.mean([r[k] for r in two])) for k in keys}})
    return out


def holdout(frf, counts, truth=None):
    """:func:`holdout_rows` of ``frf`` at each pole count, judged on the bins tcpmm fits on
    the whole response: coherence 0.5 or more, not alone over it, a response not zero [-]."""
    from tcpmm.ident.lti.frfnoise import lone_passes

    keep = frf.coherence >= 0.5
    keep &= ~lone_passes(keep) & np.isfinite(frf.H) & (frf.H != 0)
    used = frf.freq_hz[keep]
    return [r for n in counts for r in holdout_rows(frf, n, used, truth)]


def orders(text):
    """The pole counts of ``N`` or ``N0-N1`` [-]."""
    lo, _, hi = text.partition("-")
    return list(range(int(lo), int(hi or lo) + 1))


def skrf_ready() -> bool:
    """Whether scikit-rf can be imported (else it says how to install it), its log kept to
    errors [-]."""
    try:
        import skrf  # noqa: F401
    except ImportError:
        print(f"scikit-rf is not installed; this comparison needs it: {INSTALL}")
        return False
    logging.getLogger("skrf").setLevel(logging.ERROR)
    return True


def _print(rows):
    print(f"{'response':<20} {'poles':>5}  {'total rel. error':>25}  {'median rel. error':>25}")
    print(f"{'':<20} {'':>5}  {'tcpmm':>12} {'skrf VF':>12}  {'tcpmm':>12} {'skrf VF':>12}")
    by = {(r["response"], r["poles"], r["fitter"]): r for r in rows}
    for name, n in dict.fromkeys((r["response"], r["poles"]) for r in rows):
        a, b = by[name, n, "tcpmm"], by[name, n, "skrf VF"]
        print(f"{name:<20} {n:>5}  {a['total_rel']:>12.3g} {b['total_rel']:>12.3g}  "
              f"{a['median_rel']:>12.3g} {b['median_rel']:>12.3g}")
        if "truth_total_rel" in a:
            print(f"{'  against the truth':<20} {'':>5}  {a['truth_total_rel']:>12.3g} "
                  f"{b['truth_total_rel']:>12.3g}  {a['truth_median_rel']:>12.3g} "
                  f"{b['truth_median_rel']:>12.3g}")


def _print_holdout(rows):
    """The mean over both splits: errors on the held-out half, then on the half fitted."""
    print("errors on the bins not fitted (held out) and on the bins fitted, mean of the "
          "even and the odd half")
    head = ("held total", "held median", "fitted total", "fitted median")
    print(f"{'response':<24} {'poles':>5} {'kept':>5}" + "".join(f"  {h:>19}" for h in head))
    print(f"{'':<24} {'':>5} {'':>5}" + "  {:>9} {:>9}".format("tcpmm", "skrf VF") * 4)
    by = {(r["response"], r["poles"], r["fitter"], r["split"]): r for r in rows}
    for name, n in dict.fromkeys((r["response"], r["poles"]) for r in rows):
        a, b = by.get((name, n, "tcpmm", "mean")), by.get((name, n, "skrf VF", "mean"))
        if a is None:
            why = "; ".join(r["refused"] for r in rows if r["response"] == name
                            and r["poles"] == n and r["fitter"] == "tcpmm" and "refused" in r)
            print(f"{name:<24} {n:>5}  tcpmm refuses a half: {why}")
            continue
        kept = "/".join(str(k) for k in a["kept"])
        cells = "".join(f"  {a[k]:>9.3g} {b[k]:>9.3g}" for k in (
            "held_total_rel", "held_median_rel", "fit_total_rel", "fit_median_rel"))
        print(f"{name:<24} {n:>5} {kept:>5}{cells}")
        if "held_truth_total_rel" in a:
            print(f"{'  against the truth':<24} {'':>5} {'':>5}  {a['held_truth_total_rel']:>9.3g} "
                  f"{b['held_truth_total_rel']:>9.3g}  {a['held_truth_median_rel']:>9.3g} "
                  f"{b['held_truth_median_rel']:>9.3g}  (the truth against the data: "
                  f"{a['truth_held_total_rel']:.3g}, {a['truth_held_median_rel']:.3g})")


def bundle_frfs(folder, axis: str = "X") -> list:
    """G_M and G_T of ``axis`` from the servo-excitation sweep of a measurement bundle,
    estimated as ``tcpmm identify`` does (5-2000 Hz): measured responses of machines the
    project did not make, with their noise and their unexcited bands."""
    from tcpmm.ident.frf.response import reduced_frfs
    from tcpmm.io.bundle import read_bundle

    s = read_bundle(folder).axes[axis].sweep
    name = Path(folder).resolve().parent.name if Path(folder).name == "bundle" else folder
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the unexcited bands are said by identify
        got = reduced_frfs(s.excitation_A, s.current_cmd_A, s.motor_angle_rad, s.scale_m,
                           fs_hz=s.fs_hz, fmin_hz=5.0, fmax_hz=2000.0)
    return [replace(got[k], name=f"{name} {axis} {k}") for k in ("G_M", "G_T")]


def bundle_truth(folder, frf, axis: str = "X"):
    """The true response at the bins of ``frf`` (a G_M or G_T of :func:`bundle_frfs`) from
    the ``truth.yaml`` beside the bundle: the mechanics, and for G_M the current loop.
    None without a truth file, or where the truth is not what the sweep measured: its own
    chi2 ratio against the data (noise of :func:`~tcpmm.ident.lti.frffit.noise_level`,
    bins of coherence >= 0.5) above :data:`TRUTH_CHI2`, as on a nut whose lost motion the
    linear model leaves out."""
    from tcpmm.ident.lti.frffit import noise_level
    from tcpmm.ident.physical.axisfrfs import model_frfs
    from tcpmm.io.truthfile import machine_from_truth

    path = Path(folder).resolve().parent / "truth.yaml"
    if not path.is_file():
        return None
    key = frf.name.split()[-1]
    ax = machine_from_truth(path).axes[axis]
    bw = ax.servo.current_bandwidth_hz if key == "G_M" else None
    truth = model_frfs(ax.mechanics, {key: frf.freq_hz}, bw)[key]
    keep = frf.coherence >= 0.5
    sigma = noise_level(frf.freq_hz, frf.H, frf.rel_std)[keep]
    chi2 = np.mean(np.abs(frf.H[keep] / truth[keep] - 1) ** 2 / sigma**2) / 2
    if chi2 > TRUTH_CHI2:
        print(f"{frf.name}: the truth leaves a chi2 ratio of {chi2:.3g} against the data; "
              "no rows against it", file=sys.stderr)
        return None
    return truth


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--poles", default="4-9", help="pole counts, N or N0-N1")
    ap.add_argument("--file", action="append", default=None,
                    help="measured FRF (repeatable; skipped if absent); default the trace")
    ap.add_argument("--no-made", action="store_true", help="leave out the made responses")
    ap.add_argument("--bundle", action="append", default=[],
                    help="measurement bundle folder: its X sweep's G_M and G_T (repeatable)")
    ap.add_argument("--holdout", action="store_true",
                    help="fit each half of the bins, judge on the other (see the module)")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args(argv)
    if not skrf_ready():
        return 0
    from tcpmm._threads import limit_blas_threads
    from tcpmm.io.frffile import read_frf

    limit_blas_threads()
    counts = orders(args.poles)
    if args.holdout:  # no truth needed: the bins not fitted judge
        run, show = (lambda frf, truth: holdout(frf, counts, truth)), _print_holdout
    else:
        run, show = (lambda frf, truth: compare(frf, truth, counts)), _print
    rows = []
    for path in args.file or [str(TRACE)]:
        if Path(path).is_file():
            rows += run(read_frf(path), None)
        else:
            print(f"{path} not found: the measured response is left out", file=sys.stderr)
    for folder in args.bundle:
        for frf in bundle_frfs(folder):
            rows += run(frf, bundle_truth(folder, frf))
    for name in [] if args.no_made else MADE:
        rows += run(*made_frf(name))
    if args.json:
        print(json.dumps(rows, indent=1))
    else:
        show(rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
