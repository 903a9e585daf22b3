"""Friction models and lost motion: holders, stick, reversal, pre-sliding, dead zone."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tcpmm.errors import InputError
from tcpmm.mechanics.friction import (
    MODEL_LUGRE,
    MODEL_NONE,
    MODEL_STATIC,
    N_FRICTION_PARAMS,
    P_FC_NEG,
    P_FS_POS,
    P_MODEL,
    STUCK,
    Backlash,
    LuGreFriction,
    StribeckFriction,
    backlash_params_array,
    friction_params_array,
)
from tcpmm.sim.contact import (
    at_rest,
    backlash_force,
    friction_force,
    friction_step,
    lugre_steady_state,
    sliding_friction,
    static_levels,
)

ASYM = StribeckFriction(fc_pos=20.0, fc_neg=25.0, fs_pos=30.0, fs_neg=27.0, vs=2e-3,
                        fv_pos=200.0, fv_neg=250.0)


def test_holder_defaults_and_layout():
    m = StribeckFriction(fc_pos=3.0, fc_neg=4.0)
    assert m.fs_pos == 3.0 and m.fs_neg == 4.0
    p = friction_params_array(ASYM)
    assert p.shape == (N_FRICTION_PARAMS,)
    assert p[P_MODEL] == MODEL_STATIC and p[P_FC_NEG] == 25.0 and p[P_FS_POS] == 30.0
    assert friction_params_array(None)[P_MODEL] == MODEL_NONE
    lg = LuGreFriction(fc_pos=1.0, fc_neg=1.0, sigma0=1e5)
    assert friction_params_array(lg)[P_MODEL] == MODEL_LUGRE
    assert static_levels(p) == (30.0, 27.0)


@pytest.mark.parametrize(
    "kwargs, word",
    [
        ({"fc_pos": -1.0, "fc_neg": 1.0}, "fc_pos"),
        ({"fc_pos": 1.0, "fc_neg": 1.0, "fv_neg": -2.0}, "fv_neg"),
        ({"fc_pos": 1.0, "fc_neg": 1.0, "vs": 0.0}, "vs"),
        ({"fc_pos": 1.0, "fc_neg": 1.0, "mu": 0.1}, "mu"),
    ],
)
def test_holder_rejects_bad_input(kwargs, word):
    with pytest.raises(InputError, match=word):
        StribeckFriction(**kwargs)


def test_lugre_and_backlash_holders_validate():
    with pytest.raises(InputError, match="sigma0"):
        LuGreFriction(fc_pos=1.0, fc_neg=1.0, sigma0=0.0)
    with pytest.raises(InputError, match="play"):
        Backlash(k=1e8, play=-2e-6)
    with pytest.raises(InputError):
        friction_params_array("coulomb")


def test_sliding_curve_is_asymmetric_with_stribeck_peak():
    p = friction_params_array(ASYM)
    assert sliding_friction(0.0, p) == 0.0
    # near zero speed the level tends to the static one, far away to Coulomb + viscous
    assert sliding_friction(1e-9, p) == pytest.approx(30.0, rel=1e-6)
    assert sliding_friction(-1e-9, p) == pytest.approx(-27.0, rel=1e-6)
    assert sliding_friction(0.1, p) == pytest.approx(20.0 + 200.0 * 0.1, rel=1e-9)
    assert sliding_friction(-0.1, p) == pytest.approx(-25.0 - 250.0 * 0.1, rel=1e-9)


def _run_explicit(p, m, f_of_t, dt, n, v0=0.0, m_eff=None):
    """Body integrated step by step with the friction API (semi-implicit position)."""
    v, x, z = v0, 0.0, 0.0
    me = m if m_eff is None else m_eff
    vs = np.empty(n)
    fs = np.empty(n)
    for k in range(n):
        f = f_of_t(k * dt)
        fr, z = friction_force(v, f, z, p, dt, me)
        v = v + dt * (f - fr) / m
        if at_rest(z, p):
            v = 0.0
        x += dt * v
        vs[k] = v
        fs[k] = fr
    return vs, fs


@pytest.mark.parametrize("f_app", [29.9, -26.9, 0.0, 15.0])
def test_stick_below_static_level_is_exact(f_app):
    p = friction_params_array(ASYM)
    v, fr = _run_explicit(p, 2.0, lambda t: f_app, 1e-4, 5000)
    assert np.all(v == 0.0)
    assert np.allclose(fr, f_app)


def test_breakaway_is_direction_dependent():
    p = friction_params_array(ASYM)
    # 28 N breaks away in the negative direction (Fs- = 27) but not in the positive one
    v_pos, _ = _run_explicit(p, 2.0, lambda t: 28.0, 1e-4, 2000)
    v_neg, _ = _run_explicit(p, 2.0, lambda t: -28.0, 1e-4, 2000)
    assert np.all(v_pos == 0.0)
    assert v_neg[-1] < 0.0


def test_friction_step_reports_stick_and_lands_on_zero():
    p = friction_params_array(ASYM)
    # decelerating under 5 N against 20 N of Coulomb friction: stops within the step
    v_end, f, s = friction_step(1e-4, 5.0, 0.0, p, 1e-3, 2.0)
    assert v_end == 0.0 and s == STUCK
    assert f == pytest.approx(5.0 + 2.0 * 1e-4 / 1e-3)
    # far from zero it slides with the Stribeck curve
    v_end, f, s = friction_step(0.1, 5.0, 0.0, p, 1e-3, 2.0)
    assert f == pytest.approx(sliding_friction(0.1, p)) and not at_rest(s, p)
    # beyond the static band it slips through zero into the other direction
    v_end, f, s = friction_step(1e-4, -40.0, 0.0, p, 1e-3, 2.0)
    assert v_end < 0.0 and f == pytest.approx(-27.0)


def test_karnopp_band_without_mass_keeps_rest():
    p = friction_params_array(ASYM)
    v, _ = _run_explicit(p, 2.0, lambda t: 25.0, 1e-4, 3000, m_eff=0.0)
    assert np.all(v == 0.0)


def _sign_flips(v):
    s = np.sign(v[v != 0.0])
    return int(np.sum(s[1:] != s[:-1]))


def test_no_chattering_at_reversal():
    p = friction_params_array(ASYM)
    freq, periods, dt = 2.0, 3, 1e-4
    n = int(periods / freq / dt)
    force = lambda t: 60.0 * math.sin(2 * math.pi * freq * t)  # noqa: E731
    v, _ = _run_explicit(p, 2.0, force, dt, n)
    assert _sign_flips(v) <= 2 * periods
    assert np.sum(v == 0.0) > 0  # it sticks while |force| is below the static level
    # the same body with the friction evaluated explicitly as sign(v) chatters
    vn, x = 0.0, []
    for k in range(n):
        f = force(k * dt)
        fr = sliding_friction(vn, p) if vn != 0.0 else float(np.clip(f, -27.0, 30.0))
        vn = vn + dt * (f - fr) / 2.0
        x.append(vn)
    assert _sign_flips(np.array(x)) > 10 * periods


def test_lugre_presliding_hysteresis_loop():
    lg = LuGreFriction(fc_pos=20.0, fc_neg=20.0, fs_pos=25.0, fs_neg=25.0, vs=1e-3,
                       sigma0=1e6, sigma1=0.0)
    p = friction_params_array(lg)
    amp = 0.5 * 20.0 / 1e6  # half of the Coulomb deflection: pre-sliding regime
    freq, dt, n_per = 10.0, 1e-5, 10000
    n_cyc = 12
    t = np.arange(n_cyc * n_per + 1) * dt
    x = amp * np.sin(2 * np.pi * freq * t)
    v = np.gradient(x, dt)
    z = 0.0
    f = np.empty_like(t)
    for k in range(t.size):
        fk, z = friction_force(v[k], 0.0, z, p, dt, 0.0)
        f[k] = fk
    # initial stiffness from rest equals sigma0
    k0 = (f[50] - f[0]) / (x[50] - x[0])
    assert k0 == pytest.approx(1e6, rel=0.02)
    # the loop closes: the force at the end of the last two cycles coincides
    last, prev = n_cyc * n_per, (n_cyc - 1) * n_per
    assert abs(f[last] - f[prev]) < 1e-3 * np.max(np.abs(f))
    # enclosed area = dissipated energy per cycle > 0
    seg = slice(prev, last + 1)
    area = np.trapezoid(f[seg], x[seg])
    assert area > 0.01 * amp * np.max(np.abs(f))
    # and the force stays inside the static band
    assert np.max(np.abs(f)) < 25.0


def test_lugre_steady_sliding_matches_stribeck_curve():
    lg = LuGreFriction(fc_pos=20.0, fc_neg=22.0, fs_pos=28.0, fs_neg=26.0, vs=2e-3,
                       fv_pos=100.0, fv_neg=120.0, sigma0=1e7, sigma1=300.0)
    p = friction_params_array(lg)
    for v in (-0.05, -1e-3, 5e-4, 0.02):
        z = 0.0
        for _ in range(20000):
            f, z = friction_force(v, 0.0, z, p, 1e-5, 0.0)
        assert z == pytest.approx(lugre_steady_state(v, p), rel=1e-9)
        assert f == pytest.approx(sliding_friction(v, p), rel=1e-9)


@settings(max_examples=300, deadline=None)
@given(v=st.one_of(st.just(0.0), st.floats(-0.5, 0.5, allow_subnormal=False),
                   st.floats(-1e-5, 1e-5, allow_subnormal=False)),
       fc=st.floats(1.0, 200.0), rise=st.sampled_from([0.0, 0.1, 0.7]),
       vs=st.floats(1e-4, 1e-2), delta=st.sampled_from([1.0, 1.5, 2.0]),
       sigma1=st.sampled_from([0.0, 300.0, 5e4]), fades=st.booleans())
def test_lugre_rates_are_the_damping_and_decay_rate_to_the_bit(v, fc, rise, vs, delta,
                                                                sigma1, fades):
    """The LuGre step takes the micro-damping and the bristles' decay rate from one
    Stribeck shape: the numbers of ``micro_damping`` and ``lugre_decay_rate`` computed
    apart, to the bit, on both sides, at rest, with and without a Stribeck rise."""
    from tcpmm.sim.frictionlaw import lugre_decay_rate, lugre_rates, micro_damping

    lg = LuGreFriction(fc_pos=fc, fc_neg=1.1 * fc, fs_pos=fc * (1 + rise),
                       fs_neg=1.1 * fc * (1 + rise), vs=vs, delta=delta, sigma0=1e7,
                       sigma1=sigma1, sigma1_fades=fades)
    p = friction_params_array(lg)
    assert lugre_rates(v, p) == (micro_damping(v, p), lugre_decay_rate(v, p))


def test_lugre_implicit_step_is_stable_for_stiff_bristles():
    # sigma0 = 1e8 N/m on 1 kg: sqrt(k/m) * dt = 10, far beyond explicit stability
    lg = LuGreFriction(fc_pos=10.0, fc_neg=10.0, fs_pos=12.0, fs_neg=12.0, vs=1e-3,
                       fv_pos=50.0, fv_neg=50.0, sigma0=1e8, sigma1=0.0)
    p = friction_params_array(lg)
    v, fr = _run_explicit(p, 1.0, lambda t: 15.0, 1e-3, 3000)
    assert np.all(np.isfinite(v))
    v_ss = (15.0 - 10.0) / 50.0  # Coulomb + viscous balance, Stribeck negligible at 0.1 m/s
    assert v[-1] == pytest.approx(v_ss, rel=1e-3)
    assert np.max(np.abs(fr)) < 15.0 + 1e-9
    # below break-away the bristles hold the body (pre-sliding creep only)
    v2, _ = _run_explicit(p, 1.0, lambda t: 8.0, 1e-3, 3000)
    assert np.max(np.abs(v2)) < 1e-4


def test_backlash_dead_zone():
    p = backlash_params_array(Backlash(k=2e8, play=10e-6, c=1e3))  # +/- 5 um dead zone
    for d in np.linspace(-5e-6, 5e-6, 11):
        assert backlash_force(d, 0.3, p) == 0.0
    assert backlash_force(6e-6, 0.0, p) == pytest.approx(2e8 * 1e-6)
    assert backlash_force(-7e-6, 0.0, p) == pytest.approx(-2e8 * 2e-6)
    # damping never makes the contact pull
    assert backlash_force(5.1e-6, -10.0, p) == 0.0
    assert backlash_force(-5.1e-6, 10.0, p) == 0.0
    # lost motion: the output does not follow an input reversal until the gap is crossed
    x_in = np.r_[np.linspace(0, 20e-6, 50), np.linspace(20e-6, 0, 50)]
    x_out = 0.0
    trace = []
    for xi in x_in:
        # quasi-static follower with a very stiff contact: the output sits at the contact
        d = xi - x_out
        if d > 5e-6:
            x_out = xi - 5e-6
        elif d < -5e-6:
            x_out = xi + 5e-6
        trace.append(x_out)
        assert abs(backlash_force(xi - x_out, 0.0, p)) < 1e-9
    trace = np.array(trace)
    i_rev = 50
    moved = np.flatnonzero(np.abs(trace[i_rev:] - trace[i_rev]) > 0)
    # after the reversal the output waits while the input crosses the full gap 2 b
    assert x_in[i_rev] - x_in[i_rev + moved[0]] >= 2 * 5e-6 - 1e-12


def test_backlash_is_the_total_free_play_and_the_half_gap_is_deprecated():
    """``play`` is the total free play, as in the model file; the former ``b`` (half the
    gap) still gives the same element, with a warning."""
    new = Backlash(k=2e8, play=10e-6)
    with pytest.warns(DeprecationWarning, match="play=2\\*b"):
        old = Backlash(k=2e8, b=5e-6)
    assert old == new
    assert backlash_params_array(new)[1] == 5e-6  # the compiled function reads the half gap
    with pytest.raises(InputError, match="play"), pytest.warns(DeprecationWarning):
        Backlash(k=2e8, b=-1e-6)
