"""A deflection between encoder and scale drifting with time over the friction runs is
read from the plateaus' slopes, told, and taken off before the split of the friction
(:mod:`tcpmm.ident.friction.recorddrift`)."""

import dataclasses
import re
import warnings

import numpy as np
import pytest

from conftest import bench_path
from tcpmm.ident.friction.plateaus import Plateau
from tcpmm.ident.friction.recorddrift import DRIFT_Z, deflection_drift, record_drift
from tcpmm.ident.friction.steadycurve import stribeck_from_record
from tcpmm.ident.pipeline import identify_bundle
from tcpmm.io.bundle import read_bundle
from tcpmm.io.truthfile import machine_from_truth

R_L = 0.01 / (2 * np.pi)


def _runs(rate_m_per_s: float, lead_error_m_per_m: float, seed: int = 0):
    """Plateaus at six speeds, each run out over 2 s and back over the same stretch, as
    the reference bundles' friction runs are; the deflection carries a drift with time,
    an offset growing along the travel (a lead error) and a 50 nm scale's rounding."""
    rng = np.random.default_rng(seed)
    t_parts, x_parts, plateaus, t0, n0 = [], [], [], 0.0, 0
    for v in (0.5e-3, 2e-3, 5e-3, 15e-3, 40e-3, 100e-3):
        for sgn in (1.0, -1.0):
            t = t0 + np.arange(2000) * 1e-3
            x = (0.0 if sgn > 0 else v * 2.0) + sgn * v * (t - t0)
            t_parts.append(t), x_parts.append(x)
            plateaus.append(Plateau(n0 + 200, n0 + 1800, sgn * v, 0.0, 0.0))
            t0, n0 = t[-1] + 0.3, n0 + t.size
    t, x = np.concatenate(t_parts), np.concatenate(x_parts)
    d = rate_m_per_s * t + lead_error_m_per_m * x + rng.normal(0.0, 2e-8, t.size)
    scale = np.round(x / 5e-8) * 5e-8
    return t, (scale + d) / R_L, scale, plateaus


@pytest.mark.parametrize("lead_error", [0.0, 2e-5])
def test_a_drift_is_read_apart_from_a_deflection_along_the_travel(lead_error):
    """0.1 um/s found within its deviation, beside an offset of 20 um/m along the travel
    (which slopes each plateau by 0.01-2 um/s, one way out and the other back); without
    drift none is found."""
    t, th, xs, plateaus = _runs(1e-7, lead_error)
    got = deflection_drift(t, th, xs, R_L, plateaus, 5e-8)
    assert got.found and got.pairs == 6
    assert abs(got.rate - 1e-7) < 3 * got.rate_std < 1e-8, got
    t, th, xs, plateaus = _runs(0.0, lead_error)
    got = deflection_drift(t, th, xs, R_L, plateaus, 5e-8)
    assert not got.found and abs(got.rate) < DRIFT_Z * got.rate_std, got


@pytest.mark.parametrize("letter", ["c", "d", "e", "h", "r05", "r17"])
def test_no_reference_machine_drifts(letter):
    """The independent simulator's friction runs have no drift: none is found or taken off
    on any axis."""
    b = read_bundle(bench_path(letter) / "bundle")
    for name, rec in b.axes.items():
        cfg = b.machine.axes[name]
        *_, plateaus = stribeck_from_record(rec.friction, cfg, name)
        got = record_drift(rec.friction, cfg, plateaus)
        assert got.pairs >= 6 and not got.found, (letter, name, got)


def _drifting(bundle, scale_um: float, tcp_um: float, tau_s: float | None):
    """Machine D's X alone, its friction runs' scale drifting by ``scale_um`` over the
    record (rounded to the scale's 0.05 um), evenly or as a warming of time constant
    ``tau_s``, and its sweep's TCP by ``tcp_um``."""
    x = bundle.axes["X"]
    fr, sw = x.friction, x.sweep
    tf = (fr.time_s - fr.time_s[0]) / (fr.time_s[-1] - fr.time_s[0])
    if tau_s is not None:
        span = fr.time_s[-1] - fr.time_s[0]
        tf = (1.0 - np.exp(-tf * span / tau_s)) / (1.0 - np.exp(-span / tau_s))
    scale = np.round((fr.scale_m + scale_um * 1e-6 * tf) / 5e-8) * 5e-8
    ts = (sw.time_s - sw.time_s[0]) / (sw.time_s[-1] - sw.time_s[0])
    x = dataclasses.replace(x, friction=dataclasses.replace(fr, scale_m=scale),
                            sweep=dataclasses.replace(sw, tcp_m=sw.tcp_m + tcp_um * 1e-6 * ts))
    return dataclasses.replace(bundle, axes={"X": x})


@pytest.mark.filterwarnings("ignore::tcpmm.errors.InputWarning")
@pytest.mark.parametrize("tau_s", [None, 8.0])
def test_a_drifting_scale_and_tcp_device_leave_the_share_where_it_is(tau_s):
    """The scale drifting by 3 um over machine D's friction runs and the TCP device by 5
    um over its sweep: the runs' step between the directions, 0.3 um of drift, was read as
    a guideway share of 0.83 +- 0.02 for 0.55; as a warming that slows (time constant 8
    s), 0.75 +- 0.07. Told once, naming the file and column, and taken off: the share lies
    within three of its deviations of the truth, with no lost motion, as without the
    drifts."""
    b = _drifting(read_bundle(bench_path("d") / "bundle"), 3.0, 5.0, tau_s)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        split = identify_bundle(b, verdict=False).axes["X"].friction_split
    said = [str(w.message) for w in caught if "drifts by" in str(w.message)
            and "friction runs" in str(w.message)]
    assert len(said) == 1 and "friction.csv" in said[0] and "scale_mm" in said[0], said
    # the deflection, encoder minus scale, falls by the drift
    drift_um = float(re.search(r"drifts by ([-+0-9.]+) um", said[0]).group(1))
    assert abs(drift_um + 3.0) < 0.2, said[0]
    t = machine_from_truth(bench_path("d") / "truth.yaml").axes["X"].friction
    true = t.guideway.fc_pos / (t.guideway.fc_pos + t.screw.fc_pos)
    assert abs(split.guideway_share - true) < 3 * split.guideway_share_std, (
        split.guideway_share, split.guideway_share_std, true)
    assert split.backlash == 0.0
