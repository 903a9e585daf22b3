"""Steady friction curve from the accelerations of the friction runs
(``tcpmm.ident.friction.transients``)."""

import numpy as np
import pytest

from conftest import bench_path
from tcpmm.errors import InputError
from tcpmm.ident.friction import fit_stribeck_transients, steady_curve, stribeck_from_record
from tcpmm.io.bundle import read_bundle
from tcpmm.io.truthfile import machine_from_truth


def synthetic_runs(fc=80.0, fs=110.0, vs=1.5e-3, fv=900.0, mass=300.0, dt=1e-3, seed=0):
    """A rigid body moved back and forth through cosine blends, the force it needs plus
    noise: known answer for the inverse model."""
    rng = np.random.default_rng(seed)
    v_pieces = []
    for speed in (5e-4, 2e-3, 5e-3, 1.5e-2, 4e-2):
        for sign in (1.0, -1.0):
            ramp = max(int(np.pi * speed / (2 * 0.8) / dt), 3)
            up = speed * 0.5 * (1 - np.cos(np.linspace(0, np.pi, ramp)))
            v_pieces += [np.zeros(100), sign * up, np.full(300, sign * speed), sign * up[::-1]]
    v = np.concatenate(v_pieces)
    t = np.arange(v.size) * dt
    x = np.cumsum(v) * dt
    a = np.gradient(v, dt)
    fric = np.sign(v) * (fc + (fs - fc) * np.exp(-((v / vs) ** 2))) + fv * v
    force = mass * a + fric + rng.normal(0, 2.0, v.size)
    return t, x, force


def test_known_curve_is_recovered():
    t, x, f = synthetic_runs()
    est = fit_stribeck_transients(t, x, f, slowest_plateau=5e-4)
    got = dict(zip(est.names, est.values, strict=True))
    for k, want in (("Fc+", 80.0), ("Fc-", 80.0), ("Fs+", 110.0), ("Fs-", 110.0),
                    ("Fv", 900.0)):
        assert got[k] == pytest.approx(want, rel=0.05), k
    assert got["vs"] == pytest.approx(1.5e-3, rel=0.25)
    assert est.extra["M"] == pytest.approx(300.0, rel=0.05)
    # its standard deviations cover the error
    for k, want in (("Fc+", 80.0), ("Fs+", 110.0)):
        assert abs(got[k] - want) < 4 * est.std_of(k) + 1.0


def test_runs_without_slow_motion_are_refused():
    t, x, f = synthetic_runs()
    with pytest.raises(InputError, match="Stribeck hump"):
        fit_stribeck_transients(t, x, f, slowest_plateau=1e-5)


def test_plateaus_that_do_not_show_the_hump_give_way_to_the_accelerations():
    """Reference machine E, axis X: its plateaus (slowest 0.5 mm/s) put the Stribeck speed at
    0.2 mm/s and the static level at tens of kilonewtons against a Coulomb level of 530 N;
    the accelerations through the hump give the static level of the two contacts within
    10 %."""
    d = bench_path("e")
    b = read_bundle(d / "bundle")
    true = machine_from_truth(d / "truth.yaml").axes["X"]
    rec, cfg = b.axes["X"].friction, b.machine.axes["X"]
    t, _, force, plateau_fit, plateaus = stribeck_from_record(rec, cfg, "X")
    assert plateau_fit["Fs+"] > 10 * plateau_fit["Fc+"]  # the extrapolation
    est = steady_curve(t, rec, force, plateau_fit, plateaus, true.mechanics)
    fr = true.friction
    for key, attr in (("Fc+", "fc_pos"), ("Fs+", "fs_pos")):
        want = getattr(fr.screw, attr) + getattr(fr.guideway, attr)
        assert est[key] == pytest.approx(want, rel=0.1), key
    assert fr.guideway.vs <= est["vs"] <= fr.screw.vs * 1.2


def test_plateaus_that_show_the_hump_are_kept():
    d = bench_path("d")
    b = read_bundle(d / "bundle")
    m = machine_from_truth(d / "truth.yaml").axes["X"].mechanics
    rec, cfg = b.axes["X"].friction, b.machine.axes["X"]
    t, _, force, plateau_fit, plateaus = stribeck_from_record(rec, cfg, "X")
    assert steady_curve(t, rec, force, plateau_fit, plateaus, m) is plateau_fit


@pytest.mark.parametrize(("fc", "fs", "fv", "seed"), [
    (80.0, 110.0, 900.0, 0),    # the hump: every excess free
    (80.0, 60.0, 900.0, 1),     # a dip: the excesses held at zero
    (80.0, 110.0, 0.0, 2),      # no viscous slope: its noise may fall below zero
    (0.5, 0.5, 900.0, 3),       # hardly any Coulomb level
])
def test_the_projected_cost_is_the_bounded_fits_cost(fc, fs, fv, seed):
    """The grid of Stribeck speeds takes the cost with the fixed regressors projected out;
    at every speed it is the bounded fit's cost to rounding, whichever bounds are active."""
    from tcpmm.ident.friction import transients as tr
    t, x, f = synthetic_runs(fc=fc, fs=fs, fv=fv, seed=seed)
    p = tr._prepare(t, x, f, 30.0, tr.V_MIN)
    fast = tr._profiled_cost(p, 2.0)
    for vs in np.logspace(np.log10(tr.VS_RANGE[0]), np.log10(tr.VS_RANGE[1]), 25):
        assert fast(vs) == pytest.approx(tr._solve(p, vs, 2.0)[1], rel=1e-9), vs


def test_rank_deficient_fixed_regressors_take_the_bounded_fits_cost():
    from tcpmm.ident.friction import transients as tr
    t, x, f = synthetic_runs()
    p = tr._prepare(t, x, f, 30.0, tr.V_MIN)
    p["rests"] = np.column_stack([p["rests"], p["rests"][:, :1]])  # a rest counted twice
    fast = tr._profiled_cost(p, 2.0)
    for vs in (1e-4, 1.5e-3, 1e-2):
        assert fast(vs) == tr._solve(p, vs, 2.0)[1]
