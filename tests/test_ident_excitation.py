"""Excitation design: band content, amplitude, crest factor, PRBS properties, errors."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tcpmm.errors import InputError, InputWarning
from tcpmm.ident.excitation import (
    Excitation,
    design_excitation,
    linear_sweep,
    log_sweep,
    multisine,
    prbs,
    prbs_for_band,
    schroeder_phases,
)
from tcpmm.io.bundle import check_excitation_band


def band_fraction(x, fs, f0, f1):
    p = np.abs(np.fft.rfft(x)) ** 2
    f = np.fft.rfftfreq(x.size, 1 / fs)
    return p[(f >= f0) & (f <= f1)].sum() / p.sum()


@pytest.mark.parametrize("fn", [linear_sweep, log_sweep])
def test_sweep_power_is_in_band_and_bounded(fn):
    e = fn(5.0, 200.0, 3.0, 4.0, 2000.0, taper_s=0.1)
    assert isinstance(e, Excitation)
    assert band_fraction(e.signal_A, 2000.0, 5.0, 200.0) > 0.97
    assert band_fraction(e.signal_A, 2000.0, 250.0, 1000.0) < 1e-3
    assert e.peak_A <= 3.0 + 1e-12 and e.peak_A > 2.9
    assert e.signal_A[0] == 0.0 and abs(e.signal_A[-1]) < 3.0 * 1e-3
    assert e.band_hz == (5.0, 200.0)


def _cycles(x):
    return np.count_nonzero(np.diff(np.signbit(x))) / 2


def test_log_and_linear_sweeps_follow_their_frequency_law():
    f0, f1, T, fs = 2.0, 64.0, 10.0, 5000.0
    lin = linear_sweep(f0, f1, 1.0, T, fs)
    log = log_sweep(f0, f1, 1.0, T, fs)
    assert _cycles(lin.signal_A) == pytest.approx((f0 + f1) / 2 * T, abs=1)
    assert _cycles(log.signal_A) == pytest.approx(f0 * T / math.log(f1 / f0) * (f1 / f0 - 1), abs=1)
    # equal time per octave: the first half of a log sweep covers 2..11.3 Hz
    half = log.signal_A[: log.n_samples // 2]
    assert _cycles(half) == pytest.approx(f0 * T / math.log(32) * (math.sqrt(32) - 1), abs=1)


@pytest.mark.parametrize(
    "make",
    [
        lambda: linear_sweep(1, 100, 1, 2.0005, 1000),
        lambda: log_sweep(1, 100, 1, 2.0005, 1000),
        lambda: multisine(1, 100, 1, 2.0005, 1000),
    ],
)
def test_exact_length_and_sample_rate(make):
    e = make()
    assert e.n_samples == 2001 and e.time_s.size == 2001
    assert e.time_s[0] == 0.0
    np.testing.assert_allclose(np.diff(e.time_s), 1e-3, rtol=1e-9)
    assert e.fs_hz == 1000.0


def test_multisine_lines_period_and_crest_factor():
    fs, P = 1000.0, 3
    e = multisine(10.0, 100.0, 2.0, 3.0, fs, n_periods=P)
    n = e.n_samples // P
    one = e.signal_A[:n]
    np.testing.assert_array_equal(e.signal_A, np.tile(one, P))
    spec = np.abs(np.fft.rfft(one))
    f = np.fft.rfftfreq(n, 1 / fs)
    lines = f[spec > 1e-9 * spec.max()]
    np.testing.assert_allclose(lines, e.params["lines_hz"])
    assert lines.min() == 10.0 and lines.max() == 100.0 and lines.size == 91
    np.testing.assert_allclose(spec[spec > 1e-9 * spec.max()], spec.max(), rtol=1e-9)  # flat
    assert e.peak_A == pytest.approx(2.0)
    assert e.params["crest_factor"] == pytest.approx(e.crest_factor)
    rand = [
        multisine(10.0, 100.0, 2.0, 3.0, fs, n_periods=P, phases="random", seed=s)
        for s in range(10)
    ]
    assert e.crest_factor < 2.0 < min(r.crest_factor for r in rand)


def test_schroeder_phases_flat_formula_and_pink_shape():
    K = 7
    k = np.arange(1, K + 1)
    np.testing.assert_allclose(schroeder_phases(np.ones(K)), -np.pi * k * (k - 1) / K)
    e = multisine(10.0, 80.0, 1.0, 1.0, 1000.0, spectrum="pink")
    spec = np.abs(np.fft.rfft(e.signal_A))
    assert spec[80] / spec[20] == pytest.approx(0.5, rel=1e-9)


def test_prbs_period_balance_and_autocorrelation():
    order, m, P, A = 7, 4, 3, 1.5
    e = prbs(order, 250.0, A, 1000.0, n_periods=P)
    L = 2**order - 1
    assert e.n_samples == L * m * P
    assert set(np.unique(e.signal_A)) == {-A, A}
    bits = e.signal_A[: L * m : m] / A
    np.testing.assert_array_equal(np.repeat(bits, m), e.signal_A[: L * m] / A)
    np.testing.assert_array_equal(e.signal_A, np.tile(e.signal_A[: L * m], P))
    assert bits.sum() == 1  # 2**(n-1) ones against 2**(n-1) - 1 minus-ones
    r = np.array([bits @ np.roll(bits, s) for s in range(L)])
    assert r[0] == L and np.all(r[1:] == -1)
    assert e.band_hz == pytest.approx((250.0 / L, 0.443 * 250.0))


def test_prbs_for_band_covers_band_within_duration():
    e = prbs_for_band(2.0, 100.0, 1.0, 5.0, 1000.0)
    assert e.band_hz[0] <= 2.0 and e.band_hz[1] >= 100.0
    assert e.duration_s <= 5.0 and e.params["n_periods"] >= 1
    assert band_fraction(e.signal_A, 1000.0, 2.0, 100.0) > 0.3


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda: linear_sweep(1, 600, 1, 1, 1000), "Nyquist"),
        (lambda: log_sweep(0, 100, 1, 1, 1000), "f0_hz must be > 0"),
        (lambda: log_sweep(-1, 100, 1, 1, 1000), "f0_hz must be > 0"),
        (lambda: linear_sweep(100, 50, 1, 1, 1000), "below f1"),
        (lambda: linear_sweep(1, 100, -1, 1, 1000), "amplitude_A must be positive"),
        (lambda: linear_sweep(1, 100, 1, 0, 1000), "duration_s must be positive"),
        (lambda: linear_sweep(1, 100, 1, 1, float("nan")), "fs_hz must be positive"),
        (lambda: linear_sweep(1, 100, 1, 1, 1000, taper_s=0.6), "taper_s"),
        (lambda: multisine(1, 100, 1, 1, 1000, n_periods=0), "n_periods"),
        (lambda: multisine(1, 1.5, 1, 0.5, 1000), "no frequency line"),
        (lambda: multisine(1, 100, 1, 1, 1000, phases="zero"), "phases"),
        (lambda: multisine(1, 100, 1, 1, 1000, spectrum="blue"), "spectrum"),
        (lambda: prbs(1, 100, 1, 1000), "order"),
        (lambda: prbs(33, 100, 1, 1000), "order"),
        (lambda: prbs(7, 300, 1, 1000), "whole number"),
        (lambda: prbs(7, 2000, 1, 1000), "whole number"),
        (lambda: prbs_for_band(0.01, 100, 1, 5, 1000), "longer than"),
        (lambda: design_excitation("chirp", 1, 100, 1, 1, 1000), "unknown"),
    ],
)
def test_bad_arguments_raise_input_error(call, match):
    with pytest.raises(InputError, match=match):
        call()


def test_design_excitation_dispatch_and_csv(tmp_path):
    for kind, expect in [
        ("linear", "linear_sweep"),
        ("log", "log_sweep"),
        ("multisine", "multisine"),
        ("PRBS", "prbs"),
    ]:
        e = design_excitation(kind, 2.0, 100.0, 1.0, 4.0, 1000.0)
        assert e.kind == expect
        with warnings.catch_warnings():
            warnings.simplefilter("error", InputWarning)
            assert check_excitation_band(e, 2.0, 100.0) == []
    e = design_excitation("log-sweep", 2.0, 100.0, 1.0, 4.0, 1000.0, taper_s=0.05)
    path = e.write_csv(tmp_path / "exc.csv")
    df = pd.read_csv(path)
    assert list(df.columns) == ["time_s", "excitation_A"]
    np.testing.assert_allclose(df["excitation_A"], e.signal_A, rtol=1e-11, atol=1e-12)
    np.testing.assert_allclose(df["time_s"], e.time_s, rtol=1e-11)
    pd.testing.assert_frame_equal(
        e.to_pandas(), pd.DataFrame({"time_s": e.time_s, "excitation_A": e.signal_A})
    )


@settings(max_examples=30, deadline=None)
@given(
    f0=st.floats(0.5, 50),
    ratio=st.floats(1.5, 100),
    fs=st.sampled_from([500.0, 1000.0, 4096.0, 10000.0]),
    T=st.floats(0.1, 3),
    amp=st.floats(1e-3, 50),
    log=st.booleans(),
)
def test_sweep_length_and_bound_property(f0, ratio, fs, T, amp, log):
    f1 = f0 * ratio
    fn = log_sweep if log else linear_sweep
    if f1 > fs / 2:
        with pytest.raises(InputError, match="Nyquist"):
            fn(f0, f1, amp, T, fs)
        return
    e = fn(f0, f1, amp, T, fs)
    assert e.n_samples == round(T * fs)
    assert np.all(np.abs(e.signal_A) <= amp * (1 + 1e-12))


def test_band_check_finds_both_gaps_of_a_multisine():
    e = multisine(10.0, 100.0, 1.0, 4.0, 1000.0)
    with pytest.warns(InputWarning, match=r"no power in 2-[0-9.]+ Hz, [0-9.]+-200 Hz"):
        gaps = check_excitation_band(e, 2.0, 200.0)
    assert len(gaps) == 2
    assert gaps[0][0] == 2.0 and 8.0 <= gaps[0][1] <= 10.0
    assert 100.0 <= gaps[1][0] <= 130.0 and gaps[1][1] == 200.0


def test_a_signal_shorter_than_a_period_of_its_band_start_is_refused():
    """0.1 s of a sweep from 2 Hz was designed and said 'band 2-1000 Hz': it holds a fifth
    of a period of 2 Hz, which it cannot excite."""
    from tcpmm.errors import InputError
    from tcpmm.ident.excitation.kinds import design_excitation

    for kind in ("linear", "log", "multisine"):
        with pytest.raises(InputError, match=r"holds 0\.2 periods of the band's start, 2 Hz"):
            design_excitation(kind, 2.0, 1000.0, 1.0, 0.1, 8000.0)
    # a PRBS's period reaching down to 2 Hz is longer than the 0.5 s of one at 2 Hz
    with pytest.raises(InputError, match=r"lasts 0\.7676 s, .* at least 0\.768 s long"):
        design_excitation("prbs", 2.0, 1000.0, 1.0, 0.1, 8000.0)
    assert design_excitation("linear", 2.0, 1000.0, 1.0, 0.5, 8000.0).time_s.size == 4000


def test_what_excite_takes_and_refuses_is_said_by_its_option(capsys, tmp_path):
    """A band from 0 Hz stopped on an internal ZeroDivisionError; an option of another
    kind of signal gave Python's own words (multisine() got an unexpected keyword argument
    'taper_s'); a PRBS too short was told to last at least 2 s, and refused again at 2 s;
    -o signal.json held CSV; machine export -o of a folder or of .json pointed to a --json
    it does not have."""
    from conftest import run_cli

    base = ["--amplitude-A", 2, "--duration-s", 2, "--fs-hz", 8000, "-o", tmp_path / "s.csv"]
    for args, said in (
            (["log", "--band", "0,1500"], "the band starts at 0 Hz"),
            (["multisine", "--band", "1,100", "--taper-s", 0.1],
             "taper_s does not apply to a multisine signal; it is an option of linear and log"),
            (["log", "--band", "1,100", "--seed", 3], "seed does not apply to a log signal")):
        code, _, err = run_cli(capsys, "excite", *args, *base)
        assert code == 2 and said in " ".join(err.split()), err
    code, _, err = run_cli(capsys, "excite", "prbs", "--band", "0.5,10", *base[:2],
                           "--duration-s", 0.3, *base[4:])
    least = float(" ".join(err.split()).split("make it at least ")[1].split(" s")[0])
    assert run_cli(capsys, "excite", "prbs", "--band", "0.5,10", *base[:2], "--duration-s",
                   least, *base[4:])[0] == 0
    code, _, err = run_cli(capsys, "excite", "log", "--band", "1,100", *base[:-1],
                           tmp_path / "s.json")
    assert code == 2 and "an excitation is written as CSV; name it s.csv" in " ".join(err.split())
    for o, said in ((tmp_path, "is a folder"), (tmp_path / "m.json", "name it m.yaml")):
        code, _, err = run_cli(capsys, "machine", "export", "vmc", "-o", o)
        err = " ".join(err.split())
        assert code == 2 and said in err and "--json" not in err, err
