"""Circle diagnostics recover known injected errors from a CCW and a CW circle.

Each error is injected as the position error it is (a lag, a shear, lost motion...), not as
the radial term the fit uses, so a wrong sign or factor in a term fails its test. Tolerance:
2 % of the true value or 0.1 um of the radial error the term makes, whichever is larger;
the noise (0.05 um rms on each axis, ~7000 samples per circle) moves a fitted term by a few
nm. A reversal spike is the extreme sample of a 20 deg window (docs/formats.md section 4), so an
absent one reads the extreme of the noise over ~400 samples, about 3.5 noise rms: its
tolerance is at least 4.5 noise rms.
"""

import json
import warnings

import numpy as np
import pytest

from conftest import bench_path, run_cli
from tcpmm.analysis.circle_single import diagnose_single
from tcpmm.analysis.circle_tails import radial_size
from tcpmm.analysis.circular import analyse_circle
from tcpmm.analysis.diagnostics import circle_diagnostics, diagnose_pair
from tcpmm.cli import main
from tcpmm.errors import InputError, InputWarning
from tcpmm.io.runfile import read_run
from tcpmm.result import AxisRun, Run

R, DT, N = 0.035, 1e-3, 7200  # 7.2 s per turn
W = 2 * np.pi / (N * DT)  # angular speed [rad/s]
NOISE = 0.05e-6
#: radial error per unit of each term, to express 0.1 um of radial error in its unit
PER_UNIT = {"squareness": R / 2, "scale_mismatch": R / 2, "servo_mismatch": R * W / 2,
            "lateral_play_X": 0.5, "lateral_play_Y": 0.5}
SPIKE_AT = {"A": 0.0, "B": 90.0, "C": 180.0, "D": 270.0}


START = 45.0 + 0.5 * np.degrees(W * DT)  # no sample on a reversal, where a step has no side


def circle(direction, err, seed=0, start_deg=START, noise=NOISE, n=N):
    """``(angle, radial error)`` of one turn of ``n`` samples from ``start_deg`` with the
    errors ``err`` applied as position errors of the tool, plus noise on each axis; each axis
    lags its command by its ``tau``, reverses where its own velocity turns and has its
    cyclic error and its bow at its own position [rad, m]."""
    s = 1.0 if direction == "ccw" else -1.0
    w = 2 * np.pi / (n * DT)
    th = np.radians(start_deg) + s * w * DT * np.arange(n + 1)
    g = err.get
    ax, ay = th - s * w * g("tau_x", 0.0), th - s * w * g("tau_y", 0.0)
    xa, ya = R * np.cos(ax), R * np.sin(ay)  # the axes where they are
    x, y = (1 + g("eps_x", 0.0)) * xa, (1 + g("eps_y", 0.0)) * ya
    x = x - g("alpha", 0.0) * y
    sx, sy = np.sign(-s * np.sin(ax)), np.sign(s * np.cos(ay))
    x = x - g("b_x", 0.0) / 2 * sx + g("p_y", 0.0) / 2 * sy
    y = y - g("b_y", 0.0) / 2 * sy + g("p_x", 0.0) / 2 * sx
    y = y + g("str_x", 0.0) * (1 - (xa / R) ** 2)
    x = x + g("str_y", 0.0) * (1 - (ya / R) ** 2)
    for axis, pos in (("x", xa), ("y", ya)):
        c, lam, ph = g(f"cyc_{axis}", (0.0, 1.0, 0.0))
        d = c * np.sin(2 * np.pi * pos / lam + ph)
        x, y = (x + d, y) if axis == "x" else (x, y + d)
    bump = g("r0", 0.0) + sum(  # a Gaussian of 1.5 deg, ``at`` deg after the point
        h * np.exp(-0.5 * (((s * (np.degrees(th) - SPIKE_AT[q]) - at + 180) % 360 - 180)
                           / 1.5) ** 2)
        for (d, q), (h, at) in g("spikes", {}).items() if d == direction)
    x, y = x + bump * np.cos(th) + g("cx", 0.0), y + bump * np.sin(th) + g("cy", 0.0)
    rng = np.random.default_rng(seed)
    x, y = x + noise * rng.standard_normal(x.size), y + noise * rng.standard_normal(y.size)
    return np.unwrap(np.arctan2(y, x)), np.hypot(x, y) - R


def diagnose(err, noise=NOISE, n=N, **kw):
    w = 2 * np.pi / (n * DT)
    return diagnose_pair(circle("ccw", err, 1, noise=noise, n=n, **kw),
                         circle("cw", err, 2, noise=noise, n=n, **kw), R, (w, w))


def expected(err, n=N):
    """The terms ``err`` should give, in the units of the diagnostics [SI]."""
    g = err.get
    out = {"backlash_X": g("b_x", 0.0), "backlash_Y": g("b_y", 0.0),
           "lateral_play_X": g("p_x", 0.0), "lateral_play_Y": g("p_y", 0.0),
           "squareness": g("alpha", 0.0), "servo_mismatch": g("tau_y", 0.0) - g("tau_x", 0.0),
           "scale_mismatch": g("eps_x", 0.0) - g("eps_y", 0.0),
           "straightness_X": g("str_x", 0.0), "straightness_Y": g("str_y", 0.0),
           "centre_offset_X": g("cx", 0.0), "centre_offset_Y": g("cy", 0.0)}
    for axis in "XY":
        c, lam, _ = g(f"cyc_{axis.lower()}", (0.0, float("nan"), 0.0))
        # none injected: none found, which says so (NaN and why) rather than read 0
        out[f"cyclic_amplitude_{axis}"] = c if c else float("nan")
        if c:
            out[f"cyclic_period_{axis}"] = lam
    for d in ("ccw", "cw"):
        for q in "ABCD":
            out[f"spike_{q}_{d}"] = g("spikes", {}).get((d, q), (0.0, 0.0))[0]
        # mean radius minus nominal over the command's angle, as the samples of a steady
        # feed come: the noise-free circle without its spikes, one turn of samples
        clean = {k: v for k, v in err.items() if k != "spikes"}
        out[f"radial_deviation_{d}"] = float(np.mean(circle(d, clean, noise=0.0, n=n)[1][:-1]))
    return out


def assert_recovered(diag, want, w=W):
    per_unit = dict(PER_UNIT, servo_mismatch=R * w / 2)
    for term, true in want.items():
        if np.isnan(true):
            assert np.isnan(diag[term]) and term in diag.undetermined, term
            continue
        tol = max(0.02 * abs(true), 0.1e-6 / per_unit.get(term, 1.0))
        if term.startswith("cyclic_period"):
            tol = 0.02 * true
        if term.startswith("spike"):
            tol = max(tol, 4.5 * NOISE)
        found = diag[term]
        assert abs(found - true) <= tol, f"{term}: found {found:.4g}, injected {true:.4g}"
        if abs(true) > tol:  # the opposite sign would fail: the test sees the convention
            assert abs(found + true) > tol, term


def draw(rng):
    """Every error at once, magnitudes and signs drawn at random [SI]."""
    def pm(lo, hi):
        return rng.choice([-1.0, 1.0]) * rng.uniform(lo, hi)

    return {"r0": pm(1e-6, 5e-6), "cx": pm(1e-6, 10e-6), "cy": pm(1e-6, 10e-6),
            "b_x": pm(2e-6, 10e-6), "b_y": pm(2e-6, 10e-6),
            "p_x": pm(1e-6, 6e-6), "p_y": pm(1e-6, 6e-6),
            "alpha": pm(30e-6, 150e-6), "tau_x": 0.0, "tau_y": pm(0.1e-3, 0.5e-3),
            "eps_x": pm(30e-6, 150e-6), "eps_y": 0.0,
            "cyc_x": (rng.uniform(0.5e-6, 2e-6), rng.uniform(3e-3, 12e-3), rng.uniform(0, 6)),
            "cyc_y": (rng.uniform(0.5e-6, 2e-6), rng.uniform(3e-3, 12e-3), rng.uniform(0, 6)),
            "spikes": {(d, q): (pm(8e-6, 20e-6), rng.uniform(4.0, 8.0))
                       for d in ("ccw", "cw") for q in "ABCD"},
            "str_x": pm(1e-6, 5e-6), "str_y": pm(1e-6, 5e-6)}


ALL = draw(np.random.default_rng(2305))
SINGLE = ["r0", "cx", "b_x", "b_y", "p_x", "p_y", "alpha", "tau_y", "tau_x", "eps_x", "eps_y",
          "cyc_x", "cyc_y", "spikes", "str_x", "str_y"]


@pytest.mark.parametrize("name", SINGLE)
def test_each_error_alone_is_recovered_and_the_others_are_zero(name):
    err = {name: ALL[name] if name != "tau_x" else -ALL["tau_y"]}
    if name == "spikes":  # one spike only, so that the other seven must read zero
        err = {"spikes": {("cw", "C"): ALL["spikes"][("cw", "C")]}}
    diag = diagnose(err)
    assert_recovered(diag, expected(err))
    assert diag["residual_rms"] < 1.5 * NOISE * np.sqrt(2)


@pytest.mark.parametrize("cx, cy, others", [(300e-6, -150e-6, {}), (-1.0e-3, 0.7e-3, {}),
                                            (300e-6, -150e-6, ALL),
                                            (300e-6, -150e-6, {"str_x": 4e-6, "str_y": -3e-6})],
                         ids=["335um", "1.2mm", "335um_with_all", "335um_with_bows"])
def test_a_large_centre_offset_makes_no_other_term(cx, cy, others):
    """A circle 0.3 to 1.2 mm off the nominal centre. About the nominal centre the offset's
    second order is a constant and an ellipse along it (0.8 um of each at 335 um on R 35 mm),
    which read as 37 um/m of squareness and 28 ppm of scale mismatch, and as the radial
    deviation, the mean radius of the fitted circle. A bow read where the tool is about
    the nominal centre, not where its axis is in its travel, made 0.13 um of backlash."""
    err = {**others, "cx": cx, "cy": cy}
    diag = diagnose(err)
    want = expected(err)
    for d in ("ccw", "cw"):  # about the circle's own centre: that of the same circle centred
        want[f"radial_deviation_{d}"] = expected({**err, "cx": 0.0, "cy": 0.0})[
            f"radial_deviation_{d}"]
    assert_recovered(diag, want)
    if not others:  # one direction: its ellipses are squareness (or servo) and scale alone
        one = diagnose_single(*circle("ccw", err, 1), "ccw", R)
        for term in ("squareness_or_servo", "scale_mismatch"):
            assert abs(one[term]) <= 0.1e-6 / PER_UNIT["squareness"], (term, one[term])


def test_all_errors_together_are_recovered():
    diag = diagnose(ALL)
    assert_recovered(diag, expected(ALL))
    assert diag["radial_deviation_pair"] == pytest.approx(
        (diag["radial_deviation_ccw"] + diag["radial_deviation_cw"]) / 2)


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("n", [N, 1320], ids=["F1800", "F10000"])
def test_all_errors_with_a_servo_mismatch_of_1_ms(seed, n):
    """With Y lagging X by 1 ms each axis reverses where its own velocity turns, a sample
    or more from the quadrant point of the tool's angle (at F10000 on R35, 1320 samples a
    turn, 0.27 deg), and the lag's ellipse has a part at four times the angle of 0.15 um:
    neither may read as backlash, scale mismatch or a cyclic error."""
    err = draw(np.random.default_rng(seed))
    err["tau_y"] = np.sign(err["tau_y"]) * 1e-3
    assert_recovered(diagnose(err, n=n), expected(err, n), w=2 * np.pi / (n * DT))


@pytest.mark.parametrize("seed, other", [(0, {"b_x": 60e-6, "alpha": 30e-6}),
                                         (1, {"b_x": 60e-6, "alpha": 30e-6}),
                                         (2, {"b_x": 4e-6, "alpha": 700e-6})],
                         ids=["backlash-0", "backlash-1", "squareness"])
def test_a_step_the_other_axis_turns_samples_away_is_no_spike(seed, other):
    """Each axis reverses where its own velocity turns; the tool's angle there is off the
    quadrant point by the other axis' errors across the radius. 30 um of X's half backlash
    turn it by 0.9 mrad at B and D, three samples of a turn of 20 000; a squareness of
    700 um/m by 0.7 mrad (150 um/m at F1000 sampled at 10 kHz: two samples). The model's
    step of Y's backlash stood where the tool's angle put it, and the samples between read
    spikes of the backlash's size: 6 um (of 3) after the terms, within ±0.3 um (found at
    F1000 sampled at 10 kHz, with 4 um of X's backlash and 30 um/m)."""
    n = 20000
    err = {"b_y": 6e-6, "tau_y": 1e-3, **other,
           "spikes": {(d, q): (3e-6, 3.0) for d in ("ccw", "cw") for q in "ABCD"}}
    w = 2 * np.pi / (n * DT)
    diag = diagnose_pair(circle("ccw", err, 2 * seed + 1, n=n), circle("cw", err, 2 * seed + 2,
                                                                      n=n), R, (w, w))
    assert_recovered(diag, {f"spike_{q}_{d}": 3e-6 for d in ("ccw", "cw") for q in "ABCD"})


@pytest.mark.parametrize("seed", range(4))
def test_all_errors_with_a_large_servo_mismatch(seed):
    """Y lagging X by 2 ms on a fast circle (754 samples a turn: F10000 on R 20 mm, a
    mismatch angle of 0.017 rad) makes an ellipse 290 um deep about 45 deg; a position
    error across the radius turns the tool's angle, and the ellipse is read that much
    further along: without that slope a backlash or lateral play read 3-12 % off."""
    n = 754
    err = draw(np.random.default_rng(seed))
    err["tau_y"] = np.sign(err["tau_y"]) * 2e-3
    assert_recovered(diagnose(err, n=n), expected(err, n), w=2 * np.pi / (n * DT))


def test_squareness_and_servo_mismatch_part_on_the_direction():
    """Both are an ellipse at 45 deg, the same in one circle for a lag ty - tx = a / w:
    what tells them apart is only whether the CW circle's ellipse has the CCW one's sign."""
    a = 80e-6
    same = diagnose_pair(circle("ccw", {"alpha": a}, 1), circle("cw", {"alpha": a}, 2), R,
                         (W, W))
    flipped = diagnose_pair(circle("ccw", {"alpha": a}, 1), circle("cw", {"alpha": -a}, 2), R,
                            (W, W))
    assert_recovered(same, {"squareness": a, "servo_mismatch": 0.0})
    assert_recovered(flipped, {"squareness": 0.0, "servo_mismatch": a / W})


def test_circles_given_in_the_wrong_order_are_refused():
    """A CW circle passed as the CCW one would turn the sign of every direction-bound
    term (backlash, lateral play, servo mismatch)."""
    with pytest.raises(InputError, match="the CCW circle runs clockwise"):
        diagnose_pair(circle("cw", {}), circle("ccw", {}), R)


def test_scale_mismatch_circularity_is_the_ellipse_peak_to_valley():
    """Without noise G is the peak-to-valley of the ellipse, eps R, in each direction and
    for the pair, and the two circles coincide (hysteresis 0)."""
    diag = diagnose({"eps_x": 100e-6}, noise=0.0)
    for d in ("ccw", "cw", "pair"):
        assert diag[f"circularity_{d}"] == pytest.approx(100e-6 * R, rel=1e-3)
    assert diag["hysteresis"] < 1e-9


def test_backlash_makes_hysteresis():
    """Backlash b shifts the two circles' halves apart by b at the reversal points."""
    diag = diagnose({"b_x": 6e-6}, noise=0.0)
    assert diag["hysteresis"] == pytest.approx(6e-6, rel=0.02)


def test_from_runs_with_the_speed_from_the_time():
    """The same through the analysis of runs: passes found from the command, the angular
    speed from the time stamps."""
    err = {"tau_y": 0.4e-3, "b_y": 3e-6}
    res = [analyse_circle(run_of(d, err, i), R) for i, d in enumerate(("ccw", "cw"))]
    diag = circle_diagnostics(res[0], res[1])
    assert diag.sensor == "tcp"
    assert diag["servo_mismatch"] == pytest.approx(0.4e-3, rel=0.02)
    assert diag["backlash_Y"] == pytest.approx(3e-6, rel=0.02)
    assert circle_diagnostics(res[1], res[0])["backlash_Y"] == diag["backlash_Y"]
    with pytest.raises(InputError, match="no CW circle"):
        circle_diagnostics(res[0])
    with pytest.raises(InputError, match="sensor scale is not in both"):
        circle_diagnostics(res[0], res[1], sensor="scale")


def run_of(direction, err, seed=0, start_deg=START, n=N):
    """A run of one turn of ``n`` samples without feed-in: the command and the TCP with
    ``err`` [-]."""
    s = 1.0 if direction == "ccw" else -1.0
    a_cmd = np.radians(start_deg) + s * 2 * np.pi / n * np.arange(n + 1)
    a, e = circle(direction, err, seed, start_deg=start_deg, noise=0.0, n=n)
    cmd = R * np.c_[np.cos(a_cmd), np.sin(a_cmd)]
    tcp = (R + e)[:, None] * np.c_[np.cos(a), np.sin(a)]
    return Run(DT * np.arange(n + 1), {"X": AxisRun(cmd=cmd[:, 0], tcp=tcp[:, 0]),
                                       "Y": AxisRun(cmd=cmd[:, 1], tcp=tcp[:, 1])})


@pytest.mark.parametrize("seed", range(4))
def test_time_stamps_with_jitter_leave_squareness_and_servo_mismatch_apart(seed):
    """A recorder whose time stamps jitter by +-0.3 ms about a 1 ms step: the angular speed
    of each direction, the median over single steps, came out up to 1 % apart, and with
    0.5 ms of servo mismatch at F10000 on R 35 mm (1.3 s a turn) a squareness of 20 um/m
    read 9.1 to 34.8 um/m over 20 draws: the servo's ellipse, scaled by the wrong speed,
    taken for it."""
    err = {"tau_y": 0.5e-3, "alpha": 20e-6}
    rng = np.random.default_rng(seed)
    res = []
    for i, d in enumerate(("ccw", "cw")):
        run = run_of(d, err, i, n=1320)
        run = Run(run.time_s + rng.uniform(-0.3e-3, 0.3e-3, run.time_s.size), run.axes)
        res.append(analyse_circle(run, R))
    diag = circle_diagnostics(res[0], res[1])
    assert_recovered(diag, {"squareness": 20e-6, "servo_mismatch": 0.5e-3},
                     w=2 * np.pi / (1320 * DT))


def test_results_table_dict_and_plot():
    diag = diagnose(ALL)
    df = diag.to_pandas()
    assert list(df.columns) == ["term", "value", "unit"]
    assert dict(zip(df["term"], df["unit"], strict=True))["squareness"] == "m/m"
    d = diag.to_dict()
    assert {t["term"] for t in d["terms"]} == set(df["term"])
    fig = diag.plot()
    assert len(fig.axes) == 1 and len(fig.axes[0].lines) >= 4  # dots and fit per direction
    from tcpmm.plot import pyplot

    plt = pyplot()
    own, ax = plt.subplots()
    assert diag.plot(ax=ax) is own
    plt.close("all")


def test_a_short_arc_is_refused():
    a, e = circle("ccw", {})
    with pytest.raises(InputError, match="need a full turn"):
        diagnose_pair((a[:3000], e[:3000]), circle("cw", {}), R)


@pytest.fixture(scope="module")
def pair(tmp_path_factory):
    d = tmp_path_factory.mktemp("pair")
    err = {"b_x": 4e-6, "alpha": 50e-6, "eps_x": 80e-6, "tau_y": 0.2e-3}
    for i, direction in enumerate(("ccw", "cw")):
        run_of(direction, err, i).write_csv(d / f"{direction}.csv")
    return d


def test_each_ccw_and_cw_circle_of_a_run_are_a_pair_and_a_circle_left_over_says_so(
        tmp_path, capsys):
    """A run of CCW, CW, CCW, CW circles, alike, with backlash and spikes of 3 um: the
    second pair's spikes were each circle's own, backlash in them (6.3-7.7 um), under the
    legend of the pair's terms. Each k-th CCW and CW are a pair; a CW circle given in a
    second run beside a pair is marked as paired with none, and the diagnostics are of
    the pair whose spikes the table gives."""
    err = {"b_x": 4e-6, "b_y": 6e-6, "alpha": 30e-6,
           "spikes": {(d, q): (3e-6, 3.0) for d in ("ccw", "cw") for q in "ABCD"}}
    parts = [run_of(d, err, i) for i, d in enumerate(("ccw", "cw", "ccw", "cw"))]
    t = np.concatenate([p.time_s + k * (N + 1) * DT for k, p in enumerate(parts)])
    axes = {a: AxisRun(cmd=np.concatenate([p.axes[a].cmd for p in parts]),
                       tcp=np.concatenate([p.axes[a].tcp for p in parts])) for a in "XY"}
    Run(t, axes).write_csv(tmp_path / "four.csv")
    res = analyse_circle(read_run(tmp_path / "four.csv"), R)
    assert [p.direction for p in res.passes] == ["ccw", "cw", "ccw", "cw"]
    for p in res.passes:
        after = p.sensors["tcp"].spikes_after_terms()
        assert all(abs(after[q] - 3e-6) < 0.25e-6 for q in "ABCD"), (p.direction, after)
    Run(t[:2 * (N + 1)], {a: AxisRun(cmd=r.cmd[:2 * (N + 1)], tcp=r.tcp[:2 * (N + 1)])
                          for a, r in axes.items()}).write_csv(tmp_path / "pair.csv")
    parts[3].write_csv(tmp_path / "cw.csv")
    assert main(["circle", str(tmp_path / "pair.csv"), str(tmp_path / "cw.csv"),
                 "--radius", "35"]) == 0
    out = capsys.readouterr().out
    rows = {line.split("  ")[0]: line.split() for line in out.splitlines()
            if line.startswith(("CCW ", "CW ")) and " tcp " in line}
    assert set(rows) == {"CCW", "CW 1", "CW 2*"}, rows
    assert "*: a circle the run pairs with none" in " ".join(out.split())
    assert float(rows["CW 2*"][3]) > 5.0  # its own terms: the backlash in its spikes
    assert "circle diagnostics (tcp, of CCW 1 and CW 1)" in out


def test_the_circle_table_says_what_its_contour_error_is_measured_from(capsys, pair):
    """The circle's contour error is the largest radial error about the nominal circle;
    tcpmm contour measures against the command, and a command a filter pulled inside the
    circle read the same run 15.24 against 16.44 um under one name."""
    code, out, _ = run_cli(capsys, "circle", pair / "ccw.csv", pair / "cw.csv", "--radius", 35)
    assert code == 0 and "contour max |e| of the radial error about the nominal circle" in out


def test_cli_pair_prints_the_diagnostics_in_80_columns_and_json(capsys, pair):
    code, out, _ = run_cli(capsys, "circle", pair / "ccw.csv", pair / "cw.csv", "--radius", 35)
    assert code == 0
    # the tables in 80 columns; their titles (the runs' names), captions and what is not
    # determined are lines of their own, never wrapped in a pipe
    lines = [line for line in out.splitlines() if not line.startswith(
        (str(pair), "A-D: reversal spike", "G(b) alone: the G(b)", "±95%: 2 standard",
         "not ranked: "))
        and ": not determined; " not in line]
    assert max(len(line) for line in lines) <= 80 and "…" not in out  # COLUMNS=80 for rich
    for text in ("backlash X", "squareness", "µm/m", "scale mismatch", "ppm", "servo mismatch",
                 "ms", "circularity G, G(b)", "spike A after the pair's terms"):
        assert text in out, text
    code, out, _ = run_cli(capsys, "circle", pair / "cw.csv", pair / "ccw.csv", "--radius", 35,
                       "--json")
    assert code == 0
    got = json.loads(out)
    terms = {t["term"]: (t["value"], t["unit"]) for t in got["diagnostics"]["terms"]}
    assert [p["direction"] for p in got["passes"]] == ["cw", "ccw"]
    # run files round the positions to 0.1 nm: the injected terms at well under 1 %
    assert terms["backlash_X"] == (pytest.approx(4.0, rel=0.01), "um")
    assert terms["squareness"] == (pytest.approx(50.0, rel=0.01), "um/m")
    assert terms["scale_mismatch"] == (pytest.approx(80.0, rel=0.01), "ppm")
    assert terms["servo_mismatch"] == (pytest.approx(0.2, rel=0.01), "ms")
    assert terms["cyclic_period_X"] == (None, "mm")
    # each spike after the terms carries the 95 % uncertainty the table of passes gives it
    u95 = {t["term"]: t["uncertainty_95"] for t in got["diagnostics"]["terms"]}
    for p in got["passes"]:
        sc = next(c for c in p["sensors"] if c["sensor"] == got["diagnostics"]["sensor"])
        for q in "ABCD":
            given = sc.get(f"spike_after_terms_{q}_uncertainty_95_um")
            if given is not None:
                assert u95[f"spike_{q}_{p['direction']}"] == pytest.approx(given, rel=1e-9)
    assert any(v is not None for k, v in u95.items() if k.startswith("spike_"))


def test_cli_single_run_stays_as_it_was(capsys, pair):
    code, out, _ = run_cli(capsys, "circle", pair / "ccw.csv", "--radius", 35, "--json")
    assert code == 0
    got = json.loads(out)
    assert "diagnostics" not in got and [p["direction"] for p in got["passes"]] == ["ccw"]
    code, _, err = run_cli(capsys, "circle", pair / "ccw.csv", pair / "ccw.csv", "--radius", 35)
    assert code == 2 and "no CW circle" in err and "Traceback" not in err
    code, _, err = run_cli(capsys, "circle", pair / "ccw.csv", pair / "cw.csv", "--radius", 35,
                       "--direction", "ccw")
    assert code == 2 and "not both" in err


def test_cli_names_a_quadrant_point_at_the_start(capsys, tmp_path):
    run_of("ccw", {}, start_deg=90.0).write_csv(tmp_path / "b.csv")
    code, out, err = run_cli(capsys, "circle", tmp_path / "b.csv", "--radius", 35)
    assert code == 0
    assert "warning:" in err and "quadrant point B (90 deg)" in " ".join(err.split())
    row = next(line for line in out.splitlines() if "tcp" in line)
    assert row.split()[3] == "n/a"  # column B


def test_bench_c_pair_finds_no_geometric_error(capsys):
    """Machine C's simulator has no geometric errors and no lateral play: squareness and
    lateral play read ~0 whatever its servo and friction do to the circles."""
    d = bench_path("c")
    code, out, _ = run_cli(capsys, "circle", d / "circle_ccw_meas.csv", d / "circle_cw_meas.csv",
                       "--radius", 35, "--json")
    assert code == 0
    terms = {t["term"]: t["value"] for t in json.loads(out)["diagnostics"]["terms"]}
    assert abs(terms["squareness"]) < 2.0  # um/m: 0.035 um of radial error
    assert abs(terms["lateral_play_X"]) < 0.2 and abs(terms["lateral_play_Y"]) < 0.2
    assert abs(terms["centre_offset_X"]) < 0.2 and abs(terms["centre_offset_Y"]) < 0.2


def _bench_arcs(d, lo, span, tmp_path):
    """Machine ``d``'s measured CCW and CW circles cut to the angles ``lo`` to ``lo + span``
    [deg], as run files [-]."""
    import pandas as pd

    out = []
    for way in ("ccw", "cw"):
        run = pd.read_csv(d / f"circle_{way}_meas.csv")
        a = np.degrees(np.unwrap(np.arctan2(run.y_cmd_mm, run.x_cmd_mm))) % 360.0
        k = np.flatnonzero((a >= lo) & (a <= lo + span))
        k = k[k >= 300]  # past the start from rest at 0 deg: one stretch of the turn
        run.iloc[k[0]:k[-1] + 1].to_csv(path := tmp_path / f"{way}_{lo}_{span}.csv",
                                         index=False)
        out.append(path)
    return out


def test_short_and_one_way_arcs_of_bench_circles_give_no_terms(tmp_path):
    """Machine D's measured circles cut to arcs: one direction over 120 deg read a centre
    offset of 14.4 um, a bow of 10.6 um and a backlash of 5.1 um where its full turns read
    0, 0 and 2.0 um, and a pair of 120 deg arcs a lateral play of 6.2 um for 0; now neither
    gives terms, and both say why. A pair of 220 deg arcs, a ballbar's, comes within
    0.25 um of the full turns' centre, backlash, lateral play and bows."""
    from tcpmm.analysis.circle_single import one_direction_diagnostics

    d = bench_path("d")
    whole = circle_diagnostics(*[analyse_circle(read_run(d / f"circle_{w}_meas.csv"), R)
                                 for w in ("ccw", "cw")])
    ccw, cw = _bench_arcs(d, 100.0, 120.0, tmp_path)
    with warnings.catch_warnings():  # the arcs hold some quadrant points only
        warnings.simplefilter("ignore", InputWarning)
        one = one_direction_diagnostics(analyse_circle(read_run(ccw), R))
        pair = circle_diagnostics(analyse_circle(read_run(ccw), R),
                                  analyse_circle(read_run(cw), R))
        long = circle_diagnostics(*[analyse_circle(read_run(p), R)
                                    for p in _bench_arcs(d, 60.0, 220.0, tmp_path)])
    for diag, what in ((one, "one direction over an arc"), (pair, "a pair of arcs")):
        for term in ("centre_offset_X", "centre_offset_Y", "backlash_X", "straightness_X"):
            assert np.isnan(diag[term]) and what in diag.undetermined[term], term
        # nor spikes after terms it does not have: they were the raw ones, ranked the only
        # source of the error, 100 % of it
        spikes = [v for k, (v, _) in diag.terms.items() if k.startswith("spike_")]
        assert spikes and all(np.isnan(spikes)) and "reversal_spikes" in diag.undetermined
        assert diag.ranking == []
    for term in ("centre_offset_X", "centre_offset_Y", "backlash_X", "backlash_Y",
                 "lateral_play_X", "lateral_play_Y", "straightness_X", "straightness_Y"):
        assert long[term] == pytest.approx(whole[term], abs=0.25e-6), term


SPIKE_5 = {(d, "B"): (5e-6, 6.0) for d in ("ccw", "cw")}


@pytest.mark.parametrize("direction", ["ccw", "cw"])
@pytest.mark.parametrize("err, spike_b", [
    ({"tau_y": 1e-3}, 0.0),
    ({"cx": 10e-6}, 0.0),
    ({"tau_y": 1e-3, "cx": 10e-6, "spikes": SPIKE_5}, 5e-6),
    ({"tau_y": 1e-3, "cx": 10e-6, "eps_x": 80e-6, "alpha": 50e-6, "spikes": SPIKE_5}, 5e-6),
], ids=["servo", "centre", "spike+servo+centre", "spike+all"])
def test_the_headline_spike_is_after_the_fitted_terms(direction, err, spike_b):
    """A servo mismatch of 1 ms alone makes raw spikes of 18.6 um at A-D, a centre offset of
    10 um 6.5 um at B and D: the headline spike, after the terms fitted to the circle, is
    the reversal transient alone (0, or the 5 um injected at B); the raw e - b stays."""
    res = analyse_circle(run_of(direction, err), R)
    [p] = res.passes
    sc = p.sensors["tcp"]
    after = sc.spikes_after_terms()
    for q in "ABCD":
        want = spike_b if q == "B" else 0.0
        assert after[q] == pytest.approx(want, abs=0.1e-6 + 0.02 * want), q
    raw = sc.spikes
    assert max(abs(raw[q] - (spike_b if q == "B" else 0.0)) for q in "ABCD") > 5e-6
    [row] = [r for r in p.table() if r["sensor"] == "tcp"]
    assert row["spike_after_terms_B_um"] == pytest.approx(after["B"] * 1e6)
    assert row["spike_B_um"] == pytest.approx(raw["B"] * 1e6)  # what compare takes


def test_the_circle_table_and_the_report_lead_with_the_spike_after_the_terms(capsys,
                                                                            tmp_path):
    from tcpmm.report.circles import key_figures

    err = {"tau_y": 1e-3, "cx": 10e-6, "spikes": SPIKE_5}
    run = run_of("ccw", err)
    run.write_csv(tmp_path / "r.csv")
    code, out, _ = run_cli(capsys, "circle", tmp_path / "r.csv", "--radius", 35)
    assert code == 0 and "after the fitted terms" in " ".join(out.split())
    row = next(line for line in out.splitlines() if "tcp" in line).split()
    assert [float(c) for c in row[2:6]] == pytest.approx([0, 5, 0, 0], abs=0.06)
    code, out, _ = run_cli(capsys, "circle", tmp_path / "r.csv", "--radius", 35, "--json")
    [tcp] = [r for r in json.loads(out)["passes"][0]["sensors"] if r["sensor"] == "tcp"]
    assert tcp["spike_after_terms_B_um"] == pytest.approx(5.0, abs=0.06)
    assert tcp["spike_B_um"] == pytest.approx(analyse_circle(run, R).passes[0]
                                              .sensors["tcp"].spikes["B"] * 1e6)
    text = key_figures(analyse_circle(run, R))
    assert "largest reversal spike after the fitted terms 5.0" in text and " at B" in text


def test_the_terms_are_ranked_by_the_g_each_makes_alone():
    """Each term's contribution is the peak to valley of its radial error alone: b for
    backlash, m R for a scale mismatch, w dt R for a servo mismatch, a R for squareness,
    2 |c| for a centre offset, 2 k for a bow, the spike's height for the spikes; the rank
    is by the G it alone makes, the same but k / 2 for a bow (half of it is a shift of the
    circle) and none for the centre offset."""
    err = {"b_x": 4e-6, "eps_x": 150e-6, "tau_y": 0.2e-3, "alpha": 80e-6, "cx": 1e-6,
           "str_y": 1.5e-6, "spikes": {("ccw", "B"): (8e-6, 6.0)}}
    diag = diagnose(err)
    want = {"backlash_X": 4e-6, "scale_mismatch": 150e-6 * R, "servo_mismatch": W * 0.2e-3 * R,
            "squareness": 80e-6 * R, "centre_offset": 2e-6, "straightness_Y": 3e-6,
            "reversal_spikes": 8e-6}
    alone = {**want, "centre_offset": 0.0, "straightness_Y": 0.75e-6}
    got = {r["term"]: r for r in diag.ranking}
    for term, v in want.items():
        assert got[term]["contribution_m"] == pytest.approx(v, rel=0.02, abs=0.1e-6), term
        assert got[term]["g_alone_m"] == pytest.approx(alone[term], rel=0.02, abs=0.1e-6), term
    order = [r["term"] for r in diag.ranking]
    moving = [k for k in sorted(alone, key=lambda k: -alone[k]) if alone[k] > 0]
    assert order[:len(moving)] == moving
    assert [r["rank"] for r in diag.ranking] == list(range(1, len(order) + 1))
    assert sum(r["share"] for r in diag.ranking) == pytest.approx(1.0)
    for r in diag.ranking:  # what of G(b) each makes alone
        assert r["share_of_G"] == pytest.approx(r["g_alone_m"] / diag["circularity_pair"])
    assert diag.to_dict()["ranking"][0]["term"] == "reversal_spikes"


@pytest.mark.parametrize("seed", [1, 6, 11])
def test_one_direction_reads_no_spike_from_a_reversal_a_little_off_its_point(seed):
    """One CCW circle, backlash X 3 um and Y 4 um, Y lagging by 0.4 ms: its ellipse would
    move the reversals by 0.35 samples, under the half sample at which the backlash and
    the spikes are left open, and the fit places each step at its point. A sample between
    the point and the real reversal read the whole backlash as a spike, -4.0 um at B and
    D where none is, in 7 of 12 such runs. The samples the reversal may lie among are no
    part of the spike's window."""
    from tcpmm.analysis.circle_single import diagnose_single

    err = {"b_x": 3e-6, "b_y": 4e-6, "tau_y": 0.4e-3}
    d = diagnose_single(*circle("ccw", err, seed, start_deg=45.0 + 0.37 * seed), "ccw", R)
    assert d["backlash_X"] == pytest.approx(3e-6, abs=0.1e-6)
    for q in "ABCD":
        assert abs(d[f"spike_{q}_ccw"]) < 4.5 * NOISE, q


def test_one_direction_gives_what_it_determines_and_says_why_the_rest_needs_the_pair():
    """A CCW circle alone: radius, centre, scale mismatch, straightness, backlash and the
    45 deg ellipse of squareness and servo mismatch together; squareness and servo
    mismatch apart, lateral play, hysteresis and G(b) need the CW circle, and it says so."""
    from tcpmm.analysis.circle_single import diagnose_single

    err = {"eps_x": 120e-6, "str_x": 2e-6, "cx": 4e-6, "cy": -2e-6, "b_x": 5e-6,
           "b_y": -3e-6, "alpha": 50e-6, "tau_y": 0.3e-3, "cyc_x": ALL["cyc_x"]}
    for d, s in (("ccw", 1.0), ("cw", -1.0)):
        diag = diagnose_single(*circle(d, err, 3), d, R)
        want = {k: v for k, v in expected(err).items()
                if k in ("scale_mismatch", "straightness_X", "straightness_Y",
                         "centre_offset_X", "centre_offset_Y", "backlash_X", "backlash_Y",
                         "cyclic_amplitude_X", "cyclic_period_X", f"radial_deviation_{d}")}
        want["squareness_or_servo"] = 50e-6 + s * W * 0.3e-3
        assert_recovered(diag, want)
        assert diag.directions == (d,)
        for term in ("squareness", "servo_mismatch", "lateral_play_X", "hysteresis",
                     "circularity_pair"):
            assert term in diag.undetermined, term
        assert "squareness keeps its sign" in diag.undetermined["servo_mismatch"]


def test_cli_one_direction_prints_its_terms_and_why_the_others_need_the_pair(capsys, pair):
    code, out, _ = run_cli(capsys, "circle", pair / "ccw.csv", "--radius", 35)
    assert code == 0
    text = " ".join(out.split())
    assert "squareness or servo" in text and "terms ranked by their share of G" in text
    assert "servo mismatch: not determined; one direction shows" in text
    code, out, _ = run_cli(capsys, "circle", pair / "ccw.csv", "--radius", 35, "--json")
    one = json.loads(out)["diagnostics_one_direction"]
    terms = {t["term"]: t["value"] for t in one["terms"]}
    # 50 um/m of squareness and 0.2 ms of Y lag at 0.87 rad/s: 224.5 um/m of ellipse
    assert terms["squareness_or_servo"] == pytest.approx(50.0 + W * 0.2e-3 * 1e6, rel=0.01)
    assert terms["scale_mismatch"] == pytest.approx(80.0, rel=0.01)
    assert "hysteresis" in one["undetermined"] and one["directions"] == ["ccw"]
    assert one["ranking"][0]["rank"] == 1 and "share_percent" in one["ranking"][0]
    assert "percent_of_G" in one["ranking"][0]


def test_cli_one_direction_with_its_sensor_named_is_the_same(capsys, pair):
    """``--sensor tcp``, the sensor taken by default, refused a run of one direction
    ("circle diagnostics need a CCW and a CW circle"), so no other sensor's could be had."""
    code, plain, _ = run_cli(capsys, "circle", pair / "ccw.csv", "--radius", 35)
    code_tcp, named, err = run_cli(capsys, "circle", pair / "ccw.csv", "--radius", 35,
                                   "--sensor", "tcp")
    assert code == code_tcp == 0, err
    assert named == plain and "circle diagnostics (tcp" in named


def arc(direction, err, lo, span, seed=0):
    """The part of a turn from ``lo`` over ``span`` deg, run in ``direction`` [rad, m]."""
    start = (lo if direction == "ccw" else lo + span) + 0.5 * np.degrees(W * DT)
    a, e = circle(direction, err, seed, start_deg=start)
    m = round(span / 360 * N)
    return a[:m + 1], e[:m + 1]


#: What no arc determines: a cyclic error (over part of a turn its columns are a centre and
#: a bow)
ARC_CYCLIC = {f"cyclic_{q}_{a}" for a in "XY" for q in ("amplitude", "period")}
#: Errors of a 220 deg arc test; of those the arc cannot determine, the one lying along the
#: arc's chord is left out (an arc from -20 deg cannot tell X's lateral play and bow)
ARC_ERR = {"alpha": 60e-6, "eps_x": 80e-6, "b_x": 4e-6, "b_y": -3e-6, "tau_y": 0.3e-3,
           "cx": 5e-6, "cy": -3e-6, "p_x": 2e-6, "p_y": 2e-6, "str_x": 2e-6, "str_y": 2e-6}


@pytest.mark.parametrize("lo, blind", [(-20.0, "X"), (70.0, "Y"), (160.0, "X")])
def test_a_pair_of_220_deg_arcs_gives_the_terms_it_determines(lo, blind):
    """A ballbar's 220 deg arcs, out and back: squareness, scale and servo mismatch,
    backlash, centre and the other axis' lateral play and bow are recovered; the lateral play
    and the bow of the axis whose ends the arc does not both reach are named undetermined."""
    err = {k: v for k, v in ARC_ERR.items() if k not in (f"p_{blind.lower()}",
                                                        f"str_{blind.lower()}")}
    diag = diagnose_pair(arc("ccw", err, lo, 220, 1), arc("cw", err, lo, 220, 2), R, (W, W))
    assert set(diag.undetermined) == {f"lateral_play_{blind}", f"straightness_{blind}",
                                      *ARC_CYCLIC}
    assert np.isnan(diag[f"straightness_{blind}"])
    # the radial deviation is the fitted circle's radius: the full circle's mean radius
    want = {k: v for k, v in expected(err).items() if k not in diag.undetermined
            and not k.startswith(("spike", "cyclic"))}
    assert_recovered(diag, want)


@pytest.mark.parametrize("lo", [130.0, -20.0, 250.0])
def test_a_lag_on_220_deg_arcs_makes_no_squareness_or_scale(lo):
    """A pair of 220 deg arcs with nothing but one axis lagging by 8.3 mrad (1 ms at F10000
    on R 20 mm): squareness 16.31 +- 0.03 um/m from 130 deg, a scale mismatch of -8 to
    +19 ppm from other starts. Over an arc the lag's ellipse leans on the centre's
    columns, and the second order of the centre so read went into the terms."""
    err = {"tau_y": 8.33e-3 / W}
    diag = diagnose_pair(arc("ccw", err, lo, 220, 1), arc("cw", err, lo, 220, 2), R, (W, W))
    want = {k: v for k, v in expected(err).items() if k not in diag.undetermined
            and k in ("squareness", "scale_mismatch", "servo_mismatch", "backlash_X",
                      "backlash_Y")}
    assert_recovered(diag, want)


def arc_run(err, lo, span, axes=("X", "Y")):
    """A run out along an arc CCW and back CW, the command and the TCP with ``err``, in the
    plane of ``axes`` [-]."""
    cmd, tcp = [], []
    for i, d in enumerate(("ccw", "cw")):
        s = 1.0 if d == "ccw" else -1.0
        a, e = arc(d, err, lo, span, i)
        start = (lo if d == "ccw" else lo + span) + 0.5 * np.degrees(W * DT)
        th = np.radians(start) + s * W * DT * np.arange(a.size)
        cmd.append(R * np.c_[np.cos(th), np.sin(th)])
        tcp.append((R + e)[:, None] * np.c_[np.cos(a), np.sin(a)])
    cmd, tcp = np.vstack(cmd), np.vstack(tcp)
    return Run(DT * np.arange(len(cmd)), {ax: AxisRun(cmd=cmd[:, j], tcp=tcp[:, j])
                                          for j, ax in enumerate(axes)})


@pytest.mark.parametrize("axes", [("X", "Z"), ("Y", "Z")])
def test_220_deg_arcs_in_xz_and_yz_are_found_and_diagnosed(axes, tmp_path, capsys):
    """A run of a ballbar's 220 deg arcs out and back, in XZ and YZ, was refused as holding
    no full circle; now each arc is a pass and the pair is diagnosed with the terms it
    determines."""
    err = {k: v for k, v in ARC_ERR.items() if k not in ("p_x", "str_x")}
    run = arc_run(err, -20.0, 220.0, axes)
    with pytest.warns(InputWarning, match="arc of 220 deg does not hold quadrant points A"):
        res = analyse_circle(run, R, plane=axes)
    assert [(p.direction, p.is_arc) for p in res.passes] == [("ccw", True), ("cw", True)]
    assert [p.arc_deg for p in res.passes] == pytest.approx([220.0, 220.0], abs=0.5)
    diag = circle_diagnostics(res)
    a, b = axes
    assert set(diag.undetermined) == {f"lateral_play_{a}", f"straightness_{a}",
                                      *{f"cyclic_{q}_{ax}" for ax in axes
                                        for q in ("amplitude", "period")}}
    assert diag["squareness"] == pytest.approx(60e-6, rel=0.02)
    assert diag["scale_mismatch"] == pytest.approx(80e-6, rel=0.02)
    assert diag[f"backlash_{b}"] == pytest.approx(-3e-6, rel=0.02)
    assert diag["servo_mismatch"] == pytest.approx(0.3e-3, rel=0.02)
    run.write_csv(tmp_path / "arcs.csv")
    code, out, _ = run_cli(capsys, "circle", tmp_path / "arcs.csv", "--radius", 35, "--plane",
                       "".join(axes))
    text = " ".join(out.split())
    assert code == 0 and "CCW: an arc of 220 deg" in text
    assert f"straightness {a}: not determined" in text


def test_a_90_deg_arc_is_analysed_with_what_it_determines():
    """A quarter circle over B, refused before: its raw spike at B is the 5 um injected
    there, the points it does not hold are left out; it gives no terms, and says why, and
    so no spike after them, as a pair of such arcs gives none (one direction's own fit of
    centre and ellipses over an arc gave one, where the diagnostics call those terms
    undetermined), nor a residual after them."""
    err = {"spikes": {("ccw", "B"): (5e-6, 6.0)}, "r0": 2e-6}
    run = arc_run(err, 30.0, 90.0)
    with pytest.warns(InputWarning, match="arc of 90 deg does not hold quadrant points A"):
        res = analyse_circle(run, R, direction="ccw")
    [p] = res.passes
    assert p.is_arc and p.arc_deg == pytest.approx(90.0, abs=0.5)
    after, raw = p.sensors["tcp"].spikes_after_terms(), p.sensors["tcp"].spikes
    assert raw["B"] == pytest.approx(5e-6, abs=0.1e-6)
    assert all(np.isnan(after[q]) for q in "ABCD")
    assert all(np.isnan(raw[q]) for q in "ACD")
    with pytest.warns(InputWarning, match="CW arc of 90 deg"):
        diag = circle_diagnostics(analyse_circle(run, R))
    # a pair of 90 deg arcs gives no terms: over so short an arc they carry the servo's
    # and the friction's radial error (test_short_and_one_way_arcs_of_bench_circles...)
    assert {"centre_offset_X", "centre_offset_Y", "squareness", "scale_mismatch",
            "straightness_X", "backlash_X"} <= set(diag.undetermined)
    assert "a pair of arcs of 90 deg" in diag.undetermined["centre_offset_X"]
    from tcpmm.analysis.circle_single import one_direction_diagnostics

    one = one_direction_diagnostics(res)
    for d in (diag, one):  # every term left open says why
        nan = {t for t, (v, _) in d.terms.items() if np.isnan(v) and not t.startswith(
            ("spike", "cyclic_period"))}
        assert nan <= set(d.undetermined), nan - set(d.undetermined)
        # no term fitted leaves no residual: its rms was the radial error's, 14 um
        assert np.isnan(d["residual_rms"]) and "no term is fitted" in d.undetermined[
            "residual_rms"]


def test_the_report_has_the_command_deviation_the_ranking_and_one_directions_terms(
        capsys, tmp_path):
    """A CCW run whose command a filter has pulled in: the report says how far, gives the
    one direction's diagnostics with the ranking, and what needs the CW circle and why."""
    from test_circle import filtered_circle, make_run, polar_perturb

    cmd, shrink = filtered_circle(feed_m_s=5.0 / 60, window_s=0.120)
    tcp = polar_perturb(cmd, (0, 0), lambda a: 2e-6 * np.cos(2 * a))
    make_run(cmd, tcp).write_csv(tmp_path / "ccw.csv")
    out = tmp_path / "r.html"
    code = main(["report", "-o", str(out), "--run", str(tmp_path / "ccw.csv"), "--radius",
                 "35"])
    assert code == 0, capsys.readouterr().err
    text = " ".join(out.read_text(encoding="utf-8").split())
    assert f"the command lies {-shrink * 1e6:.2f} µm inside the nominal radius" in text
    assert "command radius - nominal [µm]" in text
    assert "Diagnostics of the CCW circle alone (TCP)" in text
    assert "Terms ranked by their share of G" in text and "scale mismatch" in text
    assert "servo mismatch: not determined; one direction shows" in text


def test_one_arc_in_one_direction_gives_no_terms_and_says_why():
    """A single CCW arc of 220 deg: one direction over an arc does not separate its terms
    from the servo's and the friction's radial error along it (on bench circles, centre
    offsets and bows of 10 um and more); its radial deviation and G it gives, the terms
    it leaves open each with the reason."""
    from tcpmm.analysis.circle_single import diagnose_single

    err = {"eps_x": 80e-6, "b_y": -3e-6, "cy": -3e-6, "cx": 2e-6, "b_x": 2.5e-6}
    diag = diagnose_single(*arc("ccw", err, -20.0, 220.0, 1), "ccw", R)
    for term in ("centre_offset_X", "centre_offset_Y", "backlash_X", "backlash_Y",
                 "scale_mismatch", "straightness_X", "squareness_or_servo"):
        assert np.isnan(diag[term]), term
        assert "one direction over an arc of 220 deg" in diag.undetermined[term]
    assert np.isfinite(diag["radial_deviation_ccw"]) and diag["circularity_ccw"] > 0
    assert set(ARC_CYCLIC) <= set(diag.undetermined)


def test_a_circle_of_no_error_shares_out_no_g():
    """Where G is a rounding (a circle of a centre offset alone, noise free), a term's share
    of it is no figure: it read 77 392 800 %."""
    from tcpmm.analysis.circle_display import ranking_rows

    rows = ranking_rows({"centre_offset": (13e-6, 0.0), "squareness": (2e-15, 2e-15),
                         "backlash_X": (np.nan, np.nan)}, g=3e-21)
    assert [r["term"] for r in rows] == ["squareness", "centre_offset"]
    assert all(np.isnan(r["share_of_G"]) for r in rows)
    assert ranking_rows({"squareness": (2e-6, 2e-6)}, g=4e-6)[0]["share_of_G"] == 0.5


def test_a_share_of_g_above_100_percent_says_the_other_terms_cancel_part_of_it():
    """A term alone can make more G(b) than the circles, whose other terms cancel part of
    it: 100.6 % printed without a word read as an error of the ranking."""
    from tcpmm.analysis.circle_display import beyond_g_note, ranking_rows
    from tcpmm.report.circles import ranking_html

    rows = ranking_rows({"backlash_X": (5.03e-6, 5.03e-6), "squareness": (1e-6, 1e-6)},
                        g=5e-6)
    assert rows[0]["share_of_G"] == pytest.approx(1.006)
    note = beyond_g_note(rows, "G(b)")
    assert note.startswith("backlash X alone makes more G(b) than the circles")
    assert beyond_g_note(rows[1:], "G(b)") == ""
    diag = diagnose({"b_x": 5e-6})
    diag.ranking[:] = rows
    assert "Backlash X alone makes more G(b)" in " ".join(ranking_html(diag, "c").split())


@pytest.mark.parametrize("start_deg", [START, 47.3, 51.1])
def test_a_centre_offset_moves_no_reversal_step_into_the_spikes(start_deg):
    """The axes of a circle off the nominal centre by c reverse c / R from the nominal
    quadrant points (about the circle's own centre). Sampled finer than that (0.2 mrad a
    sample, c / R = 0.29 mrad), a backlash step placed at the nominal point left a spike of
    the whole backlash after the pair's terms, ranked second."""
    n = 30_000
    w = 2 * np.pi / (n * DT)
    err = {"cx": 10e-6, "b_y": 5e-6}
    diag = diagnose(err, n=n, start_deg=start_deg)
    assert_recovered(diag, expected(err, n=n), w=w)
    ranked = {r["term"]: r for r in diag.ranking}
    # in the noise, not ranked at all, or ranked at the noise's size
    assert ranked.get("reversal_spikes", {"contribution_m": 0.0})["contribution_m"] < 4.5 * NOISE


def test_lateral_play_makes_its_size_of_g_between_the_directions():
    """A lateral play p shifts the circles of the two directions apart by p: all of G(b),
    which the ranking gave as p / 2 (the most within one direction) and 50 %."""
    diag = diagnose({"p_y": 2e-6, "p_x": 1.5e-6}, noise=0.0)
    ranked = {r["term"]: r for r in diag.ranking}
    assert ranked["lateral_play_Y"]["contribution_m"] == pytest.approx(2e-6, rel=0.02)
    assert ranked["lateral_play_X"]["contribution_m"] == pytest.approx(1.5e-6, rel=0.02)
    assert ranked["lateral_play_Y"]["share_of_G"] == pytest.approx(1.0, rel=0.02)


@pytest.mark.parametrize("lo, span", [(100.0, 220.0), (-5.0, 220.0), (51.0, 220.0),
                                      (35.0, 180.0), (130.0, 300.0)])
def test_arcs_from_any_start_keep_the_centre_and_find_no_other_error(lo, span):
    """A centre offset alone, on arcs from start angles the ballbar tests do not use: the
    centre was dropped for terms that stood in for it over the arc (a squareness of 96
    um/m, a bow of 5 um, from a 7 um offset); now the circle's own centre comes first and
    every term found is none."""
    from tcpmm.analysis.circle_stable import MIN_TERMS_DEG

    err = {"cx": -4e-6, "cy": 6e-6}
    diag = diagnose_pair(arc("ccw", err, lo, span, 1), arc("cw", err, lo, span, 2), R, (W, W))
    if span < MIN_TERMS_DEG:  # a pair of short arcs gives no terms, and says why
        assert "a pair of arcs of 180 deg" in diag.undetermined["centre_offset_X"]
        return
    assert not {"centre_offset_X", "centre_offset_Y"} & set(diag.undetermined)
    want = {k: v for k, v in expected(err).items() if k not in diag.undetermined
            and not k.startswith(("spike", "cyclic", "radial_deviation"))}
    assert_recovered(diag, want)


def test_two_columns_that_are_the_same_are_not_each_determined():
    """Over an arc inside one quadrant, backlash X and lateral play Y make the same radial
    error (no X reversal on it): the pseudo-inverse gave each a share of a half, and both
    were reported as determined, each with half of the error. Neither is now: the one a
    twin was left out for goes too, rather than carry both under its name."""
    from tcpmm.analysis.circle_model import column_shares, determined, drop_twins

    a = np.linspace(0.0, 2 * np.pi, 720, endpoint=False)
    same = 0.5 * np.cos(2 * a)
    A = np.c_[np.ones_like(a), np.cos(a), np.sin(a), same, 2 * same]
    share = column_shares(A)
    assert share[3] < 1e-6 and share[4] < 1e-6 and min(share[:3]) > 0.99
    keep = determined(A, protect=[0])
    assert keep.tolist() == [True, True, True, False, True]
    assert drop_twins(A, keep, protect=[0]).tolist() == [True, True, True, False, False]


def test_an_arc_inside_a_quadrant_claims_neither_of_two_terms_it_cannot_tell_apart():
    """60 deg over 15-75 deg, out and back, a lateral play of Y alone: reported as backlash
    X 1.00 and lateral play Y 1.00 um, each at half of G(b). Neither is determined now, and
    no term the arc keeps claims the play (a short arc still lets some of it into others)."""
    err = {"p_y": 2e-6}
    diag = diagnose_pair(arc("ccw", err, 15.0, 60.0, 1), arc("cw", err, 15.0, 60.0, 2), R,
                         (W, W))
    assert {"backlash_X", "lateral_play_Y"} <= set(diag.undetermined)
    for r in diag.ranking:
        if r["term"] not in ("centre_offset", "reversal_spikes"):
            assert r["contribution_m"] < 1e-6, r


def test_one_direction_leaves_the_backlash_open_where_its_ellipse_may_move_the_reversals():
    """CCW only, Y lagging 1 ms at F10000 (a sample's angle at 1 kHz): the ellipse may be
    that mismatch, which moves the reversals by a sample: the backlash read 12 % off and a
    2.6 um spike appeared. Both are left open now, with the reason; a squareness alone of
    the same ellipse's size reads as before, up to the reversals' placing."""
    from tcpmm.analysis.circle_single import diagnose_single

    n = 1320  # 10000 mm/min on R 35: 4.76 rad/s, 1.32 s a turn at 1 kHz
    diag = diagnose_single(*circle("ccw", {"tau_y": 1e-3, "b_x": 4e-6, "b_y": -3e-6}, 1, n=n),
                           "ccw", R)
    for k in ("backlash_X", "backlash_Y", "reversal_spikes"):
        assert "cannot place the axes' reversals" in diag.undetermined[k]
    assert np.isnan(diag["backlash_Y"]) and np.isnan(diag["spike_A_ccw"])
    assert not any(r["term"].startswith("backlash") for r in diag.ranking)
    small = diagnose_single(*circle("ccw", {"alpha": 20e-6, "b_x": 4e-6}, 1, n=n), "ccw", R)
    assert small["backlash_X"] == pytest.approx(4e-6, abs=0.1e-6)
    assert "backlash_X" not in small.undetermined


def test_a_circle_of_few_samples_keeps_its_table_and_says_why_no_diagnostics(tmp_path,
                                                                             capsys):
    """A full circle of 13 samples lost its whole table to an internal message ('needs
    angle and radial error ... at least 100 samples (got (13,) and (13,))')."""
    th = np.radians(30.0) + np.linspace(0, 2 * np.pi, 13)
    x, y = 35 * np.cos(th), 35 * np.sin(th)
    rows = "\n".join(f"{k * 0.05:.3f},{a:.6f},{a:.6f},{b:.6f},{b:.6f}"
                     for k, (a, b) in enumerate(zip(x, y, strict=True)))
    run = tmp_path / "few.csv"
    run.write_text("time_s,x_cmd_mm,x_tcp_mm,y_cmd_mm,y_tcp_mm\n" + rows + "\n")
    assert main(["circle", str(run), "--radius", "35"]) == 0
    cap = capsys.readouterr()
    assert "CCW" in cap.out
    assert ("no diagnostics: the diagnostics need at least 100 samples of a circle; the ccw "
            "one has 13") in " ".join(cap.err.split())


def test_an_arc_just_short_of_the_least_says_so_in_its_reason():
    """A pair of arcs just short of 210 deg was refused its terms "as a pair of arcs of 210
    deg", beside "run the arc ... over 210 deg or more". Sampled finely (0.01 deg), a span
    of 209.7 deg lies short of 210 deg by more than the samples at its ends and the turn
    of the tool's angle (:func:`tcpmm.analysis.circle_model.covers`)."""
    from tcpmm.analysis.circle_fit import Arc
    from tcpmm.analysis.circle_stable import arc_fit
    from tcpmm.analysis.diagnostics import SHARED

    a = np.radians(np.linspace(-20.0, 189.7, 20000))
    arcs = [Arc(a, np.zeros_like(a), 1.0), Arc(a[::-1], np.zeros_like(a), -1.0)]
    _, why = arc_fit(arcs, R, SHARED)
    columns = {k: text for k, text in why.items() if k != "reversal_spikes"}
    assert columns and all("a pair of arcs of 209.7 deg" in t for t in columns.values())
    assert "no terms to take off" in why["reversal_spikes"]


def _pulsed_circle(direction, lag_y_s, n=1320, h=5e-6, tau_s=0.010):
    """One turn at 1 kHz (F10000 on R35) from 45 deg, Y lagging X by ``lag_y_s``, and on X
    a decaying outward pulse from where X itself reverses [rad, m]."""
    s = 1.0 if direction == "ccw" else -1.0
    w = 2 * np.pi / (n * DT)
    t = DT * np.arange(n + 1)
    th = np.radians(START) + s * w * t
    x, y = R * np.cos(th), R * np.sin(th - s * w * lag_y_s)
    sx = np.sign(-s * np.sin(th))
    flips = np.flatnonzero(np.diff(sx) != 0) + 1
    for k in flips:
        x[k:] += np.sign(x[k]) * h * np.exp(-(t[k:] - t[k]) / tau_s)
    return np.unwrap(np.arctan2(y, x)), np.hypot(x, y) - R


@pytest.mark.parametrize("lag_y_s", [0.0, 0.3e-3, 1e-3])
def test_a_reversal_transient_under_a_servo_mismatch_leaves_the_terms_alone(lag_y_s):
    """With Y 1 ms behind X, X reverses a sample before its quadrant point (by the
    mismatch's angle): the first and largest sample of its 5 um transient was fitted as
    the circle, and read 1.8 um of backlash, 78 ppm of scale mismatch and a 1.6 um cyclic
    error, the spikes after the pair's terms 2.8 and 1.4 um where they are 5 and 0."""
    w = 2 * np.pi / (1320 * DT)
    d = diagnose_pair(_pulsed_circle("ccw", lag_y_s), _pulsed_circle("cw", lag_y_s), R,
                      (w, w))
    t = {k: v for k, (v, _) in d.terms.items()}
    assert t["servo_mismatch"] == pytest.approx(lag_y_s, abs=2e-6)
    for k in ("backlash_X", "backlash_Y", "lateral_play_X", "lateral_play_Y"):
        assert abs(t[k]) < 0.05e-6, (k, t[k])
    assert abs(t["scale_mismatch"]) * R < 0.05e-6
    # none found (NaN) or a trace of one
    assert not t["cyclic_amplitude_X"] >= 0.05e-6 and not t["cyclic_amplitude_Y"] >= 0.05e-6
    for dirn in ("ccw", "cw"):
        assert t[f"spike_A_{dirn}"] == pytest.approx(5e-6, abs=0.05e-6)
        assert t[f"spike_C_{dirn}"] == pytest.approx(5e-6, abs=0.05e-6)
        assert abs(t[f"spike_B_{dirn}"]) < 0.05e-6 and abs(t[f"spike_D_{dirn}"]) < 0.05e-6


def test_terms_are_ranked_by_the_g_each_alone_makes():
    """A bow of 2 um peaks at 4 um about the nominal centre, but half of it is a shift of
    the circle that G leaves out: alone it makes G 1 um. It was credited with 4 um and
    100 % of G(b) and ranked above a backlash of 3 um (which makes 3 um of G)."""
    d = diagnose({"str_x": 2e-6, "b_y": 3e-6}, noise=0.0)
    rows = {r["term"]: r for r in d.ranking}
    assert [r["term"] for r in d.ranking[:2]] == ["backlash_Y", "straightness_X"]
    assert rows["straightness_X"]["g_alone_m"] == pytest.approx(1e-6, abs=0.02e-6)
    assert rows["straightness_X"]["contribution_m"] == pytest.approx(4e-6, abs=0.02e-6)
    assert rows["backlash_Y"]["g_alone_m"] == pytest.approx(3e-6, abs=0.02e-6)
    gb = d.terms["circularity_pair"][0]
    assert rows["backlash_Y"]["share_of_G"] == pytest.approx(rows["backlash_Y"]["g_alone_m"] / gb)
    assert rows["centre_offset"]["g_alone_m"] < 1e-9
    alone = diagnose({"str_x": 2e-6}, noise=0.0)
    top = alone.ranking[0]
    assert top["term"] == "straightness_X" and top["share_of_G"] == pytest.approx(1, abs=0.02)


def test_the_radial_deviation_of_arcs_is_the_fitted_circles_radius():
    """On a pair of 220 deg arcs the radial deviation was the mean of the whole fitted
    curve over the arc: a centre offset of (4, -3) um with the radius exact read -1.47 um.
    It is the fitted circle's radius less the nominal, as on full circles."""
    a = np.radians(np.linspace(-20.0, 200.0, 2201))
    cx, cy, dr = 4e-6, -3e-6, 0.5e-6
    x, y = (R + dr) * np.cos(a) + cx, (R + dr) * np.sin(a) + cy
    ang, e = np.unwrap(np.arctan2(y, x)), np.hypot(x, y) - R
    w = 2 * np.pi / (N * DT)
    d = diagnose_pair((ang, e), (ang[::-1], e[::-1]), R, (w, w))
    for k in ("radial_deviation_ccw", "radial_deviation_cw", "radial_deviation_pair"):
        assert d.terms[k][0] == pytest.approx(dr, abs=0.01e-6), k
    assert d.terms["centre_offset_X"][0] == pytest.approx(cx, abs=0.01e-6)


@pytest.mark.parametrize(("err", "other_points"), [
    ({"str_x": 2e-6}, "ABCD"), ({"cyc_x": (1e-6, 10e-3, 0.5)}, "ABCD"),
    ({"b_y": -3e-6}, "AC"), ({"b_x": 4e-6}, "BD")])
def test_the_headline_spikes_of_a_pair_are_after_the_pairs_terms(err, other_points):
    """One circle's own fit left a bow (0.76 um), a cyclic error (0.99 um) and 15 % of the
    other axis's backlash in the spikes a user reads first; with a CCW and a CW circle the
    headline is the spike after the pair's terms, which fit them. None of these runs has a
    reversal transient."""
    from tcpmm.analysis.circular import CircleResult

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", InputWarning)
        ccw, cw = (analyse_circle(run_of(d, err), R) for d in ("ccw", "cw"))
    both = CircleResult(R, (0.0, 0.0), ccw.passes + cw.passes)
    for p in both.passes:
        s = p.sensors["tcp"]
        assert s.after_pair
        for q in other_points:
            assert abs(s.spikes_after_terms()[q]) < 0.02e-6, (p.direction, q)
    alone = analyse_circle(run_of("ccw", {"str_x": 2e-6}), R).passes[0].sensors["tcp"]
    assert not alone.after_pair
    assert max(abs(v) for v in alone.spikes_after_terms().values()) > 0.5e-6


def test_an_arc_says_its_undetermined_terms_bias_the_others_where_present():
    """An arc that leaves a bow out of its fit misreads the other terms where the bow is in
    the data (1.5 um read as 30 um/m of squareness), and said only that it did not
    determine the bow."""
    err = {k: v for k, v in ARC_ERR.items() if k not in ("p_x", "str_x")}
    d = diagnose_pair(arc("ccw", err, -20.0, 220, 1), arc("cw", err, -20.0, 220, 2), R,
                      (W, W))
    why = d.undetermined["straightness_X"]
    assert "take it over where it is present" in why and "another start angle" in why


def test_a_circle_without_a_cyclic_error_reports_no_period():
    """On noise-free circles without any cyclic error, a period of 38.7 mm was reported
    with an amplitude of 0.002 um: the noise floor the search needs to stand out of
    vanishes without noise."""
    w = 2 * np.pi / (1320 * DT)
    d = diagnose_pair(_pulsed_circle("ccw", 0.0), _pulsed_circle("cw", 0.0), R, (w, w))
    for axis in "XY":
        assert np.isnan(d.terms[f"cyclic_amplitude_{axis}"][0])
        assert np.isnan(d.terms[f"cyclic_period_{axis}"][0])
    found = diagnose({"cyc_x": (0.5e-6, 10e-3, 0.3)}, noise=0.0)
    assert found.terms["cyclic_amplitude_X"][0] == pytest.approx(0.5e-6, rel=0.02)


def ringing(direction, err, seed, amp, period_deg=12.0, decay_deg=25.0):
    """A circle whose radius rings after every quadrant point, as the tool does once a
    reversal has flipped the friction under the column: a decaying sine of the angle past
    the point, ``amp`` at its start [rad, m]."""
    a, e = circle(direction, err, seed)
    s = 1.0 if direction == "ccw" else -1.0
    past = (s * np.degrees(a)) % 90.0
    return a, e + amp * np.exp(-past / decay_deg) * np.sin(2 * np.pi * past / period_deg)


@pytest.mark.parametrize("amp", [0.5e-6, 2e-6])
def test_ringing_after_the_reversals_is_no_cyclic_error(amp):
    """A circle without any cyclic error that rings after its reversals was given one
    (0.5 to 1.8 um at the demo's TCP, with a period of 1.1 mm that only the samples after
    a reversal hold): a screw's pitch error is the same whichever way the axis turned
    last, and a period seen after the reversals only is none."""
    d = diagnose_pair(ringing("ccw", {}, 1, amp), ringing("cw", {}, 2, amp), R, (W, W))
    for axis in "XY":
        assert np.isnan(d[f"cyclic_amplitude_{axis}"])
        assert np.isnan(d[f"cyclic_period_{axis}"])


def test_a_cyclic_error_beside_ringing_is_still_found():
    """The test of a period against the direction of travel keeps a screw's pitch error
    whose circle rings after its reversals as well."""
    err = {"cyc_x": (0.8e-6, 6e-3, 1.0), "cyc_y": (0.5e-6, 9e-3, 2.0)}
    d = diagnose_pair(ringing("ccw", err, 1, 0.5e-6), ringing("cw", err, 2, 0.5e-6), R,
                      (W, W))
    assert_recovered(d, {k: v for k, v in expected(err).items() if k.startswith("cyclic")})


@pytest.mark.parametrize("seed", [127, 139])
def test_cyclic_errors_under_a_servo_mismatch_and_noise(seed):
    """Every error at once with a 1 ms servo mismatch and 0.2-0.5 um of noise: the test of
    a period against the direction of travel is made on the periods refined with the other
    axis' fitted; made on the first scan's, whose period was a little off, it dropped one
    axis' cyclic error of 0.97 um (and put the other's 15 % off)."""
    rng = np.random.default_rng(seed)
    err = draw(rng)
    err["tau_y"] = rng.choice([-1.0, 1.0]) * 1e-3
    noise = rng.choice([0.05e-6, 0.2e-6, 0.5e-6])
    assert noise >= 0.2e-6
    d = diagnose(err, noise=noise)
    assert_recovered(d, {k: v for k, v in expected(err).items() if k.startswith("cyclic")})


def test_circle_command_places_the_terms_past_the_scale(capsys, tmp_path):
    """``tcpmm circle`` of bench C's TCP gave "backlash Y 13.5 um" with nothing to say that
    the scale sees 0.2 um of it (its nut has none: the column flips with the guideway's
    friction); the ranking now has the scale's figure beside each term, marked where the
    scale sees less than half, and ``--json`` says where it lies. A run without a scale
    has neither."""
    import pandas as pd

    c = bench_path("c")
    runs = [c / "circle_ccw_meas.csv", c / "circle_cw_meas.csv"]
    code, out, _ = run_cli(capsys, "circle", *runs, "--radius", 35, "--json")
    assert code == 0
    rank = {r["term"]: r for r in json.loads(out)["diagnostics"]["ranking"]}
    back = rank["backlash_Y"]
    assert back["g_alone_um"] > 5 and back["scale_g_alone_um"] < 0.2 * back["g_alone_um"]
    assert back["where"].startswith("mostly past the linear scale")
    code, out, _ = run_cli(capsys, "circle", *runs, "--radius", 35)
    assert code == 0 and "scale µm" in out
    assert any("backlash Y" in line and line.rstrip().endswith("*")
               for line in out.splitlines())
    bare = []
    for f in runs:
        df = pd.read_csv(f)
        bare.append(tmp_path / f.name)
        df.drop(columns=[k for k in df if "_scale_" in k]).to_csv(bare[-1], index=False)
    code, out, _ = run_cli(capsys, "circle", *bare, "--radius", 35, "--json")
    assert code == 0
    assert all("scale_g_alone_um" not in r for r in json.loads(out)["diagnostics"]["ranking"])


@pytest.mark.parametrize("machine", ["r05", "h"])
def test_no_cyclic_error_on_machines_without_one(machine):
    """The reference machines of the independent simulator have no pitch error. At F10000
    R05's TCP circles read a cyclic error of 42.7 um of X at a period of 35.0 mm (the
    radius: the scan's refinement left its band); H's, whose reversals are 200 um, hold
    periods whose halves agree (58.7 um of Y at 9.7 mm where eight periods are tried). A
    period over fewer than three turns of the diameter, or a cyclic error below what the
    fit leaves, is none."""
    d = bench_path(machine)
    res = [analyse_circle(read_run(d / f"circle_{w}_fast_meas.csv"), 0.035)
           for w in ("ccw", "cw")]
    diag = circle_diagnostics(*res)
    for axis in "XY":
        assert np.isnan(diag[f"cyclic_amplitude_{axis}"]), axis


def test_a_cyclic_error_not_found_says_so():
    """A cyclic error that does not stand out of the residual read 0.00 um beside "e.g.
    screw pitch error", as if the screw had none, where one about as large as the residual
    may hide in it: a 1 um pitch error under 5 um of ringing after the reversals (0.8 um
    rms left) is not found.
    It reads n/a, and the diagnostics say why and by how much the axis may have one. The
    report's ranking, which holds only cyclic errors found, does not carry the note."""
    from tcpmm.analysis.diagnostics import term_note
    from tcpmm.report.acceptance import ranked_sources

    assert term_note("cyclic_amplitude_X").endswith("; n/a: unresolved")
    err = {"cyc_x": (1e-6, 6e-3, 0.5)}
    d = diagnose_pair(ringing("ccw", err, 1, 5e-6), ringing("cw", err, 2, 5e-6), R, (W, W))
    rms_um = d["residual_rms"] * 1e6
    assert rms_um > 0.5
    for axis in "XY":
        assert np.isnan(d[f"cyclic_amplitude_{axis}"]) and np.isnan(d[f"cyclic_period_{axis}"])
        why = d.undetermined[f"cyclic_amplitude_{axis}"]
        assert f"({rms_um:.2f} µm rms)" in why and "not resolved" in why
    d = diagnose({"cyc_x": (1e-6, 6e-3, 0.5)})
    assert "cyclic_amplitude_X" not in d.undetermined
    assert "cyclic_amplitude_Y" in d.undetermined
    (cyc,) = [n for s, _, n, _ in ranked_sources(d) if s == "cyclic X"]
    assert cyc == "e.g. pitch error"


@pytest.mark.parametrize("fast, others_um", [("", 0.1), ("_fast", 0.2)])
def test_lost_motion_where_the_axis_reverses_is_recovered_on_a_measured_pair(
        tmp_path, fast, others_um):
    """5 um of lost motion in X put into bench C's TCP circles (an independent simulator's
    machine, with a 25 ms servo lag and a column that flips at each reversal) where X
    reverses: the backlash X rises by 5 um within 2 %, and every other term moves by less
    than ``others_um`` of radial error. Put in where the command reverses instead, 25 ms
    before the axis does, it is no backlash of the axis and reads 2.6-4.1 um: a test must
    step the axis where it turns."""
    import pandas as pd

    c = bench_path("c")
    before, after = [], []
    for d in ("ccw", "cw"):
        run = pd.read_csv(c / f"circle_{d}{fast}_meas.csv")
        v = np.gradient(run["x_scale_mm"].to_numpy(), run["time_s"].to_numpy())
        sign = np.sign(v) * (np.abs(v) > 1.0)  # held through the reversal's rest
        for k in range(1, sign.size):
            sign[k] = sign[k] or sign[k - 1]
        run["x_tcp_mm"] -= 2.5e-3 * sign
        run.to_csv(tmp_path / f"{d}.csv", index=False)
        before.append(analyse_circle(read_run(c / f"circle_{d}{fast}_meas.csv"), 0.035))
        after.append(analyse_circle(read_run(tmp_path / f"{d}.csv"), 0.035))
    d0, d1 = circle_diagnostics(*before, sensor="tcp"), circle_diagnostics(*after, sensor="tcp")
    assert d1["backlash_X"] - d0["backlash_X"] == pytest.approx(5e-6, rel=0.02)
    radial = {"servo_mismatch_angle": 0.035, "scale_mismatch": 0.035, "squareness": 0.035}
    for term in ("backlash_Y", "lateral_play_X", "lateral_play_Y", "centre_offset_X",
                 "centre_offset_Y", "straightness_X", "straightness_Y", *radial):
        moved = abs(d1[term] - d0[term]) * radial.get(term, 1.0)
        assert moved < others_um * 1e-6, (term, moved)


@pytest.mark.parametrize("machine", ["c", "d"])
def test_a_full_circle_sampled_at_250_hz_is_a_full_circle(tmp_path, machine):
    """Bench C's and D's F5000 circles with every fourth row kept (250 Hz, a ballbar's
    rate): the pair was refused ("covers 359 deg and 359 deg of other angles") and one run
    alone called an arc of 358.5 deg. A sensor's turn lacks up to a sample at either end
    beyond the command's; it is a full circle, whose terms are those of all the rows."""
    import pandas as pd

    d = bench_path(machine)
    full, coarse = [], []
    for w in ("ccw", "cw"):
        full.append(analyse_circle(read_run(d / f"circle_{w}_meas.csv"), 0.035))
        pd.read_csv(d / f"circle_{w}_meas.csv").iloc[::4].to_csv(tmp_path / f"{w}.csv",
                                                                 index=False)
        coarse.append(analyse_circle(read_run(tmp_path / f"{w}.csv"), 0.035))
    a, b = (circle_diagnostics(*r, sensor="tcp") for r in (full, coarse))
    assert not any(k.startswith(("backlash", "centre")) for k in b.undetermined)
    for term in ("backlash_X", "backlash_Y", "centre_offset_X", "centre_offset_Y"):
        assert b[term] == pytest.approx(a[term], abs=0.15e-6), term


def test_a_term_of_the_geometry_seen_at_the_scale_is_called_the_loops():
    """A scale mismatch or squareness at the TCP that the linear scale sees as well was
    called "at the linear scale too: in the axis", and one the scale does not see "the
    structure ... not the drive". The scale reads its own axis: a geometric error between
    two axes cannot show in it, so seen there it is the loops' response to the path (it
    changes with the feed); unseen there it is the geometry or the structure deflecting,
    which a slower circle tells apart. Other terms read as before."""
    from tcpmm.analysis.circle_display import term_place

    for term in ("scale_mismatch", "squareness", "squareness_or_servo"):
        seen = term_place(10e-6, 8e-6, "linear scale", term)
        assert seen.startswith("at the linear scale too: the loops' response") and \
            "changes with the feed" in seen
        unseen = term_place(10e-6, 1e-6, "linear scale", term)
        assert "the geometry between the axes" in unseen and "lower feed" in unseen
    assert term_place(10e-6, 8e-6, "linear scale", "backlash_X") == \
        "at the linear scale too: in the axis"
    assert term_place(10e-6, 1e-6, "linear scale", "backlash_X").endswith("not the drive")


@pytest.mark.parametrize("start_deg", [45.0, 10.0, 60.0])
def test_a_sample_on_a_reversal_point_makes_no_spike(start_deg):
    """Started on a round angle, a circle has samples on the quadrant points to the
    rounding, where the backlash step has no side (or lies half-way): the spike after the
    pair's terms read the backlash, 3-10 um for none, from that one sample."""
    err = {"b_x": 6e-6, "b_y": 3e-6}
    diag = diagnose(err, start_deg=start_deg)
    spikes = [diag[f"spike_{q}_{d}"] for q in "ABCD" for d in ("ccw", "cw")]
    assert sum(np.isfinite(spikes)) >= 6  # those whose window the circles hold
    assert all(abs(v) <= 4.5 * NOISE for v in spikes if np.isfinite(v)), spikes
    assert diag["backlash_X"] == pytest.approx(6e-6, rel=0.02)
    assert diag["backlash_Y"] == pytest.approx(3e-6, rel=0.02)


def fed_in_filtered_turn(direction, window_s=0.036, start_deg=58.0, radius=R,
                         feed_m_s=10.0 / 60, dt=1e-3):
    """One turn entered and left by semicircles of R/2 from the centre (a ballbar program),
    through a moving average of ``window_s`` as a controller's filter after interpolation
    [m]."""
    s = 1.0 if direction == "ccw" else -1.0
    v, a0 = feed_m_s, np.radians(start_deg)
    th = a0 + s * (v / radius) * dt * np.arange(round(2 * np.pi * radius / (v * dt)) + 1)
    m = round(np.pi * radius / 2 / (v * dt))

    def half(a, phases):
        u, t = np.array([np.cos(a), np.sin(a)]), s * np.array([-np.sin(a), np.cos(a)])
        return (radius / 2) * (np.outer(1 + np.cos(phases), u) + np.outer(np.sin(phases), t))

    fin = half(a0, np.linspace(np.pi, 2 * np.pi, m + 1)[:-1])
    fout = half(th[-1], np.linspace(0, np.pi, m + 1)[1:])
    p = np.vstack([np.repeat(fin[:1], 200, axis=0), fin,
                   radius * np.c_[np.cos(th), np.sin(th)], fout,
                   np.repeat(fout[-1:], 200, axis=0)])
    k = round(window_s / dt)
    pad = np.vstack([np.repeat(p[:1], k - 1, axis=0), p])
    return np.c_[[np.convolve(pad[:, j], np.ones(k) / k, "valid") for j in (0, 1)]].T


def test_a_filtered_turn_out_of_a_feed_in_arc_reads_no_terms_the_machine_has_not():
    """A filter after interpolation (36 ms at F10000) leaves the command 1-16 um off the
    circle's level over the first and last degrees of a turn entered from a feed-in arc.
    Taken as part of the circle, those samples read as 16 um/m of squareness and 24 ppm of
    scale on a machine that follows its command exactly; the pass is the part the command
    has settled on, and with a scale mismatch of 60 ppm the terms are the machine's."""
    from test_circle import make_run, polar_perturb

    scale = 60e-6
    runs = {}
    for d in ("ccw", "cw"):
        cmd = fed_in_filtered_turn(d)
        tcp = polar_perturb(cmd, (0, 0), lambda a: scale * R / 2 * np.cos(2 * a))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            runs[d] = analyse_circle(make_run(cmd, tcp), R)
    [p] = runs["ccw"].passes
    assert 345.0 < p.arc_deg < 360.0  # the settled part of the turn
    assert p.command_radial_deviation == pytest.approx(-42.81e-6, abs=0.02e-6)
    diag = circle_diagnostics(runs["ccw"], runs["cw"])
    assert diag["scale_mismatch"] == pytest.approx(scale, rel=0.02)
    for term in ("squareness", "backlash_X", "backlash_Y", "centre_offset_X",
                 "centre_offset_Y", "straightness_X", "straightness_Y"):
        size = radial_size(term, diag[term], R)
        assert size < 0.1e-6, (term, diag[term])


def test_the_servo_mismatch_of_arcs_run_from_standstill_is_over_their_steady_feed():
    """A ballbar's 220 deg arcs in XZ, out and back from standstill at 0.5 m/s^2 and
    F4000 on R 50 mm, X lagging Z by 1 ms: the mean angular speed counts the ramps and read
    the mismatch as 1.04 ms; the feed the arcs are taken at gives 1.00 ms."""
    radius, v, acc, dt = 0.05, 4000 / 60e3, 0.5, 1e-3
    span, a0 = np.radians(220.0), np.radians(-20.0)
    length, ta = radius * span, v / acc
    total = 2 * ta + (length - v * ta) / v
    t = np.arange(0.0, total + dt, dt)
    s = np.where(t < ta, 0.5 * acc * t**2,
                 np.where(t < total - ta, 0.5 * v * ta + v * (t - ta),
                          length - 0.5 * acc * (total - t) ** 2)).clip(0, length)
    ang = np.r_[np.full(100, a0), a0 + s / radius, np.full(100, a0 + span),
                a0 + span - s / radius, np.full(100, a0)]
    t = np.arange(ang.size) * dt
    x, z = radius * np.cos(ang), radius * np.sin(ang)
    run = Run(t, {"X": AxisRun(cmd=x, tcp=np.interp(t - 1e-3, t, x)),
                  "Z": AxisRun(cmd=z, tcp=z)})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = analyse_circle(run, radius, plane=("X", "Z"))
    assert [round(p.arc_deg) for p in res.passes] == [220, 220]
    diag = circle_diagnostics(res)
    assert diag["servo_mismatch"] == pytest.approx(-1e-3, rel=0.005)


def test_one_direction_over_a_220_deg_arc_gives_no_spike_after_terms(tmp_path, capsys):
    """One direction over a ballbar's 220 deg arc, a centre offset of 10 um the only
    error: the pass table gave spikes after a fit of centre and ellipses to the arc alone,
    terms its own diagnostics call undetermined. Now the spikes after terms are n/a, the
    note says why and where the raw ones are, and --json keeps the raw ones."""
    run = arc_run({"cx": 10e-6}, -20.0, 220.0)
    run.write_csv(tmp_path / "arc.csv")
    code, out, _ = run_cli(capsys, "circle", tmp_path / "arc.csv", "--radius", 35,
                           "--direction", "ccw")
    text = " ".join(out.split())
    assert code == 0
    assert "one direction over an arc (or a pair under 210 deg) gives no terms" in text
    assert "squareness); an arc alone gives none (below); n/a: left out" in text
    code, out, _ = run_cli(capsys, "circle", tmp_path / "arc.csv", "--radius", 35,
                           "--direction", "ccw", "--json")
    [p] = json.loads(out)["passes"]
    [tcp] = [s for s in p["sensors"] if s["sensor"] == "tcp"]
    assert all(tcp[f"spike_after_terms_{q}_um"] is None for q in "ABCD")
    assert abs(tcp["spike_B_um"]) > 3.0  # the raw spike carries the centre offset


@pytest.mark.parametrize("period", [1.5e-3, 0.6e-3])
def test_a_pitch_error_shorter_than_ten_steps_is_found_at_f10000(period):
    """At F10000 on R 35 mm and 1 kHz the tool steps 0.17 mm a sample: a cyclic error of
    1.5 or 0.6 mm is under ten steps a period, unresolved in time at full speed, but a sine
    of the axis' position is resolved where the axis slows towards its reversals. Left
    unsearched, 3 um of it read as 2.5 um of backlash and 10 ppm of scale mismatch."""
    n = 1320
    err = {"cyc_x": (3e-6, period, 0.7), "b_y": 4e-6}
    assert_recovered(diagnose(err, n=n), expected(err, n), w=2 * np.pi / (n * DT))


def test_a_cyclic_error_shorter_than_the_band_names_the_band_searched():
    """0.2 mm at F10000 is two steps a period: not searched, and the reason an axis reads
    no cyclic error says which periods were searched and that a shorter one reads in part
    as the terms, which it then moves with the window after the reversals: 0.6 um of
    backlash X and 1.5 ppm of scale mismatch, none injected, move to 1.4 um and 17 ppm
    with 40 deg left out. Without the error no term moves."""
    from tcpmm.analysis.circle_tails import moving_terms

    diag = diagnose({"cyc_x": (3e-6, 0.2e-3, 0.7)}, n=1320)
    assert np.isnan(diag["cyclic_amplitude_X"])
    why = diag.undetermined["cyclic_amplitude_X"]
    assert "periods from 23.3 down to 0.5 mm were searched" in why
    assert "reads in part as the terms, which then move with the window" in why
    assert {"backlash_X", "scale_mismatch"} <= set(moving_terms(diag))
    assert moving_terms(diagnose({"b_y": 4e-6}, n=1320)) == {}


@pytest.mark.parametrize("b_x", [3.7e-6, -6.5e-6])
def test_one_direction_reads_its_ellipse_as_a_mismatch_with_the_backlash_fitted(b_x):
    """One direction with a servo mismatch of 0.9 ms: its ellipse moves the reversals by a
    sample, so the backlash is left open; read again as a servo mismatch the fit must keep
    the backlash's columns all the same. Without them the scale mismatch took the backlash
    (about 6 ppm per um), differed between the two readings and was left open, or said
    with a wrong reading beside the right one."""
    from tcpmm.analysis.circle_single import diagnose_single

    err = {"tau_y": 0.9e-3, "b_x": b_x, "b_y": 0.7e-6, "eps_x": 87e-6}
    diag = diagnose_single(*circle("ccw", err, 3), "ccw", R)
    assert "scale_mismatch" not in diag.undetermined
    assert_recovered(diag, {"scale_mismatch": 87e-6})
    assert np.isnan(diag["backlash_X"]) and "cannot place" in diag.undetermined["backlash_X"]


def test_a_pitch_error_under_a_servo_mismatch_sampled_every_4_ms_is_found(monkeypatch):
    """At F10000 on R 35 mm sampled every 4 ms a servo mismatch of 1 ms moves the radius by
    some 3 um a sample; taken as noise, it put the floor a cyclic error must stand out of
    above a pitch error of 0.76 um, which then read as 1.4 um of backlash."""
    import sys

    monkeypatch.setattr(sys.modules[__name__], "DT", 4e-3)
    n = 330
    err = {"tau_y": 1e-3, "cyc_y": (0.76e-6, 8e-3, 0.03)}
    assert_recovered(diagnose(err, n=n), expected(err, n), w=2 * np.pi / (n * 4e-3))


@pytest.mark.parametrize("span", [352.0, 357.0])
def test_a_pair_of_nearly_full_arcs_finds_its_cyclic_error(span):
    """A turn cut short by some degrees (one programmed turn behind a 30 ms filter keeps
    358 deg of steady circle): no cyclic error was searched on an arc, and a pitch error of
    X read as X's backlash (5.6 um for 4) and turned its spikes (-2 um for +2). Arcs of
    :data:`~tcpmm.analysis.circle_stable.CYCLIC_ARC_DEG` or more are searched as full
    turns are; every term and spike is recovered."""
    err = {"b_x": 4e-6, "b_y": -3e-6, "cx": 3e-6, "alpha": 30e-6, "cyc_x": ALL["cyc_x"],
           "spikes": {(d, q): (2e-6, 4.0) for d in ("ccw", "cw") for q in "AC"}}
    diag = diagnose_pair(arc("ccw", err, 60.0, span, 1), arc("cw", err, 60.0, span, 2), R,
                         (W, W))
    # a point within some 30 deg of an arc's start has no spike (too few samples before it)
    want = {k: v for k, v in expected(err).items() if k not in diag.undetermined
            and not k.startswith("radial_deviation")
            and not (k.startswith("spike") and np.isnan(diag[k]))}
    assert {"cyclic_amplitude_X", "cyclic_period_X", "spike_A_ccw", "spike_C_ccw",
            "spike_A_cw", "spike_C_cw"} <= set(want)
    assert_recovered(diag, want)


def test_a_dead_band_read_as_a_cyclic_error_at_the_end_of_the_search_is_not_ranked():
    """The built-in machine with 40 and 30 um of play in its nuts, R 50 mm at F8000, read
    at the scale: the lingering take-up read as a cyclic error of X of 13 um at 33.1 mm,
    the search's end at 33.3 mm, and the ranking put it and Y's (not determined) first,
    sending the user after a pitch error. A period within a tenth of the scan's step of
    the end is not determined, and no term not determined is ranked."""
    from tcpmm.machines.builtin import builtin_machine
    from tcpmm.machines.paper import circle_test_command
    from tcpmm.sim.simulate import simulate

    vmc = builtin_machine()
    axes = {n: a.replace(friction=a.friction.model_copy(update={"backlash": b}))
            if n in ("X", "Y") else a for n, a, b in
            ((n, a, {"X": 40e-6, "Y": 30e-6}.get(n)) for n, a in vmc.axes.items())}
    machine = vmc.model_copy(update={"axes": axes})
    run = simulate(machine, circle_test_command(0.05, 8.0 / 60.0))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        d = circle_diagnostics(analyse_circle(run, 0.05), sensor="scale")
    assert not np.isfinite(d.terms["cyclic_amplitude_X"][0])
    ranked = {r["term"] for r in d.ranking}
    assert not any(t.startswith("cyclic") for t in ranked), ranked


def test_a_transient_beside_the_take_up_names_the_points_the_arc_holds():
    """The take-up width of an axis left open beside a reversal transient named "the
    spikes after the terms at B and D" on arcs of 220 deg that hold only B: the reason
    names the points whose spikes it read."""
    from tcpmm.analysis.circle_takeup import beside_transient

    terms = {"spike_B_ccw": (5e-6, "m"), "spike_B_cw": (5e-6, "m"),
             "spike_D_ccw": (float("nan"), "m"), "spike_D_cw": (float("nan"), "m")}
    u95 = {k: 0.2e-6 for k in terms}
    said = beside_transient(terms, u95, "BD")
    assert "at B, more than noise" in said and "B and D" not in said
    terms["spike_D_ccw"] = terms["spike_D_cw"] = (5e-6, "m")
    assert "at B and D, more than noise" in beside_transient(terms, u95, "BD")


def test_a_command_inside_the_nominal_radius_scales_no_term():
    """A command 1.5 % inside the nominal radius (a radius offset, a controller's filter):
    the lag's angle, the squareness and the scale mismatch were fitted on the nominal
    radius and read that much small, 7 to 20 times their +- (0.981 ms for 1 ms at 1.9 %).
    They make radial errors in proportion to the radius the axes run on, the command's:
    the terms read as on a command on the nominal radius, to 0.1 %."""
    from tcpmm.analysis.circle_single import one_direction_diagnostics

    err = {"tau_y": 0.5e-3, "alpha": 80e-6, "eps_x": 100e-6, "b_x": 3e-6}
    got = {}
    for inside in (0.0, 0.015):
        res = [analyse_circle(run_of(d, err, i, n=1320), R / (1.0 - inside))
               for i, d in enumerate(("ccw", "cw"))]
        pair, one = circle_diagnostics(res[0], res[1]), one_direction_diagnostics(res[0])
        got[inside] = [pair[k] for k in ("servo_mismatch", "squareness", "scale_mismatch")] + [
            one["scale_mismatch"], one["squareness_or_servo"]]
        assert_recovered(pair, {"squareness": 80e-6, "servo_mismatch": 0.5e-3,
                                "scale_mismatch": 100e-6}, w=2 * np.pi / (1320 * DT))
    np.testing.assert_allclose(got[0.015], got[0.0], rtol=1e-3)


@pytest.mark.parametrize("start_deg, sweep_deg", [(45.0, 450.0), (45.0, 400.0),
                                                  (10.0, 450.0), (0.0, 450.0)])
def test_whole_turns_are_taken_clear_of_the_reversal_windows(start_deg, sweep_deg):
    """1.25 turns from 45 deg, between quadrant points as the analysis advises, were
    trimmed symmetrically to one turn from 90 deg: spike B (CCW) and A (CW) read n/a, and
    the warning advised starting between quadrant points. The turn is moved within the
    run to where its ends lie clear of every reversal window; one that is clear there
    already (from A, as the reference machines' circles run) stays where it was."""
    n = int(sweep_deg * 20)
    for d, s in (("ccw", 1.0), ("cw", -1.0)):
        a = np.radians(start_deg) + s * np.radians(sweep_deg) * np.arange(n + 1) / n
        xy = R * np.c_[np.cos(a), np.sin(a)]
        tcp = xy + 0.05e-6 * np.random.default_rng(1).standard_normal(xy.shape)
        run = Run(DT * np.arange(n + 1), {"X": AxisRun(cmd=xy[:, 0], tcp=tcp[:, 0]),
                                          "Y": AxisRun(cmd=xy[:, 1], tcp=tcp[:, 1])})
        with warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always")
            [p] = analyse_circle(run, R).passes
        assert not [w for w in said if "quadrant point" in str(w.message)], d
        assert all(np.isfinite(v) for v in p.sensors["tcp"].spikes.values()), (d, p)
        if (start_deg, sweep_deg) == (0.0, 450.0):  # symmetric: from 45 deg
            start = np.degrees(np.arctan2(xy[p.index.start, 1], xy[p.index.start, 0]))
            assert abs(start % 360 - (45.0 if s > 0 else 315.0)) < 0.1, start
