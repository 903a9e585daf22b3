"""Known answers: simulate the core model (noise, quantisation), identify, recover it."""

import warnings

import numpy as np
import pytest

from tcpmm.ident.pipeline import identify_axis
from tcpmm.machines.builtin import builtin_machine
from tcpmm.machines.virtual import axis_config, virtual_sweep
from tcpmm.mechanics.statespace import plant

#: Parameters that shape the motion of carriage, bed and TCP structure; they must lie
#: within 3 reported standard deviations of the truth.
STRUCTURE = ("M_t", "K_t", "M_b", "K_b", "M_h", "K_h", "C_h")


def modes(mech):
    ev = np.linalg.eigvals(plant(mech).A)
    ev = ev[ev.imag > 0]
    ev = ev[np.argsort(np.abs(ev))]
    return np.abs(ev) / (2 * np.pi), -ev.real / np.abs(ev)


@pytest.fixture(scope="module")
def machine():
    return builtin_machine(friction=False)


@pytest.mark.parametrize("open_loop", [False, True], ids=["closed-loop", "torque-mode"])
@pytest.mark.parametrize("ax", ["X", "Y"])
def test_identify_recovers_the_model(machine, ax, open_loop, identify_builtin):
    a = machine.axes[ax]
    if open_loop:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            idn = identify_axis(ax, virtual_sweep(a, name=ax, open_loop=True,
                                                  travel_speed_m_per_s=0.0),
                                axis_config(machine, ax))
    else:  # the default sweep travels at 20 mm/s under the axis's loops
        idn, _ = identify_builtin(ax, friction=False)
    f_true, z_true = modes(a.mechanics)
    f_id, z_id = modes(idn.axis.mechanics)
    inband = f_true < 500.0  # the 700 Hz torsion has 0.1 % damping: only its frequency
    np.testing.assert_allclose(f_id[inband], f_true[inband], rtol=0.01)
    # Damping within 10 % in closed loop (the paper's set-up). In torque mode the lightly
    # damped structural mode of Y scatters to 10-15 % with the segment length.
    np.testing.assert_allclose(z_id[inband], z_true[inband], rtol=0.15 if open_loop else 0.10)
    assert abs(f_id[-1] / f_true[-1] - 1) < 0.03
    got, true = idn.axis.mechanics.model_dump(), a.mechanics.model_dump()
    for p in STRUCTURE:
        if open_loop:  # the Jacobian's standard deviations are optimistic in torque mode
            # masses and stiffnesses to 3 %; damping is checked through the modes above
            assert p.startswith("C_") or abs(got[p] / true[p] - 1) < 0.03, p
        else:
            assert abs(got[p] - true[p]) < 3 * idn.physical.std[p], p
        assert p not in idn.physical.undetermined
    # The TF fits find the same modes as the physical model.
    tcp_modes = np.sort(idn.tf_fits["G_tcp"].natural_freq_hz)
    assert abs(tcp_modes[0] / f_true[0] - 1) < 0.01
    q = {r["tf"]: r for r in idn.quality()}
    assert q["G_tcp"]["physical_fit_percent"] > 70
    assert idn.axis.servo.K_pp == a.servo.K_pp


def test_identified_model_predicts_the_circle(machine, identify_builtin):
    """Closed loop with quantisation and noise: the identified model's circle matches the
    true machine's within the paper's contour-error difference (0.6 um)."""
    from tcpmm.analysis.circular import analyse_circle
    from tcpmm.analysis.compare import compare_circles
    from tcpmm.demo import paper_circle_command
    from tcpmm.sim.simulate import simulate

    identified = machine
    for ax in ("X", "Y"):
        idn, _ = identify_builtin(ax, friction=False)
        identified = identified.with_axis(ax, idn.axis)
    cmd = paper_circle_command()
    truth = analyse_circle(simulate(machine, cmd), 0.035)
    pred = analyse_circle(simulate(identified, cmd), 0.035)
    for row in compare_circles(truth, pred).rows:
        if row["sensor"] == "tcp":
            assert abs(row["contour_error_um"]) < 0.6, row


def test_a_light_carriage_on_a_heavy_screw_is_found(unseen):
    """Unseen machine 6 of seed 2 without play, axis X: the carriage carries a fifth of the
    rigid-body inertia (screw and motor the rest) and the column mode is at 29 Hz. Every
    start that gave the carriage 30 % or more of the inertia ended in a basin with the
    carriage at 35-65 % of its mass and a cost 5-200 times the truth's; the one kept had
    the column 13 times too stiff (with this axis's friction: 1000 times too soft, and
    the predicted circle 500 um off)."""
    true, _ = unseen.draw_machine(2, 6)
    a = true.axes["X"].replace(friction=None)
    m = a.mechanics
    assert m.M_t * m.R_L**2 / m.J_total < 0.25
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        idn = identify_axis("X", virtual_sweep(a, name="X"), axis_config(true, "X"))
    got = idn.axis.mechanics
    for p in ("M_t", "K_t", "M_h", "K_h", "K_L"):
        assert abs(getattr(got, p) / getattr(m, p) - 1) < 0.06, p
