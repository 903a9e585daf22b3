"""Friction and reversal inside the compiled five-inertia loop."""

import numpy as np
import pytest

from tcpmm.analysis.circular import analyse_circle
from tcpmm.mechanics.friction import StribeckFriction
from tcpmm.model import AxisFriction
from tcpmm.path import circle_command
from tcpmm.sim.simulate import simulate, simulate_axis

R = 0.035


def with_friction(machine, fc, axes=("X", "Y"), substeps=16):
    out = machine
    for ax in axes:
        a = machine.axes[ax]
        fr = None if fc == 0 else AxisFriction(
            guideway=StribeckFriction.symmetric(fc=fc, fs=1.2 * fc, fv=200.0, vs=2e-3),
            substeps=substeps)
        out = out.with_axis(ax, a.replace(friction=fr))
    return out


@pytest.fixture(scope="module")
def circle():
    return circle_command(radius_m=R, feed_m_per_s=5000 / 60e3, start_angle_rad=np.pi / 4)


def test_spike_grows_with_coulomb_and_vanishes_without(vmc, circle):
    spikes = []
    for fc in (0.0, 40.0, 120.0):
        res = analyse_circle(simulate(with_friction(vmc, fc), circle), R)
        spikes.append(abs(res.passes[0].sensors["scale"].spikes["B"]))
    assert spikes[0] < 0.2e-6
    assert spikes[0] < spikes[1] < spikes[2]
    assert spikes[2] > 2 * spikes[1] * 0.9


def test_stick_is_exact(vmc):
    """At rest under a load below the static level, the carriage does not creep."""
    a = vmc.axes["X"].replace(friction=AxisFriction(
        guideway=StribeckFriction.symmetric(fc=300.0, fs=400.0, fv=0.0)))
    a = a.replace(mechanics=a.mechanics.replace(load_force=0.0))
    t = np.arange(0, 0.2, 1e-3)
    r = simulate_axis(a, t, np.zeros_like(t), quantise_feedback=False)
    assert np.max(np.abs(r.scale)) == 0.0


def test_reversal_converges_with_substeps(vmc):
    """Refining the sub-steps at reversals converges (differences shrink)."""
    t = np.arange(0, 0.6, 1e-3)
    cmd = 0.002 * np.sin(2 * np.pi * 2 * t)
    outs = []
    for n in (1, 2, 4, 8, 16, 32, 64):
        a = with_friction(vmc, 150.0, axes=("X",), substeps=n).axes["X"]
        outs.append(simulate_axis(a, t, cmd, quantise_feedback=False).scale)
    d = [np.max(np.abs(outs[k] - outs[-1])) for k in range(len(outs) - 1)]
    assert d[-1] < d[0]
    assert d[-1] < 0.25 * d[1]
    assert np.all(np.diff(d[1:]) < 0)


def test_friction_round_trips_in_model_file(vmc, tmp_path):
    from tcpmm.io.modelfile import read_machine, write_machine

    write_machine(vmc, tmp_path / "m.yaml")
    m2 = read_machine(tmp_path / "m.yaml")
    assert m2 == vmc
    assert m2.axes["Y"].friction.guideway.fc_pos == vmc.axes["Y"].friction.guideway.fc_pos


def _circle_metrics_um(machine):
    from tcpmm.demo import paper_circle_command

    res = analyse_circle(simulate(machine, paper_circle_command(machine)), R)
    return {(p.direction, r["sensor"], k): v for p in res.passes for r in p.table()
            for k, v in r.items() if isinstance(v, float)}


def test_paper_circle_converged_in_substeps(vmc):
    """The paper's circle (3 axes, friction on screw and guideway): doubling the sub-steps
    of the steps in which friction reverses or breaks away, 16 -> 32, moves no spike,
    contour error or circular deviation by 0.01 um. Sub-steps taken with the wrong
    matrices or period would move them by far more."""
    def sub(n):
        m = vmc
        for name, a in vmc.axes.items():
            m = m.with_axis(name, a.replace(friction=a.friction.model_copy(
                update={"substeps": n})))
        return _circle_metrics_um(m)

    a, b = sub(16), sub(32)
    assert a.keys() == b.keys() and len(a) >= 24
    worst = max(abs(a[k] - b[k]) for k in a if a[k] == a[k])
    assert worst < 0.01


def test_axes_in_turn_give_the_run_of_axes_side_by_side(vmc, circle):
    """The axes share nothing in the kernel: run in threads or one after another, the
    run is the same to the bit."""
    side, turn = simulate(vmc, circle), simulate(vmc, circle, threads=1)
    for name, r in side.axes.items():
        for col in ("scale", "tcp", "current"):
            np.testing.assert_array_equal(getattr(turn.axes[name], col), getattr(r, col))


def _run_kernel(axis, t, pos, shortcuts):
    import dataclasses

    from tcpmm.sim.inputs import kernel_inputs
    from tcpmm.sim.kernel import run_axis

    T_c = float(t[1] - t[0])
    n = int(np.rint((t[-1] - t[0]) / axis.servo.T_v)) + 1
    k = kernel_inputs(axis, pos, np.zeros(t.size), T_c, n)
    k = dataclasses.replace(k, shortcuts=shortcuts)
    rec = k.empty_record()
    x = run_axis(*k.as_args(rec))
    return rec, x


@pytest.mark.parametrize("variant", ["built-in", "relative guideway", "screw only",
                                     "guideway only", "LuGre screw", "held"])
def test_the_shortcuts_change_no_bit(vmc, circle, variant):
    """A step in which both contacts slide on, or both stay held, is taken in registers
    (``_sliding_step``, ``_held_step``) instead of the general path: the same tests on
    the same numbers, so every state of every step is the same to the bit, through
    reversals, stick and break-away, and on an axis held still (Z, both contacts stuck
    against its load)."""
    from tcpmm.mechanics.friction import LuGreFriction

    a = vmc.axes["Z" if variant == "held" else "X"]
    fr = a.friction
    update = {"built-in": {}, "held": {}, "relative guideway": {"guideway_velocity": "relative"},
              "screw only": {"guideway": None}, "guideway only": {"screw": None},
              "LuGre screw": {"screw": LuGreFriction(**fr.screw.model_dump(), sigma0=1e8,
                                                     sigma1=300.0)}}[variant]
    fr = fr.model_copy(update=update)
    axis = a.replace(friction=fr)
    t = circle.time_s[circle.time_s < 4.0]
    pos = np.ascontiguousarray(circle.positions["X"][: t.size])
    if variant == "held":
        pos = np.zeros(t.size)
    rec_on, x_on = _run_kernel(axis, t, pos, True)
    rec_off, x_off = _run_kernel(axis, t, pos, False)
    assert np.array_equal(rec_on, rec_off) and np.array_equal(x_on, x_off)
    if variant == "held":
        assert x_on[6] == 0.0 and x_on[7] == 0.0
    else:  # the axis moved, and reversed (the circle's quadrants)
        assert np.ptp(rec_on[3]) > 0.1


@pytest.mark.parametrize("seed", range(4))
def test_a_held_axis_stays_held_whatever_the_rounding(vmc, seed):
    """The built-in machine's Z held still, screw and guideway both stuck, with its
    discrete matrices changed by one unit in the last place here and there (another
    build of the discretisation): both contacts end every step at exactly zero velocity.
    Stopped one after the other, the guideway's force left the screw at some 1e-16 m/s,
    whose sign flipped with the rounding: a reversal, sub-stepped, at every step."""
    from tcpmm.sim.inputs import kernel_inputs
    from tcpmm.sim.kernel import run_axis

    a = vmc.axes["Z"]
    t = np.arange(0.0, 0.5, 1e-3)
    pos = np.zeros_like(t)
    n = int(np.rint(t[-1] / a.servo.T_v)) + 1
    k = kernel_inputs(a, pos, np.zeros(t.size), 1e-3, n, x_start=0.0)
    rng = np.random.default_rng(seed)
    for M in (k.AdT, k.BdT, k.AdsT, k.BdsT):
        flip = rng.random(M.shape) < 0.3
        M[flip] = np.nextafter(M[flip], np.where(rng.random(flip.sum()) < 0.5, -1.0, 1.0)
                               * np.inf)
    rec = k.empty_record()
    x = run_axis(*k.as_args(rec))
    assert a.friction is not None and x[6] == 0.0 and x[7] == 0.0
    assert np.ptp(rec[1]) < 1e-15  # the scale does not creep


def test_the_kernels_bed_velocity_is_the_plants():
    """A relative guideway velocity is taken to the kernel's ``BED_VELOCITY``, which must
    be the plant's ``v_b`` (a change of the state order would silently relate the
    guideway to another body)."""
    from tcpmm.mechanics.statespace import STATES
    from tcpmm.sim.layout import BED_VELOCITY

    assert STATES[BED_VELOCITY] == "v_b"


def test_axes_kept_from_an_earlier_run_are_its_bits_and_not_run_again(vmc, circle,
                                                                      monkeypatch):
    """``simulate(..., axis_runs=kept)``: a machine that shares axes with the one run
    before (a variant of one axis, as the verdict runs some 45) runs only the axis it
    changed, and gets the run it would have got from scratch, to the bit. An axis that is
    another object, or the same on another command, is run again."""
    import dataclasses

    from tcpmm.sim import simulate as sim

    real, ran = sim.simulate_axis, []

    def counted(axis, *args, **kw):
        ran.append(axis)
        return real(axis, *args, **kw)

    monkeypatch.setattr(sim, "simulate_axis", counted)
    kept: dict = {}
    simulate(vmc, circle, axis_runs=kept)
    assert len(ran) == 3 and set(kept) == {"X", "Y", "Z"}
    x = vmc.axes["X"]
    variant = vmc.with_axis("X", x.replace(mechanics=x.mechanics.scaled(K_t=1.3)))
    ran.clear()
    again = simulate(variant, circle, axis_runs=kept)
    assert ran == [variant.axes["X"]]
    fresh = simulate(variant, circle)
    for name in "XYZ":
        a, b = again.axes[name], fresh.axes[name]
        for s in ("cmd", "motor", "scale", "tcp", "current", "motor_speed"):
            assert np.array_equal(getattr(a, s), getattr(b, s)), (name, s)
    ran.clear()
    simulate(variant, dataclasses.replace(circle), axis_runs=kept)
    assert len(ran) == 3


@pytest.mark.parametrize("axis_name", ["X", "Z"])
def test_the_loop_of_the_common_runs_changes_no_bit(vmc, circle, axis_name):
    """The kernel's loop is compiled apart, with its settings as constants, for the common
    kind of run (``_plain``: friction without free play, the shortcuts on, no excitation,
    no current filters, ...). The same run made of the other kind by a current filter
    that passes the current unchanged (``b0 = 1``, the rest 0: ``1 u + 0`` is ``u``)
    takes the general loop, and gives every record and the end state to the bit: on X
    moving through the circle's reversals and on Z held still."""
    import dataclasses

    from tcpmm.sim.inputs import kernel_inputs
    from tcpmm.sim.kernel import _plain, run_axis

    axis = vmc.axes[axis_name]
    t = circle.time_s[circle.time_s < 4.0]
    pos = np.ascontiguousarray(circle.positions.get(axis_name, 0.0 * circle.time_s)[: t.size])
    n = int(np.rint((t[-1] - t[0]) / axis.servo.T_v)) + 1
    k = kernel_inputs(axis, pos, np.zeros(t.size), float(t[1] - t[0]), n)
    through = dataclasses.replace(k, fsec=np.array([[1.0, 0.0, 0.0, 0.0, 0.0]]))
    out = []
    for inputs, common in ((k, True), (through, False)):
        rec = inputs.empty_record()
        args = inputs.as_args(rec)
        assert _plain(args[5].any(), inputs.fsec, args[6], args[7], inputs.pf_s,
                      inputs.pf_g) == common
        out.append((rec, run_axis(*args)))
    assert np.array_equal(out[0][0], out[1][0]) and np.array_equal(out[0][1], out[1][1])
    assert np.ptp(out[0][0][3]) > 0.1 if axis_name == "X" else out[0][1][6] == 0.0
