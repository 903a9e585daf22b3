"""The part of a reversal's transient that lasts past the window the circle fit leaves out
(tcpmm.analysis.circle_reversal_tail), on the suite's circles (tests/test_circle_diagnostics.py:
every error as the position error it is) with a decaying tail after every quadrant point
added. A slow position loop pulls an axis back after its reversal with its own time
constant: 1/K_v of 60 ms is 8 deg of travel at F5000 on R 35 mm and 16 deg at F10000. Such
tails read as backlash, scale mismatch and a cyclic error before the fit modelled them: 2
um of backlash X read 2.3-3.5 um, 20 ppm of scale mismatch 28 ppm."""

import re

import numpy as np
import pytest

import test_circle_diagnostics as gen
from tcpmm.analysis.circle_tail_terms import NONE_WHY
from tcpmm.analysis.circle_tails import moving_terms
from tcpmm.analysis.diagnostics import diagnose_pair

#: every error of a ballbar test but the cyclic ones and the spikes, whose tails these are
BASE = {"b_x": 2e-6, "b_y": -1.5e-6, "tau_y": 0.5e-3, "eps_x": 20e-6, "alpha": 10e-6,
        "p_x": 1e-6, "str_y": 1.5e-6, "cx": 4e-6}
#: the errors under a tail as long as the half turn: the backlash and play alone
LONG = {**BASE, "eps_x": 0.0, "alpha": 0.0, "str_y": 0.0}
#: each reversal's own tail, as a share of the largest (gravity, friction unlike at the ends)
SHARES = (1.0, 0.3, -0.5, 0.8)


def tailed(direction, err, height, decay_deg, shape, seed, shares=SHARES):
    """A circle of the suite with a tail after every quadrant point: ``height`` times the
    reversal's share of ``shares`` (CCW's, :data:`SHARES`) at the point, decaying over
    ``decay_deg`` along the travel until the axis reverses again; ``shape`` "axis": the
    reversing axis' position error, seen along the radius as the angle turns from it, or
    "radial" [m, deg]."""
    a, e = gen.circle(direction, err, seed)
    s = 1.0 if direction == "ccw" else -1.0
    shares = shares if direction == "ccw" else shares[::-1]
    for (_, at), share in zip(gen.SPIKE_AT.items(), shares, strict=True):
        since = (s * (np.degrees(a) - at)) % 360.0
        seen = np.cos(np.radians(since)) if shape == "axis" else 1.0
        e = e + np.where(since < 180.0, share * height * np.exp(-since / decay_deg) * seen, 0.0)
    return a, e


def pair(height, decay_deg, shape, err=BASE, shares=SHARES):
    return diagnose_pair(tailed("ccw", err, height, decay_deg, shape, 1, shares),
                         tailed("cw", err, height, decay_deg, shape, 2, shares), gen.R,
                         (gen.W, gen.W))


@pytest.mark.parametrize(("decay_deg", "shape"), [(8.0, "axis"), (16.0, "axis"),
                                                  (10.0, "radial"), (20.0, "radial")])
def test_the_terms_are_recovered_under_a_tail_past_the_window(decay_deg, shape):
    """Tails of 3 um at the quadrant point, each reversal its own, 0.1-1 um left at the
    window's end: every term within 2 % or 0.1 um of radial error, as without them; the
    tails' time constant within 10 %, from the circles' speed, and the largest tail at the
    window's end within 0.1 um."""
    d = pair(3e-6, decay_deg, shape)
    gen.assert_recovered(d, {k: v for k, v in gen.expected(BASE).items()
                             if not k.startswith(("spike_", "cyclic_", "radial_deviation"))})
    assert d["reversal_tail_decay"] == pytest.approx(np.radians(decay_deg) / gen.W, rel=0.1)
    seen = np.cos(np.radians(20.0)) if shape == "axis" else 1.0
    assert abs(d["reversal_tail_X"]) == pytest.approx(
        3e-6 * np.exp(-20.0 / decay_deg) * seen, abs=0.1e-6)


def test_a_tail_as_long_as_the_half_turn_is_said_to_move_the_terms():
    """A radial tail of 10 um over 40 deg, alike at every reversal, is nearly a step to
    the next reversal, which is a backlash: the samples fit it as well as an axis' tail
    over 31 deg, with a backlash 2.6 um apart. The terms it moves are said to move by at
    least nine tenths of how far they are off."""
    d = pair(10e-6, 40.0, "radial", LONG, (1.0,) * 4)
    moving = moving_terms(d)
    offs = {t: abs(d[t] - BASE["b_" + t[-1].lower()]) for t in ("backlash_X", "backlash_Y")}
    assert max(offs.values()) > 1e-6  # the case is the one that cannot be told apart
    for term, off in offs.items():
        if off > 0.1e-6:
            now, other = moving[term]
            assert abs(other - now) >= 0.9 * off, term


@pytest.mark.parametrize("seed", range(3))
@pytest.mark.parametrize("n", [gen.N, 1320], ids=["F1800", "F10000"])
def test_circles_without_a_tail_fit_none(seed, n):
    """Every error at once with a 1 ms servo mismatch, drawn at random, and no transient
    past the window: no tail is fitted, and the diagnostics say why they read none (what
    the terms do not model there, reversals placed between samples and cyclic errors,
    is no reversal's tail: the same columns turned away from the reversals take as
    much of it)."""
    err = gen.draw(np.random.default_rng(seed))
    err["tau_y"] = np.sign(err["tau_y"]) * 1e-3
    d = gen.diagnose(err, n=n)
    for term in ("reversal_tail_X", "reversal_tail_Y", "reversal_tail_decay"):
        assert np.isnan(d[term]) and d.undetermined[term] == NONE_WHY.format(
            rms=f"{d['residual_rms'] * 1e6:.2f} µm rms")


def test_each_tail_carries_its_uncertainty():
    """The largest tail of each axis is given with its standard uncertainty at the
    tails' time constant, from the fit's covariance: a few nm on 0.05 um of noise, and the
    tail of 3 um at the point lies within two of them of what is left of it at the
    window's end, 20 deg on."""
    d = pair(3e-6, 10.0, "radial", shares=(1.0,) * 4)
    for axis in "XY":
        sigma = d.sigma[f"reversal_tail_{axis}"]
        assert 0 < sigma < 0.02e-6
        assert abs(d[f"reversal_tail_{axis}"] - 3e-6 * np.exp(-2.0)) <= 2 * sigma + 0.01e-6


def test_the_time_constant_reads_to_tenths_of_a_millisecond():
    """Its interval spans milliseconds (bench R05: 46.0 ± 4.4 ms, which read 45.999 ±
    4.413 ms); a servo mismatch in ms keeps its microseconds."""
    from tcpmm.analysis.circle_tails import pair_text

    d = pair(3e-6, 16.0, "axis")
    tau = d["reversal_tail_decay"]
    assert re.fullmatch(r"reversal tail decay \d+\.\d ± \d+\.\d ms",
                        pair_text(d, "reversal_tail_decay", tau, 0.1 * tau, "±"))
    assert re.fullmatch(r"servo mismatch \d\.\d{3} ± \d\.\d{3} ms",
                        pair_text(d, "servo_mismatch", 4e-5, 1e-5, "±"))


def test_the_line_names_the_other_tails_only_where_tails_are_fitted():
    """The terms' moves over the tails that fit as well are tried only where a pair of
    full circles is fitted with tails; one direction is fitted without, and its line
    says only what the wider window moves."""
    from tcpmm.analysis.circle_single import diagnose_single
    from tcpmm.analysis.circle_tails import moving_line

    alike = "or with another tail past the window that fits the samples as well"
    both = pair(10e-6, 40.0, "radial", LONG, (1.0,) * 4)
    assert alike in moving_line(both)
    one = diagnose_single(*tailed("ccw", BASE, 3e-6, 30.0, "axis", 1), "ccw", gen.R)
    line = moving_line(one)
    assert line.startswith("uncertain by the reversals' tails") and alike not in line


def test_the_line_names_the_other_tails_where_the_circles_speed_is_not_known():
    """Without the circles' angular speed the tails' time constant reads n/a, with that
    reason, though a tail is fitted: the line still names the tails that fit as well,
    from what the tails are (``tails``), not from the reason's words."""
    from tcpmm.analysis.circle_tails import moving_line

    nan = float("nan")
    d = diagnose_pair(tailed("ccw", LONG, 10e-6, 40.0, "radial", 1, (1.0,) * 4),
                      tailed("cw", LONG, 10e-6, 40.0, "radial", 2, (1.0,) * 4), gen.R,
                      (nan, nan))
    assert d.tails == "fitted" and np.isnan(d["reversal_tail_decay"])
    assert "speed is not known" in d.undetermined["reversal_tail_decay"]
    assert "or with another tail past the window that fits the samples as well" in \
        moving_line(d)


@pytest.mark.parametrize(("decay_deg", "shape", "shares", "widest"), [
    (8.0, "axis", (1.0,) * 4, 0.2), (16.0, "axis", (1.0,) * 4, 0.2),
    (10.0, "radial", SHARES, 0.2), (45.0, "radial", (1.0,) * 4, 1.0)])
def test_the_time_constant_carries_its_interval(decay_deg, shape, shares, widest):
    """The time constant is given with two standard uncertainties, the larger side of its
    95 % interval: the time constants whose fit lies within 3.84 noise variances of the
    best, over either shape where the other fits as well. The injected one lies within the
    interval where the other shape is taken (an axis' tail of 16 deg read as a radial one
    of 14.9 deg, 14.5-16.2) and where the tail is as long as the half turn (45 deg read
    as 31, 29-51, and the ± says so: 63 % of the value; the others' under 20 %)."""
    d = pair(3e-6, decay_deg, shape, shares=shares)
    value, u95 = d["reversal_tail_decay"], 2 * d.sigma["reversal_tail_decay"]
    assert 0 < u95 < widest * value
    assert abs(value - np.radians(decay_deg) / gen.W) <= u95
