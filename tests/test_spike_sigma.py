"""The reversal spikes' 95 % uncertainty (tcpmm.analysis.circle_spike_sigma) against the
scatter of the spikes over circles measured again with fresh noise: where there is no
spike the circle reads the noise's extreme over the window, and the bound holds that;
where there is one it holds the injected value. The circles are the suite's generator
(tests/test_circle_diagnostics.py: every error as the position error it is)."""

import json

import numpy as np
import pytest
from scipy.signal import lfilter
from scipy.special import stdtrit

import test_circle_diagnostics as gen
from conftest import bench_path, run_cli
from tcpmm.analysis.circle_spike_sigma import spike_uncertainty
from tcpmm.analysis.circle_terms import spikes_with_uncertainty
from tcpmm.analysis.diagnostics import diagnose_pair


def noisy(direction, err, n, phi, noise, rng):
    """One turn of ``n`` samples with radial noise ``noise`` of AR(1) correlation ``phi``
    [rad, m]."""
    a, e = gen.circle(direction, err, noise=0.0, n=n)
    z = lfilter([np.sqrt(1 - phi**2)], [1, -phi], rng.standard_normal(e.size))
    return a, e + noise * z


@pytest.mark.parametrize(("n", "phi"), [(1800, 0.0), (7200, 0.0), (7200, 0.9)])
def test_a_circle_without_spikes_reads_the_noises_extreme_within_the_bound(n, phi):
    """No spike: the spike read is the noise's largest value over the window (0.26-0.39
    um on 0.1 um of noise), four times one sample's noise. The bound holds at least 88 %
    of them (95 % expected; 240 points, binomial scatter 1.4 %, and the noise's level
    read from one window of 25 deg), and it is no wider than 1.3 times the 95th
    percentile of what it bounds. Noise alike over 19 samples has the smaller extreme of
    fewer independent samples; it is bounded as white noise (Slepian's inequality)."""
    rng = np.random.default_rng(11 + n)
    err, got = [], []
    for _ in range(30):
        spikes, u95, _ = spikes_with_uncertainty(*noisy("ccw", {}, n, phi, 0.1e-6, rng), "ccw")
        err += [abs(spikes[q]) for q in "ABCD"]
        got += [u95[q] for q in "ABCD"]
    err, got = np.array(err), np.array(got)
    assert np.mean(err) > 2.5 * 0.1e-6  # the extreme, not one sample
    assert np.mean(err <= got) >= 0.88
    assert np.median(got) <= 1.3 * np.percentile(err, 95)


def test_the_pairs_spikes_lie_within_their_bound_of_the_injected_ones():
    """Every error at once (backlash, lateral play, servo mismatch, cyclic errors, bows)
    and spikes of 8-20 um, 0.1 um of noise: the spikes after the pair's terms lie within
    their 95 % uncertainty of the injected ones (all 48 over six pairs), which moves with
    the noise: ten times the noise, about ten times the bound."""
    rng = np.random.default_rng(7)
    w = 2 * np.pi / (1800 * gen.DT)
    want = gen.expected(gen.ALL, 1800)
    bounds = {}
    for noise in (0.1e-6, 1e-6):
        inside, u = [], []
        for _ in range(6 if noise < 1e-6 else 2):
            d = diagnose_pair(noisy("ccw", gen.ALL, 1800, 0.0, noise, rng),
                              noisy("cw", gen.ALL, 1800, 0.0, noise, rng), gen.R, (w, w))
            assert set(d.spike_u95) == {f"spike_{q}_{c}" for q in "ABCD" for c in ("ccw", "cw")}
            inside += [abs(d[k] - want[k]) <= v for k, v in d.spike_u95.items()]
            u += list(d.spike_u95.values())
        assert all(inside), noise
        bounds[noise] = np.median(u)
    assert 7.0 < bounds[1e-6] / bounds[0.1e-6] < 12.0
    assert json.dumps(d.to_dict()["spike_u95"])


def test_the_bound_adds_the_extreme_the_median_and_the_terms():
    """Known answer: a window of white noise of known scatter, the spike's sample and the
    model's columns chosen so that each part is known: ``z sqrt(sigma^2 + var)`` with
    ``z`` Student's quantile of 1 - 0.025 / n after, of n_before - 1 degrees of freedom
    (sigma is read off the window before), ``var`` the median's ``pi/2 sigma^2 /
    n_before`` and the terms' ``g^T C g``: a shift of every sample of the window, here a
    fifth of sigma, where the union bound over the samples is that of their variance and
    the shift's added (tcpmm.analysis.extreme_bound, whose integral over the shift gives
    within 0.2 % of that there: Student's tails of the noise against a normal shift)."""
    n = 3600
    a = np.radians(45.0) + 2 * np.pi * np.arange(n) / n
    rest = np.zeros(n)
    u = np.degrees(a)
    before = (u >= 60.0) & (u <= 85.0)
    after = (u >= 90.0) & (u <= 110.0)
    rest[before] = np.tile([1e-6, -1e-6], before.sum() // 2 + 1)[:before.sum()]
    rest[np.flatnonzero(after)[5]] = 3e-6
    columns = np.zeros((n, 2))
    columns[:, 0] = np.where(after, 1.0, 0.0)
    cov = np.diag([4e-14, 1.0])
    got = spike_uncertainty(a, rest, "ccw", columns=columns, cov=cov)[0]["B"]
    nb = before.sum()
    tau = 1.0  # alternating samples: the correlation time the sum of the lags gives is below 1
    sigma = np.sqrt(nb * 1e-12 / (nb - tau))
    extreme = sigma * stdtrit(nb - 1.0, 1 - 0.025 / after.sum())
    var = np.pi / 2 * sigma**2 * tau / nb + 4e-14
    assert np.sqrt(var) < 0.5 * sigma
    assert got == pytest.approx(extreme * np.sqrt(1.0 + var / sigma**2), rel=2e-3)


def test_a_noise_free_circle_has_no_uncertainty_and_a_part_of_a_turn_none():
    """Without noise only what the terms leave of the spikes' own flanks in the fit
    (under 0.001 um) is left to bound; three quarters of a turn, which one direction's
    own fit does not take, have no spike and no uncertainty."""
    a, e = gen.circle("ccw", {"spikes": gen.ALL["spikes"]}, noise=0.0, n=1800)
    _, u95, _ = spikes_with_uncertainty(a, e, "ccw")
    assert all(0.0 <= v < 1e-9 for v in u95.values())
    part = slice(0, 1800 * 3 // 4)
    spikes, u95, _ = spikes_with_uncertainty(a[part], e[part], "ccw")
    assert all(np.isnan(v) for v in [*spikes.values(), *u95.values()])


def test_the_circle_table_shows_the_spikes_uncertainty(capsys, tmp_path):
    """``tcpmm circle`` gives the largest of a row's spike uncertainties in a ±95% column,
    and --json each point's."""
    from tcpmm.result import AxisRun, Run

    n = 1800
    a_cmd = np.radians(gen.START) + 2 * np.pi / n * np.arange(n + 1)
    a, e = gen.circle("ccw", {"spikes": gen.ALL["spikes"]}, noise=0.1e-6, n=n)
    cmd = gen.R * np.c_[np.cos(a_cmd), np.sin(a_cmd)]
    tcp = (gen.R + e)[:, None] * np.c_[np.cos(a), np.sin(a)]
    path = tmp_path / "run.csv"
    Run(gen.DT * np.arange(n + 1), {"X": AxisRun(cmd=cmd[:, 0], tcp=tcp[:, 0]),
                                    "Y": AxisRun(cmd=cmd[:, 1], tcp=tcp[:, 1])}).write_csv(path)
    code, out, _ = run_cli(capsys, "circle", path, "--radius", 35)
    assert code == 0
    head = next(line for line in out.splitlines() if line.startswith("dir"))
    assert head.split() == ["dir", "sensor", "A", "B", "C", "D", "±95%", "contour", "G"]
    assert "±95%: the largest of the spikes' 95 % uncertainties" in out.replace("\n", " ")
    assert "counts what the terms leave before the points as noise" not in out  # white
    code, out, _ = run_cli(capsys, "circle", path, "--radius", 35, "--json")
    rows = {r["sensor"]: r for r in json.loads(out)["passes"][0]["sensors"]}
    assert all(rows["cmd"][f"spike_after_terms_{q}_uncertainty_95_um"] < 1e-3 for q in "ABCD")
    u = [rows["tcp"][f"spike_after_terms_{q}_uncertainty_95_um"] for q in "ABCD"]
    assert all(0.0 < v < 1.0 for v in u), u


def test_an_oscillation_the_terms_leave_before_the_points_is_named_with_both_bounds(capsys):
    """Machine C of the independent simulator at F10000: at the TCP the pair's terms leave
    micrometres of oscillation before each point (3.5 um rms over the circle: a column that
    rings at 31 Hz), which the bound counts as noise (above 5 um at A and C); the line
    under the table says so and gives the bound from the sample-to-sample noise alone
    (under 2 um), which the four spikes of X's reversals (A and C, both directions), alike
    by the physics, keep to."""
    d = bench_path("c")
    code, out, _ = run_cli(capsys, "circle", d / "circle_ccw_fast_meas.csv",
                           d / "circle_cw_fast_meas.csv", "--radius", 35, "--json")
    assert code == 0
    rows = [r for p in json.loads(out)["passes"] for r in p["sensors"] if r["sensor"] == "tcp"]
    u = [r[f"spike_after_terms_{q}_uncertainty_95_um"] for r in rows for q in "AC"]
    assert min(u) > 5.0
    x = [r[f"spike_after_terms_{q}_um"] for r in rows for q in "AC"]
    code, out, _ = run_cli(capsys, "circle", d / "circle_ccw_fast_meas.csv",
                           d / "circle_cw_fast_meas.csv", "--radius", 35)
    line = next(t for t in out.splitlines() if "counts what the terms leave" in t)
    fast = float(line.split("CCW tcp ±")[1].split()[0])
    assert fast < 2.0 and max(x) - min(x) < fast


@pytest.mark.filterwarnings("ignore::tcpmm.errors.InputWarning")
def test_the_sample_to_sample_bound_names_its_point_in_console_and_report():
    """Bench H: the console said "CCW tcp ±1.35 µm ... from the sample-to-sample noise
    alone", the report in the same words ± 0.68 µm for the same circle: the largest over
    A-D against the one at the largest spike's point, neither saying which. Each names its
    point, and the console's is the report's where they are the same point."""
    import html
    import re

    from tcpmm.analysis.circle_spike_sigma import slow_line
    from tcpmm.analysis.circular import CircleResult, analyse_circle
    from tcpmm.analysis.diagnostics import circle_diagnostics
    from tcpmm.io.runfile import read_run
    from tcpmm.report.circles import key_figures

    h = bench_path("h")
    res = [analyse_circle(read_run(h / f"circle_{w}_meas.csv"), 0.035) for w in ("ccw", "cw")]
    both = CircleResult(0.035, (0.0, 0.0), res[0].passes + res[1].passes)
    sc = both.passes[0].sensors["tcp"]
    fast = sc.spike_uncertainty(sample_noise=True)
    line = slow_line([("CCW tcp", sc.spike_uncertainty(), fast)])
    at = max(fast, key=lambda q: fast[q])
    assert f"CCW tcp ±{fast[at] * 1e6:.2f} µm at {at}" in line
    assert "the largest over the points" in line
    text = html.unescape(key_figures(both, circle_diagnostics(*res)))
    q = re.search(r"at ([A-D]) \(the ± counts[^)]*µm at ([A-D])\)", text).group(1, 2)
    assert q[0] == q[1]  # the report's bound is at the point of the spike it qualifies
    pm = float(re.search(r"as they are, ± ([\d.]+) µm at", text).group(1))
    assert pm == pytest.approx(fast[q[0]] * 1e6, abs=0.006)


@pytest.mark.parametrize(("n_before", "n_after", "phi"), [(23, 18, 0.0), (60, 45, 0.0)])
def test_the_bound_holds_the_extreme_of_a_short_window_as_often_as_it_says(n_before,
                                                                             n_after, phi):
    """At 4 ms on a fast circle the window before a point holds some 23 samples, from which
    the noise's level is read: with the normal's quantile the extreme of white noise and no
    spike passed the 95 % bound in 10.7 % of the windows (8.2 % at 60 samples). Student's
    quantile, of the window's degrees of freedom, holds it to 5 % (2000 windows each:
    binomial scatter 0.5 %)."""
    from tcpmm.analysis.circle_spike_sigma import _bound

    rng = np.random.default_rng(3)
    n = n_before + n_after
    before = np.arange(n) < n_before
    past = 0
    for _ in range(2000):
        r = lfilter([1.0], [1.0, -phi], rng.standard_normal(n + 100))[100:]
        past += np.max(np.abs(r[~before] - np.median(r[before]))) > _bound(
            r, before, ~before, None, None)
    assert past / 2000 <= 0.065


def test_the_bound_of_a_shifted_extreme_runs_from_the_extreme_to_the_shift():
    """Limits of tcpmm.analysis.extreme_bound: without a shift the extreme's quantile
    ``sigma z``; a small one, that of the two variances added (``x_i - b`` is normal of
    both: within 0.1 % at a tenth of the noise); one far larger than the noise, the
    shift's own two-sided 95 % (1.96 s, within the noise's extreme over it: 2 %)."""
    from tcpmm.analysis.extreme_bound import extreme_bound

    z = stdtrit(499.0, 1 - 0.025 / 400)
    assert extreme_bound(1.0, 499.0, 400, 0.0, 0.05) == pytest.approx(z, rel=1e-12)
    assert extreme_bound(1.0, 499.0, 400, 0.1, 0.05) == pytest.approx(
        z * np.hypot(1.0, 0.1), rel=1e-3)
    assert extreme_bound(1.0, 499.0, 400, 100.0, 0.05) == pytest.approx(196.0, rel=0.02)


def test_a_shift_the_whole_window_shares_is_not_added_in_quadrature():
    """The terms' own uncertainty and the noise on the level before a point shift every
    sample of the window after it alike. Added in quadrature to the extreme's quantile
    (about 3.8 of the noise over a window of this size), a shift of the noise's size let
    the spike of noise alone pass its 95 % bound on 20 % of circles; the bound on the
    extreme of the samples less that shift holds it on 95 % (expected 4-5 %, the union
    bound over the samples; 400 circles, binomial scatter 1.1 %, so 8 % is three of it
    above)."""
    from tcpmm.analysis.circle_spikes import spike_windows, spikes_in

    rng = np.random.default_rng(5)
    a, _ = gen.circle("ccw", {}, noise=0.0, n=1800)
    windows = list(spike_windows(a, "ccw"))
    after = np.zeros(a.size, bool)
    for _, _, w in windows:
        after |= w
    columns, sd = after[:, None].astype(float), 0.1e-6
    past = total = 0
    for _ in range(100):
        rest = sd * (rng.standard_normal(a.size) + rng.standard_normal() * columns[:, 0])
        u95, _ = spike_uncertainty(a, rest, "ccw", columns=columns, cov=np.array([[sd**2]]))
        spikes = spikes_in(windows, rest)
        past += sum(abs(spikes[q]) > u95[q] for q in "ABCD")
        total += 4
    assert past / total < 0.08, past / total
