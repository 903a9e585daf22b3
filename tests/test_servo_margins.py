"""Margins of the sampled loops: known answers and agreement with python-control."""

import math

import control
import numpy as np
import pytest

from tcpmm.machines.builtin import builtin_machine
from tcpmm.servo.margins import axis_margins, discrete_freqresp, margins_of
from tcpmm.servo.sampled import position_open_loop, velocity_open_loop


@pytest.mark.parametrize(("gain", "d"), [(0.3, 0), (0.2, 1), (0.05, 3)])
def test_integrator_with_delay_has_the_analytic_margins(gain, d):
    """L(z) = k / ((z - 1) z^d): phase -180 deg at theta = pi/(2d+1), |L| = 1 at
    theta = 2 asin(k/2); GM = 2 sin(theta_180/2)/k, PM = 90 deg - (d + 1/2) theta_c."""
    dt = 1e-3
    n = d + 1
    Phi = np.zeros((n, n))
    Phi[0, 0] = 1.0
    for i in range(1, n):  # delay line feeding the integrator
        Phi[i - 1, i] = 1.0
    Gam = np.zeros((n, 1))
    Gam[-1, 0] = 1.0
    if d == 0:
        Gam[0, 0] = 1.0
    C = np.zeros((1, n))
    C[0, 0] = gain
    D = np.zeros((1, 1))
    m = margins_of(lambda f: discrete_freqresp(Phi, Gam, C, D, dt, f), 0.5 / dt,
                   poles=np.linalg.eigvals(Phi), dt=dt)
    th180 = math.pi / (2 * d + 1)
    thc = 2 * math.asin(gain / 2)
    assert m.gain_margin_db == pytest.approx(20 * math.log10(2 * math.sin(th180 / 2) / gain),
                                             abs=1e-9)
    assert m.phase_margin_deg == pytest.approx(math.degrees(math.pi / 2 - (d + 0.5) * thc),
                                               abs=1e-8)
    assert m.gain_crossover_hz == pytest.approx(thc / (2 * math.pi * dt), rel=1e-9)
    assert m.phase_crossover_hz == pytest.approx(th180 / (2 * math.pi * dt), rel=1e-9)


def _control_margins(Phi, Gam, C, D, dt, sign):
    sys = control.ss(Phi, Gam, sign * C, sign * D, dt)
    w = 2 * np.pi * np.linspace(0.05, 0.49999 / dt, 4001)
    gm, pm, wg, wc = control.margin(control.frd(sys, w))  # smooth spline of the response
    return 20 * np.log10(gm), pm, wc / (2 * np.pi), wg / (2 * np.pi)


@pytest.mark.parametrize("changes", [
    {}, {"delay_samples": 1, "velocity_feedback": "difference"},
    {"filters": [{"type": "notch", "f_hz": 728.8, "bandwidth_hz": 200.0, "depth_db": -30.0}],
     "delay_samples": 2},
])
def test_margins_agree_with_python_control(vmc, changes):
    """The same discrete loops, evaluated by python-control's frequency-response margins."""
    a = vmc.axes["X"]
    servo = type(a.servo).create(**{**a.servo.model_dump(), **changes})
    mine = axis_margins(a.mechanics, servo)
    for loop, build, sign, dt in (("velocity", velocity_open_loop, -1, servo.T_v),
                                  ("position", position_open_loop, 1, servo.T_p)):
        gm, pm, fc, f180 = _control_margins(*build(a.mechanics, servo), dt, sign)
        m = mine[loop]
        assert m.phase_margin_deg == pytest.approx(pm, abs=1e-3)
        assert m.gain_crossover_hz == pytest.approx(fc, rel=1e-5)
        if m.phase_crossover_hz < 0.49 / dt:  # python-control's grid ends short of Nyquist
            assert m.gain_margin_db == pytest.approx(gm, abs=1e-3)
            assert m.phase_crossover_hz == pytest.approx(f180, rel=1e-5)


def test_more_delay_less_margin(vmc):
    a = vmc.axes["X"]
    m0 = axis_margins(a.mechanics, a.servo)["velocity"]
    m2 = axis_margins(a.mechanics, a.servo.model_copy(update={"delay_samples": 2}))["velocity"]
    assert m2.gain_margin_db < m0.gain_margin_db
    assert m2.phase_margin_deg < m0.phase_margin_deg


def test_position_crossover_near_kpp(vmc):
    """With the velocity loop far faster, L_p ~ K_pp/s: crossover K_pp/2pi, PM ~ 90 deg."""
    a = vmc.axes["X"]
    m = axis_margins(a.mechanics, a.servo)["position"]
    assert m.bandwidth_hz == pytest.approx(a.servo.K_pp / (2 * np.pi), rel=0.05)
    assert 80 < m.phase_margin_deg < 95


def test_machine_show_and_bode_give_the_margins(capsys):
    import json

    from tcpmm.cli import main

    assert main(["machine", "show", "builtin:vmc", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    mv = data["X"]["margins"]["velocity"]
    assert set(mv) == {"gain_margin_db", "phase_margin_deg", "gain_crossover_hz",
                       "phase_crossover_hz", "bandwidth_hz", "last_crossover_hz"}
    assert mv["bandwidth_hz"] <= mv["gain_crossover_hz"] <= mv["last_crossover_hz"]
    assert main(["bode", "builtin:vmc", "--axis", "X", "--tf", "L_v", "--json", "--freq-hz",
                 f"{mv['gain_crossover_hz']!r}"]) == 0
    row = json.loads(capsys.readouterr().out)[0]
    L = complex(row["re"], row["im"])
    assert abs(L) == pytest.approx(1.0, abs=1e-9)
    assert 180 + np.degrees(np.angle(L)) == pytest.approx(mv["phase_margin_deg"], abs=1e-6)
    assert main(["machine", "show", "builtin:vmc"]) == 0
    assert "phase margin" in capsys.readouterr().out
    # the default grid reaches the Nyquist frequency, where a sampled loop's phase
    # crosses -180 deg: the gain margin can be read off the table
    assert main(["bode", "builtin:vmc", "--axis", "X", "--tf", "L_v", "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)
    nyquist = 0.5 / builtin_machine().axes["X"].servo.T_v
    assert rows[-1]["freq_hz"] == pytest.approx(nyquist, rel=1e-12)
    assert mv["phase_crossover_hz"] == pytest.approx(nyquist, rel=1e-9)
    L = complex(rows[-1]["re"], rows[-1]["im"])
    assert -20 * np.log10(abs(L)) == pytest.approx(mv["gain_margin_db"], abs=1e-6)


@pytest.mark.parametrize("loop", [velocity_open_loop, position_open_loop])
def test_the_response_is_the_resolvents_to_its_conditioning(loop):
    """``C (zI - Phi)^-1 Gam + D`` through the balanced Hessenberg form agrees with the
    resolvent solved densely and refined twice on residuals taken in extended precision,
    on each axis of the built-in machine, over a margin's grid (all frequencies at once)
    and at single frequencies (solved densely), within 1e-6: the matrices' condition
    numbers reach 1e11, the dense solve alone is within some 1e-8, and a reduction of
    the unbalanced matrix is off by 1e-4 near the Nyquist frequency."""

    def refined(Phi, Gam, C, D, dt, f):
        z = np.exp(2j * np.pi * f * dt)
        M = z[:, None, None] * np.eye(Phi.shape[0])[None] - Phi[None]
        b = np.broadcast_to(Gam[:, 0], (f.size, Phi.shape[0]))[..., None].astype(complex)
        x = np.linalg.solve(M, b)
        for _ in range(2):
            r = b.astype(np.clongdouble) - M.astype(np.clongdouble) @ x.astype(np.clongdouble)
            x = x + np.linalg.solve(M, r.astype(complex))
        return x[..., 0] @ C[0] + D[0, 0]

    for axis in builtin_machine().axes.values():
        Phi, Gam, C, D = loop(axis.mechanics, axis.servo)
        dt = axis.servo.T_v if loop is velocity_open_loop else axis.servo.T_p
        f = np.logspace(-3, np.log10(0.5 / dt), 3000)
        for fs in (f, f[-200:], f[:1], f[1234:1235], f[-1:]):
            got = discrete_freqresp(Phi, Gam, C, D, dt, fs)
            want = refined(Phi, Gam, C, D, dt, fs)
            assert np.max(np.abs(got - want) / np.abs(want)) < 1e-6


def test_a_loop_of_no_numbers_has_no_response():
    """A loop matrix holding NaN (a gain or a parameter that is none) gives NaN at every
    frequency, on the grid and at single ones, as a dense solve of it does, and raises
    nothing: the reduction refuses such a matrix."""
    Phi = 0.5 * np.eye(3)
    Phi[0, 1] = np.nan
    Gam, C, D = np.ones((3, 1)), np.ones((1, 3)), np.zeros((1, 1))
    for f in ([1.0], np.linspace(1.0, 100.0, 100)):
        assert np.isnan(discrete_freqresp(Phi, Gam, C, D, 1e-3, f)).all()
