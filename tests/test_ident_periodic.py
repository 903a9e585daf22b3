"""FRF from whole periods of a periodic excitation: exact bins, noise across periods."""

import warnings

import numpy as np
import pytest
from scipy.signal import dlsim, dlti

from tcpmm.errors import InputWarning
from tcpmm.ident.frf import estimate_frf
from tcpmm.ident.frf.periodic import detect_period

FS = 1000.0
P = 500
#: A discrete system with a resonance: poles 0.97 e^(+-j 0.6), a zero at -0.5.
SYS = dlti([1.0, 0.5], np.poly([0.97 * np.exp(0.6j), 0.97 * np.exp(-0.6j)]).real, dt=1 / FS)


def _multisine(periods, seed=0, bins=range(2, 200, 3)):
    rng = np.random.default_rng(seed)
    n = np.arange(P)
    u1 = sum(np.cos(2 * np.pi * k * n / P + rng.uniform(0, 2 * np.pi)) for k in bins)
    return np.tile(u1, periods), list(bins)


def _steady_response(u, periods_before=30):
    """Response with the system in periodic steady state from the first sample."""
    warm = np.concatenate([np.tile(u[:P], periods_before), u])
    _, y = dlsim(SYS, warm)
    return y[periods_before * P:, 0]


def _exact(bins):
    z = np.exp(2j * np.pi * np.asarray(bins) / P)
    return np.polyval(SYS.num, z) / np.polyval(SYS.den, z)


@pytest.mark.parametrize("periods", [1, 2, 5])
def test_multisine_gives_the_exact_frf_at_the_excited_bins(periods):
    u, bins = _multisine(periods)
    y = _steady_response(u)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", InputWarning)
        frf = estimate_frf(u, y, FS, period=P if periods == 1 else "auto")
    np.testing.assert_allclose(frf.freq_hz, np.asarray(bins) * FS / P, rtol=1e-12)
    np.testing.assert_allclose(frf.H, _exact(bins), rtol=1e-9)
    assert frf.meta["periodic"] and frf.meta["window"] == "none"


def test_one_period_warns_that_the_noise_is_unknown():
    u, _ = _multisine(1)
    with pytest.warns(InputWarning, match="noise is unknown"):
        frf = estimate_frf(u, _steady_response(u), FS, period=P)
    assert np.all(np.isnan(frf.rel_std))


def test_noise_is_estimated_across_periods():
    """Output noise of std s: the relative error of H at bin k is s sqrt(P/2) / (|Y_k|
    sqrt(K)) for K averaged periods (white noise spreads s^2 P over each DFT bin)."""
    periods, s = 41, 0.05
    u, bins = _multisine(periods)
    y = _steady_response(u) + np.random.default_rng(3).normal(0, s, u.size)
    frf = estimate_frf(u, y, FS)
    k = periods - 1  # the first period is left out as transient
    assert frf.n_averages == k
    expected = s * np.sqrt(P / 2) / (np.abs(_exact(bins)) * (P / 2) * np.sqrt(k))
    ratio = frf.rel_std / expected
    assert 0.85 < np.median(ratio) < 1.15  # a chi-square spread of 2*39 degrees of freedom
    err = np.abs(frf.H / _exact(bins) - 1)
    assert np.mean(err < 3 * frf.rel_std) > 0.95


def test_period_detection_rule():
    u, _ = _multisine(3)
    assert detect_period(u) == P
    chirp = np.sin(2 * np.pi * (5 + 50 * np.arange(800) / 800) * np.arange(800) / FS)
    assert detect_period(np.tile(chirp, 2)) == 800
    rng = np.random.default_rng(1)
    assert detect_period(rng.normal(size=4000)) is None
    assert detect_period(u + rng.normal(0, 0.1, u.size)) is None  # a measured, noisy signal
    assert detect_period(u[:P]) is None  # one period cannot show that it repeats
