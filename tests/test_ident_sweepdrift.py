"""The travelling sweep's deflection between scale and TCP, from which the guideway share
is read, drifting over the record: a TCP device that drifts, or whose scale differs from
the linear scale's, moves its mean, and the sweep then says so and widens it."""

from __future__ import annotations

import dataclasses
import warnings
from pathlib import Path

import numpy as np
import pytest

from tcpmm.errors import InputWarning
from tcpmm.ident.friction.sweepforce import (
    N_BLOCKS,
    deflection_drift,
    sweep_deflection,
    travel_velocity,
)
from tcpmm.io.bundle import read_bundle

DATA = Path(__file__).resolve().parents[2] / "shared" / "data"
BENCHES = ("c", "d", "e", "h", "r05", "r17")


def test_blocks_that_trend_drift_by_the_change_and_level_ones_do_not():
    rng = np.random.default_rng(0)
    level = 3e-6 + rng.normal(0.0, 0.02e-6, N_BLOCKS)
    assert deflection_drift(level) == (0.0, pytest.approx(level.std(ddof=1)))
    ramp = level + np.linspace(0.0, 5e-6, N_BLOCKS)
    change, scatter = deflection_drift(ramp)
    assert change == pytest.approx(5e-6 * N_BLOCKS / (N_BLOCKS - 1), rel=0.02)
    assert scatter < 0.05e-6
    # a trend within the scatter, or under half a micrometre, is none
    assert deflection_drift(level + np.linspace(0.0, 0.4e-6, N_BLOCKS))[0] == 0.0
    noisy = 3e-6 + rng.normal(0.0, 2e-6, N_BLOCKS) + np.linspace(0.0, 1e-6, N_BLOCKS)
    assert deflection_drift(noisy)[0] == 0.0


@pytest.mark.skipif(not DATA.is_dir(), reason="the shared data sets are not beside the project")
@pytest.mark.parametrize("bench", BENCHES)
def test_the_benches_sweeps_do_not_drift_and_a_drift_added_widens_the_mean(bench):
    """The independent simulator's sweeps, TCP and scale on one datum, hold their
    deflection level: no drift, the mean as before. The same sweep with the TCP drifting
    by 5 um over the record is said to drift by that, with a warning, and its mean is
    uncertain by at least half of it; where friction held the sweep (R05, R17: its blocks'
    means scatter by 1-3 um) a drift of 5 um may be within the scatter, and none is said.
    """
    bundle = read_bundle(DATA / f"bench_{bench}" / "bundle")
    for name, axis in bundle.axes.items():
        sweep = axis.sweep
        v = travel_velocity(sweep, 1e-3)
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            plain = sweep_deflection(sweep, v)
        assert plain.drift == 0.0, (bench, name)
        t = np.asarray(sweep.time_s, float)
        ramp = 5e-6 * (t - t[0]) / (t[-1] - t[0])
        drifting = dataclasses.replace(sweep, tcp_m=np.asarray(sweep.tcp_m) - ramp)
        with warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always")
            got = sweep_deflection(drifting, v)
        if got.drift == 0.0 and bench in ("r05", "r17"):
            assert not said
            continue
        assert [w.category for w in said] == [InputWarning]
        assert "drifts by" in str(said[0].message)
        assert got.drift == pytest.approx(5e-6, rel=0.15)
        assert got.deflection_std >= 2.4e-6 > 2 * plain.deflection_std
