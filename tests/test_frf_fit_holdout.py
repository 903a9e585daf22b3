"""``benchmarks/frf_fit.py --holdout``: each fitter judged on the bins it did not fit."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

from test_frf_fit import _bench


def test_the_halves_interleave_and_the_other_half_judges(capsys):
    """The even and the odd bins share none and hold all; each split's rows give both
    errors on the bins fitted and on the other half (and against the truth there), the mean
    row both splits' kept pole counts; a half of too few bins is refused with tcpmm's
    reason, not a traceback [-]."""
    bench = _bench()
    pytest.importorskip("skrf")
    frf, truth = bench.made_frf("coarse, 128 bins")
    even, odd = bench.half_frf(frf, 0), bench.half_frf(frf, 1)
    assert not np.intersect1d(even.freq_hz, odd.freq_hz).size
    assert np.array_equal(np.sort(np.r_[even.freq_hz, odd.freq_hz]), frf.freq_hz)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rows = bench.holdout(frf, [4], truth)
    assert [r["split"] for r in rows] == [0, 0, 1, 1, "mean", "mean"]
    for r in rows:
        assert {"fit_total_rel", "held_total_rel", "fit_median_rel", "held_median_rel"} <= set(r)
        assert r["held_total_rel"] < 0.01  # 1 % noise: both fitters describe the other half
        # against the truth the noise of the held-out bins is gone: below their own error
        assert r["held_truth_total_rel"] < r["truth_held_total_rel"]
    assert rows[4]["kept"] == [rows[0]["kept"], rows[2]["kept"]]
    few = bench.replace(frf, freq_hz=frf.freq_hz[:6], H=frf.H[:6],
                        coherence=frf.coherence[:6], rel_std=frf.rel_std[:6])
    refused = bench.holdout_rows(few, 2, few.freq_hz)
    assert refused and all("at least 4 are needed" in r["refused"] for r in refused)
    bench._print_holdout(refused)
    assert "tcpmm refuses a half" in capsys.readouterr().out


def test_the_holdout_flag_prints_json_rows(capsys, tmp_path):
    """``--holdout --json`` gives the rows of every made response; without the flag the
    rows are those of the fits on all bins, as before [-]."""
    bench = _bench()
    pytest.importorskip("skrf")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert bench.main(["--poles", "4", "--file", str(tmp_path / "none.xml"), "--json",
                           "--holdout"]) == 0
    rows = json.loads(capsys.readouterr().out)
    assert {r["response"] for r in rows} == set(bench.MADE)
    assert all("held_total_rel" in r for r in rows)
