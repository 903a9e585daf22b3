"""A fit at the noise is not traded for vector fitting's total error, which only the noise
of the largest bins lies below. Three modes with 1 % noise: vector fitting's poles leave a
total error of 3.9e-5 where the true response itself leaves 6.7e-5; the fit held to it
came out at a chi2 ratio of 14, off the truth by 4.9 dB at the antiresonance near 430 Hz."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from tcpmm.ident.frf import FRF
from tcpmm.ident.lti import fit_frf
from tcpmm.ident.lti._select import AT_NOISE_CHI2


def three_modes(seed: int):
    """Modes at 80, 250 and 700 Hz (damping 0.01, 0.005, 0.003) summed as a structure's
    receptance is, a 0.25 ms delay, on 300 log-spaced bins of 10-2000 Hz with 1 % complex
    noise, no coherence given (the noise is read from the response's roughness); and the
    truth [-]."""
    f = np.geomspace(10.0, 2000.0, 300)
    s = 2j * np.pi * f
    h = sum(r * w**2 / (s**2 + 2 * z * w * s + w**2) for w, z, r in (
        (2 * np.pi * 80, 0.01, 1.0), (2 * np.pi * 250, 0.005, 0.4), (2 * np.pi * 700, 0.003, 0.15)))
    h = h * np.exp(-s * 2.5e-4)
    rng = np.random.default_rng(seed)
    e = (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)) / np.sqrt(2)
    return FRF(f, h * (1 + 0.01 * e), np.ones(f.size), 1, np.zeros(f.size), name="three"), h


@pytest.mark.parametrize("seed", [1, 7, 11])
def test_a_fit_at_the_noise_keeps_the_antiresonances(seed):
    frf, truth = three_modes(seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = fit_frf(frf, poles=6)
    h = res.freqresp(frf.freq_hz)
    assert np.max(np.abs(h / truth - 1)) < 0.05  # 76 % at the antiresonance
    assert res.chi2_ratio <= AT_NOISE_CHI2
    # a total error above vector fitting's is said, with why
    short = any("short of" in n for n in res.notes)
    assert not short or any("the noise leaves by itself" in n for n in res.notes), res.notes


def test_the_note_of_a_fit_kept_at_the_noise_says_where_its_total_lies():
    """The fit kept at the noise over one of a lower criterion that follows the noise was
    noted as above vector fitting's total error, also where it reaches that total too."""
    from tcpmm.ident.lti._select import _quiet_or

    def fit(total, chi2, bic):
        return {"total": total, "chi2_ratio": chi2, "bic": bic, "unsupported": False,
                "notes": []}

    loud = fit(0.010, 3 * AT_NOISE_CHI2, 1.0)
    for quiet_total, words in ((0.012, "above the 0.0105 of"), (0.0104, "within the 0.0105 of")):
        quiet = fit(quiet_total, 1.0, 2.0)
        kept = _quiet_or(loud, [loud, quiet], ref=0.0105, noise=0.02)
        assert kept["total"] == quiet_total and kept["short"] is False
        assert words in kept["notes"][-1], kept["notes"]
    assert "lower criterion" in kept["notes"][-1]


def test_a_fit_at_the_noise_gives_way_to_one_of_fewer_poles_at_the_noise_too():
    """Machine C's Y sweep, its G_T (5-2000 Hz as identify estimates it), at 7 poles: of
    the fits at the noise the least criterion was the relative fit, whose total error of
    0.197 is six times the 0.032 of the fit chosen at 6 poles (chi2 ratio 0.76), and four
    times vector fitting's 0.043. The 7 poles hold every fit of 6, so that one is kept: a
    total error no more than the 6-pole fit's, at a chi2 ratio at most AT_NOISE_CHI2 [-]."""
    import sys
    from pathlib import Path

    from conftest import bench_path

    sys.path.insert(0, str(Path(__file__).parents[1] / "benchmarks"))
    from frf_fit import bundle_frfs, errors

    frf = bundle_frfs(bench_path("c") / "bundle", axis="Y")[1]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        six, seven = (fit_frf(frf, poles=n) for n in (6, 7))
    total = [errors(r.tf.H, r.freqresp(r.tf.freq_hz))["total_rel"] for r in (six, seven)]
    assert total[1] <= total[0] * (1 + 1e-9)
    assert seven.chi2_ratio <= AT_NOISE_CHI2
