"""A TCP device zeroed to the linear scale only to within a step of each: the guideway
share read from the travelling sweep's mean deflection between the two carries that.

Bench C's Y axis has a 1 um scale and a 15 N/um column, and its friction runs do not
determine the share: the share came from the sweep alone, 0.756 +- 0.004 with the TCP
device zeroed one scale step off (0.649 zeroed right), and the F10000 spike A read
"-10.20 um, firm (+- 0.72 um)" where the machine made +9.79 um."""

import math
import shutil
import warnings

import numpy as np
import pandas as pd
import pytest

from conftest import bench_path
from tcpmm.ident.chain import identify_bundle
from tcpmm.ident.friction.sweepforce import sweep_deflection
from tcpmm.ident.steps.fitcontext import zero_std_of
from tcpmm.io.bundle import read_bundle


def test_the_zero_is_known_to_a_step_of_each_sensor():
    assert zero_std_of(1e-6, 0.078e-6) == pytest.approx(math.hypot(1e-6, 0.078e-6))
    assert zero_std_of(0.05e-6, None) == pytest.approx(0.05e-6)


def test_the_deflection_carries_the_zero():
    """A sweep travelling 10 mm/s for 15 s at 1 kHz with a steady deflection of 3 um and
    0.1 um of noise: its mean's deviation is the noise's over the record without the
    zero's, and the zero's in quadrature with it."""
    t = np.arange(15000) / 1000.0
    scale = 0.01 * t
    rng = np.random.default_rng(0)
    tcp = scale - 3e-6 + 0.1e-6 * rng.standard_normal(t.size)
    sweep = type("S", (), {"time_s": t, "scale_m": scale, "tcp_m": tcp, "source": None,
                           "axis": "Y"})()
    bare = sweep_deflection(sweep, 0.01)
    zeroed = sweep_deflection(sweep, 0.01, zero_std=1e-6)
    assert bare.deflection == pytest.approx(3e-6, abs=0.01e-6)
    assert bare.deflection_std < 0.01e-6
    assert zeroed.deflection_std == pytest.approx(math.hypot(bare.deflection_std, 1e-6))


@pytest.fixture(scope="module")
def zeroed_a_step_off(tmp_path_factory):
    """Bench C with Y's TCP device zeroed one scale step (1 um) off, identified."""
    bundle = tmp_path_factory.mktemp("tcpoff") / "bundle"
    shutil.copytree(bench_path("c") / "bundle", bundle)
    p = bundle / "Y" / "sweep.csv"
    s = pd.read_csv(p)
    s["tcp_mm"] -= 0.001
    s.to_csv(p, index=False)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return identify_bundle(read_bundle(bundle))


def test_a_share_read_through_a_zero_a_step_off_is_not_firm(zeroed_a_step_off):
    """The share's deviation holds the zero's: a step of the 1 um scale on the 15 N/um
    column is some 0.15 of the share; and no figure of the circles is firm and off by
    more than its target."""
    idn = zeroed_a_step_off
    split = idn.axes["Y"].friction_split
    assert split.source == "sweep" and split.guideway_share_std > 0.1
    spikes = [f for f in idn.verdict.figures if "F10000" in f.test and "spike A" in f.figure]
    assert spikes and all(f.verdict != "firm" for f in spikes), spikes
