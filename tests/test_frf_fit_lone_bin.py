"""A bin over the coherence cut among bins under it is the scatter of its coherence
estimate, not a band the sweep excited (tcpmm.ident.lti.frfnoise.lone_passes): bench E's
G_T kept one bin at 1942 Hz of coherence 0.51 among 0.03-0.5 and 57 times the bins'
median magnitude, which held 9 % of the fitted bins' sum |H|^2, and vector fitting's
needle on it out-scored every fit of tcpmm's on the total error."""

import warnings

import numpy as np

from tcpmm.ident.frf import FRF
from tcpmm.ident.lti import fit_frf


def test_a_lone_bin_over_the_coherence_cut_is_left_out():
    """Two modes measured with coherence 0.95 up to 600 Hz, the sweep's noise above
    (coherence 0.05-0.45, |H| a hundred times the response's there); one bin of them
    passes at 0.51. It is not fitted; a pair of bins passing together above is kept."""
    rng = np.random.default_rng(3)
    f = np.linspace(5.0, 2000.0, 800)
    s = 2j * np.pi * f
    H = 1e6 / ((s**2 + 2 * 0.03 * 754 * s + 754**2) * (s**2 + 2 * 0.02 * 2513 * s + 2513**2))
    H = H * 1e8 / abs(H[0]) * 1e-8
    coh = np.full(f.size, 0.95)
    loud = f > 600.0
    coh[loud] = rng.uniform(0.05, 0.45, loud.sum())
    H = np.where(loud, 100 * np.abs(H).max() * np.exp(2j * np.pi * rng.random(f.size)), H)
    lone = int(np.searchsorted(f, 1900.0))
    coh[lone] = 0.51
    frf = FRF(f, H, coh, 10, np.sqrt((1 - coh) / (2 * 10 * coh)), name="lone")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = fit_frf(frf, poles=4)
    assert f[lone] not in res.tf.freq_hz
    assert res.tf.freq_hz.max() < 600.0
    from tcpmm.ident.lti.frfnoise import lone_passes

    pair = np.zeros(12, bool)
    pair[[5, 6]] = True  # two bins passing side by side are a band, however narrow
    assert not lone_passes(pair).any()
    pair[[6, 11]] = [False, True]
    assert lone_passes(pair)[[5, 11]].all()
