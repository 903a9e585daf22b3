"""Standard deviations of a fitted FRF's modes, poles and delay: against the spread of refits
of known systems through noise, where the data leave a mode open, and on the real trace."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from conftest import run_cli
from tcpmm.ident.frf import FRF
from tcpmm.ident.lti import fit_frf, fit_tf, tf_deviations
from tcpmm.ident.lti.tfresult import tf_result
from tcpmm.ident.lti.tfsd import DELAY_OPEN, MISFIT, Estimate
from tcpmm.io.frffile import write_frf_csv

TRACE = Path(__file__).parents[1] / ".." / "shared" / "data" / "sinumerik" / "freq_trace.XML"
needs_trace = pytest.mark.skipif(not TRACE.is_file(), reason="Sinumerik trace not available")

MODES = ((120.0, 0.03), (450.0, 0.05))
ZERO = 2 * np.pi * 300 * (-0.02 + 1j)
NOISE = 0.01
DRAWS = 50
# The sample standard deviation s of DRAWS independent normal estimates against their true
# sd: (DRAWS - 1) s^2 / sd^2 is chi-square of 49 degrees of freedom, so s / sd lies in
# 0.63..1.41 with probability 1 - 1e-4. The sd compared is the median of those reported,
# each from the noise one residual shows (a running median of 31 bins: some 10 % of its
# own error), so the bounds are widened to 0.6..1.6; a covariance off by a factor of two
# (the bins' noise instead of the residual's, a Jacobian missing the numerator) fails.
RATIO = (0.6, 1.6)
# The same for a zero's frequency and damping: the sample sd of 50 draws has a relative sd
# of 1 / sqrt(2 * 49) = 0.10, so 2.5 of it bound the ratio to 0.75..1.25, narrower than
# RATIO as the draws are fixed and the ratios measured (0.94 each): a sd a third off fails.
ZERO_RATIO = (0.75, 1.25)
TRUE_ZERO = (abs(ZERO) / (2 * np.pi), -ZERO.real / abs(ZERO))


def response(f, real_pole_hz=None, delay_s=0.0):
    """Two modes over an antiresonance at 300 Hz, a real pole and a delay if given [-]."""
    s = 2j * np.pi * np.asarray(f)
    h = (1 - s / ZERO) * (1 - s / np.conj(ZERO))
    for fn, z in MODES:
        wn = 2 * np.pi * fn
        h = h / (1 + 2 * z * s / wn + (s / wn) ** 2)
    if real_pole_hz is not None:
        h = h / (1 + s / (2 * np.pi * real_pole_hz))
    return h * np.exp(-s * delay_s)


def noisy(H, seed):
    """``H`` times ``1 + NOISE e``, ``e`` complex normal of unit variance [-]."""
    rng = np.random.default_rng(seed)
    e = (rng.standard_normal(H.size) + 1j * rng.standard_normal(H.size)) / np.sqrt(2)
    return H * (1 + NOISE * e)


def measured(delay_s: float = 0.0, name: str = "two modes") -> FRF:
    """:func:`response` with the real pole at 900 Hz and a delay of ``delay_s`` [s], on
    400 bins of 10 Hz-2 kHz, noise draw 0 [-]."""
    f = np.geomspace(10.0, 2000.0, 400)
    return FRF(f, noisy(response(f, real_pole_hz=900.0, delay_s=delay_s), 0),
               np.ones(f.size), 10, np.zeros(f.size), name=name)


def estimates(dev) -> list:
    """Frequency and damping of each mode and the real poles [-]."""
    return [e for mode in dev.modes for e in mode] + list(dev.real_poles)


def spread_against_sd(fits) -> tuple:
    """Values and reported sds of every refit, as arrays of one row per draw [-]."""
    vals = np.array([[e.value for e in estimates(d)] for d in fits])
    sds = np.array([[e.sd for e in estimates(d)] for d in fits])
    return vals, np.std(vals, axis=0, ddof=1) / np.median(sds, axis=0), np.median(sds, axis=0)


@pytest.fixture(scope="module")
def refits() -> list:
    """Deviations of fit_frf of two modes over an antiresonance at 300 Hz and a real pole
    at 900 Hz (400 bins, 1 % noise, 5 poles, no delay), one per draw [-]."""
    f = np.geomspace(10.0, 2000.0, 400)
    H = response(f, real_pole_hz=900.0)
    fits = []
    for seed in range(DRAWS):
        frf = FRF(f, noisy(H, seed), np.ones(f.size), 10, np.zeros(f.size), name="two modes")
        fits.append(fit_frf(frf, poles=5, delay_s=None).deviations)
    return fits


def test_reported_sd_of_modes_and_real_pole_matches_the_spread_of_refits(refits):
    """fit_frf of two modes and a real pole at 900 Hz (400 bins, 1 % noise), fifty draws:
    the spread of each refitted frequency and damping is the sd reported, within RATIO,
    and their mean is the truth within half of it."""
    fits = refits
    assert all(len(d.modes) == 2 and len(d.real_poles) == 1 for d in fits)
    vals, ratio, sd = spread_against_sd(fits)
    truth = [*np.ravel(MODES), 900.0]
    assert np.all((RATIO[0] < ratio) & (ratio < RATIO[1])), ratio
    assert np.all(np.abs(vals.mean(axis=0) - truth) < 0.5 * sd)
    assert all(e.determined for d in fits for e in estimates(d))


def test_reported_sd_of_an_antiresonance_matches_the_spread_of_refits(refits):
    """The same fifty refits: the antiresonance at 300 Hz between the modes (damping 0.02)
    is the one zero pair in the band, its frequency and damping spread as the sd reported
    within ZERO_RATIO and centred on the truth within half of it; the spare zeros the fit
    places far above the band, which no bin sees, are undetermined and say why."""
    inband = [[z for z in d.zeros if z.freq.determined] for d in refits]
    assert all(len(z) == 1 and z[0].kind == "pair" for z in inband)
    vals = np.array([[z[0].freq.value, z[0].damping.value] for z in inband])
    sd = np.median([[z[0].freq.sd, z[0].damping.sd] for z in inband], axis=0)
    ratio = np.std(vals, axis=0, ddof=1) / sd
    assert np.all((ZERO_RATIO[0] < ratio) & (ratio < ZERO_RATIO[1])), ratio
    assert np.all(np.abs(vals.mean(axis=0) - TRUE_ZERO) < 0.5 * sd)
    spare = [z for d in refits for z in d.zeros if z.freq.value > 2000.0]
    assert spare and all(not z.freq.determined and z.freq.bound == math.inf for z in spare)
    assert all(z.freq.why.startswith("a zero outside the fitted band") for z in spare)
    assert all(any(n.startswith("a zero outside") for n in d.notes) for d in refits)


def test_a_collocated_two_mass_antiresonance_is_found_where_it_is():
    """Force and response on the grounded mass of two (m1 = 1 kg on k1, m2 = 0.5 kg on
    k2 to it, each spring at damping 0.02): the zeros are those of m2 on k2 alone,
    sqrt(k2 / m2) = 300 Hz at damping 0.02, between the two modes (186 and 404 Hz) as
    collocation has them. The fit places them there within their sd, and the sd is a
    fraction of a per cent of the frequency."""
    m1, m2 = 1.0, 0.5
    k1, k2 = m1 * (2 * np.pi * 250) ** 2, m2 * (2 * np.pi * 300) ** 2
    c1, c2 = 2 * 0.02 * np.sqrt(k1 * m1), 2 * 0.02 * np.sqrt(k2 * m2)
    f = np.geomspace(10.0, 2000.0, 300)
    s = 2j * np.pi * f
    top = m2 * s**2 + c2 * s + k2
    H = top / ((m1 * s**2 + (c1 + c2) * s + k1 + k2) * top - (c2 * s + k2) ** 2)
    fit = fit_tf((f, noisy(H, 1), np.ones(f.size)), 2, 4, delay_s=None, max_nfev=100)
    d = tf_deviations(fit, fit_delay=False)
    (zero,) = d.zeros
    (low, _), (high, _) = d.modes
    assert low.value < zero.freq.value < high.value
    assert abs(zero.freq.value - 300.0) < 3 * zero.freq.sd < 0.01 * 300.0
    assert abs(zero.damping.value - 0.02) < 3 * zero.damping.sd < 0.1 * 0.02
    assert zero.root.real < 0 and zero.root.imag > 0
    assert d.to_dict()["zero_pairs"][0]["freq_sd_hz"] == zero.freq.sd
    assert d.to_dict()["real_zeros"] == []


def test_with_a_fitted_delay_the_modes_keep_their_sd_and_the_delay_has_none():
    """fit_tf of two modes and a 0.2 ms delay (4 poles, 2 zeros, 200 bins, 1 % noise),
    fifty draws: frequencies and dampings spread as their reported sd. The delay carries
    none: refits of fit_frf through other noise spread about 4 times its linearised sd at
    the same order, so it is undetermined, with the reason."""
    f = np.geomspace(10.0, 2000.0, 200)
    H = response(f, delay_s=2e-4)
    fits = []
    for seed in range(DRAWS):
        fit = fit_tf((f, noisy(H, seed), np.ones(f.size)), 2, 4, delay_s="fit", max_nfev=100)
        fits.append(tf_deviations(fit, fit_delay=True))
    vals, ratio, sd = spread_against_sd(fits)
    assert np.all((RATIO[0] < ratio) & (ratio < RATIO[1])), ratio
    assert np.all(np.abs(vals.mean(axis=0) - np.ravel(MODES)) < 0.5 * sd)
    assert all(not d.delay.determined and d.delay.why == DELAY_OPEN for d in fits)
    assert fits[0].to_dict()["delay"] == {"delay_s": fits[0].delay.value, "delay_sd_s": None,
                                          "delay_determined": False}
    assert fits[0].notes == [DELAY_OPEN]


def test_a_mode_outside_the_band_is_said_to_be_undetermined(capsys, tmp_path):
    """Fitted to 300 Hz or to 150 Hz, the 450 Hz mode is undetermined, frequency and
    damping: the bins see only its tail, which a numerator term gives as well, so a +-
    would place a mode where no bin saw it. The 120 Hz mode is held in both, and the
    command line says undetermined and why where JSON has the flag and a null sd."""
    frf = measured()
    for top in (300, 150):
        fit = fit_frf(frf, poles=4, band_hz=(10, top), delay_s=None)
        (low, low_z), (high, high_z) = fit.deviations.modes
        assert low.determined and low_z.determined
        assert not high.determined and not high_z.determined
    path = tmp_path / "two.csv"
    write_frf_csv(frf, path)
    args = ("frf", "fit", path, "--poles", "4", "--band", "10,150", "--delay", "none")
    code, text, _ = run_cli(capsys, *args)
    assert code == 0 and "(undetermined)" in text and "+-" in text
    assert "outside the fitted band" in text and "the delay:" not in text
    code, text, _ = run_cli(capsys, *args, "--json")
    modes = json.loads(text)["modes"]
    assert [m["damping_determined"] for m in modes] == [True, False]
    assert modes[0]["freq_sd_hz"] > 0 and modes[1]["freq_determined"] is False
    assert modes[1]["freq_sd_hz"] is None and modes[1]["damping_sd"] is None


def test_a_zero_outside_the_band_is_said_to_be_undetermined(capsys, tmp_path):
    """Fitted to 200 Hz with 3 poles, the antiresonance at 300 Hz lies above the band and
    came out at 351 Hz with a linearised sd of 13 Hz: frequency and damping undetermined,
    null sds in JSON, (undetermined) in the text's zero table and the reason under it;
    the 120 Hz mode keeps its sd."""
    frf = measured()
    path = tmp_path / "two.csv"
    write_frf_csv(frf, path)
    args = ("frf", "fit", path, "--poles", "3", "--band", "10,200", "--delay", "none")
    code, text, _ = run_cli(capsys, *args, "--json")
    d = json.loads(text)
    assert code == 0 and d["modes"][0]["freq_determined"]
    zeros = d["zero_pairs"] + d["real_zeros"]
    assert zeros and all(z["freq_sd_hz"] is None and not z["freq_determined"] for z in zeros)
    assert any(n.startswith("a zero outside the fitted band 10-198.4 Hz")
               for n in d["uncertainty"]["notes"])
    code, text, _ = run_cli(capsys, *args)
    rows = [r for r in text.split("\nzero ")[1].splitlines() if r.startswith(("pair", "real"))]
    assert code == 0 and rows and all("(undetermined)" in r and "+-" not in r for r in rows)
    assert "undetermined: a zero outside the fitted band" in text


def test_a_band_above_a_mode_leaves_it_and_the_static_gain_undetermined(capsys, tmp_path):
    """Fitted from 200 Hz up, the 120 Hz mode lies below the band and the static gain is
    an extrapolation to 0 Hz through it: both undetermined, with null sds and the reason;
    the 450 Hz mode and the 900 Hz pole inside the band keep their sd."""
    frf = measured()
    path = tmp_path / "two.csv"
    write_frf_csv(frf, path)
    args = ("frf", "fit", path, "--poles", "5", "--band", "200,2000", "--delay", "none")
    code, text, _ = run_cli(capsys, *args, "--json")
    d = json.loads(text)
    low, high = d["modes"]
    assert not low["freq_determined"] and low["freq_sd_hz"] is None
    assert high["freq_determined"] and high["damping_determined"]
    assert d["real_poles"][0]["freq_determined"]
    assert d["gain"]["gain_sd"] is None and not d["gain"]["gain_determined"]
    assert any(n.startswith("the static gain:") for n in d["uncertainty"]["notes"])
    code, text, _ = run_cli(capsys, *args)
    assert code == 0 and "static gain 0.99" in text and "(undetermined)" in text
    assert "extrapolation to 0 Hz" in " ".join(text.split())


def test_a_fit_that_misses_the_data_gives_no_sd_and_says_so(capsys, tmp_path):
    """A 2 ms delay fitted without one (chi2 ratio above 1e4): no mode, pole or gain
    carries a +-, and text and JSON warn that the fit does not describe the data."""
    frf = measured(delay_s=2e-3, name="late")
    path = tmp_path / "late.csv"
    write_frf_csv(frf, path)
    args = ("frf", "fit", path, "--poles", "5", "--delay", "none")
    code, text, err = run_cli(capsys, *args)
    assert code == 0 and "+- " not in text.split("kind")[1].split("+- one")[0]
    assert "does not describe the data" in err and "does not describe" in text
    code, text, _ = run_cli(capsys, *args, "--json")
    d = json.loads(text)
    assert d["quality"]["chi2_ratio"] > MISFIT
    assert not d["uncertainty"]["describes_data"]
    assert any("does not describe the data" in w for w in d["warnings"])
    every = [v for m in d["modes"] + d["zero_pairs"] for v in m.items()] + [
        v for p in d["real_poles"] + d["real_zeros"] for v in p.items()] + list(
        d["gain"].items())
    assert d["zero_pairs"]
    assert all(v is None for k, v in every if "_sd" in k)
    assert all(v is False for k, v in every if k.endswith("_determined"))


def test_a_pair_its_zeros_cancel_has_no_sd_and_the_gain_it_leaves_alone_has_one():
    """A pole pair at 600 Hz over a numerator that is its own two zeros: pole and zeros
    move together without changing a bin, an exactly singular direction. The pair has no
    finite sd (null in JSON); the 120 Hz mode and the static gain, which that direction
    leaves alone, keep theirs."""
    f = np.geomspace(10.0, 2000.0, 300)
    omega0 = 2 * np.pi * np.sqrt(f[0] * f[-1])
    x = 2j * np.pi * f / omega0
    poles = [2 * np.pi * fn / omega0 * (-z + 1j * np.sqrt(1 - z * z)) for fn, z in
             ((120.0, 0.03), (600.0, 0.1))]
    pn = np.array([poles[0], np.conj(poles[0]), poles[1], np.conj(poles[1])])
    bn = 3.0 * np.real(np.poly(pn[2:]))[::-1]
    H = noisy(np.polyval(bn[::-1], x) / np.prod([x - p for p in pn], axis=0), 0)
    fit = tf_result(f, H, np.ones(f.size), bn, pn, omega0, 0, 0.0, 2, 4, 7, 1.0)
    d = tf_deviations(fit, fit_delay=False).to_dict()
    held, cancelled = d["modes"]
    assert held["freq_determined"] and held["damping_determined"]
    assert cancelled["freq_sd_hz"] is None and cancelled["damping_sd"] is None
    assert d["gain"]["gain"] == pytest.approx(3.0 / abs(pn[0]) ** 2)
    assert d["gain"]["gain_determined"] and d["gain"]["gain_sd"] > 0


def test_an_estimate_says_what_the_data_leave_open():
    assert Estimate(120.0, 0.5).text() == "120 +- 0.5"
    assert Estimate(0.03, 0.02).text() == "0.03 (undetermined)"
    assert Estimate(1.0, math.inf).to_dict("freq_hz") == {
        "freq_hz": 1.0, "freq_sd_hz": None, "freq_determined": False}
    assert Estimate(2e-4, 1e-5).to_dict("delay_s")["delay_sd_s"] == 1e-5
    # undetermined by its size, or for a reason, it has no sd to be read as one
    assert Estimate(0.03, 0.02).to_dict("damping")["damping_sd"] is None
    assert Estimate(120.0, 0.5, why="outside").to_dict("freq_hz")["freq_sd_hz"] is None
    assert Estimate(120.0, 0.5).opened("outside").text() == "120 (undetermined)"


@needs_trace
def test_the_real_trace_s_modes_carry_sensible_sds(capsys):
    """The Sinumerik speed loop: each mode's frequency is held to a few per cent, the
    sharp 2.2 kHz mode's to a bin (4.9 Hz) or less, the antiresonances below the first
    mode and between the first two (629 and 1231 Hz) to a per cent, and the gain of a
    speed loop (1) closely; the delay is undetermined."""
    code, text, _ = run_cli(capsys, "frf", "fit", TRACE, "--json")
    assert code == 0
    d = json.loads(text)
    for m in d["modes"]:
        assert m["freq_determined"] and 0 < m["freq_sd_hz"] < 0.05 * m["freq_hz"]
        assert m["damping_determined"] and m["damping_sd"] > 0
    low = [z for z in d["zero_pairs"] if z["freq_hz"] < d["modes"][1]["freq_hz"]]
    assert len(low) == 2
    assert all(z["freq_determined"] and 0 < z["freq_sd_hz"] < 0.01 * z["freq_hz"]
               and z["damping_determined"] for z in low)
    sharp = max(d["modes"], key=lambda m: 1 / m["damping"])
    assert sharp["freq_sd_hz"] < 4.9
    assert not d["delay"]["delay_determined"] and d["delay"]["delay_sd_s"] is None
    assert d["gain"]["gain"] == pytest.approx(1.0, abs=0.05) and d["gain"]["gain_determined"]
    # the delay carries no +-, and the text says why
    code, text, _ = run_cli(capsys, "frf", "fit", TRACE)
    assert code == 0 and "not bounded by the linearised fit" in " ".join(text.split())
    assert "\nzero " in text and "pair       629.81 +- 3.5" in text


def collocated(seed: int) -> FRF:
    """A collocated two-mass response: modes at 100 and 300 Hz of damping 0.02, an
    antiresonance at 180 Hz of damping 0.01, on 400 bins of 10-1000 Hz, noise draw
    ``seed`` [-]."""
    f = np.geomspace(10.0, 1000.0, 400)
    s = 2j * np.pi * f
    wz = 2 * np.pi * 180.0
    h = 1 + 2 * 0.01 * s / wz + (s / wz) ** 2
    for fn in (100.0, 300.0):
        wn = 2 * np.pi * fn
        h = h / (1 + 2 * 0.02 * s / wn + (s / wn) ** 2)
    return FRF(f, noisy(h, seed), np.ones(f.size), 10, np.zeros(f.size), name="collocated")


def test_a_fit_weighted_also_by_h_keeps_its_sds():
    """The collocated two-mass response's fits mix |H| into the weights, which peak at the
    modes. The noise of each residual row was the running median of the weighted
    residual, which flattened that peak where the modes are decided: 25 refits spread
    3.2-3.7 times the sd of the modes' frequencies. Measured on the relative residual and
    weighted after, the refits of 16 draws that mix |H| in spread 0.6-1.5 times it (25
    draws, all fits: 0.97 and 1.10). Seven of the sixteen mix it in; the others stay at the
    relative fit, at the noise, where reaching vector fitting's total error would leave it."""
    fits = [fit_frf(collocated(seed)) for seed in range(100, 116)]
    fits = [fit for fit in fits if any("weighted also by |H|" in n for n in fit.notes)]
    assert len(fits) >= 6
    for fn in (100.0, 300.0):
        got = [min(fit.deviations.modes, key=lambda m: abs(m[0].value - fn))[0]
               for fit in fits]
        spread = np.std([m.value for m in got], ddof=1)
        sd = np.median([m.sd for m in got])
        assert 0.6 < spread / sd < 1.5, (fn, spread, sd)
