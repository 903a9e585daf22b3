"""The guideway share from the TCP structure's mean deflection in a travelling sweep."""

import dataclasses
import math
import warnings

import numpy as np
import pytest

from tcpmm.ident.friction import (
    SweepDeflection,
    share_from_sweep,
    sweep_deflection,
    table_viscous_estimate,
    travel_velocity,
)
from tcpmm.ident.pipeline import identify_axis
from tcpmm.machines.builtin import builtin_machine
from tcpmm.machines.virtual import FRICTION_SPEEDS, axis_config, virtual_friction, virtual_sweep


def deflection_of(mech, share, level, table_viscous, v):
    """Mean scale-minus-TCP of a steady travel at ``v`` (the statics of the five masses with
    the guideway's reaction on the bed) [m]."""
    F_g = math.copysign(share * level, v) + (table_viscous - mech.C_t) * v
    nut = F_g + mech.C_t * v - mech.load_force
    X_h = nut / mech.K_h
    X_b = (-nut + F_g) / mech.K_b
    return X_h - X_b


@pytest.mark.parametrize("v", [0.01, -0.02])
@pytest.mark.parametrize("load", [0.0, -800.0])
def test_share_from_a_known_deflection(v, load):
    mech = builtin_machine().axes["X"].mechanics.replace(load_force=load)
    d = deflection_of(mech, 0.4, 150.0, 900.0, v)
    share, std = share_from_sweep(SweepDeflection(v, d, 1e-9), mech, 150.0, 900.0)
    assert share == pytest.approx(0.4, abs=1e-12)
    assert std == pytest.approx(mech.K_h * 1e-9 / 150.0)
    # a wrong K_h is a proportional error of the force through the nut, and is counted
    _, std_kh = share_from_sweep(SweepDeflection(v, d, 1e-9), mech, 150.0, 900.0,
                                 K_h_rel_std=0.05)
    assert std_kh > 0.05 * (0.4 * 150.0) / 150.0


def test_a_share_far_outside_its_range_is_not_taken():
    mech = builtin_machine().axes["X"].mechanics
    d = deflection_of(mech, 1.6, 150.0, 900.0, 0.01)
    assert share_from_sweep(SweepDeflection(0.01, d, 1e-9), mech, 150.0, 900.0) is None
    d = deflection_of(mech, 1.0, 150.0, 900.0, 0.01) + 1e-9  # within the std of 1
    assert share_from_sweep(SweepDeflection(0.01, d, 2e-9), mech, 150.0, 900.0)[0] == 1.0


def test_a_share_the_sweep_leaves_wider_than_its_range_is_not_taken():
    """A sweep cut short leaves K_h a guess: bench C's X cut to 40 % gave a share of
    0.914 +- 8217, taken as the sweep's, and a table damping from the plateaus of
    -4e8 N s/m. A share whose interval of one deviation is wider than [0, 1] says
    nothing; the friction runs or the prior decide instead."""
    mech = builtin_machine().axes["X"].mechanics
    d = deflection_of(mech, 0.5, 150.0, 900.0, 0.01)
    got = share_from_sweep(SweepDeflection(0.01, d, 1e-9), mech, 150.0, 900.0,
                           K_h_rel_std=0.5)
    assert got is not None and got[1] < 0.5
    assert share_from_sweep(SweepDeflection(0.01, d, 1e-9), mech, 150.0, 900.0,
                            K_h_rel_std=1e3) is None
    noisy = 0.6 * 150.0 / mech.K_h  # a deflection's deviation that alone gives 0.6 [m]
    assert share_from_sweep(SweepDeflection(0.01, d, noisy), mech, 150.0, 900.0) is None


def test_only_a_sweep_that_travels_one_way_with_a_tcp_record_is_used():
    a = builtin_machine().axes["X"]
    sweep = virtual_sweep(a, name="X")
    v = travel_velocity(sweep, 1e-3)
    got = sweep_deflection(sweep, v)
    assert got is not None and got.velocity > 0 and got.deflection_std > 0
    assert sweep_deflection(dataclasses.replace(sweep, tcp_m=None), v) is None
    assert travel_velocity(sweep, 1e3) == 0.0  # travels less than asked
    assert sweep_deflection(sweep, travel_velocity(sweep, 1e3)) is None
    x = sweep.scale_m
    h = x.size // 2
    back = np.concatenate([x[:h], x[h - 1::-1][: x.size - h]])  # out and back again
    assert sweep_deflection(dataclasses.replace(sweep, scale_m=back), v) is None


def test_identified_share_of_an_axis_whose_guide_reacts_on_the_bed():
    """The built-in X with its guideway friction on the table-minus-bed velocity (as the
    model identify writes has it) and a 0.05 um scale: the share from the sweep is within
    three of its standard deviations of the true share of the Coulomb level, its deviation
    under 0.08, most of it the datum between scale and TCP, known to a step of each (0.09
    um on a 40 N/um column: 0.05). With the built-in 1 um scale the plateaus' share is
    the tighter, and identify takes it."""
    m = builtin_machine()
    a = m.axes["X"]
    a = a.model_copy(update={"friction": a.friction.model_copy(
        update={"guideway_velocity": "relative"}), "sensors": a.sensors.model_copy(
        update={"scale_resolution": 0.05e-6})})
    m = m.model_copy(update={"axes": {**m.axes, "X": a}})
    rec = virtual_friction(a, FRICTION_SPEEDS, name="X")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        idn = identify_axis("X", virtual_sweep(a, name="X"), axis_config(m, "X"), friction=rec)
    split = idn.friction_split
    g, s = a.friction.guideway, a.friction.screw
    true = g.fc_pos / (g.fc_pos + s.fc_pos)
    assert split.source == "sweep"
    assert split.guideway_share_std < 0.08
    assert abs(split.guideway_share - true) < 3 * split.guideway_share_std, (
        split.guideway_share, true)
    # the table damping the share rests on is the weighed one, and its deviation goes
    # into the model's uncertainty
    phys = idn.physical
    fv = dict(zip(idn.friction.names, idn.friction.values, strict=True))["Fv"]
    tv, tv_sd = table_viscous_estimate(split.estimate, phys.mechanics, fv, phys.std["C_t"])
    assert (split.table_viscous, split.table_viscous_std) == pytest.approx((tv, tv_sd))
    assert tv_sd != pytest.approx(split.estimate.table_viscous_std)
    assert idn.axis.uncertainty.mechanics["C_t"] == pytest.approx(tv_sd)


def plateaus(value, std):
    """A stand-in for the plateaus' estimate: its table damping and standard deviation."""
    return dataclasses.make_dataclass("LM", ["table_viscous", "table_viscous_std"])(value, std)


def test_the_table_damping_weighs_plateaus_and_frfs_by_their_variances():
    mech = builtin_machine().axes["X"].mechanics.replace(C_t=1000.0)
    # 1/100 and 1/400 of the weight: (1200/100 + 1000/400) / (1/100 + 1/400) = 1160
    tv, sd = table_viscous_estimate(plateaus(1200.0, 10.0), mech, 5000.0, 20.0)
    assert tv == pytest.approx(1160.0)
    # 8.9 standard deviations apart: the spread widens the deviation by that ratio
    assert sd == pytest.approx(math.sqrt(1 / (1 / 100 + 1 / 400)) * 200 / math.sqrt(500))
    agree = table_viscous_estimate(plateaus(1005.0, 10.0), mech, 5000.0, 20.0)
    assert agree[1] == pytest.approx(math.sqrt(1 / (1 / 100 + 1 / 400)))


@pytest.mark.parametrize("lm_std, frf_std, expected", [
    (float("nan"), 20.0, 1000.0),  # the plateaus do not tell
    (0.0, 20.0, 1000.0),
    (10.0, 0.0, 1200.0),  # the FRFs' deviation is unknown
    (10.0, float("nan"), 1200.0),
    (100.0, 600.0, 1200.0),  # the FRFs do not determine C_t (60 %)
])
def test_a_measure_without_a_deviation_does_not_count(lm_std, frf_std, expected):
    mech = builtin_machine().axes["X"].mechanics.replace(C_t=1000.0)
    tv, _ = table_viscous_estimate(plateaus(1200.0, lm_std), mech, 5000.0, frf_std)
    assert tv == pytest.approx(expected)


def test_the_table_damping_stays_within_the_steady_slope():
    mech = builtin_machine().axes["X"].mechanics.replace(C_t=1000.0)
    assert table_viscous_estimate(plateaus(-300.0, 10.0), mech, 5000.0, 0.0)[0] == 0.0
    assert table_viscous_estimate(plateaus(1200.0, 10.0), mech, 900.0, 20.0)[0] == 900.0
    # neither measure: the FRFs' C_t within the slope less the screw side's damping
    room = 5000.0 - (mech.B_m + mech.B_L) / mech.R_L**2
    tv, _ = table_viscous_estimate(plateaus(float("nan"), float("nan")), mech, 5000.0, 0.0)
    assert tv == pytest.approx(min(1000.0, max(room, 0.0)))

