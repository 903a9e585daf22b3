"""FRF estimation: accuracy against known systems, stated uncertainty, closed loop, bad input."""

from __future__ import annotations

import re

import numpy as np
import pytest
from scipy import signal

from tcpmm.errors import InputError, InputWarning
from tcpmm.ident.frf import (
    FRF,
    estimate_frf,
    frf_against_reference,
    reduced_frfs,
    remove_trend,
    sample_rate_hz,
)

FS = 2000.0


def resonant_dt(f_hz, zeta, fs=FS, gain=1.0):
    """ZOH discretisation of gain * w^2 / (s^2 + 2 zeta w s + w^2): (b, a) in z."""
    w = 2 * np.pi * f_hz
    b, a, _ = signal.cont2discrete(([gain * w * w], [1.0, 2 * zeta * w, w * w]), 1 / fs, "zoh")
    b = np.squeeze(b)
    b[np.abs(b) < 1e-12 * np.max(np.abs(b))] = 0.0  # an exact zero, not round-off
    return b, np.squeeze(a)


def true_frf(b, a, f_hz, fs=FS):
    return signal.freqz(b, a, worN=f_hz, fs=fs)[1]


def log_sweep(duration_s, f0, f1, fs=FS):
    t = np.arange(int(duration_s * fs)) / fs
    return t, signal.chirp(t, f0, duration_s, f1, method="logarithmic")


def normalised_error(frf, H_true):
    """|relative complex error|^2 / rel_std^2: chi-square with 2 degrees of freedom."""
    e = frf.H / H_true - 1.0
    return np.abs(e) ** 2 / frf.rel_std**2


# ----------------------------------------------------------------------------- accuracy


def test_sweep_frf_of_known_discrete_system_within_stated_uncertainty():
    b, a = resonant_dt(120.0, 0.05)
    _, u = log_sweep(60.0, 2.0, 800.0)
    rng = np.random.default_rng(1)
    y = signal.dlsim((np.trim_zeros(b, "f"), a, 1 / FS), u)[1][:, 0]
    y = y + 0.05 * rng.standard_normal(u.size)
    frf = estimate_frf(u, y, FS, fmin_hz=5.0, fmax_hz=700.0)
    H_true = true_frf(b, a, frf.freq_hz)
    good = frf.coherence > 0.9
    assert good.sum() > 1000
    z2 = normalised_error(frf, H_true)[good]
    # errors really are small where coherence is high ...
    assert np.median(np.abs(frf.H[good] / H_true[good] - 1)) < 0.02
    # ... and the stated uncertainty covers them: 95 % of a chi2(2) lies below 5.99
    # (a sweep is deterministic: the formula is slightly optimistic, see the module notes)
    assert np.mean(z2 < 5.99) > 0.85
    assert 0.6 < np.mean(z2) / 2 < 1.6


def test_random_excitation_uncertainty_is_calibrated():
    b, a = resonant_dt(150.0, 0.08)
    rng = np.random.default_rng(7)
    u = rng.standard_normal(int(60 * FS))
    y = signal.lfilter(b, a, u) + 0.3 * rng.standard_normal(u.size)
    frf = estimate_frf(u, y, FS, nperseg=2048, fmin_hz=5.0, fmax_hz=600.0)
    z2 = normalised_error(frf, true_frf(b, a, frf.freq_hz))
    good = frf.coherence > 0.5
    assert 0.8 < np.mean(z2[good]) / 2 < 1.25
    assert frf.n_averages < frf.meta["n_segments"]  # overlap: fewer independent averages


def test_h2_removes_input_noise_bias_that_h1_has():
    b, a = resonant_dt(100.0, 0.1)
    rng = np.random.default_rng(3)
    u = rng.standard_normal(int(40 * FS))
    y = signal.lfilter(b, a, u)
    u_meas = u + 0.7 * rng.standard_normal(u.size)  # noisy input measurement
    h1 = estimate_frf(u_meas, y, FS, estimator="H1", fmin_hz=5.0, fmax_hz=400.0)
    h2 = estimate_frf(u_meas, y, FS, estimator="H2", fmin_hz=5.0, fmax_hz=400.0)
    H_true = true_frf(b, a, h1.freq_hz)
    # H1 is biased low by S_uu/(S_uu+S_nn) = 1/1.49
    assert np.median(np.abs(h1.H / H_true)) == pytest.approx(1 / 1.49, rel=0.03)
    assert np.median(np.abs(h2.H / H_true)) == pytest.approx(1.0, abs=0.03)


# ----------------------------------------------------------------------------- closed loop


def closed_loop(b, a, kp, r, n):
    """u = r - kp y_meas, y_meas = P u + n; returns (u, y_meas)."""
    den = np.polyadd(a, kp * b)
    u = signal.lfilter(a, den, r) - kp * signal.lfilter(a, den, n)
    y = signal.lfilter(b, den, r) + signal.lfilter(a, den, n)
    return u, y


def test_closed_loop_ratio_against_reference_recovers_plant_where_h1_is_biased():
    b, a = resonant_dt(80.0, 0.3, gain=1.0)
    kp = 1.0
    assert np.all(np.abs(np.roots(np.polyadd(a, kp * b))) < 1)  # the loop is stable
    rng = np.random.default_rng(11)
    r = rng.standard_normal(int(60 * FS))
    n = 0.5 * rng.standard_normal(r.size)  # sensor noise fed back by the controller
    u, y = closed_loop(b, a, kp, r, n)
    kw = dict(nperseg=1024, fmin_hz=10.0, fmax_hz=400.0)
    h1 = estimate_frf(u, y, FS, **kw)
    ref = frf_against_reference(r, {"u": u, "y": y}, FS, **kw)
    ratio = ref["y"] / ref["u"]
    H_true = true_frf(b, a, ratio.freq_hz)
    band = ratio.coherence > 0.5
    assert band.sum() > 40
    err_ratio = np.abs(ratio.H[band] / H_true[band] - 1)
    err_h1 = np.abs(h1.H[band] / H_true[band] - 1)
    assert np.median(err_ratio) < 0.06
    assert np.median(err_h1) > 0.15  # H1 is pulled towards -1/C
    assert ratio.input == "u" and ratio.output == "y"


# ----------------------------------------------------------------------------- axis record


def axis_record(ramp_rad_per_s=0.0, quantise=False, tcp=True, seed=5, duration=40.0):
    """A weakly position-controlled motor with a screw/table and a TCP structure downstream."""
    fs = 4000.0
    t, r = log_sweep(duration, 3.0, 600.0, fs)
    J, kt = 1.2e-3, 0.73
    # theta/i = kt / (J s^2 + B s): position-controlled with a PD loop on theta
    sys_theta = signal.cont2discrete(([kt], [J, 0.02, 0.0]), 1 / fs, "zoh")
    bt, at = np.squeeze(sys_theta[0]), np.squeeze(sys_theta[1])
    kp, kd = 2.0, 0.02  # A/rad, A s/rad
    # i = r - C theta with C = kp + kd (1 - z^-1) fs; coefficients ascend in z^-1
    c = np.array([kp + kd * fs, -kd * fs])
    den = np.r_[at, 0.0] + np.convolve(c, bt)
    rng = np.random.default_rng(seed)
    theta = signal.lfilter(bt, den, r)
    i_c = signal.lfilter(np.r_[at, 0.0], den, r)
    bT, aT = resonant_dt(250.0, 0.04, fs, gain=0.01 / (2 * np.pi))
    x_ls = signal.lfilter(bT, aT, theta)
    bp, ap = resonant_dt(45.0, 0.03, fs)
    x_tcp = signal.lfilter(bp, ap, x_ls)
    ramp = ramp_rad_per_s * t
    theta_m = theta + ramp
    x_ls_m = x_ls + ramp * 0.01 / (2 * np.pi)
    x_tcp_m = x_tcp + ramp * 0.01 / (2 * np.pi) + 2e-8 * rng.standard_normal(r.size)
    if quantise:
        q = 2 * np.pi / 10000
        theta_m = np.round(theta_m / q) * q
        x_ls_m = np.round(x_ls_m / 1e-6) * 1e-6
        x_tcp_m = np.round(x_tcp_m / 7.8e-8) * 7.8e-8
    else:
        theta_m = theta_m + 1e-5 * rng.standard_normal(r.size)
        x_ls_m = x_ls_m + 1e-8 * rng.standard_normal(r.size)
    truth = {
        "theta_over_i": (bt, at),
        "G_T": (bT, aT),
        "G_tcp": (bp, ap),
    }
    return (
        dict(
            time_s=t,
            excitation_A=r,
            current_A=i_c,
            motor_angle_rad=theta_m,
            scale_m=x_ls_m,
            tcp_m=x_tcp_m if tcp else None,
        ),
        truth,
        fs,
    )


def test_reduced_frfs_are_the_plant_ratios():
    rec, truth, fs = axis_record()
    frfs = reduced_frfs(**rec, fmin_hz=5.0, fmax_hz=500.0)
    assert set(frfs) == {"G_M", "G_T", "G_tcp"}
    f = frfs["G_M"].freq_hz
    G_M_true = 2j * np.pi * f * true_frf(*truth["theta_over_i"], f, fs)
    for key, H_true in (
        ("G_M", G_M_true),
        ("G_T", true_frf(*truth["G_T"], f, fs)),
        ("G_tcp", true_frf(*truth["G_tcp"], f, fs)),
    ):
        frf = frfs[key]
        good = frf.coherence > 0.9
        assert good.sum() > 0.3 * f.size, key
        assert np.median(np.abs(frf.H[good] / H_true[good] - 1)) < 0.02, key
    assert frfs["G_T"].input == "theta_m" and frfs["G_T"].output == "X_LS"
    assert "G_tcp" not in reduced_frfs(**{**rec, "tcp_m": None}, fmin_hz=5.0, fmax_hz=500.0)


def test_quantised_ramped_positions_give_the_right_frf():
    rec, truth, fs = axis_record(ramp_rad_per_s=2.0, quantise=True)
    frfs = reduced_frfs(**rec, fmin_hz=5.0, fmax_hz=300.0)
    f = frfs["G_T"].freq_hz
    low = (f < 100) & (frfs["G_T"].coherence > 0.9)
    assert low.sum() > 50
    for key in ("G_M", "G_T"):
        H_true = (
            true_frf(*truth["G_T"], f, fs)
            if key == "G_T"
            else (2j * np.pi * f * true_frf(*truth["theta_over_i"], f, fs))
        )
        err = np.abs(frfs[key].H[low] / H_true[low] - 1)
        assert np.median(err) < 0.03, key
        # where coherence is high, the error stays within the stated uncertainty
        z2 = np.abs(frfs[key].H[low] / H_true[low] - 1) ** 2 / frfs[key].rel_std[low] ** 2
        assert np.mean(z2 < 5.99) > 0.8, key
    # quantisation shows up as lost coherence where the motion is a few counts, not as bias
    clean = reduced_frfs(**axis_record(ramp_rad_per_s=2.0)[0], fmin_hz=5.0, fmax_hz=300.0)
    high = f > 200
    assert np.median(frfs["G_T"].coherence[high]) < np.median(clean["G_T"].coherence[high]) - 0.1


# ----------------------------------------------------------------------------- FRF object


def make_frf(H, coh=0.99, rel=0.01, name="a", inp="r", out="y"):
    f = np.linspace(1.0, 100.0, np.size(H))
    return FRF(
        f,
        np.asarray(H, complex),
        np.full(f.size, coh),
        10.0,
        np.full(f.size, rel),
        name=name,
        input=inp,
        output=out,
    )


def test_frf_ratio_propagates_uncertainty_and_coherence():
    a = make_frf(np.full(5, 2.0 + 2.0j), coh=0.9, rel=0.03, out="y")
    b = make_frf(np.full(5, 1.0j), coh=0.8, rel=0.04, out="u")
    q = a / b
    np.testing.assert_allclose(q.H, (2 + 2j) / 1j)
    np.testing.assert_allclose(q.rel_std, 0.05)
    np.testing.assert_allclose(q.coherence, 0.8)
    assert (q.input, q.output) == ("u", "y")


def test_frf_band_differentiate_and_table():
    frf = make_frf(np.ones(100))
    sub = frf.band(10.0, 20.0)
    assert sub.freq_hz.min() >= 10.0 and sub.freq_hz.max() <= 20.0
    d = frf.differentiate(output="v")
    np.testing.assert_allclose(d.H, 2j * np.pi * frf.freq_hz)
    table = frf.to_pandas()
    assert list(table.columns[:3]) == ["freq_hz", "re", "im"]
    assert len(table) == 100
    with pytest.raises(InputError):
        frf.band(200.0, 300.0)


def test_frf_ratio_needs_same_grid():
    a = make_frf(np.ones(5))
    b = FRF(np.arange(1.0, 6.0) * 3, np.ones(5), np.ones(5), 1.0, np.zeros(5))
    with pytest.raises(InputError, match="different frequency grids"):
        a / b


def test_remove_trend_takes_out_ramp_and_parabola():
    t = np.linspace(0, 10, 1001)
    wave = np.cos(2 * np.pi * 5 * t)
    np.testing.assert_allclose(remove_trend(3.0 + 2.0 * t + wave, 1), wave, atol=0.01)
    np.testing.assert_allclose(remove_trend(1.0 - t + 0.3 * t**2, 2), 0.0, atol=1e-9)
    assert np.ptp(remove_trend(1.0 - t + 0.3 * t**2, 1)) > 1.0


# ----------------------------------------------------------------------------- bad input


def test_nan_is_an_error_naming_the_signal():
    u = np.random.default_rng(0).standard_normal(20000)
    y = u.copy()
    y[123] = np.nan
    with pytest.raises(InputError, match="non-finite") as e:
        estimate_frf(u, y, FS, input="excitation_A", output="scale_m")
    assert e.value.column == "scale_m"


def test_excitation_without_power_is_an_error_naming_file_and_column():
    u = np.zeros(20000)
    y = np.random.default_rng(0).standard_normal(20000)
    with pytest.raises(InputError, match="carries no power") as e:
        estimate_frf(u, y, FS, input="excitation_A", output="scale_m", file="X/sweep.csv")
    assert (e.value.column, e.value.file) == ("excitation_A", "X/sweep.csv")


def test_record_too_short_for_lowest_frequency():
    u = np.random.default_rng(0).standard_normal(int(2 * FS))  # 2 s
    with pytest.raises(InputError, match="record too short for the lowest frequency 1 Hz"):
        estimate_frf(u, u, FS, fmin_hz=1.0)
    with pytest.raises(InputError, match="too coarse for fmin_hz"):
        estimate_frf(u, u, FS, nperseg=256, fmin_hz=5.0)


def test_non_uniform_time_is_an_error():
    t = np.arange(1000) / FS
    t[500:] += 0.5 / FS  # a half-step glitch
    with pytest.raises(InputError, match="not uniformly sampled") as e:
        sample_rate_hz(t, file="X/sweep.csv")
    assert e.value.column == "time_s" and e.value.file.endswith("sweep.csv")
    r = np.random.default_rng(0).standard_normal(t.size)
    with pytest.raises(InputError, match="not uniformly sampled"):
        reduced_frfs(r, r, r, r, time_s=t)
    assert sample_rate_hz(np.arange(1000) / FS) == pytest.approx(FS)


def test_band_without_excitation_power_warns_naming_it():
    t = np.arange(int(20 * FS)) / FS
    rng = np.random.default_rng(2)
    u = sum(
        np.cos(2 * np.pi * fk * t + rng.uniform(0, 6.3))
        for fk in np.r_[np.arange(10.0, 100.0, 0.5), np.arange(300.0, 400.0, 0.5)]
    )
    with pytest.warns(InputWarning, match=r"no excitation power in 1\d\d(\.\d+)?-2\d\d(\.\d+)? Hz"):
        frf = estimate_frf(u, u, FS, nperseg=2000, fmin_hz=10.0, fmax_hz=400.0)
    assert frf.freq_hz[0] >= 10.0 and frf.freq_hz[-1] <= 400.0


def test_other_bad_arguments():
    u = np.random.default_rng(0).standard_normal(10000)
    with pytest.raises(InputError, match="estimator"):
        estimate_frf(u, u, FS, estimator="H3")
    with pytest.raises(InputError, match="overlap"):
        estimate_frf(u, u, FS, overlap=1.0)
    with pytest.raises(InputError, match="samples"):
        estimate_frf(u, u[:-1], FS)
    with pytest.raises(InputError, match="sample rate"):
        estimate_frf(u, u, 0.0)
    with pytest.raises(InputError, match="fs_hz or the time vector"):
        reduced_frfs(u, u, u, u)


def _swept_mode(f0_hz=16.0, zeta=0.035, fs_hz=10_000.0, duration_s=15.0):
    """A log sweep 2-1000 Hz through a mode of ``f0_hz`` [Hz] and damping ``zeta`` [-],
    stepped exactly (zero-order hold); the excitation, the response and the true
    response on a grid [-]."""
    t = np.arange(int(duration_s * fs_hz)) / fs_hz
    k = np.log(1000.0 / 2.0) / duration_s
    r = np.sin(2 * np.pi * 2.0 * (np.exp(k * t) - 1.0) / k)
    w0 = 2 * np.pi * f0_hz
    a = np.array([[0.0, 1.0], [-(w0**2), -2 * zeta * w0]])
    b, c = np.array([[0.0], [w0**2]]), np.array([[1.0, 0.0]])
    Ad, Bd, Cd, Dd, _ = signal.cont2discrete((a, b, c, np.zeros((1, 1))), 1.0 / fs_hz, "zoh")
    y = signal.dlsim((Ad, Bd, Cd, Dd, 1.0 / fs_hz), r)[1][:, 0]
    return r, y, fs_hz, lambda f: w0**2 / (w0**2 - (2 * np.pi * f) ** 2
                                          + 2j * zeta * w0 * 2 * np.pi * f)


def test_the_whole_record_keeps_a_mode_the_sweep_passes_faster_than_it_rings_down():
    """E's head mode: 16 Hz, 3.5 % damping, a 15 s log sweep. The segments cut its
    ringing, so their estimate sags at the peak (measured: 15 % here); weighted with the
    whole record's estimate the sag halves (7 %; a quadratic over +-2 segment bins does
    not quite follow a peak 1.1 Hz wide)."""
    from tcpmm.ident.frf import WholeRecord, combine_estimates

    r, y, fs, true = _swept_mode()
    seg = frf_against_reference(r, {"y": y}, fs, fmin_hz=3.0, fmax_hz=200.0)["y"]
    m = seg.meta["nperseg"]
    whole = WholeRecord(remove_trend(r, 1), m, np.rint(seg.freq_hz * m / fs).astype(int))
    weighed, _ = combine_estimates(seg.H, seg.rel_std, *whole.response(remove_trend(y, 1)))
    near = np.abs(seg.freq_hz - 16.0) < 1.5
    worst = {est: np.max(np.abs(H[near] / true(seg.freq_hz[near]) - 1.0))
             for est, H in (("segments", seg.H), ("weighed", weighed))}
    assert worst["segments"] > 0.1
    assert worst["weighed"] < 0.5 * worst["segments"]


def test_estimates_are_combined_by_their_inverse_variances():
    from tcpmm.ident.frf import combine_estimates

    H, rel = combine_estimates(np.array([1.0, 1.0, 2.0]), np.array([0.1, 0.1, np.inf]),
                               np.array([2.0, 3.0, 5.0]), np.array([0.1, 0.2, 0.5]))
    assert H == pytest.approx([1.5, 1.4, 5.0])
    assert rel == pytest.approx([0.1, 0.1, 0.5])


def test_gaps_beyond_the_swept_band_are_not_listed_and_the_file_is_named():
    """A sweep's leakage above its top end dips below the no-power level here and there:
    identify listed those dips (993.7-1223 Hz, ... 3928-4072 Hz above a sweep ending at
    1000 Hz) as gaps of the excitation. Only a gap within the band the excitation sweeps is
    one; the warning names the file and that band."""
    from scipy import signal as sg

    t = np.arange(int(20 * FS)) / FS
    rng = np.random.default_rng(2)
    u = sum(
        np.cos(2 * np.pi * fk * t + rng.uniform(0, 6.3))
        for fk in np.r_[np.arange(10.0, 100.0, 0.5), np.arange(300.0, 400.0, 0.5)]
    )
    leak = sg.sosfilt(sg.butter(8, 450, "highpass", fs=FS, output="sos"),
                      rng.standard_normal(t.size))
    with pytest.warns(InputWarning) as got:
        frf = estimate_frf(u + 0.05 * leak, u, FS, nperseg=2000, fmin_hz=10.0,
                           file="X/sweep.csv")
    (text,) = [str(w.message) for w in got if "no excitation power" in str(w.message)]
    assert re.fullmatch(r"X/sweep\.csv: no excitation power in 1\d\d-2\d\d Hz, within the "
                        r"band it sweeps \(10-40\d Hz; .*", text), text
    assert frf.freq_hz[-1] > 900.0  # the band of the FRF itself is as it was
