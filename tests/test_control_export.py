"""python-control export: minimal, stable where the physics is, named; round trips of
frequency and step response against the package's own state space."""

from pathlib import Path

import control
import numpy as np
import pytest
from scipy.signal import lsim

from tcpmm.errors import InputError
from tcpmm.mechanics.statespace import plant
from tcpmm.mechanics.transfer import reduced_freqresp, to_control_tf
from tcpmm.servo.closedloop import (
    closed_loop_freqresp,
    closed_loop_to_control,
    position_closed_loop,
)

#: Band of the round trips: up to the velocity-loop Nyquist frequency's half, where the
#: closed loops still pass more than 1e-9 of the command (beyond, 1e-6 of the response
#: is below the rounding of the reference itself).
F = np.logspace(-1, np.log10(2000.0), 600)
#: Minimal orders: G_M sees motor, screw, table and bed (twist, nut, bed and four
#: velocities); G_T the load chain with the motor held; G_tcp bed and structure.
ORDERS = {"G_M": 7, "G_T": 6, "G_tcp": 4}


@pytest.mark.parametrize("ax", ["X", "Y", "Z"])
@pytest.mark.parametrize("name", ["G_M", "G_T", "G_tcp"])
@pytest.mark.parametrize("bw", [None, 2500.0])
def test_reduced_export_round_trip(vmc, ax, name, bw):
    m = vmc.axes[ax].mechanics
    g = to_control_tf(m, name, bw)
    assert g.nstates == ORDERS[name] + (1 if bw and name == "G_M" else 0)
    np.testing.assert_allclose(g(2j * np.pi * F), reduced_freqresp(m, name, F, bw), rtol=1e-6)
    assert np.all(g.poles().real < 0)  # passive mechanics with damping
    assert g.input_labels and g.output_labels == [{"G_M": "w_m", "G_T": "X_LS",
                                                   "G_tcp": "X_TCP"}[name]]


def test_reduced_dc_gains_and_steps(vmc):
    m = vmc.axes["X"].mechanics
    t = np.linspace(0, 8.0, 16001)
    _, y = control.step_response(to_control_tf(m, "G_T"), t)
    assert np.all(np.isfinite(y)) and y[-1] == pytest.approx(m.R_L, rel=1e-4)
    _, y = control.step_response(to_control_tf(m, "G_tcp"), t)
    assert np.all(np.isfinite(y)) and y[-1] == pytest.approx(1.0, rel=1e-4)


def test_g_m_step_matches_the_plant(vmc):
    m = vmc.axes["X"].mechanics
    p = plant(m)
    t = np.linspace(0, 0.05, 5001)
    u = np.ones_like(t)
    _, y_ref, _ = lsim((p.A, p.B[:, :1], p.C[:1], np.zeros((1, 1))), u, t)
    _, y = control.forced_response(to_control_tf(m, "G_M"), t, u)
    np.testing.assert_allclose(y, y_ref, rtol=1e-6, atol=1e-9 * np.max(np.abs(y_ref)))


def _servo(a, **changes):
    return type(a.servo).create(**{**a.servo.model_dump(), **changes})


@pytest.mark.parametrize("changes", [
    {}, {"k_ff": 0.0, "position_feedback": "encoder", "current_bandwidth_hz": 2000.0},
    {"filters": [{"type": "notch", "f_hz": 633.0, "bandwidth_hz": 150.0, "depth_db": -25.0},
                 {"type": "lowpass", "f_hz": 3000.0, "zeta": 0.7}]},
])
@pytest.mark.parametrize("name", ["G_v", "G_p", "cmd_to_tcp", "cmd_to_motor"])
def test_closed_loop_export_round_trip(vmc, changes, name):
    a = vmc.axes["Y"]
    s = _servo(a, **changes)
    g = closed_loop_to_control(a.mechanics, s, name)
    np.testing.assert_allclose(g(2j * np.pi * F), closed_loop_freqresp(a.mechanics, s, name, F),
                               rtol=1e-6)
    assert np.all(g.poles().real < 0)
    assert g.output_labels == [{"G_v": "w_m", "G_p": "x_fb", "cmd_to_tcp": "X_TCP",
                                "cmd_to_motor": "x_motor"}[name]]
    assert g.input_labels == ["w_c" if name == "G_v" else "x_cmd"]


def test_closed_loop_step_matches_the_package(vmc):
    a = vmc.axes["X"]
    s = _servo(a, k_ff=0.0)
    cl = position_closed_loop(a.mechanics, s)
    t = np.linspace(0, 0.3, 6001)
    u = np.ones_like(t)
    k = cl.outputs.index("X_TCP")
    _, y_ref, _ = lsim((cl.A, cl.B[:, :1], cl.C[k:k + 1], cl.D[k:k + 1, :1]), u, t)
    _, y = control.forced_response(closed_loop_to_control(a.mechanics, s, "cmd_to_tcp"), t, u)
    assert np.all(np.isfinite(y))
    np.testing.assert_allclose(y, y_ref, rtol=1e-6, atol=1e-9)


def test_two_input_loop_keeps_its_names(vmc):
    a = vmc.axes["X"]
    g = closed_loop_to_control(a.mechanics, a.servo)
    assert g.input_labels == ["x_cmd", "v_cmd"]
    assert "X_TCP" in g.output_labels and "i_c" in g.output_labels
    assert g.state_labels[:2] == ["th_m", "th_L"]
    assert plant(a.mechanics).to_control().output_labels[0] == "w_m"


def test_improper_export_is_refused(vmc):
    a = vmc.axes["X"]
    with pytest.raises(InputError, match="improper"):
        closed_loop_to_control(a.mechanics, a.servo, "cmd_to_current")


def test_sampled_loop_export(vmc):
    """The lifted sampled loop: stable discrete poles, named signals, unit DC gain from
    the command to the scale, and the same response as the package's matrices."""
    from tcpmm.servo.margins import discrete_freqresp
    from tcpmm.servo.sampled import lifted_closed_loop, lifted_to_control

    a = vmc.axes["X"]
    g = lifted_to_control(a.mechanics, a.servo)
    assert g.dt == a.servo.T_p and g.input_labels == ["x_cmd", "v_cmd"]
    assert np.all(np.abs(g.poles()) < 1)
    k = g.output_labels.index("X_LS")
    assert g.dcgain()[k, 0] == pytest.approx(1.0, abs=1e-9)
    Phi, Gam, C, D = lifted_closed_loop(a.mechanics, a.servo)
    f = np.array([1.0, 30.0, 300.0])
    np.testing.assert_allclose(
        g(np.exp(2j * np.pi * f * a.servo.T_p))[k, 0],
        discrete_freqresp(Phi, Gam[:, :1], C[k:k + 1], D[k:k + 1, :1], a.servo.T_p, f),
        rtol=1e-9)


TRACE = Path(__file__).parents[1] / ".." / "shared" / "data" / "sinumerik" / "freq_trace.XML"


@pytest.mark.skipif(not TRACE.is_file(), reason="Sinumerik trace not available")
def test_fitted_trace_exports_with_its_delay(trace_fit):
    """The Sinumerik trace's fit (0.33 ms delay, band to 4 kHz, where the delay turns the
    phase by 8 rad) exported by default matches the fit's own response over its band:
    the delay is in the exported model as a Pade approximant, not left out."""
    from tcpmm.pade import PADE_TOLERANCE

    fit = trace_fit.tf
    assert fit.delay_s > 1e-4
    f = fit.freq_hz
    g = fit.to_control()
    err = np.abs(g(2j * np.pi * f) / fit.freqresp(f) - 1)
    assert np.max(err) <= PADE_TOLERANCE * 1.01
    sys = control.ss(g)
    assert np.all(sys.poles().real < 0)
    # leaving the delay out (order 0) is far off at the top of the band
    assert np.max(np.abs(fit.to_control(pade_order=0)(2j * np.pi * f) / fit.freqresp(f) - 1)) > 1


def test_a_delay_no_pade_order_holds_over_the_band_is_warned_with_where_it_holds():
    """A fit with 0.95 ms of delay over a band to 5 kHz: the highest Pade order holds the
    delay within 0.1 % up to about 2.6 kHz and is 199 % off at 5 kHz, and the export
    gave it silently, though the docs promise 0.1 % over the band. It is now warned of
    with the frequency up to which it holds, which the approximant does meet; a delay
    the order does hold (0.33 ms to 4 kHz, the Sinumerik trace's) is not warned of."""
    import warnings

    from tcpmm.errors import InputWarning
    from tcpmm.pade import MAX_PADE_ORDER, PADE_TOLERANCE, held_up_to, pade_error, with_delay

    g = control.tf([1.0], [1e-3, 1.0])
    with pytest.warns(InputWarning, match=r"holds it within 0\.1% only up to 2\d\d\d Hz; "
                                          r"at the band's top, 5000 Hz, it is 199% off"):
        with_delay(g, 0.95e-3, 5000.0)
    top = held_up_to(0.95e-3, MAX_PADE_ORDER, 5000.0)
    assert pade_error(0.95e-3, MAX_PADE_ORDER, [top])[0] <= PADE_TOLERANCE
    assert pade_error(0.95e-3, MAX_PADE_ORDER, [top * 1.01])[0] > PADE_TOLERANCE
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with_delay(g, 0.33e-3, 4000.0)
