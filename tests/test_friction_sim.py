"""Rigid axis with friction in a discrete servo loop: exactness, stick, convergence."""

import numpy as np
import pytest

from studies.rigidaxis import DiscreteServo, RigidAxis, simulate_rigid_servo
from tcpmm.errors import InputError
from tcpmm.mechanics.friction import LuGreFriction, StribeckFriction

T = 1e-3
FRIC = StribeckFriction(fc_pos=20.0, fc_neg=25.0, fs_pos=35.0, fs_neg=30.0, vs=2e-3,
                        fv_pos=200.0, fv_neg=250.0, v_stick=0.0)
OPEN = DiscreteServo(period=T, kp=0.0, kv=0.0, gain=1.0, delay=0.0)


def test_open_loop_viscous_response_is_exact():
    # M v' = F - Fv v under a constant force: exact exponential, any sub-step count
    m, fv, f = 10.0, 40.0, 8.0
    axis = RigidAxis(mass=m, friction=StribeckFriction.symmetric(fc=0.0, fv=fv, v_stick=0.0))
    ext = np.full(500, f)
    t = np.arange(500) * T
    v_exact = f / fv * (1 - np.exp(-fv / m * t))
    q_exact = f / fv * (t - m / fv * (1 - np.exp(-fv / m * t)))
    for n_sub in (1, 7):
        r = simulate_rigid_servo(np.zeros(500), axis, OPEN, ext=ext, n_sub=n_sub, q0=0.0)
        assert np.max(np.abs(r.v - v_exact)) < 1e-12
        assert np.max(np.abs(r.q - q_exact)) < 1e-14


def test_open_loop_stick_is_exact_and_breakaway_direction_dependent():
    axis = RigidAxis(mass=5.0, friction=FRIC)
    for f, moves in ((34.9, False), (-29.9, False), (35.1, True), (-30.1, True)):
        r = simulate_rigid_servo(np.zeros(300), axis, OPEN, ext=np.full(300, f), q0=0.0)
        if moves:
            assert np.sign(r.v[-1]) == np.sign(f)
        else:
            assert np.all(r.v == 0.0) and np.all(r.q == 0.0) and np.all(r.a == 0.0)


def test_coulomb_stop_time_is_exact():
    # sliding at v0 with no force: stops at t* = M v0 / Fc (no viscous) and stays
    fr = StribeckFriction.symmetric(fc=10.0, v_stick=0.0)
    axis = RigidAxis(mass=2.0, friction=fr)
    r = simulate_rigid_servo(np.zeros(100), axis, OPEN, v0=0.0123, q0=0.0, n_sub=3)
    t_stop = 2.0 * 0.0123 / 10.0
    assert r.q[-1] == pytest.approx(0.5 * 0.0123 * t_stop, rel=1e-12)
    k_stop = int(np.ceil(t_stop / T))
    assert np.all(r.v[k_stop:] == 0.0) and np.all(r.v[:k_stop] > 0.0)


def _reversing_reference(n):
    t = np.arange(n) * T
    return 0.005 * np.sin(2 * np.pi * 1.0 * t)


def _servo(delay=1.0, ki=3000.0):
    return DiscreteServo(period=T, kp=100.0, kv=300.0, ki=ki, delay=delay, u_max=10.0,
                         gain=35.0)


def test_closed_loop_reversals_do_not_chatter():
    n = 4000  # four periods of a 1 Hz sine: 8 reversals
    r = simulate_rigid_servo(_reversing_reference(n), RigidAxis(mass=50.0, friction=FRIC),
                             _servo(), n_sub=20)
    s = np.sign(r.v[r.v != 0.0])
    assert int(np.sum(s[1:] != s[:-1])) == 8
    assert np.sum(r.v == 0.0) > 8  # it sticks at every reversal


def test_closed_loop_hold_sticks_exactly():
    # a command step smaller than the static band of the P-loop output never breaks away
    axis = RigidAxis(mass=50.0, friction=FRIC)
    ref = np.full(2000, 2e-6)  # kp * kv * gain * 2 um = 2.1 N < Fs
    r = simulate_rigid_servo(ref, axis, _servo(ki=0.0), q0=0.0)
    assert np.all(r.v == 0.0) and np.all(r.q == 0.0)


@pytest.mark.parametrize(
    "fric",
    [FRIC, LuGreFriction(**FRIC.model_dump(), sigma0=1e6, sigma1=0.0)],
    ids=["stribeck", "lugre"],
)
def test_substep_convergence_is_first_order(fric):
    ref = _reversing_reference(3000)
    axis = RigidAxis(mass=50.0, offset=1.0, friction=fric)
    fine = simulate_rigid_servo(ref, axis, _servo(), n_sub=512)
    errs = []
    for n in (4, 8, 16, 32, 64):
        r = simulate_rigid_servo(ref, axis, _servo(), n_sub=n)
        errs.append(np.max(np.abs(r.q - fine.q)))
    errs = np.array(errs)
    ratios = errs[:-1] / errs[1:]
    assert np.all(ratios > 1.8), ratios
    assert errs[-1] < 1e-7


def test_delay_and_outputs_follow_their_definitions():
    ref = _reversing_reference(1000)
    axis = RigidAxis(mass=50.0, friction=FRIC)
    r1 = simulate_rigid_servo(ref, axis, _servo(delay=1.0))
    assert r1.u_applied[0] == 0.0
    assert np.array_equal(r1.u_applied[1:], r1.u_cmd[:-1])
    r0 = simulate_rigid_servo(ref, axis, _servo(delay=0.0))
    assert np.array_equal(r0.u_applied, r0.u_cmd)
    r2 = simulate_rigid_servo(ref, axis, _servo(delay=2.5), n_sub=10)
    assert np.array_equal(r2.u_applied[2:], r2.u_cmd[:-2])
    assert np.max(np.abs(r1.u_cmd)) <= 10.0


def test_external_input_enters_after_saturation():
    axis = RigidAxis(mass=10.0)
    servo = DiscreteServo(period=T, kp=100.0, kv=300.0, u_max=0.5, gain=35.0, delay=0.0)
    ref = np.full(200, 1.0)  # far away: the controller saturates at 0.5
    ext = np.zeros(200)
    ext[100:] = 2.0
    r = simulate_rigid_servo(ref, axis, servo, ext=ext, q0=0.0)
    assert np.allclose(r.force[:100], 35.0 * 0.5)
    assert np.allclose(r.force[100:], 35.0 * 2.5)
    assert r.a[150] == pytest.approx(35.0 * 2.5 / 10.0)


def test_bad_input_is_reported():
    axis = RigidAxis(mass=1.0)
    with pytest.raises(InputError, match="ext"):
        simulate_rigid_servo(np.zeros(10), axis, _servo(), ext=np.zeros(9))
    with pytest.raises(InputError, match="taps"):
        DiscreteServo(period=T, kp=1.0, kv=1.0, taps=(0.5, 0.6))
    with pytest.raises(InputError, match="mass"):
        RigidAxis(mass=0.0)


@pytest.mark.parametrize("scheme, order", [("rk4", 4), ("dopri5", 5)])
def test_explicit_integrators_reach_their_order_while_sliding(scheme, order):
    # viscous + Coulomb sliding without reversal: the explicit schemes converge to the
    # closed-form solution at their order
    axis = RigidAxis(mass=10.0, friction=StribeckFriction.symmetric(fc=3.0, fv=400.0,
                                                                    v_stick=0.0))
    ext = np.full(100, 8.0)
    exact = simulate_rigid_servo(np.zeros(100), axis, OPEN, ext=ext, q0=0.0, v0=0.01)
    errs = [np.max(np.abs(simulate_rigid_servo(np.zeros(100), axis, OPEN, ext=ext, q0=0.0,
                                               v0=0.01, n_sub=n, integrator=scheme).v
                          - exact.v)) for n in (1, 2)]
    assert errs[1] < errs[0] / 2 ** (order - 0.5)
    assert errs[0] < 1e-6


@pytest.mark.parametrize("scheme", ["rk4", "dopri5"])
def test_explicit_integrators_chatter_where_the_axis_sticks(scheme):
    # a force inside the static band: the exact solution rests; sign(v) with sign(0) = 0
    # and no rest phase leaves a chatter that shrinks with the step but does not vanish
    fr = StribeckFriction.symmetric(fc=20.0, v_stick=0.0)
    axis = RigidAxis(mass=5.0, friction=fr)
    ext = np.full(200, 12.0)
    exact = simulate_rigid_servo(np.zeros(200), axis, OPEN, ext=ext, q0=0.0)
    assert np.all(exact.v == 0.0)
    chatter = []
    for n in (1, 10):
        r = simulate_rigid_servo(np.zeros(200), axis, OPEN, ext=ext, q0=0.0, n_sub=n,
                                 integrator=scheme)
        assert np.max(np.abs(r.v)) > 0.0
        chatter.append(np.max(np.abs(r.v)))
    assert chatter[1] < chatter[0] / 5
    assert chatter[0] <= (12.0 + 20.0) / 5.0 * T  # at most one step of full force


def test_explicit_integrators_take_static_friction_only():
    axis = RigidAxis(mass=1.0, friction=LuGreFriction(**FRIC.model_dump(), sigma0=1e6))
    with pytest.raises(InputError, match="static friction"):
        simulate_rigid_servo(np.zeros(10), axis, _servo(), integrator="rk4")
    with pytest.raises(InputError, match="unknown integrator"):
        simulate_rigid_servo(np.zeros(10), RigidAxis(mass=1.0), _servo(), integrator="euler")
