"""Guideway share and lost motion from the encoder-minus-scale deflection of friction runs.

Synthetic records follow the static deflection formula of ``tcpmm.ident.friction.lostmotion``;
the known answers through the simulator use the built-in machine, whose friction table
says how much of the friction acts on the guideway at each speed.
"""

import dataclasses
import json
import warnings

import numpy as np
import pytest

from tcpmm.errors import InputError, InputWarning
from tcpmm.ident.friction import (
    GUIDEWAY_SHARE,
    estimate_lost_motion,
    friction_record_arrays,
    identify_friction,
    identify_stribeck_run,
    quantisation_bias_std,
)
from tcpmm.ident.pipeline import Identification, identify_axis
from tcpmm.io.records import FrictionRecord
from tcpmm.machines.builtin import builtin_machine
from tcpmm.machines.virtual import FRICTION_SPEEDS, axis_config, virtual_friction, virtual_sweep

Q = 1e-6  # encoder step at the table and scale step of the built-in machine [m]
#: Round speeds: a whole number of sensor steps per 1 ms sample [m/s].
LOCKED_SPEEDS = (0.002, 0.005, 0.01, 0.02, 0.05, 0.1)


def stribeck(v, fc, fs, vs, fv, delta=2.0):
    """Symmetric Stribeck force [N] at velocity ``v`` [m/s]."""
    v = np.asarray(v, dtype=float)
    return np.sign(v) * (fc + (fs - fc) * np.exp(-np.abs(v / vs) ** delta)) + fv * v


def deflection_record(mech, share, lost, offset, speeds=FRICTION_SPEEDS,
                      friction=(70, 85, 2e-3, 310), noise=3e-8, lead_error=0.0, seed=0):
    """Back-and-forth runs whose encoder-minus-scale difference is the static deflection.

    Returns time [s], motor angle [rad], scale [m] and motor force at the table [N], both
    positions quantised to ``Q`` with ``noise`` [m] of vibration; ``lead_error`` [m] is the
    amplitude of a periodic lead error of the screw seen by the encoder.
    """
    rng = np.random.default_rng(seed)
    T, acc = 1e-3, 1.0
    prof = [0.0]
    for sp in speeds:
        for target in (sp, -sp):
            n = int(np.ceil(abs(target - prof[-1]) / acc / T))
            prof += list(np.linspace(prof[-1], target, n + 1)[1:]) + [target] * 600
    prof += list(np.linspace(prof[-1], 0.0, 50)[1:]) + [0.0] * 100
    v = np.asarray(prof)
    t = np.arange(v.size) * T
    x = np.concatenate([[0.0], np.cumsum(0.5 * (v[1:] + v[:-1])) * T])
    R = mech.R_L
    fric = stribeck(v, *friction)
    force = fric + ((mech.B_m + mech.B_L) / R**2 + mech.C_t) * v + 0.3 * rng.standard_normal(v.size)
    nut = mech.C_t * v + share * fric
    d = (offset + R**2 / mech.K_L * (force - mech.B_m * v / R**2) + nut / mech.K_t
         + np.sign(nut) * lost / 2)
    xs = x + noise * rng.standard_normal(v.size)
    xm = xs + d + lead_error * np.sin(2 * np.pi * x / 0.037)
    return t, np.round(xm / Q) * Q / R, np.round(xs / Q) * Q, force


def estimate(mech, rec, **kw):
    t, th, xs, force = rec
    _, plateaus = identify_stribeck_run(t, xs, force)
    return estimate_lost_motion(t, th, xs, force, mech.R_L, mech, plateaus,
                                encoder_quantum=Q / mech.R_L, scale_resolution=Q, **kw)


@pytest.fixture(scope="module")
def machine():
    return builtin_machine()


@pytest.fixture(scope="module")
def xmech_(machine):
    return machine.axes["X"].mechanics


def test_quantisation_bias_of_a_ramp():
    t = np.arange(400) * 1e-3
    # 2 steps per sample: every sample rounds alike, the mean keeps the whole error
    assert quantisation_bias_std(t, 0.002 * t, Q) == pytest.approx(Q / np.sqrt(12), rel=1e-6)
    # an uneven advance sweeps the steps: no better than independent rounding errors
    assert quantisation_bias_std(t, 0.0021236 * t, Q) == pytest.approx(
        Q / np.sqrt(12 * t.size), rel=0.05)
    assert quantisation_bias_std(t, 0.002 * t, 0.0) == 0.0


def test_share_without_lost_motion(xmech_):
    lm = estimate(xmech_, deflection_record(xmech_, 0.6, 0.0, 3.3e-6))
    assert lm.determined and lm.model == "share", lm.reason
    assert lm.guideway_share_std < 0.03
    assert abs(lm.guideway_share - 0.6) < 3 * lm.guideway_share_std
    assert lm.backlash == 0.0
    assert abs(lm.offset - 3.3e-6) < 3e-8
    # the fitted nut deflection follows the measured one within the plateau uncertainty
    assert np.all(np.abs(lm.nut_deflection - lm.fitted) < 4 * lm.deflection_std)
    json.dumps(lm.to_dict())


def test_share_and_lost_motion_from_the_speed_dependence(xmech_):
    # a strong Stribeck and viscous part makes the friction change with speed, which
    # tells the share (scales with friction) from the lost motion (does not)
    rec = deflection_record(xmech_, 0.55, 3e-6, -2e-6, friction=(40, 120, 0.01, 600))
    lm = estimate(xmech_, rec)
    assert lm.determined and lm.model == "share+lost-motion", lm.reason
    assert abs(lm.guideway_share - 0.55) < 3 * lm.guideway_share_std
    assert abs(lm.backlash - 3e-6) < 3 * lm.backlash_std
    assert lm.backlash_std < 0.1e-6


def test_hysteresis_beyond_all_friction_becomes_lost_motion(xmech_):
    # pure Coulomb friction: share and lost motion are collinear, the explanation without
    # lost motion is preferred and only the hysteresis that s = 1 cannot explain is g
    coulomb = (70, 70, 2e-3, 0)
    lm = estimate(xmech_, deflection_record(xmech_, 1.0, 1e-6, 0.0, friction=coulomb))
    assert lm.determined and lm.model == "lost-motion", lm.reason
    assert lm.guideway_share == 1.0
    assert abs(lm.backlash - 1e-6) < 3 * lm.backlash_std
    lm = estimate(xmech_, deflection_record(xmech_, 0.4, 0.2e-6, 0.0, friction=coulomb))
    assert lm.model == "share" and lm.backlash == 0.0
    assert lm.guideway_share == pytest.approx(0.4 + 0.2e-6 * xmech_.K_t / (2 * 70), abs=0.03)
    # with the Stribeck part of the built-in friction the slow plateaus tell them apart
    lm = estimate(xmech_, deflection_record(xmech_, 1.0, 1e-6, 0.0))
    assert lm.determined and lm.backlash > 0, lm.reason
    assert abs(lm.backlash - 1e-6) < 3 * lm.backlash_std
    assert abs(lm.guideway_share - 1.0) < 3 * lm.guideway_share_std


def test_offset_per_speed_cancels_the_lead_error(xmech_):
    rec = deflection_record(xmech_, 0.6, 0.0, 1e-6, lead_error=2e-6)
    common = estimate(xmech_, rec)
    assert not common.determined and "chi-square" in common.reason
    lm = estimate(xmech_, rec, offset="per_speed")
    assert lm.determined, lm.reason
    assert abs(lm.guideway_share - 0.6) < 3 * lm.guideway_share_std < 0.1


def test_fitted_viscous_part_does_not_need_the_damping(xmech_):
    rec = deflection_record(xmech_, 0.6, 0.0, 0.0)
    wrong = xmech_.model_copy(update={"C_t": 0.3 * xmech_.C_t, "B_m": 3 * xmech_.B_m,
                                      "B_L": 0.2 * xmech_.B_L})
    # taken as known, wrong damping shifts the speed-proportional nut force into the
    # share and the lost motion
    known = estimate(wrong, rec)
    assert not known.determined or abs(known.guideway_share - 0.6) > 0.1
    lm = estimate(wrong, rec, viscous="fit")
    assert lm.determined, lm.reason
    assert abs(lm.guideway_share - 0.6) < 3 * lm.guideway_share_std < 0.1


def test_locked_quantisation_is_not_determined(xmech_):
    lm = estimate(xmech_, deflection_record(xmech_, 0.6, 0.0, 0.0, speeds=LOCKED_SPEEDS,
                                            noise=0.0))
    assert not lm.determined
    assert np.median(lm.deflection_std) > 0.3e-6  # the rounding error of both sensors


def test_stiff_nut_is_not_determined(xmech_):
    # a nut 100 times stiffer deflects by nanometres: far below what the plateaus resolve
    stiff = xmech_.model_copy(update={"K_t": 100 * xmech_.K_t})
    lm = estimate(stiff, deflection_record(stiff, 0.6, 0.0, 0.0))
    assert not lm.determined and "do not resolve" in lm.reason


# ---- known answers through the simulator -------------------------------------------

_RECORDS = {}


def record(machine, ax, backlash=0.0, speeds=FRICTION_SPEEDS):
    key = (ax, backlash, speeds)
    if key not in _RECORDS:
        a = machine.axes[ax]
        if backlash:
            a = a.model_copy(update={"friction": a.friction.model_copy(
                update={"backlash": backlash})})
        _RECORDS[key] = virtual_friction(a, speeds, name=ax)
    return _RECORDS[key]


def true_forces(axis, v, part):
    """Guideway and total friction of the built-in axis at velocities ``v``: all of it
    (``part="all"``) or the Coulomb and Stribeck part only (``"static"``) [N]."""
    def f(m):
        fv = m.fv_pos if part == "all" else 0.0
        return stribeck(v, m.fc_pos, m.fs_pos, m.vs, fv, m.delta)

    fg = f(axis.friction.guideway)
    return fg, fg + f(axis.friction.screw)


def level_share(friction, level):
    """Guideway share of one friction level (``"fc_pos"``, ``"fv_pos"``, ...) [-]."""
    g, s = getattr(friction.guideway, level), getattr(friction.screw, level)
    return g / (g + s)


def weighted_share(fg, ft, sd, v=None):
    """The single share that best explains the guideway friction of every plateau, with
    the plateau weights of the fit (and the part proportional to speed projected out when
    the fit takes it up) [-]."""
    w = 1.0 / sd**2
    if v is not None:
        B = np.column_stack([np.ones_like(v), v]) * np.sqrt(w)[:, None]

        def proj(z):
            zw = z * np.sqrt(w)
            return (zw - B @ np.linalg.lstsq(B, zw, rcond=None)[0]) / np.sqrt(w)

        fg, ft = proj(fg), proj(ft)
    return float(np.sum(w * fg * ft) / np.sum(w * ft * ft))


@pytest.mark.parametrize("ax", ["X", "Y"])
def test_builtin_share_with_the_true_mechanics(machine, ax):
    """Scatter over 25 sets of plateau speeds (each speed times 1.0-1.1): share minus the
    weighted true share has std 0.011 (X) / 0.007 (Y), largest 0.026, and the reported std
    matches it (0.012 / 0.007); 0.04 is 3.5 times the scatter of X."""
    a = machine.axes[ax]
    fr, _, split = identify_friction(record(machine, ax), axis_config(machine, ax), a.mechanics,
                                     axis=ax, viscous="known")
    e = split.estimate
    assert split.source == "data" and e.model == "share", e.reason
    fg, ft = true_forces(a, e.velocity, "all")
    assert abs(split.guideway_share - weighted_share(fg, ft, e.deflection_std)) < 0.04
    assert e.guideway_share_std < 0.03
    # per plateau, the measured nut deflection gives the true share of that speed to
    # within the deflection uncertainty of one plateau (20-30 nm of about 0.5-1.5 um)
    per_plateau = e.nut_deflection * a.mechanics.K_t / e.friction_force
    assert np.sqrt(np.mean((per_plateau - fg / ft) ** 2)) < 0.06
    assert split.backlash == 0.0 and fr.backlash == 0.0
    assert fr.guideway.fc_pos / (fr.guideway.fc_pos + fr.screw.fc_pos) == pytest.approx(
        split.guideway_share)


@pytest.mark.parametrize("ax", ["X", "Y"])
def test_builtin_static_share_with_the_true_mechanics(machine, ax):
    """With the speed-proportional part fitted, the share is that of the Coulomb and
    Stribeck friction (0.64-0.67 on X, 0.75-0.77 on Y). Over the 25 speed sets: error
    std 0.015 (X) / 0.010 (Y), largest 0.048, reported std 0.017 / 0.010: tolerance 0.05."""
    a = machine.axes[ax]
    _, _, split = identify_friction(record(machine, ax), axis_config(machine, ax), a.mechanics,
                                    axis=ax)
    e = split.estimate
    assert split.source == "data" and e.model == "share", e.reason
    fg, ft = true_forces(a, e.velocity, "static")
    truth = weighted_share(fg, ft, e.deflection_std, e.velocity)
    assert abs(split.guideway_share - truth) < 0.05
    assert e.guideway_share_std < 0.03


@pytest.mark.parametrize("ax", ["X", "Y"])
def test_builtin_share_with_identified_mechanics(machine, ax):
    """The FRFs leave the damping undetermined, so the speed-proportional deflection is
    fitted and the share is that of the Coulomb and Stribeck friction. Over 25 speed sets
    the error has mean +0.025 (X) / +0.015 (Y) (K_t identified 3 % / 1 % high) and std
    0.016 / 0.010, largest 0.056: tolerance 0.07."""
    a = machine.axes[ax]
    # without a TCP record the share comes from the friction runs alone
    sweep = dataclasses.replace(virtual_sweep(a, name=ax), tcp_m=None)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        idn = identify_axis(ax, sweep, axis_config(machine, ax), friction=record(machine, ax))
    split = idn.friction_split
    e = split.estimate
    assert split.source == "data", e.reason
    fg, ft = true_forces(a, e.velocity, "static")
    truth = weighted_share(fg, ft, e.deflection_std, e.velocity)
    assert abs(split.guideway_share - truth) < 0.07
    assert idn.axis.friction.backlash == 0.0
    report = Identification({ax: idn}, builtin_machine()).to_dict()["axes"][ax]
    json.dumps(report)
    got = report["friction_split"]
    assert got["source"] == "data"
    assert got["guideway_share"]["value"] == pytest.approx(split.guideway_share)
    assert got["guideway_share"]["std"] == pytest.approx(e.guideway_share_std)
    assert got["backlash_m"]["value"] == 0.0
    assert len(got["estimate"]["plateaus"]) == e.velocity.size


@pytest.mark.parametrize("ax", ["X", "Y"])
def test_lost_motion_through_the_simulator(machine, ax):
    """5 um of free play in the nut. The accelerations give the lost motion (5.06-5.07 um;
    tolerance 0.5 um) and the plateaus the share with it. The guideway share differs
    between the Coulomb (0.64 / 0.75) and the viscous friction (0.81 / 0.85); the fitted
    one lies between them within 3 standard deviations (measured 0.58-0.61 +- 0.05 on X,
    0.72 +- 0.025 on Y)."""
    a = machine.axes[ax]
    rec = record(machine, ax, backlash=5e-6)
    for viscous in ("known", "fit"):
        fr, _, split = identify_friction(rec, axis_config(machine, ax), a.mechanics, axis=ax,
                                         viscous=viscous)
        e = split.estimate
        assert split.source == "data" and e.model != "share", e.reason
        assert abs(split.backlash - 5e-6) < 0.5e-6
        assert fr.backlash == split.backlash
        sd = split.guideway_share_std
        coulomb, viscous = (level_share(a.friction, k) for k in ("fc_pos", "fv_pos"))
        assert coulomb - 3 * sd < split.guideway_share < viscous + 3 * sd


def test_undetermined_split_falls_back_to_the_prior(machine):
    # round speeds advance whole sensor steps per sample: the rounding never averages out
    a = machine.axes["X"]
    rec = record(machine, "X", speeds=LOCKED_SPEEDS)
    with pytest.warns(InputWarning, match=r"axis X: .*prior guideway share 0\.7"):
        fr, _, split = identify_friction(rec, axis_config(machine, "X"), a.mechanics, axis="X")
    assert split.source == "prior" and split.guideway_share == GUIDEWAY_SHARE
    assert not split.estimate.determined
    assert fr.backlash == 0.0
    assert fr.guideway.fc_pos == pytest.approx(0.7 / 0.3 * fr.screw.fc_pos)
    assert split.to_dict()["guideway_share"]["std"] is None


def test_stiff_nut_through_the_pipeline_falls_back(machine):
    a = machine.axes["Y"]
    stiff = a.mechanics.model_copy(update={"K_t": 100 * a.mechanics.K_t})
    with pytest.warns(InputWarning, match="axis Y: .*do not resolve the nut") as caught:
        _, _, split = identify_friction(record(machine, "Y"), axis_config(machine, "Y"), stiff,
                                        axis="Y")
    assert split.source == "prior"
    # the estimate a share the plateaus cannot fix is not given: it may lie far outside 0-1
    sd = split.estimate.guideway_share_std
    said = " ".join(str(w.message) for w in caught)
    assert f"{split.estimate.guideway_share:.2f}" not in said, said
    assert "fix the guideway share only to" in said or not np.isfinite(sd), said


def test_given_share_overrides_the_data(machine):
    a = machine.axes["Y"]
    rec = record(machine, "Y", backlash=5e-6)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fr, _, split = identify_friction(rec, axis_config(machine, "Y"), a.mechanics,
                                         guideway_share=0.75)
    assert split.source == "given" and split.guideway_share == 0.75
    assert fr.guideway.fc_pos == pytest.approx(3 * fr.screw.fc_pos)
    # with the true share given, the lost motion is the rest of the hysteresis
    assert abs(split.backlash - 5e-6) < 0.15e-6


def test_friction_record_round_trip_keeps_the_split(machine, tmp_path):
    from tcpmm.io.bundle import read_friction_csv, write_friction_csv

    rec = record(machine, "X")
    write_friction_csv(rec, tmp_path / "friction.csv")
    back = read_friction_csv(tmp_path / "friction.csv")
    assert isinstance(back, FrictionRecord)
    cfg = axis_config(machine, "X")
    a = machine.axes["X"]
    s0 = identify_friction(rec, cfg, a.mechanics)[2].guideway_share
    s1 = identify_friction(back, cfg, a.mechanics)[2].guideway_share
    assert s1 == pytest.approx(s0, abs=0.01)
    t, x, f = friction_record_arrays(back, cfg.lead_m, cfg.torque_constant)
    assert t.size == x.size == f.size


@pytest.mark.parametrize("ax", ["X", "Y"])
def test_viscous_force_is_placed_where_the_runs_say(machine, ax):
    """The speed-proportional part of the nut deflection gives the viscous force through
    the nut (table damping plus viscous guideway friction); the rest of the measured
    slope goes to the motor side, and the total is kept."""
    from tcpmm.ident.friction import place_steady_viscous

    a = machine.axes[ax]
    m, f = a.mechanics, a.friction
    fr, est, split = identify_friction(record(machine, ax), axis_config(machine, ax), m, axis=ax)
    e = split.estimate
    table = m.C_t + f.guideway.fv_pos
    motor = (m.B_m + m.B_L) / m.R_L**2 + f.screw.fv_pos
    assert e.table_viscous == pytest.approx(table, abs=4 * e.table_viscous_std)
    assert e.table_viscous == pytest.approx(table, rel=0.2)
    total = est.values[est.names.index("Fv")]
    assert total == pytest.approx(table + motor, rel=0.05)
    mech, fr2 = place_steady_viscous(m, fr, total, e.table_viscous)
    assert mech.C_t == pytest.approx(e.table_viscous)
    assert (mech.B_m + mech.B_L) / m.R_L**2 + mech.C_t == pytest.approx(total)
    assert mech.B_m / mech.B_L == pytest.approx(m.B_m / m.B_L)
    assert fr2.guideway.fv_pos == fr2.screw.fv_neg == 0.0
    assert fr2.guideway.fc_pos == fr.guideway.fc_pos
    # a table share above the measured total is clipped to it
    mech, _ = place_steady_viscous(m, fr, total, 2 * total)
    assert mech.C_t == pytest.approx(total) and mech.B_m == mech.B_L == 0.0


@pytest.mark.parametrize("ax", ["X", "Y"])
def test_motor_bearing_damping_is_not_put_through_the_nut(machine, ax, identify_builtin):
    """Motor-bearing damping does not twist the shaft: a B_m 30 times too large moves the
    nut's share of the viscous force by K_t 29 B_m/K_L (measured 1105 / 1574 N s/m of
    1088 / 1547). The identification puts no viscous force through the motor bearings
    and the table damping comes out at 702 / 1638 N s/m of 750 / 1650."""
    a = machine.axes[ax]
    m, f = a.mechanics, a.friction
    table = m.C_t + f.guideway.fv_pos
    _, _, split = identify_friction(record(machine, ax), axis_config(machine, ax),
                                    m.replace(B_m=30 * m.B_m), axis=ax)
    shift = m.K_t * 29 * m.B_m / m.K_L
    assert split.estimate.table_viscous - table == pytest.approx(shift, rel=0.1)
    idn, _ = identify_builtin(ax)
    assert idn.axis.mechanics.B_m == 0.0
    assert idn.axis.mechanics.C_t == pytest.approx(table, rel=0.1)


def test_the_stribeck_hump_does_not_tilt_the_viscous_slope():
    """The speed-proportional deflection gives the table's viscous force once the
    plateau forces lose their viscous part. A line through those forces is tilted by the
    Stribeck hump at the slow plateaus (here 25 N up to 5 mm/s), and the table's viscous
    force comes out low by the share times the slope error: measured 0.938 of the truth,
    3.3 standard deviations. With the slope of a curve that models the hump: 0.995."""
    m = builtin_machine().axes["Y"].mechanics
    share, (fc, fs, vs, fv) = 0.4, (70.0, 95.0, 5e-3, 310.0)
    rec = deflection_record(m, share, 0.0, 2e-6, friction=(fc, fs, vs, fv))
    table = m.C_t + share * fv
    total = (m.B_m + m.B_L) / m.R_L**2 + m.C_t + fv
    line = estimate(m, rec, viscous="fit", offset="per_speed")
    curve = estimate(m, rec, viscous="fit", offset="per_speed", total_viscous=total)
    assert line.table_viscous < table - 2 * line.table_viscous_std
    assert curve.table_viscous == pytest.approx(table, abs=2 * curve.table_viscous_std)
    assert curve.table_viscous == pytest.approx(table, rel=0.02)
    assert curve.guideway_share == pytest.approx(share, abs=0.01)


def test_the_runs_give_the_table_viscous_force_of_an_unseen_axis(unseen):
    """Axis Y of machine 1 of ``studies/unseen_machines.py --seed 0 --backlash``, on its
    true mechanics: 4.4 um of play, guideway share 0.33, Stribeck velocities of 4.0 mm/s
    on the screw and 5.8 mm/s on the guideway. The table's viscous force (``C_t`` and the
    guideway's viscous friction), which sets when the nut crosses its play before a
    reversal, comes out at 0.988 of the truth; with a line through the plateau forces it
    was 0.863."""
    true, _ = unseen.draw_machine(0, 1, backlash=True)
    a = true.axes["Y"]
    m, g = a.mechanics, a.friction.guideway
    table = m.C_t + 0.5 * (g.fv_pos + g.fv_neg)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        _, _, split = identify_friction(virtual_friction(a, FRICTION_SPEEDS, name="Y"),
                                        axis_config(true, "Y"), m, axis="Y")
    assert split.source == "data" and split.nut is not None
    assert split.estimate.table_viscous == pytest.approx(table, rel=0.03)


def test_friction_runs_without_passes_name_file_axis_and_fix(machine):
    t = np.arange(4000) * 1e-3
    still = np.zeros_like(t)
    rec = FrictionRecord(t, 0.1 * np.sin(t), still, still, source="b/X/friction.csv", axis="X")
    with pytest.raises(InputError) as info:
        identify_friction(rec, axis_config(machine, "X"), machine.axes["X"].mechanics, axis="X")
    err = info.value
    assert err.file == "b/X/friction.csv" and err.column == "scale_mm"
    assert err.message.startswith("axis X: no constant-speed passes")
    assert "min_duration" not in err.message  # not an option of the command line


def test_bundle_with_bad_friction_runs_fails_before_any_fit(machine, monkeypatch):
    from types import SimpleNamespace

    from tcpmm.ident import chain

    def no_fit(*args, **kwargs):
        raise AssertionError("an axis was fitted before the friction runs were checked")

    monkeypatch.setattr(chain, "run_axis", no_fit)
    t = np.arange(4000) * 1e-3
    still = np.zeros_like(t)
    bad = FrictionRecord(t, 0.1 * np.sin(t), still, still, source="b/Y/friction.csv", axis="Y")
    bundle = SimpleNamespace(
        axes={"X": SimpleNamespace(sweep=None, friction=record(machine, "X")),
              "Y": SimpleNamespace(sweep=None, friction=bad)},
        machine=SimpleNamespace(axes={a: axis_config(machine, a) for a in ("X", "Y")}))
    with pytest.raises(InputError, match="axis Y: no constant-speed passes") as info:
        chain.identify_bundle(bundle)
    assert info.value.file == "b/Y/friction.csv"
