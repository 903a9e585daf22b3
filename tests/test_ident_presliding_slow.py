"""Pre-sliding from friction runs without slow plateaus: the reversals from 5 mm/s up are
braked into, and the inertia and the servo shape them. Bench D's runs cut to start at
5 mm/s gave X's distance 2.14 +- 0.27 um (3.71 +- 0.16 um from the whole runs), and the
F5000 spikes A and C read firm (+- 0.53 um) where they were 1.5 um off."""

import shutil
import warnings

import numpy as np
import pandas as pd
import pytest

from conftest import bench_path
from tcpmm.ident.chain import identify_bundle
from tcpmm.ident.friction.preslidingfit import SLOW_REVERSAL_SPEED, _plateau_speeds
from tcpmm.io.bundle import read_bundle


def test_a_plateau_speed_is_the_fastest_since_the_last_reversal():
    v = np.array([0.0, 0.5, 0.5, 0.1, -0.1, -2.0, -2.0, -0.2, 0.3, 0.3])
    assert _plateau_speeds(v, [(3, 4), (7, 8)]) == pytest.approx([0.5, 2.0])


def test_a_reversal_before_the_last_one_travelled_back_has_no_plateau():
    """Two reversals whose windows overlap (the axis turned again before it had travelled
    back past the last one's window) have no plateau between them: the second counts as
    no slow reversal, where the empty span between them stopped identify of one machine
    in eight of a drawn population with "zero-size array to reduction operation"."""
    v = np.array([0.0, 0.5, 0.5, 0.1, -0.1, -0.05, 0.05, 0.3, 0.3, 0.3])
    speeds = _plateau_speeds(v, [(3, 6), (5, 8)])
    assert speeds[0] == pytest.approx(0.5) and speeds[1] == np.inf


@pytest.fixture(scope="module")
def from_5_mm_s(tmp_path_factory):
    """Bench D with each axis's friction runs kept from its 5 mm/s plateaus up."""
    bundle = tmp_path_factory.mktemp("fast") / "bundle"
    shutil.copytree(bench_path("d") / "bundle", bundle)
    for ax in ("X", "Y"):
        p = bundle / ax / "friction.csv"
        f = pd.read_csv(p)
        f = f[f.time_s >= 9.7].copy()
        f["time_s"] = (f.time_s - f.time_s.iloc[0]).round(4)
        f.to_csv(p, index=False)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return identify_bundle(read_bundle(bundle))


def test_reversals_from_fast_plateaus_alone_leave_the_distance_open(from_5_mm_s):
    """No reversal turns round from 2.5 mm/s or slower: the distance is not determined,
    the prior is kept and named open, and no F5000 spike is firm."""
    fit = from_5_mm_s.axes["X"].presliding_fit
    assert not fit.determined
    assert f"turn round from {SLOW_REVERSAL_SPEED * 1e3:g} mm/s or slower" in fit.reason
    open_ = [r.quantity for r in from_5_mm_s.machine.axis("X").uncertainty.open]
    assert "presliding" in open_
    spikes = [f for f in from_5_mm_s.verdict.figures
              if "F5000" in f.test and "spike" in f.figure]
    assert spikes and all(f.verdict != "firm" for f in spikes)
