"""Friction identification: IDIM-LS and Stribeck plateaus on simulated runs."""

import numpy as np
import pytest

from studies.rigidaxis import (
    DiscreteServo,
    RigidAxis,
    friction_from_idim,
    idim_ls,
    simulate_rigid_servo,
)
from tcpmm.errors import InputError
from tcpmm.ident.frf import decimate
from tcpmm.ident.friction import (
    PLATEAU_DURATIONS_S,
    find_plateaus,
    fit_stribeck,
    identify_stribeck_run,
    read_friction_csv,
)
from tcpmm.mechanics.friction import StribeckFriction

T = 1e-3
EMPS_LIKE = DiscreteServo(period=T, kp=160.18, kv=243.45, delay=0.0, u_max=10.0,
                          gain=35.15)


def trapezoid_reference(speeds, accel=2.0, cruise=0.6, dwell=0.2):
    """Back-and-forth moves with trapezoidal velocity, one cruise speed per move."""
    v = [0.0]
    for s in speeds:
        n_acc = int(abs(s) / accel / T)
        v += list(np.linspace(0, s, n_acc)) + [s] * int(cruise / T)
        v += list(np.linspace(s, 0, n_acc)) + [0.0] * int(dwell / T)
    return np.cumsum(v) * T


REF = trapezoid_reference([0.05, -0.05, 0.1, -0.1, 0.02, -0.02, 0.15, -0.15, 0.08, -0.08])


def _closed_loop_run(friction, mass=95.0, offset=0.0):
    axis = RigidAxis(mass=mass, offset=offset, friction=friction)
    return simulate_rigid_servo(REF, axis, EMPS_LIKE, n_sub=20, q0=0.0)


def test_idim_recovers_symmetric_rigid_axis():
    r = _closed_loop_run(StribeckFriction.symmetric(fc=20.0, fv=200.0, v_stick=0.0),
                         offset=-3.0)
    # with delay 0 the force sampled at k acts over [k, k+1): it is centred half a
    # sample later than the acceleration estimate
    est = idim_ls(r.q, r.force, T, decimation=10, force_shift=0.5, v_min=2e-3)
    assert est["M"] == pytest.approx(95.0, rel=3e-3)
    assert est["Fv"] == pytest.approx(200.0, rel=3e-3)
    assert est["Fc"] == pytest.approx(20.0, rel=3e-3)
    assert est["offset"] == pytest.approx(-3.0, rel=1e-2)
    assert est.relative_error < 1.0
    assert np.all(est.std > 0)
    # mis-aligned force (no shift) fits visibly worse
    worse = idim_ls(r.q, r.force, T, decimation=10, force_shift=0.0, v_min=2e-3)
    assert worse.relative_error > 2 * est.relative_error
    fr, off = friction_from_idim(est)
    assert fr.fc_pos == fr.fc_neg == pytest.approx(est["Fc"]) and off == est["offset"]


def test_idim_recovers_asymmetric_friction():
    truth = StribeckFriction(fc_pos=20.0, fc_neg=23.0, fv_pos=180.0, fv_neg=230.0,
                             v_stick=0.0)
    r = _closed_loop_run(truth)
    est = idim_ls(r.q, r.force, T, decimation=10, friction="asymmetric", force_shift=0.5,
                  v_min=2e-3)
    for name, val in (("M", 95.0), ("Fv+", 180.0), ("Fv-", 230.0), ("Fc+", 20.0),
                      ("Fc-", 23.0)):
        assert est[name] == pytest.approx(val, rel=5e-3), name
    fr, off = friction_from_idim(est)
    assert fr.fc_neg == pytest.approx(est["Fc-"]) and fr.fv_pos == pytest.approx(est["Fv+"])
    assert off == 0.0  # absorbed into Fc+ and Fc-


def test_idim_stribeck_option_finds_low_speed_excess():
    truth = StribeckFriction(fc_pos=20.0, fc_neg=23.0, fs_pos=30.0, fs_neg=28.0, vs=0.01,
                             fv_pos=180.0, fv_neg=230.0, v_stick=0.0)
    r = _closed_loop_run(truth)
    plain = idim_ls(r.q, r.force, T, decimation=10, friction="asymmetric",
                    force_shift=0.5, v_min=2e-3)
    est = idim_ls(r.q, r.force, T, decimation=10, friction="asymmetric", force_shift=0.5,
                  v_min=2e-3, stribeck_velocity="fit")
    assert est.relative_error < 0.5 * plain.relative_error
    assert est["M"] == pytest.approx(95.0, rel=5e-3)
    fr, _ = friction_from_idim(est)
    assert fr.fs_pos == pytest.approx(30.0, rel=0.1) and fr.fs_neg == pytest.approx(28.0, rel=0.1)
    assert 0.003 < fr.vs < 0.03


@pytest.fixture(scope="module")
def stribeck_run():
    speeds = [0.002, 0.004, 0.008, 0.015, 0.03, 0.06, 0.1]
    seq = [x for s in speeds for x in (s, -s)]
    ref = trapezoid_reference(seq, accel=0.5, cruise=1.0, dwell=0.1)
    truth = StribeckFriction(fc_pos=20.0, fc_neg=23.0, fs_pos=30.0, fs_neg=28.0, vs=0.01,
                             fv_pos=200.0, fv_neg=200.0, v_stick=0.0)
    servo = DiscreteServo(period=T, kp=30.0, kv=1e4, ki=3e5, delay=0.0, u_max=1000.0,
                          gain=1.0)
    r = simulate_rigid_servo(ref, RigidAxis(mass=50.0, friction=truth), servo, q0=0.0)
    return r, speeds


def test_plateaus_found_in_both_directions(stribeck_run):
    r, speeds = stribeck_run
    from tcpmm.ident.frf import central_difference, lowpass_filtfilt

    v = central_difference(lowpass_filtfilt(r.q, T, 20.0), T)
    pl = find_plateaus(r.t, v, r.force)
    got = sorted(round(p.velocity, 4) for p in pl)
    assert got == sorted([x for s in speeds for x in (s, -s)])


def test_stribeck_curve_recovered_from_plateaus(stribeck_run):
    r, _ = stribeck_run
    est, pl = identify_stribeck_run(r.t, r.q, r.force)
    assert len(pl) == 14
    for name, val in (("Fc+", 20.0), ("Fc-", 23.0), ("Fs+", 30.0), ("Fs-", 28.0),
                      ("vs", 0.01), ("Fv", 200.0)):
        assert est[name] == pytest.approx(val, rel=5e-3), name
        assert est.std_of(name) < 0.01 * val
    tied = fit_stribeck([p.velocity for p in pl], [p.force for p in pl], tie_static=True)
    assert tied["Fs+"] == tied["Fs-"]
    assert tied.relative_error > est.relative_error


def test_stribeck_fit_needs_both_directions():
    with pytest.raises(InputError, match="both directions"):
        fit_stribeck([0.01, 0.02, 0.03, 0.04, 0.05, 0.06, 0.07], np.arange(7.0))


def test_read_friction_csv(tmp_path, stribeck_run):
    r, _ = stribeck_run
    lead, ktc = 0.01, 0.5
    theta = r.q * 2 * np.pi / lead
    current = r.force * lead / (2 * np.pi * ktc)
    p = tmp_path / "friction.csv"
    rows = ["time_s,current_cmd_A,motor_angle_rad,scale_mm"]
    rows += [",".join(repr(float(v)) for v in row) for row in
             zip(r.t, current, theta, r.q * 1e3, strict=True)]
    p.write_text("\n".join(rows) + "\n")
    t, x, f = read_friction_csv(p, lead=lead, torque_constant=ktc)
    assert np.allclose(x, r.q, rtol=0, atol=1e-15) and np.allclose(f, r.force)
    _, xm, _ = read_friction_csv(p, lead=lead, torque_constant=ktc, position="motor")
    assert np.allclose(xm, r.q, atol=1e-15)
    est, _ = identify_stribeck_run(t, x, f)
    assert est["Fc-"] == pytest.approx(23.0, rel=5e-3)
    bad = tmp_path / "bad.csv"
    bad.write_text("time_s,current_cmd_A,scale_mm\n0,1,2\n")
    with pytest.raises(InputError, match="motor_angle_rad"):
        read_friction_csv(bad, lead=lead, torque_constant=ktc)
    bad.write_text("time_s,current_cmd_A,motor_angle_rad,scale_mm\n0,1,2,3\n0.001,x,2,3\n")
    with pytest.raises(InputError, match="line 3"):
        read_friction_csv(bad, lead=lead, torque_constant=ktc)


def test_decimate_keeps_last_sample_aligned():
    n = 1003
    k = np.arange(n)
    x = 1.0 + 0.5 * np.sin(2 * np.pi * k / 400.0)
    y = decimate(x, 10)
    assert y.size == 101  # ceil(1003 / 10)
    # MATLAB convention: the kept samples end on the last one, 2, 12, ..., 1002
    # (compared after a best gain: the Chebyshev I pass band is 0.05 dB below 1 at DC)
    def misfit(start):
        xs = x[start::10][5:95]
        g = (xs @ y[5:95]) / (xs @ xs)
        return np.max(np.abs(y[5:95] - g * xs))

    fits = [misfit(o) for o in range(10)]
    assert int(np.argmin(fits)) == 2 and fits[2] < 4e-3 < min(fits[1], fits[3])
    assert np.array_equal(decimate(x, 1), x)


def test_idim_bad_input():
    with pytest.raises(InputError, match="same length"):
        idim_ls(np.zeros(500), np.zeros(400), T)
    with pytest.raises(InputError, match="friction"):
        idim_ls(np.zeros(500), np.zeros(500), T, friction="lugre")
    with pytest.raises(InputError, match="Nyquist"):
        idim_ls(np.zeros(500), np.zeros(500), T, cutoff=600.0)


def test_short_passes_are_found_too():
    """Passes of 0.3 s at four speeds: with plateaus of at least 0.2 s only the fastest pair
    is left (the steadiness window and the trim eat the ends), too few for the fit; the
    shorter durations tried next find the others, at the true steady friction."""
    speeds = [0.002, 0.01, 0.03, 0.1]
    ref = trapezoid_reference([x for s in speeds for x in (s, -s)], accel=0.5, cruise=0.3,
                              dwell=0.1)
    truth = StribeckFriction(fc_pos=20.0, fc_neg=23.0, fs_pos=30.0, fs_neg=28.0, vs=0.01,
                             fv_pos=200.0, fv_neg=200.0, v_stick=0.0)
    servo = DiscreteServo(period=T, kp=30.0, kv=1e4, ki=3e5, delay=0.0, u_max=1000.0,
                          gain=1.0)
    r = simulate_rigid_servo(ref, RigidAxis(mass=50.0, friction=truth), servo, q0=0.0)
    with pytest.raises(InputError, match="both directions"):
        identify_stribeck_run(r.t, r.q, r.force, min_duration=PLATEAU_DURATIONS_S[0])
    est, pl = identify_stribeck_run(r.t, r.q, r.force)
    found = {round(p.velocity, 2) for p in pl}
    assert found >= {x for s in speeds[1:] for x in (s, -s)}  # 2 mm/s is not steady enough
    # The plateaus' forces are the true steady friction; three or four speeds per
    # direction do not pin the six Stribeck parameters one by one.
    for p in pl:
        fc, fs = (20.0, 30.0) if p.velocity > 0 else (23.0, 28.0)
        true = np.sign(p.velocity) * (fc + (fs - fc) * np.exp(-((p.velocity / 0.01) ** 2)))
        assert p.force == pytest.approx(true + 200.0 * p.velocity, rel=0.01), p.velocity
    assert set(est.names) >= {"Fc+", "Fc-", "Fv"}


def _estimate(values, std):
    from tcpmm.ident.friction.estimate import ParameterEstimate

    return ParameterEstimate(names=("Fc+", "Fc-", "Fs+", "Fs-", "vs", "Fv"),
                             values=np.array(values, float), std=np.array(std, float),
                             relative_error=1.0, residual_std=1.0, condition=1.0, n_samples=12)


def test_a_hump_the_runs_fix_is_kept():
    """Machine C's X from its runs: static levels 30 N above Coulomb, known within 2 N."""
    from tcpmm.ident.friction.stribeck import without_undetermined_hump

    est = _estimate([97.7, 98.7, 128.2, 127.3, 1.68e-3, 1679.0],
                    [0.9, 0.9, 1.6, 1.6, 1.0e-4, 14.0])
    kept, why = without_undetermined_hump(est)
    assert kept is est and why == ""


def test_a_hump_the_runs_do_not_fix_is_taken_out():
    """Runs of an axis without friction: the fit extrapolates meganewtons of static friction
    from noise; the curve keeps the Coulomb level at rest and says so."""
    from tcpmm.ident.friction.stribeck import without_undetermined_hump

    est = _estimate([0.0, 0.0, 6756.0, 6.4e6, 5.1e-5, 2859.0],
                    [0.11, 0.11, 5305.0, 1.9e8, 2.2e-4, 2.0])
    kept, why = without_undetermined_hump(est)
    assert kept["Fs+"] == kept["Fc+"] == 0.0 and kept["Fs-"] == 0.0
    assert np.isnan(kept.std_of("Fs+")) and kept["Fv"] == 2859.0
    assert "no sliding friction" in why and "slower" in why
    # one loose side only: the other keeps its hump
    est = _estimate([97.7, 98.7, 128.2, 900.0, 1.68e-3, 1679.0],
                    [0.9, 0.9, 1.6, 700.0, 1.0e-4, 14.0])
    kept, why = without_undetermined_hump(est)
    assert kept["Fs+"] == 128.2 and kept["Fs-"] == 98.7 and "Fs-" in why
    assert "no sliding friction" not in why


def test_a_lugre_contact_needs_sliding_friction():
    """With no Coulomb level the bristles' relaxation ``|v| z / g(v)`` divides by zero."""
    from tcpmm.mechanics.friction import LuGreFriction

    with pytest.raises(InputError, match="Coulomb level above 0"):
        LuGreFriction(fc_pos=0.0, fc_neg=10.0, fs_pos=50.0, fs_neg=50.0, sigma0=1e8)
    assert LuGreFriction(fc_pos=10.0, fc_neg=10.0, sigma0=1e8).fs_pos == 10.0


def test_a_gap_in_the_friction_runs_names_the_file(stribeck_run):
    """Rows missing from friction.csv were refused by the fit as 'time must increase with
    a uniform step', naming no file."""
    from types import SimpleNamespace

    from tcpmm.ident.friction.steadycurve import stribeck_from_record
    from tcpmm.io.records import FrictionRecord

    r, _ = stribeck_run
    lead, ktc = 0.01, 0.5
    keep = np.r_[0:500, 521:r.t.size]
    rec = FrictionRecord.from_arrays(r.t[keep], (r.force * lead / (2 * np.pi * ktc))[keep],
                                     (r.q * 2 * np.pi / lead)[keep], r.q[keep],
                                     source="X/friction.csv", axis="X")
    with pytest.raises(InputError, match="sampled uniformly") as e:
        stribeck_from_record(rec, SimpleNamespace(lead_m=lead, torque_constant=ktc), "X")
    assert (e.value.file, e.value.column) == ("X/friction.csv", "time_s")
    assert f"the step after t = {r.t[499]:.6g} s" in e.value.message
