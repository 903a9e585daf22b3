"""Current-setpoint filters: designed gains, validation, and the simulator against the
frequency-domain model of the sampled loop."""

import math

import numpy as np
import pytest

from tcpmm.errors import InputError
from tcpmm.servo.currentfilters import LowPass, Notch, biquads, filters_freqresp
from tcpmm.servo.margins import discrete_freqresp
from tcpmm.servo.params import ServoParams
from tcpmm.servo.sampled import lifted_closed_loop, sampled_spectral_radius
from tcpmm.sim.simulate import simulate_axis

T_V = 1.25e-4


@pytest.mark.parametrize(("f0", "bw", "depth"), [(633.0, 150.0, -25.0), (150.0, 40.0, -40.0),
                                                 (2500.0, 500.0, -6.0)])
def test_notch_has_its_depth_at_f0_and_unity_far_away(f0, bw, depth):
    n = [Notch(f_hz=f0, bandwidth_hz=bw, depth_db=depth)]
    for dt in (None, T_V):
        h = filters_freqresp(n, [f0, 1e-3, 0.01 * f0], dt)
        assert 20 * np.log10(abs(h[0])) == pytest.approx(depth, abs=1e-9)
        np.testing.assert_allclose(np.abs(h[1:]), 1.0, atol=2e-3)
    # bilinear: infinite frequency maps to Nyquist, where the notch passes exactly
    assert abs(filters_freqresp(n, [0.5 / T_V], T_V)[0]) == pytest.approx(1.0, abs=1e-9)
    # -3 dB points of a full notch are bandwidth apart (continuous filter)
    full = [Notch(f_hz=f0, bandwidth_hz=bw, depth_db=-120.0)]
    w = np.linspace(0.5 * f0, 1.5 * f0, 200_001)
    half = w[np.abs(filters_freqresp(full, w)) < 1 / math.sqrt(2)]
    assert half[-1] - half[0] == pytest.approx(bw, rel=1e-3)


def test_lowpass_gain_at_its_frequency_is_one_over_two_zeta():
    lp = [LowPass(f_hz=1200.0, zeta=0.4)]
    for dt in (None, T_V):
        assert abs(filters_freqresp(lp, [1200.0], dt)[0]) == pytest.approx(1 / 0.8, rel=1e-9)
        assert abs(filters_freqresp(lp, [1e-3], dt)[0]) == pytest.approx(1.0, abs=1e-9)


def test_sections_have_unit_dc_gain_and_stable_poles():
    sec = biquads([Notch(f_hz=500, bandwidth_hz=100), LowPass(f_hz=3500, zeta=0.3)], T_V)
    for b0, b1, b2, a1, a2 in sec:
        assert (b0 + b1 + b2) / (1 + a1 + a2) == pytest.approx(1.0, abs=1e-12)
        assert np.all(np.abs(np.roots([1, a1, a2])) < 1)


BASE = dict(K_pp=40, K_vp=1, K_vi=10)


@pytest.mark.parametrize(("filters", "needle"), [
    ([{"type": "notch", "f_hz": 500, "bandwidth_hz": 50, "width": 3}], "width"),
    ([{"type": "bandpass", "f_hz": 500}], "bandpass"),
    ([{"type": "notch", "f_hz": 500}], "bandwidth_hz"),
    ([{"type": "lowpass", "f_hz": 3900}], "Nyquist"),
    ([{"type": "notch", "f_hz": 500, "bandwidth_hz": 50, "depth_db": 6}], "depth_db"),
    ([{"type": "lowpass", "f_hz": 500}] * 5, "filters"),
])
def test_bad_filters_are_errors(filters, needle):
    with pytest.raises(InputError, match=needle):
        ServoParams.create(**BASE, filters=filters)


def _steady_sine(a, f, periods=40):
    """Kernel run on a sine command; amplitude and phase of X_LS over whole periods."""
    s = a.servo
    n_per = round(1 / (f * s.T_p))
    f = 1 / (n_per * s.T_p)  # a whole number of position-loop samples per period
    t = np.arange(periods * n_per) * s.T_p
    cmd = 1e-6 * np.sin(2 * np.pi * f * t)
    run = simulate_axis(a, t, cmd, record_period_s=s.T_p, quantise_feedback=False)
    last = slice(-10 * n_per, None)
    e = np.exp(-2j * np.pi * f * t[last])
    return f, 2 * np.mean(run.scale[last] * e) / 1e-6 / (-1j)


def _model(a, f):
    Phi, Gam, C, D = lifted_closed_loop(a.mechanics, a.servo)
    k = 1  # X_LS
    return discrete_freqresp(Phi, Gam[:, :1], C[k:k + 1], D[k:k + 1, :1], a.servo.T_p, f)[0]


@pytest.mark.parametrize("filters", [[Notch(f_hz=117.7, bandwidth_hz=60, depth_db=-20)],
                                     [LowPass(f_hz=1500.0, zeta=0.7)]])
def test_kernel_sine_matches_the_sampled_model(vmc_linear, filters):
    """Steady sine through the compiled loop against the lifted model's frequency response.
    The start excites the 633 Hz mode (damping 0.001, time constant 0.25 s): after 0.35 s
    its remainder is some 1e-4 of the response, hence the 1e-3 tolerance; the filters
    change the response by far more."""
    a0 = vmc_linear.axes["Y"]
    a = a0.replace(servo=a0.servo.model_copy(update={"filters": filters}))
    assert sampled_spectral_radius(a.mechanics, a.servo) < 1.0
    for f in (20.0, 117.7):
        f, h = _steady_sine(a, f)
        ref = _model(a, f)
        assert abs(h / ref - 1) < 1e-3, (f, h, ref)
    assert abs(ref / _model(a0, f) - 1) > 1e-2  # the filter matters at 117.7 Hz


def test_declared_filters_reach_the_identified_servo(vmc):
    """A drive's filters, declared in the bundle, are carried into the identified model."""
    from tcpmm.ident.pipeline import axis_config_to_servo
    from tcpmm.machines.virtual import axis_config, bundle_machine_yaml

    notch = Notch(f_hz=728.8, bandwidth_hz=150.0, depth_db=-20.0)
    a = vmc.axes["X"]
    m = vmc.model_copy(update={"axes": {**vmc.axes, "X": a.replace(
        servo=a.servo.model_copy(update={"filters": [notch]}))}})
    assert axis_config_to_servo(axis_config(m, "X")).filters == [notch]
    assert axis_config_to_servo(axis_config(vmc, "X")).filters == []
    assert "current_setpoint_filters" not in bundle_machine_yaml(vmc, ["X"])["axes"]["X"]["servo"]
