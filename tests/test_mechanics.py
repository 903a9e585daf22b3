"""Physical properties of the five-inertia model (docs/model.md section 2)."""

import math

import numpy as np
import pytest

from tcpmm.errors import InputError
from tcpmm.mechanics.lumped import AxisMechanics
from tcpmm.mechanics.statespace import discretize_zoh, plant
from tcpmm.mechanics.transfer import (
    block_freqresp,
    freqresp_ss,
    g_t_closed_form,
    g_tcp_closed_form,
    reduced_freqresp,
    to_control_tf,
)

F = np.logspace(-1, 3, 200)


@pytest.mark.parametrize(("field", "value", "needle"), [
    ("M_t", -150.0, "M_t"), ("lead", 0.0, "lead"), ("K_t", float("nan"), "K_t"),
    ("C_b", -1.0, "C_b"), ("J_m", True, "J_m"),
])
def test_bad_parameter_names_the_field(xmech, field, value, needle):
    with pytest.raises(InputError, match=needle):
        AxisMechanics.create(**{**xmech.model_dump(), field: value})


def test_unknown_parameter_is_an_error(xmech):
    with pytest.raises(InputError, match="K_x"):
        AxisMechanics.create(**{**xmech.model_dump(), "K_x": 1.0})


def test_g_t_dc_gain_is_screw_ratio(xmech):
    g = reduced_freqresp(xmech, "G_T", [0.01])[0]
    assert abs(g / xmech.R_L - 1) < 1e-3
    assert abs(xmech.R_L - 0.01 / (2 * math.pi)) < 1e-15


def test_state_space_matches_corrected_closed_forms(xmech):
    np.testing.assert_allclose(reduced_freqresp(xmech, "G_T", F), g_t_closed_form(xmech, F),
                               rtol=1e-9)
    np.testing.assert_allclose(reduced_freqresp(xmech, "G_tcp", F), g_tcp_closed_form(xmech, F),
                               rtol=1e-9)


def test_printed_eq6_is_wrong_at_dc(xmech):
    """Eq. (6) as printed lacks the G_L K_L (1 + K_t D) terms: its DC gain is not R_L."""
    f = np.array([0.01])
    GL = block_freqresp(xmech, "G_L", f)
    D = block_freqresp(xmech, "G_t", f) - block_freqresp(xmech, "G_b", f)
    m = xmech
    printed = GL * m.K_L * m.K_t * m.R_L * D / (1 + GL * m.K_t * m.R_L**2 + m.K_t * D)
    assert abs(printed[0]) > 100 * m.R_L
    assert abs(g_t_closed_form(m, f)[0] / m.R_L - 1) < 1e-3


def test_g_tcp_tends_to_one_for_rigid_structure(xmech):
    stiff = xmech.scaled(K_b=1e6, K_h=1e6)
    f = np.linspace(0.1, 500, 400)
    assert np.max(np.abs(reduced_freqresp(stiff, "G_tcp", f) - 1)) < 1e-3
    # ... and the flexible one is not.
    assert np.max(np.abs(reduced_freqresp(xmech, "G_tcp", f) - 1)) > 0.5


def test_g_m_low_frequency_is_rigid_inertia(xmech):
    m = xmech.replace(B_m=0.0, B_L=0.0, C_t=0.0, C_b=0.0, C_h=0.0)
    f = np.array([0.05, 0.2])
    expected = m.K_tc / (m.J_total * 2j * np.pi * f)
    np.testing.assert_allclose(reduced_freqresp(m, "G_M", f), expected, rtol=2e-3)


def test_blocks_compose_g_m(xmech):
    """omega_m/i_c from the blocks (correct algebra) equals the state-space G_M."""
    m = xmech
    f = F
    s = 2j * np.pi * f
    Gm, GL = block_freqresp(m, "G_m", f), block_freqresp(m, "G_L", f)
    D = block_freqresp(m, "G_t", f) - block_freqresp(m, "G_b", f)
    # Screw side: load seen by th_L is K_t R^2 D/(1+K_t D) over G_L.
    Z_L = 1 / GL + m.K_t * m.R_L**2 / (1 + m.K_t * D)  # torque per rad at th_L
    th_L_per_th_m = m.K_L / (Z_L + m.K_L)
    Z_m = m.K_L * (1 - th_L_per_th_m)  # shaft torque per rad of th_m
    G_M = m.K_tc * Gm / (1 + Gm * Z_m / s)
    np.testing.assert_allclose(reduced_freqresp(m, "G_M", f), G_M, rtol=1e-8)


def test_control_export_matches(xmech):
    f = np.array([1.0, 30.0, 300.0])
    for name in ("G_M", "G_T", "G_tcp"):
        tf = to_control_tf(xmech, name)
        np.testing.assert_allclose(tf(2j * np.pi * f), reduced_freqresp(xmech, name, f),
                                   rtol=1e-5)
    assert to_control_tf(xmech, "G_h")(0.0) == pytest.approx(1 / xmech.K_h)
    ss = plant(xmech).to_control()
    assert ss.nstates == 10


def test_modes_and_rigid_body(xmech):
    ev = np.linalg.eigvals(plant(xmech).A)
    assert np.sum(np.abs(ev) < 1e-6) == 1  # one rigid-body position mode
    assert np.all(ev.real <= 1e-9)  # passive mechanics: no unstable mode


def test_energy_decays_in_free_motion(xmech):
    """The feed drive (motor, screw, carriage, bed) is passive: its mechanical energy never
    increases in free motion. The TCP structure is driven by the nut force one way (it is
    outside the loop and does not react on the drive), so it is not part of that energy."""
    p = plant(xmech)
    Ad, _ = discretize_zoh(p.A, p.B, 1e-4)
    m = xmech
    Mdiag = np.array([m.J_m, m.J_L, m.M_t, m.M_b])
    K = -p.A[5:9, :4] * Mdiag[:, None]
    np.testing.assert_allclose(K, K.T, rtol=1e-12, atol=1e-6)  # reciprocity
    assert np.all(np.linalg.eigvalsh(K) > -1e-6 * np.abs(K).max())  # no negative spring
    x = np.zeros(10)
    x[5:] = [50.0, -30.0, 0.02, 0.001, -0.01]
    E = []
    for _ in range(3000):
        v, q = x[5:9], x[:4]
        E.append(0.5 * v @ (Mdiag * v) + 0.5 * q @ K @ q)
        x = Ad @ x
    E = np.array(E)
    assert np.all(np.diff(E) <= 1e-12 * E[0])
    assert E[-1] < 0.5 * E[0]


def test_freqresp_helper_with_d_term(xmech):
    p = plant(xmech)
    h = freqresp_ss(p, [10.0], "X_LS")
    assert h.shape == (1,)


def test_fast_block_algebra_equals_state_space(vmc):
    from tcpmm.ident.physical import model_frfs

    for a in vmc.axes.values():
        got = model_frfs(a.mechanics, {k: F for k in ("G_M", "G_T", "G_tcp")})
        for k, v in got.items():
            np.testing.assert_allclose(v, reduced_freqresp(a.mechanics, k, F), rtol=1e-8)
