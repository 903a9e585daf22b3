"""Closed loops: stability, DC gains, and the compiled simulator against an LTI reference."""

import numpy as np
import pytest
from scipy.signal import dlsim

from tcpmm.errors import InputError
from tcpmm.servo.closedloop import closed_loop_freqresp, is_stable
from tcpmm.servo.currentfilters import LowPass, Notch
from tcpmm.servo.params import ServoParams
from tcpmm.servo.sampled import (
    LIFTED_OUTPUTS,
    initial_state,
    lifted_closed_loop,
    sampled_spectral_radius,
)
from tcpmm.sim.inputs import command_velocity, sensor_datums
from tcpmm.sim.simulate import simulate_axis


@pytest.mark.parametrize("ax", ["X", "Y", "Z"])
def test_builtin_loops_are_stable(vmc, ax):
    a = vmc.axes[ax]
    assert is_stable(a.mechanics, a.servo)
    assert sampled_spectral_radius(a.mechanics, a.servo) < 1.0


@pytest.mark.parametrize("name", ["G_p", "cmd_to_tcp", "cmd_to_motor", "G_v"])
def test_closed_loop_dc_gain_is_one(vmc, name):
    a = vmc.axes["X"]
    h = closed_loop_freqresp(a.mechanics, a.servo, name, [1e-3])[0]
    assert abs(h - 1) < 1e-3


def test_position_bandwidth_follows_kpp(vmc_linear):
    a = vmc_linear.axes["X"]
    f = np.logspace(-1, 2, 400)
    h = np.abs(closed_loop_freqresp(a.mechanics, a.servo, "G_p", f))
    f3 = f[np.argmax(h < 1 / np.sqrt(2))]
    assert 0.6 < 2 * np.pi * f3 / a.servo.K_pp < 1.6


def test_too_high_gain_is_unstable(vmc):
    a = vmc.axes["X"]
    hot = a.servo.model_copy(update={"K_vp": a.servo.K_vp * 60})
    assert sampled_spectral_radius(a.mechanics, hot) > 1.0


def test_servo_validation():
    with pytest.raises(InputError, match="integer multiple"):
        ServoParams.create(K_pp=40, K_vp=1, K_vi=10, T_p=3e-4, T_v=1.25e-4)
    with pytest.raises(InputError, match="K_vp"):
        ServoParams.create(K_pp=40, K_vp=-1, K_vi=10)


def test_velocity_filter_taps_are_validated():
    base = dict(K_pp=40, K_vp=1, K_vi=10, velocity_feedback="difference")
    assert ServoParams.create(**base, velocity_filter=[0.5, 0.5]).velocity_filter == [0.5, 0.5]
    with pytest.raises(InputError, match="velocity_filter"):
        ServoParams.create(**base, velocity_filter=[0.5, 0.4])
    with pytest.raises(InputError, match="velocity_filter"):
        ServoParams.create(**base, velocity_filter=[])
    with pytest.raises(InputError, match="velocity_filter"):
        ServoParams.create(**base, velocity_filter=[0.125] * 8 + [0.0])


CASES = [
    dict(),
    dict(velocity_feedback="difference"),
    dict(delay_samples=1, current_bandwidth_hz=2500.0),
    dict(position_feedback="encoder", k_ff=0.7, T_p=1.25e-4),
    dict(T_p=1e-3, velocity_feedback="difference", delay_samples=1, k_ff=1.0),
    dict(velocity_feedback="difference", velocity_filter=[0.5, 0.5], delay_samples=1),
    dict(velocity_feedback="difference", velocity_filter=[0.25, 0.5, 0.25]),
    dict(filters=[Notch(f_hz=633.0, bandwidth_hz=150.0, depth_db=-25.0),
                  LowPass(f_hz=3000.0, zeta=0.7)], delay_samples=1),
]


@pytest.mark.parametrize("changes", CASES)
def test_kernel_equals_lti_reference(vmc_linear, changes):
    """The compiled loop and scipy dlsim of the lifted sampled loop agree to 1e-9."""
    a = vmc_linear.axes["Y"]
    a = a.replace(servo=a.servo.model_copy(update=changes),
                  sensors=a.sensors.model_copy(update={"encoder_counts_per_rev": 0,
                                                       "scale_resolution": 0.0}))
    s, m = a.servo, a.mechanics
    T_p = s.T_p
    n = 800
    t = np.arange(n) * T_p
    cmd = 0.004 * (1 - np.cos(2 * np.pi * 3 * t)) + 2e-6 * np.sin(2 * np.pi * 40 * t)
    cmd[t > 0.25] += 2e-5  # a small step too
    run = simulate_axis(a, t, cmd, record_period_s=T_p)
    assert np.max(np.abs(run.current)) < 0.9 * s.current_limit  # linear regime: no saturation
    # The simulator fine-interpolates the command linearly; at position-loop instants the
    # command equals the samples, and the feedforward is the slope of the current segment.
    Phi, Gam, C, D = lifted_closed_loop(m, s)
    assert sampled_spectral_radius(m, s) < 1.0
    z0 = initial_state(m, s, np.zeros(10))
    u = np.column_stack([cmd, command_velocity(cmd, T_p, s.feedforward)])
    _, y, _ = dlsim((Phi, Gam, C, D, T_p), u, x0=z0)
    got = {"th_m": run.motor_angle, "X_LS": run.scale, "X_TCP": run.tcp, "w_m": run.motor_speed}
    for k, name in enumerate(LIFTED_OUTPUTS):
        ref = y[:, k]
        err = np.max(np.abs(got[name] - ref)) / np.max(np.abs(ref))
        assert err < 1e-9, (name, err)


def test_current_limit_and_anti_windup(vmc_linear):
    a = vmc_linear.axes["X"]
    a = a.replace(servo=a.servo.model_copy(update={"current_limit": 3.0}))
    t = np.arange(0, 0.6, 1e-3)
    cmd = np.where(t > 0.05, 0.01, 0.0)  # 10 mm step: saturates
    r = simulate_axis(a, t, cmd)
    assert np.max(np.abs(r.current)) <= 3.0 + 1e-12
    assert np.max(np.abs(r.current)) == pytest.approx(3.0)
    # Anti-windup: the overshoot stays small after the long saturation.
    assert np.max(r.scale) < 0.01 * 1.05
    assert abs(r.scale[-1] - 0.01) < 2e-6


def test_gravity_axis_starts_at_rest(vmc_linear):
    a = vmc_linear.axes["Z"]
    t = np.arange(0, 0.3, 1e-3)
    r = simulate_axis(a, t, np.full_like(t, 0.02), quantise_feedback=False)
    assert np.max(np.abs(r.scale - 0.02)) < 1e-12
    hold = -a.mechanics.load_force * a.mechanics.R_L / a.mechanics.K_tc
    np.testing.assert_allclose(r.current, hold, rtol=1e-9)
    # The head sags under the load by F (1/K_b + 1/K_h), some 50 µm, and the screw winds
    # up; the sensors are read from their datums at rest, as the tool-length, zero-point
    # and reference settings take these up.
    m = a.mechanics
    d_motor, d_scale, d_tcp = sensor_datums(a)
    assert d_tcp == pytest.approx(m.load_force * (1 / m.K_b + 1 / m.K_h), rel=1e-12)
    assert abs(d_tcp) > 40e-6 and abs(d_motor) > 10e-6 and d_scale == 0.0
    for sensor in (r.tcp, r.motor, r.scale):
        assert np.max(np.abs(sensor - 0.02)) < 1e-12


def test_open_loop_torque_mode_moves_by_rigid_inertia(vmc_linear):
    a = vmc_linear.axes["X"]
    m = a.mechanics.replace(B_m=0.0, B_L=0.0, C_t=0.0)
    a = a.replace(mechanics=m)
    t = np.arange(0, 0.2, 1e-4)
    exc = np.where(t < 0.1, 1.0, 0.0)
    r = simulate_axis(a, t, np.zeros_like(t), excitation_A=exc, open_loop=True,
                      record_period_s=5e-4)
    # After the pulse, momentum = impulse (no damping of the rigid-body motion).
    w_expected = m.K_tc * 1.0 * 0.1 / m.J_total
    k = np.searchsorted(np.arange(r.motor_speed.size) * 5e-4, 0.1)
    assert r.motor_speed[k] == pytest.approx(w_expected, rel=0.05)


def test_a_p_velocity_loop_is_not_called_unstable_for_its_idle_integrator(vmc):
    """K_vi 0 (a P velocity loop, which a model may carry): the integrator's state still
    sums the error but feeds nothing back, an eigenvalue of exactly 1 that is no mode of
    the loop, and the loop read unstable ("spectral radius 1.0000"). It is left out: the
    radius is the largest of the other eigenvalues, below 1."""
    from tcpmm.servo.params import ServoParams
    from tcpmm.servo.sampled import lifted_closed_loop, sampled_spectral_radius

    a = vmc.axes["X"]
    p_only = ServoParams.create(**{**a.servo.model_dump(), "K_vi": 0.0})
    ev = np.abs(np.linalg.eigvals(lifted_closed_loop(a.mechanics, p_only)[0]))
    idle = np.abs(ev - 1.0) < 1e-12
    assert idle.sum() == 1  # the idle integrator
    rho = sampled_spectral_radius(a.mechanics, p_only)
    assert rho == pytest.approx(np.max(ev[~idle]), rel=1e-9) and rho < 0.9999
