"""Poles outside the fitted band: a mode just beyond it that the bins' tail shows is kept,
and needles below it are not kept for reaching vector fitting's total error."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from tcpmm.ident.frf import FRF
from tcpmm.ident.lti import fit_frf

F = np.linspace(5.0, 2000.0, 800)  # bins 2.5 Hz apart


def _pair(fn, zeta):
    return 2 * np.pi * fn * (-zeta + 1j * np.sqrt(1 - zeta**2))


def _noisy(H, seed, name):
    """1 % complex noise; no coherence column (coherence 1, noise from the roughness)."""
    rng = np.random.default_rng(seed)
    e = (rng.standard_normal(F.size) + 1j * rng.standard_normal(F.size)) / np.sqrt(2)
    return FRF(F, H * (1 + 0.01 * e), np.ones(F.size), 10, np.zeros(F.size), name=name)


def test_auto_keeps_a_mode_just_beyond_the_band_that_the_bins_need():
    """Two modes (120 Hz, 3 %; 450 Hz, 1 %), a 0.25 ms delay, 1 % noise, fitted on
    0-100 Hz: the 120 Hz pair outside the band was flagged unsupported, so --poles auto
    kept one pole at 2e9 Hz with a 2 ms delay (chi2 ratio 108) over two poles (0.7)."""
    s = 2j * np.pi * F
    H = 3.0 * np.exp(-s * 2.5e-4)
    for fn, z in ((120.0, 0.03), (450.0, 0.01)):
        p = _pair(fn, z)
        H = H / ((1 - s / p) * (1 - s / np.conj(p)))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = fit_frf(_noisy(H, 1, "two_modes"), poles="auto", band_hz=(0, 100))
    assert res.tf.n_den >= 2
    assert res.chi2_ratio < 2
    assert np.all(np.abs(res.tf.poles) < 1e6)  # no pole standing in for a gain


def test_needle_pairs_below_the_band_are_not_kept_to_reach_the_total_error():
    """An integrator with a 300/420 Hz zero/pole pair and a 0.15 ms delay on 5-2000 Hz,
    fitted at 8 poles: a pair below the first bin with damping 1e-4 (here at 0.42 Hz;
    on the reported file two at 2.6 Hz, where |H| peaked at 8.8e7 against 61; bins 2.5 Hz
    apart) was kept because that fit alone reached vector fitting's total error."""
    s = 2j * np.pi * F
    pz, pp = _pair(300.0, 0.02), _pair(420.0, 0.02)
    H = (2 * np.pi * 159 / s * (1 - s / pz) * (1 - s / np.conj(pz))
         / ((1 - s / pp) * (1 - s / np.conj(pp))) * np.exp(-s * 1.5e-4))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = fit_frf(_noisy(H, 0, "gm_like"), poles=8)
    fn, zeta = res.tf.natural_freq_hz, res.tf.damping
    outside = (fn < F[0]) | (fn > F[-1])
    assert not np.any(outside & (zeta < 0.2) & (2 * zeta * fn < 2.5))
    # below the band the fit follows the integrator, no resonance of its own
    f_low = np.geomspace(1.0, 5.0, 200)
    truth = 159 / f_low
    assert np.all(np.abs(res.freqresp(f_low)) < 3 * truth)


def test_a_pair_far_above_the_band_is_folded_and_its_spare_zeros_go():
    """Two modes (80 Hz, 3 %; 400 Hz, 2 %) and an antiresonance at 410 Hz given two more
    poles as a pair at 6.5e4 times the top bin (damping 1e-4) and six zeros, as the fit of
    8 poles below found them. The pair changes the response over the band by 2e-10, so it
    is folded into the gain and the numerator refitted with at most the four poles left:
    no zero beyond them, whatever the bins [-]."""
    from tcpmm.ident.lti.tfresult import tf_result

    f = np.geomspace(10.0, 2000.0, 300)
    omega0 = 2 * np.pi * 400.0
    x = 2j * np.pi * f / omega0
    modes = [_pair(80.0, 0.03), _pair(400.0, 0.02)]
    pn = np.array([p / omega0 for q in (*modes, _pair(1.3e8, 1e-4)) for p in (q, np.conj(q))])
    zn = np.array([_pair(410.0, 0.02), _pair(4954.0, -0.014), _pair(2808.0, 0.78)]) / omega0
    bn = np.real(np.poly(np.r_[zn, np.conj(zn)]))[::-1]
    H = np.polyval(bn[::-1], x) / np.prod([x - p for p in pn], axis=0)
    fit = tf_result(f, H, np.ones(f.size), bn, pn, omega0, 0, 0.0, 6, 6, 13, 0.0)
    assert fit.n_den == 4
    assert fit.n_num <= 4


def test_a_fit_of_more_poles_than_the_response_does_not_grow_above_the_band():
    """The response of the test above (no far pair), 300 log-spaced bins over 10-2000 Hz,
    1 % noise, fitted at 8 poles: the fit kept a pair at 1.3e8 Hz and six zeros, and grew
    823-fold two decades above the band, where the response falls as 1 / f^2 (other noise
    draws led to 4 poles; the test above holds the rule whatever the draw). A fit of no more
    zeros than poles the bins see stays within twice the top bins' magnitude (room for a
    zero it places beyond the band) [-]."""
    f = np.geomspace(10.0, 2000.0, 300)
    s = 2j * np.pi * f
    zeros = [_pair(410.0, 0.02), np.conj(_pair(410.0, 0.02))]
    poles = [q for p in (_pair(80.0, 0.03), _pair(400.0, 0.02)) for q in (p, np.conj(p))]
    H = np.prod([1 - s / z for z in zeros], axis=0) / np.prod([1 - s / p for p in poles],
                                                              axis=0)
    rng = np.random.default_rng(2)
    e = (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)) / np.sqrt(2)
    frf = FRF(f, H * (1 + 0.01 * e), np.full(f.size, 1 / 1.001), 10, np.full(f.size, 0.01),
              name="near_cancel")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = fit_frf(frf, poles=8)
    above = np.geomspace(f[-1], 100 * f[-1], 50)
    assert np.abs(res.freqresp(above)).max() <= 2 * np.abs(frf.H[-5:]).max()


def test_a_real_pole_far_above_a_narrow_band_that_carries_a_zero_is_folded():
    """A narrow band (500-750 kHz, 201 bins, 1 % noise) fitted with a real pole at 5600
    times its top, as a reflection measurement's fit at 6 poles had, and as many zeros as
    poles: the pole changes the response over the band by 1.8e-4, a fiftieth of the
    noise, yet carries the fourth zero, and the fit grew 17-fold two decades above the
    band. Judged against the bins' noise it is folded into the gain, and the numerator
    has no more zeros than the three poles left [-]."""
    from tcpmm.ident.lti._needles import clean_fit
    from tcpmm.ident.lti.tfresult import tf_result

    f = np.linspace(5e5, 7.5e5, 201)
    omega0 = 2 * np.pi * 6e5
    x = 2j * np.pi * f / omega0
    mode = _pair(4.13e5, 0.165)
    pn = np.array([-2 * np.pi * 2.67e5, mode, np.conj(mode), -2 * np.pi * 4.18e9]) / omega0
    zn = np.array([_pair(4.38e5, 0.11), _pair(2.06e6, 0.05)]) / omega0
    bn = np.real(np.poly(np.r_[zn, np.conj(zn)]))[::-1]
    rng = np.random.default_rng(0)
    e = (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)) / np.sqrt(2)
    H = np.polyval(bn[::-1], x) / np.prod([x - p for p in pn], axis=0) * (1 + 0.01 * e)
    fit = tf_result(f, H, np.ones(f.size), bn, pn, omega0, 0, 0.0, 4, 4, 10, 0.0)
    cleaned, notes = clean_fit(fit, np.full(f.size, 0.01), 1e-4, f)
    assert cleaned.n_den == 3
    assert cleaned.n_num <= 3
    assert any("folded the real pole" in n for n in notes)


def test_a_pair_below_the_band_raised_to_the_bin_spacing_is_still_a_needle():
    """A narrow band (500-750 Hz, 201 bins 1.25 Hz apart) fitted with a pair at 372 Hz
    whose damping was raised from 5e-13 to the bins' spacing, as the fit of 4 poles of a
    reflection measurement had (scikit-rf's ``ro,1.s1p``, 500-750 GHz): its half-power
    width came out 2.2e-16 above one bin, so ``width < spacing`` called it no needle and
    the fit holding it, 103 times the band's largest magnitude at 372 Hz, reached vector
    fitting's total error. A pair at the spacing has the floor's damping, not a bin's: a
    needle all the same. The width here is the spacing and 1e-12 of it, a rounding of
    the raise larger than the one met and far below any damping a bin could show [-]."""
    from tcpmm.ident.lti._select import score
    from tcpmm.ident.lti.tfresult import tf_result

    f = np.linspace(500.0, 750.0, 201)
    omega0 = 2 * np.pi * float(np.sqrt(f[0] * f[-1]))
    x = 2j * np.pi * f / omega0
    raised = 1.25 / (2 * 371.7) * (1 + 1e-12)
    pn = np.array([q for p in (_pair(371.7, raised), _pair(700.7, 0.933))
                   for q in (p, np.conj(p))]) / omega0
    zn = np.array([q for p in (_pair(409.0, 0.042), _pair(2650.0, 0.31))
                   for q in (p, np.conj(p))]) / omega0
    bn = np.real(np.poly(zn))[::-1]
    H = np.polyval(bn[::-1], x) / np.prod([x - p for p in pn], axis=0)
    fit = tf_result(f, H, np.ones(f.size), bn, pn, omega0, 0, 0.0, 4, 4, 9, 0.0)
    ctx = {"f": f, "H": H, "sigma": np.full(f.size, 0.01), "grid": f}
    assert score(ctx, fit, [], (4, 4))["unsupported"]


def test_a_reflection_measurement_fitted_at_4_poles_has_no_peak_below_its_band():
    """scikit-rf's ``ro,1.s1p`` (a measured reflection, 201 bins over 500-750 GHz), fitted
    at 4 poles, kept a pair at 372 GHz raised to the bins' spacing: 103 times the band's
    largest magnitude a quarter below the band. Vector fitting's 4 poles (scikit-rf's and
    tcpmm's own) peak at 6.0 times it at 456 GHz, a pair of damping 0.005 that the bins'
    tail shows; the fit is held to 10 times down to half the band's lowest frequency [-]."""
    skrf = pytest.importorskip("skrf")
    from pathlib import Path

    ntw = skrf.Network(str(Path(skrf.__file__).parent / "data" / "ro,1.s1p"))
    frf = FRF(ntw.f, ntw.s[:, 0, 0], np.ones(ntw.f.size), 10, np.zeros(ntw.f.size),
              name="ro,1")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = fit_frf(frf, poles=4)
    below = np.linspace(ntw.f[0] / 2, ntw.f[0], 2001)  # 0.125 GHz apart, a tenth of a bin
    assert np.abs(res.freqresp(below)).max() <= 10 * np.abs(frf.H).max()
