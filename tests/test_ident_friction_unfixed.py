"""Friction runs that leave part of the friction open: without slow plateaus the runs fix
no static level, and identify holds it at the Coulomb level and names it open, where a fit
extrapolated 1e14 N of static friction and identify stopped on it."""

import shutil
import warnings

import pandas as pd
import pytest

from conftest import bench_path
from tcpmm.errors import InputWarning
from tcpmm.ident.chain import identify_bundle
from tcpmm.ident.friction.hump import HELD_STRIBECK_SPEED
from tcpmm.io.bundle import read_bundle
from tcpmm.uncertainty.frictionranges import STATIC_RANGE

#: Time from which bench R05's and C's friction runs hold their 5 mm/s plateaus and faster [s].
FROM_5_MM_S = 9.7


def _runs_from(bundle, axes, start_s):
    """``bundle``'s friction runs of ``axes`` kept from ``start_s`` on, time from zero."""
    for ax in axes:
        p = bundle / ax / "friction.csv"
        f = pd.read_csv(p)
        f = f[f.time_s >= start_s].copy()
        f["time_s"] = (f.time_s - f.time_s.iloc[0]).round(4)
        f.to_csv(p, index=False)


def _x_from_5_mm_s(folder, bench: str):
    """Bench ``bench`` with X's friction runs kept from their 5 mm/s plateaus up,
    identified, and the warnings said [-]."""
    bundle = folder / "bundle"
    shutil.copytree(bench_path(bench) / "bundle", bundle)
    _runs_from(bundle, ("X",), FROM_5_MM_S)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        found = identify_bundle(read_bundle(bundle))
    return found, [str(w.message) for w in caught if issubclass(w.category, InputWarning)]


@pytest.fixture(scope="module")
def r05_x_from_5_mm_s(tmp_path_factory):
    """Bench R05 with X's friction runs kept from 5 mm/s up, identified, with the
    warnings said."""
    return _x_from_5_mm_s(tmp_path_factory.mktemp("r05"), "r05")


def test_a_static_level_the_runs_do_not_fix_is_held_and_open(r05_x_from_5_mm_s):
    """The fit to the whole record puts its Stribeck speed below the slowest speed it reads
    (0.02 against 0.1 mm/s): the static level is held at the Coulomb level, named open over
    :data:`STATIC_RANGE`, said once with what settles it, and no figure the axis moves is
    firm."""
    found, said = r05_x_from_5_mm_s
    x = found.machine.axis("X")
    for c in (x.friction.guideway, x.friction.screw):
        assert (c.fs_pos, c.fs_neg) == (c.fc_pos, c.fc_neg)
        assert c.vs == HELD_STRIBECK_SPEED
    [held] = [r for r in x.uncertainty.open if r.quantity == "static_level"]
    assert (held.low, held.high) == STATIC_RANGE and "below the slowest speed" in held.cause
    assert "plateaus at low speed" in held.settle
    told = [s for s in said if "axis X: the friction runs do not determine a static level" in s]
    assert len(told) == 1 and "plateaus slower than the Stribeck speed" in told[0]
    assert found.verdict.figures and all(f.verdict != "firm" for f in found.verdict.figures)


def test_a_hump_below_the_slowest_speed_read_is_held():
    """The fit of bench R05's X from 5 mm/s up: static levels within 45 % of their excess,
    but at a Stribeck speed below the 0.1 mm/s the fit reads as moving."""
    import numpy as np

    from tcpmm.ident.friction.estimate import ParameterEstimate
    from tcpmm.ident.friction.hump import without_undetermined_hump

    est = ParameterEstimate(names=("Fc+", "Fc-", "Fs+", "Fs-", "vs", "Fv"),
                            values=np.array([262.4, 262.1, 1.27e14, 8.8e13, 2e-5, 2376.0]),
                            std=np.array([2.2, 2.1, 5.3e13, 4.3e13, 8e-6, 37.0]),
                            relative_error=1.0, residual_std=1.0, condition=1.0,
                            n_samples=12, extra={"v_min": 1e-4})
    assert without_undetermined_hump(est)[1] == ""  # the speeds read not known
    kept, why = without_undetermined_hump(est, slowest=1e-4)
    assert kept["Fs+"] == kept["Fc+"] and kept["Fs-"] == kept["Fc-"]
    assert kept["vs"] == HELD_STRIBECK_SPEED and kept["Fv"] == 2376.0
    assert "below the slowest speed the fit reads, 0.1 mm/s" in why
    assert kept.extra["static_held"] in why and kept.extra["v_min"] == 1e-4


@pytest.fixture(scope="module")
def c_x_from_5_mm_s(tmp_path_factory):
    """Bench C with X's friction runs kept from 5 mm/s up, identified, with the warnings
    said."""
    return _x_from_5_mm_s(tmp_path_factory.mktemp("c"), "c")


def test_a_lost_motion_the_runs_cannot_bound_is_open(c_x_from_5_mm_s):
    """Without slow plateaus the whole record gives X's lost motion a deviation of 15 mm:
    the runs find none but cannot bound one, far beyond any screw-nut's, and the model takes
    the lost motion open over its whole range, where it said a nut could hide 46 mm."""
    from tcpmm.model import BACKLASH_MAX_M

    found, said = c_x_from_5_mm_s
    a = found.axes["X"]
    assert a.friction_split.lost_motion_unbounded and a.lost_motion_sensitivity is None
    assert not [s for s in said if "axis X:" in s and "would not find one of up to" in s]
    [told] = [s for s in said if "axis X:" in s and "cannot bound one" in s]
    assert "plateaus at low speed" in told
    x = found.machine.axis("X")
    [play] = [r for r in x.uncertainty.open if r.quantity == "backlash"]
    assert (play.low, play.high) == (0.0, BACKLASH_MAX_M) and x.friction.backlash == 0.0
    assert x.uncertainty.backlash == 0.0
    blamed = [f for f in found.verdict.figures if f.cause == "axis X backlash, open"]
    assert blamed and all(f.verdict != "firm" for f in blamed)


def test_a_sweep_share_on_an_unfixed_level_names_the_level_once(tmp_path):
    """Bench C's runs kept to their 0.5, 2 and 5 mm/s plateaus leave the Coulomb level to
    trade with the viscous slope (0.9 +- 13 N): the travelling sweep's deflection, divided
    by it, read a share of a million, and identify asked whether the TCP device was zeroed
    to the scale, once per refit of the mechanics. It names the level, once per axis."""
    bundle = tmp_path / "bundle"
    shutil.copytree(bench_path("c") / "bundle", bundle)
    for ax in ("X", "Y"):
        p = bundle / ax / "friction.csv"
        f = pd.read_csv(p)
        f[f.time_s < 14.4].to_csv(p, index=False)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        identify_bundle(read_bundle(bundle), verdict=False)
    said = [str(w.message) for w in caught if "travelling sweep's deflection" in str(w.message)]
    for ax in ("X", "Y"):
        [told] = [s for s in said if f"axis {ax}:" in s]
        assert "do not fix the friction level" in told and "Coulomb levels" in told
        assert "zeroed" not in told and "wider range of speeds" in told
