"""Circular-test analysis recovers known injected errors (docs/formats.md section 4)."""

import warnings

import numpy as np
import pytest

from tcpmm.analysis.circular import (
    CircleResult,
    analyse_circle,
    lsq_circle,
    reversal_lobes,
    reversal_spikes,
)
from tcpmm.analysis.compare import compare_circles, sign_flips
from tcpmm.errors import InputError, InputWarning
from tcpmm.result import AxisRun, Run

R = 0.035


def circle_path(direction="ccw", n=7200, start_deg=45.0, centre=(0.0, 0.0)):
    """Feed-in semicircle of R/2 from the centre, one turn, feed-out back to the centre."""
    sgn = 1.0 if direction == "ccw" else -1.0
    a0 = np.radians(start_deg)
    u = np.array([np.cos(a0), np.sin(a0)])
    v = sgn * np.array([-np.sin(a0), np.cos(a0)])
    ph = np.linspace(np.pi, 2 * np.pi, 600)[:-1]  # arrives at the start moving along +v
    fi = (R / 2) * (np.outer(1 + np.cos(ph), u) + np.outer(np.sin(ph), v))
    th = np.linspace(0, 2 * np.pi, n + 1)
    c = R * (np.outer(np.cos(th), u) + np.outer(np.sin(th), v))
    ps = np.linspace(0, np.pi, 600)  # leaves the circle along +v, back to the centre
    fo = (R / 2) * (np.outer(1 + np.cos(ps), u) + np.outer(np.sin(ps), v))
    p = np.vstack([fi, c, fo[1:]]) + np.asarray(centre)
    return p


def make_run(p, sensor_xy, name="tcp"):
    t = np.arange(len(p)) * 1e-3
    return Run(t, {"X": AxisRun(cmd=p[:, 0], **{name: sensor_xy[:, 0]}),
                   "Y": AxisRun(cmd=p[:, 1], **{name: sensor_xy[:, 1]})})


def polar_perturb(p, centre, de):
    """Move each point radially by de(angle) [m]."""
    d = p - np.asarray(centre)
    r = np.hypot(d[:, 0], d[:, 1])
    a = np.arctan2(d[:, 1], d[:, 0])
    return np.asarray(centre) + (r + de(a))[:, None] * np.c_[np.cos(a), np.sin(a)]


@pytest.mark.parametrize("direction", ["ccw", "cw"])
@pytest.mark.parametrize(("start_deg", "left_out"), [(0.0, ["A"]), (45.0, []), (217.0, []),
                                                     (270.0, ["D"])])
def test_radius_offset(direction, start_deg, left_out):
    """A circle that starts (and so ends) at a quadrant point says so and reports no spike
    there: the 30 deg before it are the end of the circle, not the approach to it."""
    p = circle_path(direction, start_deg=start_deg, centre=(0.01, -0.02))
    s = polar_perturb(p, (0.01, -0.02), lambda a: 4e-6 + 0 * a)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = analyse_circle(make_run(p, s), R, (0.01, -0.02))
    said = [str(w.message) for w in caught if issubclass(w.category, InputWarning)]
    assert len(said) == len(left_out[:1])
    for q in left_out:
        assert f"{direction.upper()} circle starts or ends at quadrant point {q}" in said[0]
    assert len(res.passes) == 1
    ps = res.passes[0]
    assert ps.direction == direction
    sc = ps.sensors["tcp"]
    assert sc.contour_error == pytest.approx(4e-6, abs=1e-10)
    assert sc.circular_deviation < 1e-9
    span = abs(sc.angle_rad[-1] - sc.angle_rad[0])
    assert span == pytest.approx(2 * np.pi, abs=np.radians(0.2))  # feed-in/out trimmed
    assert all(np.isnan(v) == (q in left_out) for q, v in sc.spikes.items())
    assert all(abs(v) < 1e-9 for q, v in sc.spikes.items() if q not in left_out)
    assert all(v is None for q, v in res.to_dict()["passes"][0]["sensors"][1].items()
               if q[-4:-3] in left_out and q.startswith("spike"))


def test_a_circle_without_feed_in_from_a_quadrant_point_leaves_it_out():
    """One turn from A with no feed-in: the start is no reversal of X at all, yet a spike
    taken across the seam would be the jump from the end of the circle to its start."""
    th = np.linspace(0, 2 * np.pi, 3601)
    p = R * np.c_[np.cos(th), np.sin(th)]
    s = polar_perturb(p, (0, 0), lambda a: np.where(np.degrees(a) % 360 < 10, 6e-6, 0.0))
    with pytest.warns(InputWarning, match=r"quadrant point A \(0 deg\)") as caught:
        spikes = analyse_circle(make_run(p, s), R).passes[0].sensors["tcp"].spikes
    assert len(caught) == 1
    assert np.isnan(spikes["A"])
    assert [spikes[q] for q in "BCD"] == pytest.approx([0.0, 0.0, 0.0], abs=1e-12)
    # crossed within a path, the same rise after A is a 6 um spike
    assert reversal_spikes(np.r_[th - 2 * np.pi, th], np.r_[0 * th, 6e-6 * (th < 0.17)],
                           "ccw")["A"] == pytest.approx(6e-6)


def test_ellipse_circular_deviation():
    p = circle_path()
    d = 3e-6
    s = polar_perturb(p, (0, 0), lambda a: d * np.cos(2 * a))
    sc = analyse_circle(make_run(p, s), R).passes[0].sensors["tcp"]
    assert sc.circular_deviation == pytest.approx(2 * d, rel=1e-3)
    assert sc.contour_error == pytest.approx(d, rel=1e-3)


def test_offset_centre_gives_lsq_centre_and_small_g():
    p = circle_path()
    s = p + np.array([2e-6, -1e-6])
    sc = analyse_circle(make_run(p, s), R).passes[0].sensors["tcp"]
    assert sc.lsq_centre == pytest.approx((2e-6, -1e-6), abs=1e-10)
    assert sc.circular_deviation < 1e-9
    assert sc.contour_error == pytest.approx(np.hypot(2e-6, 1e-6), rel=1e-3)


@pytest.mark.parametrize("direction", ["ccw", "cw"])
@pytest.mark.parametrize(("quadrant", "deg"), [("A", 0), ("B", 90), ("C", 180), ("D", 270)])
def test_known_spike_at_known_quadrant(direction, quadrant, deg):
    """A spike of +5 um, 6 deg after the quadrant point in the direction of travel,
    on a baseline offset of -2 um: reported +5 um (relative to the baseline) there, 0
    elsewhere; a spike placed before P is not attributed to P."""
    p = circle_path(direction, start_deg=45.0)
    sgn = 1 if direction == "ccw" else -1
    centre_deg = deg + sgn * 6.0

    def de(a):
        da = (np.degrees(a) - centre_deg + 180) % 360 - 180
        return -2e-6 + 5e-6 * np.exp(-0.5 * (da / 1.5) ** 2)

    s = polar_perturb(p, (0, 0), de)
    spikes = analyse_circle(make_run(p, s), R).passes[0].sensors["tcp"].spikes
    assert spikes[quadrant] == pytest.approx(5e-6, rel=1e-3)
    for q, v in spikes.items():
        if q != quadrant:
            assert abs(v) < 1e-9


def test_negative_spike_is_signed():
    ang = np.radians(np.linspace(0, 360, 3601))
    e = np.where((np.degrees(ang) > 92) & (np.degrees(ang) < 95), -3e-6, 0.0)
    assert reversal_spikes(ang, e, "ccw")["B"] == pytest.approx(-3e-6)
    assert reversal_spikes(ang, e, "cw")["B"] == 0.0  # for CW the window lies before B


def test_ccw_then_cw_run_gives_two_passes_and_direction_filter():
    p = np.vstack([circle_path("ccw"), circle_path("cw")])
    s = polar_perturb(p, (0, 0), lambda a: 1e-6 + 0 * a)
    res = analyse_circle(make_run(p, s), R)
    assert [q.direction for q in res.passes] == ["ccw", "cw"]
    assert analyse_circle(make_run(p, s), R, direction="cw").passes[0].direction == "cw"
    df = res.to_pandas()
    assert set(df["sensor"]) == {"cmd", "tcp"}


def test_compare_is_measured_minus_predicted():
    p = circle_path()
    meas = analyse_circle(make_run(p, polar_perturb(p, (0, 0), lambda a: 3e-6 + 0 * a)), R)
    pred = analyse_circle(make_run(p, polar_perturb(p, (0, 0), lambda a: 1e-6 + 0 * a)), R)
    row = compare_circles(meas, pred).rows[0]
    assert row["contour_error_um"] == pytest.approx(2.0, abs=1e-6)
    assert row["radial_rms_um"] == pytest.approx(2.0, abs=1e-3)


@pytest.mark.parametrize("direction", ["ccw", "cw"])
def test_runs_that_start_at_other_angles_are_compared_at_the_same_places(direction):
    """The same radial error as a function of the angle (a smooth bump at 95 degrees), the
    measured circle started at 45 degrees and the predicted at 40: nothing between them."""
    def bump(a):
        return 2e-6 + 3e-6 * np.exp(-0.5 * ((np.degrees(a) % 360 - 95.0) / 8.0) ** 2)

    runs = {}
    for name, start in (("measured", 45.0), ("predicted", 40.0)):
        p = circle_path(direction, start_deg=start)
        runs[name] = analyse_circle(make_run(p, polar_perturb(p, (0, 0), bump)), R)
    row = compare_circles(runs["measured"], runs["predicted"]).rows[0]
    assert row["radial_max_um"] < 0.01 and row["radial_rms_um"] < 0.005


def arc_path(direction, start_deg, end_deg):
    """An arc of the circle from ``start_deg`` to ``end_deg`` (less for CW), at the speed
    of :func:`circle_path` (no feed-in) [m]."""
    assert (end_deg > start_deg) == (direction == "ccw")
    th = np.radians(np.linspace(start_deg, end_deg, round(abs(end_deg - start_deg) * 20) + 1))
    return R * np.column_stack([np.cos(th), np.sin(th)])


@pytest.mark.parametrize("direction", ["ccw", "cw"])
@pytest.mark.parametrize("predicted", [(40.0, None), (100.0, 200.0)])
def test_an_arc_is_compared_only_where_both_runs_are(direction, predicted):
    """A measured arc (60 to 150 deg of travel) against a predicted full circle, or an arc
    that overlaps it from 100 deg on, with the same radial error as a function of the
    angle: nothing between them. The point-by-point difference filled the angles the arc
    does not hold in by a straight line (some 0.7 um here), and the contour error set the
    arc's against the whole circle's."""
    def bump(a):
        return 2e-6 + 3e-6 * np.exp(-0.5 * ((np.degrees(a) % 360 - 95.0) / 8.0) ** 2) \
            - 1e-6 * np.cos(3 * a)

    sgn = 1.0 if direction == "ccw" else -1.0
    pm = arc_path(direction, 60.0 * sgn, 150.0 * sgn)
    a0, a1 = predicted
    pp = circle_path(direction, start_deg=a0) if a1 is None else \
        arc_path(direction, a0 * sgn, a1 * sgn)
    with warnings.catch_warnings():  # the arcs hold few quadrant points: said, not asked
        warnings.simplefilter("ignore", InputWarning)
        meas = analyse_circle(make_run(pm, polar_perturb(pm, (0, 0), bump)), R)
        pred = analyse_circle(make_run(pp, polar_perturb(pp, (0, 0), bump)), R)
        row = compare_circles(meas, pred).rows[0]
    assert row["radial_max_um"] < 0.01 and abs(row["contour_error_um"]) < 0.01
    assert row["common_deg"] == pytest.approx(90.0 if a1 is None else 50.0, abs=1.0)


def test_a_prediction_of_another_test_is_refused():
    """A measured circle run twice as fast as the predicted one (F10000 against F5000):
    the prediction is of another test, and every difference would be of the feeds."""
    p = circle_path()
    meas = make_run(p, p)
    fast = Run(meas.time_s / 2.0, meas.axes)
    with pytest.raises(InputError, match="prediction is of another test"):
        compare_circles(analyse_circle(fast, R), analyse_circle(meas, R))
    assert compare_circles(analyse_circle(meas, R), analyse_circle(meas, R)).rows


def ramped_arc_run(accel_rad_s2, rate_rad_s=2.381):
    """A 220 deg CCW arc from -20 deg sampled at 1 kHz, run up from standstill to its feed
    at ``accel_rad_s2`` and down again [-]."""
    span = np.radians(220.0)
    t_ramp = rate_rad_s / accel_rad_s2
    ramp = 0.5 * accel_rad_s2 * t_ramp**2
    t_end = 2.0 * t_ramp + (span - 2.0 * ramp) / rate_rad_s
    t = np.arange(0.0, t_end + 5e-4, 1e-3)
    down = t_end - t
    th = np.where(t < t_ramp, 0.5 * accel_rad_s2 * t**2,
                  np.where(down < t_ramp, span - 0.5 * accel_rad_s2 * down**2,
                           ramp + rate_rad_s * (t - t_ramp)))
    p = R * np.column_stack([np.cos(th - np.radians(20.0)), np.sin(th - np.radians(20.0))])
    return Run(t, {"X": AxisRun(cmd=p[:, 0], tcp=p[:, 0]), "Y": AxisRun(cmd=p[:, 1], tcp=p[:, 1])})


def test_one_arc_at_one_feed_ramped_otherwise_is_the_same_test():
    """The same 220 deg arc at F5000 ramped at 28.6 and 7.1 rad/s^2 (1 and 0.25 m/s^2 on
    R 35 mm): the same feed. The mean speed, which counts the ramps, differs by 13 %, and
    the two were refused as two tests."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", InputWarning)
        fast, slow = (analyse_circle(ramped_arc_run(a / R), R) for a in (1.0, 0.25))
        assert abs(fast.passes[0].rate_rad_s / slow.passes[0].rate_rad_s - 1.0) > 0.1
        row = compare_circles(fast, slow).rows[0]
    assert abs(row["contour_error_um"]) < 0.01


def two_lobes(rise, fall):
    """Radial error with a rise at 93 deg then a fall at 100 deg (after B, CCW) [m]."""
    def de(a):
        d = np.degrees(a) % 360.0
        return np.where((d > 92) & (d < 94), rise, np.where((d > 99) & (d < 101), fall, 0.0))
    return de


def test_lobes_hold_rise_and_fall_and_the_spike_is_the_larger():
    ang = np.radians(np.linspace(0, 360, 3601))
    e = two_lobes(4.6e-6, -4.8e-6)(ang)
    assert reversal_lobes(ang, e, "ccw")["B"] == pytest.approx((4.6e-6, -4.8e-6))
    assert reversal_spikes(ang, e, "ccw")["B"] == pytest.approx(-4.8e-6)
    assert np.isnan(reversal_lobes(ang, e, "ccw")["A"]).all()  # starts and ends at A
    assert reversal_lobes(ang, e, "cw")["B"] == (0.0, 0.0)  # for CW the window lies before B


def test_a_sign_flip_is_reported_with_both_lobes():
    # Rise and fall of similar size: measured picks the fall, predicted the rise, so the
    # spike difference is their sum although each lobe is within 0.5 um.
    p = circle_path()
    meas = analyse_circle(make_run(p, polar_perturb(p, (0, 0), two_lobes(4.6e-6, -4.8e-6))), R)
    pred = analyse_circle(make_run(p, polar_perturb(p, (0, 0), two_lobes(5.0e-6, -4.3e-6))), R)
    cmp = compare_circles(meas, pred)
    assert cmp.rows[0]["spike_B_um"] == pytest.approx(-9.8, abs=1e-3)
    [flip] = cmp.sign_flips
    assert (flip["direction"], flip["sensor"], flip["point"]) == ("CCW", "tcp", "B")
    assert flip["measured_rise_um"] == pytest.approx(4.6, abs=1e-3)
    assert flip["predicted_fall_um"] == pytest.approx(-4.3, abs=1e-3)
    assert flip["lobe_difference_um"] == pytest.approx(0.5, abs=1e-3)
    assert cmp.to_dict()["sign_flips"] == [flip]
    [note] = cmp.notes()
    assert "CCW tcp at B" in note and "measured +4.60/-4.80 um" in note
    assert note.endswith("differ by at most 0.50 um")
    # The same shape predicted with the fall the larger: no flip.
    pred = analyse_circle(make_run(p, polar_perturb(p, (0, 0), two_lobes(4.3e-6, -5.0e-6))), R)
    assert compare_circles(meas, pred).sign_flips == []
    assert sign_flips(meas.passes[0].sensors["tcp"], meas.passes[0].sensors["tcp"]) == []


def test_a_spike_predicted_as_none_is_no_sign_flip():
    """A measured spike of 8 um against a prediction with none at all (a spike of a few
    nm, either sign): the spike does not change sign, and no note says it does because
    rise and fall are of similar size (both predicted lobes are nothing)."""
    p = circle_path()
    meas = analyse_circle(make_run(p, polar_perturb(p, (0, 0), two_lobes(8e-6, -0.5e-6))), R)
    pred = analyse_circle(make_run(p, polar_perturb(p, (0, 0), two_lobes(2e-9, -3e-9))), R)
    cmp = compare_circles(meas, pred)
    assert cmp.rows[0]["spike_B_um"] == pytest.approx(8.0, abs=0.01)
    assert cmp.sign_flips == [] and cmp.notes() == []


def test_a_sign_flip_names_its_cause_only_where_it_holds():
    """A model without friction predicted -3.55 um at A where the circle measured +13.75
    (rise +13.75, fall -6.32; predicted -2.11/-3.55): the note said the sign changed
    "because rise and fall are of similar size", which neither run shows. It says so only
    where one run's lobes are within half of each other; else that the lobes differ."""
    p = circle_path()
    meas = analyse_circle(make_run(p, polar_perturb(p, (0, 0), two_lobes(13.75e-6,
                                                                           -6.32e-6))), R)
    pred = analyse_circle(make_run(p, polar_perturb(p, (0, 0), two_lobes(-2.11e-6,
                                                                           -3.55e-6))), R)
    [note] = compare_circles(meas, pred).notes()
    assert "because the lobes after the reversal differ themselves" in note
    assert "similar size" not in note
    pred = analyse_circle(make_run(p, polar_perturb(p, (0, 0), two_lobes(5.0e-6, -4.3e-6))), R)
    meas = analyse_circle(make_run(p, polar_perturb(p, (0, 0), two_lobes(4.6e-6, -4.8e-6))), R)
    [note] = compare_circles(meas, pred).notes()
    assert "because rise and fall after the reversal are of similar size" in note


def test_wrong_radius_is_a_clear_error():
    p = circle_path()
    with pytest.raises(InputError, match="no full circle of radius 30 mm"):
        analyse_circle(make_run(p, p), 0.030)


def test_lsq_circle_exact():
    th = np.linspace(0, 2 * np.pi, 50, endpoint=False)
    cx, cy, r = lsq_circle(1 + 2 * np.cos(th), -3 + 2 * np.sin(th))
    assert (cx, cy, r) == pytest.approx((1, -3, 2))


def filtered_circle(radius=R, feed_m_s=10.0 / 60, window_s=0.040, dt=1e-3, turns=1.25):
    """A command from rest at (R, 0) round ``turns`` and back to rest, through a moving
    average of ``window_s`` as a controller's acceleration filter after interpolation is,
    and the radius it pulls the circle in by [m]."""
    w = feed_m_s / radius
    n = round(turns * 2 * np.pi / (w * dt))
    ang = np.r_[np.zeros(300), w * dt * np.arange(n), np.full(600, w * dt * (n - 1))]
    k = round(window_s / dt)
    p = radius * np.c_[np.cos(ang), np.sin(ang)]
    pad = np.vstack([np.repeat(p[:1], k - 1, axis=0), p])
    f = np.c_[[np.convolve(pad[:, j], np.ones(k) / k, "valid") for j in (0, 1)]].T
    shrink = radius * (np.sin(k * w * dt / 2) / (k * np.sin(w * dt / 2)) - 1)
    return f, shrink


def test_a_command_the_controller_has_pulled_in_is_found_and_its_deviation_said():
    """A 40 ms moving average at F10000 pulls R 35 in by 53 um, beyond the 35 um the
    command had to keep to R: the circle was refused. It is found, and the command's radial
    deviation is reported; the TCP's radial error stays about the nominal radius."""
    cmd, shrink = filtered_circle()
    assert shrink == pytest.approx(-52.9e-6, abs=0.5e-6)
    tcp = polar_perturb(cmd, (0, 0), lambda a: 3e-6 + 0 * a)
    res = analyse_circle(make_run(cmd, tcp), R)
    [p] = res.passes
    assert p.command_radial_deviation == pytest.approx(shrink, abs=0.05e-6)
    assert np.mean(p.sensors["tcp"].radial_error) == pytest.approx(shrink + 3e-6, abs=0.05e-6)
    assert abs(p.sensors["tcp"].angle_rad[-1] - p.sensors["tcp"].angle_rad[0]) == \
        pytest.approx(2 * np.pi, abs=np.radians(0.5))
    [row] = [r for r in p.table() if r["sensor"] == "tcp"]
    assert row["command_radial_deviation_um"] == pytest.approx(shrink * 1e6, abs=0.05)
    assert res.to_dict()["passes"][0]["command_radial_deviation_um"] == \
        pytest.approx(shrink * 1e6, abs=0.05)


@pytest.mark.parametrize("offset, found", [(0.3e-3, True), (-0.3e-3, True), (0.8e-3, False),
                                           (-5e-3, False)])
def test_a_command_off_the_radius_is_a_circle_up_to_two_percent_of_it(offset, found):
    """A radius offset of 0.3 mm is the circle asked for, 0.3 mm off; 0.8 mm (over 2 % of
    R 35) or 5 mm is another circle and stays refused."""
    p = circle_path()
    p = polar_perturb(p, (0, 0), lambda a: offset + 0 * a)
    if not found:
        with pytest.raises(InputError, match="no full circle of radius 35 mm"):
            analyse_circle(make_run(p, p), R)
        return
    [ps] = analyse_circle(make_run(p, p), R).passes
    assert ps.command_radial_deviation == pytest.approx(offset, abs=1e-9)


def test_a_path_of_no_constant_radius_near_r_is_no_circle():
    """A square whose corners touch the circle passes through R but never keeps to it."""
    s = np.linspace(-1, 1, 4000)
    h = R / np.sqrt(2)
    p = np.vstack([np.c_[h + 0 * s, h * s], np.c_[-h * s, h + 0 * s],
                   np.c_[-h + 0 * s, -h * s], np.c_[h * s, -h + 0 * s]])
    with pytest.raises(InputError, match="no full circle"):
        analyse_circle(make_run(p, p), R)


def test_the_bench_h_fast_circle_is_found_with_its_command_pulled_in(capsys):
    """Machine H's controller filter takes 52.85 um off the F10000 circle's command."""
    from conftest import bench_path
    from tcpmm.cli import main
    from tcpmm.io.runfile import read_run

    d = bench_path("h")
    [p] = analyse_circle(read_run(d / "circle_ccw_fast_meas.csv"), R).passes
    assert p.command_radial_deviation == pytest.approx(-52.85e-6, abs=0.05e-6)
    code = main(["circle", str(d / "circle_ccw_fast_meas.csv"), "--radius", "35"])
    out = " ".join(capsys.readouterr().out.split())
    assert code == 0 and "the command lies 52.85 µm inside the nominal radius" in out
    code = main(["compare", str(d / "circle_ccw_fast_meas.csv"),
                 str(d / "circle_ccw_fast_meas.csv"), "--radius", "35"])
    assert code == 0


def test_a_dwell_on_the_circle_of_a_noisy_sensor_does_not_split_it():
    """A run with no command, its TCP at rest for 0.3 s half-way round with 0.05 um of
    noise: the noise turns the path back and forth at rest, yet it is one full circle."""
    p = circle_path()
    half = 600 + 3600
    p = np.vstack([p[:half], np.repeat(p[half:half + 1], 300, axis=0), p[half:]])
    p = p + 0.05e-6 * np.random.default_rng(1).standard_normal(p.shape)
    t = np.arange(len(p)) * 1e-3
    run = Run(t, {"X": AxisRun(cmd=None, tcp=p[:, 0]), "Y": AxisRun(cmd=None, tcp=p[:, 1])})
    [ps] = analyse_circle(run, R).passes
    assert not ps.is_arc and ps.direction == "ccw"


def test_a_circle_short_of_a_turn_by_less_than_a_sample_is_a_full_circle():
    """F10000 on R 35 at 1 kHz is 4.8 mrad a sample: a run of one turn that ends 2.3 mrad
    short (359.87 deg) was refused ('no full circle ... nor an arc'), and not offered as an
    arc either."""
    step = 10.0 / 60 / R * 1e-3
    span = 2 * np.pi - 0.48 * step
    th = np.radians(45.0) + np.linspace(0.0, span, round(span / step) + 1)
    p = R * np.c_[np.cos(th), np.sin(th)]
    [pas] = analyse_circle(make_run(p, p), R).passes
    assert pas.direction == "ccw" and not pas.is_arc


def test_a_point_one_sensor_holds_by_a_sample_is_left_out_for_all_as_said():
    """A 220 deg arc out and back, the TCP's Y leading by 0.5 ms: the command's arc ends a
    hair short of C's 20 deg window, the TCP's just holds it. The warning said the CCW arc
    does not hold C while the TCP's row printed a spike there."""
    r, w, dt = 0.1, 2000.0 / 60e3 / 0.1, 1e-3
    n = round(np.radians(220.0) / (w * dt))
    u = np.r_[w * dt * np.arange(n + 1), w * dt * (n - np.arange(1, n + 1))]
    s = np.r_[np.ones(n + 1), -np.ones(n)]
    th = np.radians(-20.0) + u
    cmd = r * np.c_[np.cos(th), np.sin(th)]
    tcp = np.c_[cmd[:, 0], r * np.sin(th - s * w * -0.5e-3)]
    run = Run(np.arange(th.size) * dt, {
        "X": AxisRun(cmd=cmd[:, 0], tcp=tcp[:, 0]), "Y": AxisRun(cmd=cmd[:, 1], tcp=tcp[:, 1])})
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        res = analyse_circle(run, r)
    assert any("CCW arc of 220 deg does not hold quadrant points A (0 deg), C (180 deg)"
               in str(w.message) for w in said)
    for p in res.passes:
        out = {q for q, v in p.sensors["cmd"].spikes.items() if np.isnan(v)}
        for sc in p.sensors.values():
            assert {q for q, v in sc.spikes.items() if np.isnan(v)} == out
            assert {q for q, v in sc.spikes_after_terms().items() if np.isnan(v)} == out


def test_a_value_that_rounds_to_zero_prints_without_a_sign():
    from tcpmm.cli._tables import fixed

    assert [fixed(v) for v in (-0.0, -0.004, -1e-12, 0.004, -0.02, -12.0)] == \
        ["0.00", "0.00", "0.00", "0.00", "-0.02", "-12.00"]


@pytest.mark.parametrize("jitter_s", [0.0, 2e-4])
@pytest.mark.parametrize(("ramp", "warned"), [("start", True), ("end", True), (None, False)])
def test_a_pass_whose_command_changes_speed_is_said(ramp, warned, jitter_s):
    """A 120 deg arc whose command is still speeding up at its start (or slows down at its
    end) is said: the diagnostics take a steady feed, and the servo's transient after the
    change reads as their terms. A steady arc is not, also where a logger's time stamps
    jitter by up to 0.2 of the 1 ms sample period (each step's speed then scatters by
    some 20 %: a steady circle of the benches read "slows down at its end (93 %)")."""
    n = 2401
    speed = np.ones(n - 1)
    if ramp == "start":
        speed[:40] = np.linspace(0.6, 1.0, 40)
    elif ramp == "end":
        speed[-40:] = np.linspace(1.0, 0.6, 40)
    th = np.radians(20.0) + np.concatenate([[0.0], np.cumsum(speed)]) * np.radians(0.05)
    p = R * np.column_stack([np.cos(th), np.sin(th)])
    run = make_run(p, p)
    jitter = np.random.default_rng(3).uniform(-jitter_s, jitter_s, n)
    run = Run(run.time_s + jitter, run.axes)
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        analyse_circle(run, R)
    said = [str(w.message) for w in got if "steady feed" in str(w.message)]
    assert bool(said) == warned
    if warned:
        assert ("speeding up at its start" if ramp == "start" else "slows down at its end") \
            in said[0]


def test_no_spike_where_its_window_reaches_into_the_feed_ramp():
    """A 280 deg arc whose command slows to a stop over its last 16 deg, with Y 1 ms
    behind X: the window after D (270 deg) lies on the arc, but the lag changes with the
    feed there, and D read a spike of the changing lag (-17.9 um on a 220 deg arc where
    4 um was injected). Only the windows where the feed is steady give a spike."""
    n = 5901
    speed = np.ones(n - 1)
    speed[-600:] = np.linspace(1.0, 0.05, 600)  # from 275 deg
    th = np.radians(10.0) + np.concatenate([[0.0], np.cumsum(speed)]) * np.radians(0.05)
    dt = 1e-3
    w = np.radians(0.05) / dt
    cmd = R * np.column_stack([np.cos(th), np.sin(th)])
    t = np.arange(n) * dt
    tcp = np.column_stack([cmd[:, 0], np.interp(t - 1e-3, t, cmd[:, 1])])
    run = Run(t, {"X": AxisRun(cmd=cmd[:, 0], tcp=tcp[:, 0]),
                  "Y": AxisRun(cmd=cmd[:, 1], tcp=tcp[:, 1])})
    assert np.degrees(th[-1]) > 270.0 + 20.0 and R * w * 1e-3 > 1e-6  # D's windows, a lag
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        res = analyse_circle(run, R)
    assert any("does not hold quadrant points A (0 deg), D (270 deg)" in str(m.message)
               for m in said), [str(m.message) for m in said]
    spikes = res.passes[0].sensors["tcp"].spikes
    assert np.isnan(spikes["D"]) and np.isfinite(spikes["B"]) and np.isfinite(spikes["C"])


def test_a_time_logged_in_milliseconds_is_refused_and_a_slow_log_said(tmp_path):
    """Machine D's measured circle with its time in ms under ``time_s``: read as a circle
    at 5 mm/min sampled every second, whose servo mismatch came out 85.7 "ms" for 0.086,
    silently, then with a warning and exit 0 (the report: "feed 5 mm/min", PASS). It is
    refused, with the likely cause; a circle at its feed logged slowly (every 50 ms) is
    said, not refused."""
    import pandas as pd

    from conftest import bench_path
    from tcpmm.analysis.circular import analyse_circle
    from tcpmm.errors import InputWarning
    from tcpmm.io.runfile import read_run

    run = pd.read_csv(bench_path("d") / "circle_ccw_meas.csv")
    slow = run.iloc[::50]
    run.time_s *= 1000.0
    run.to_csv(tmp_path / "ms.csv", index=False)
    with pytest.raises(InputError, match=r"samples are 1 s apart at a feed of 5 mm/min.*"
                                         r"milliseconds"):
        analyse_circle(read_run(tmp_path / "ms.csv"), 0.035)
    slow.to_csv(tmp_path / "slow.csv", index=False)
    with pytest.warns(InputWarning, match=r"samples are 0\.05 s apart, at a feed of 5000"):
        analyse_circle(read_run(tmp_path / "slow.csv"), 0.035)


def _program_run(text, plane=("X", "Y"), lag_s=0.0):
    """The run of an NC program whose sensor is its own command (a machine without error),
    or the command delayed by ``lag_s`` on both axes [m]."""
    from tcpmm.path import program_to_command

    cmd = program_to_command(text)
    t = cmd.time_s
    axes = {}
    for a in plane:
        c = cmd.positions[a]
        axes[a] = AxisRun(cmd=c, tcp=np.interp(t - lag_s, t, c))
    return Run(t, axes)


@pytest.mark.filterwarnings("ignore::tcpmm.errors.InputWarning")
def test_a_perfect_circle_fed_in_from_the_centre_reads_no_error():
    """The end of a radial approach comes within 0.1 % of R at the start angle: those
    samples were taken as the circle, and a command without error read G 32 um and
    backlash 0.34 um."""
    run = _program_run("G17 G21 G90\nG0 X0 Y0\nG1 X24.7487 Y24.7487 F3000\n"
                       "G3 X24.7487 Y24.7487 I-24.7487 J-24.7487\n"
                       "G2 X24.7487 Y24.7487 I-24.7487 J-24.7487\nG1 X0 Y0\nM30\n")
    res = analyse_circle(run, R)
    assert [p.direction for p in res.passes] == ["ccw", "cw"]
    for p in res.passes:
        s = p.sensors["tcp"]
        assert s.circular_deviation < 0.01e-6 and s.contour_error < 0.1e-6


@pytest.mark.filterwarnings("ignore::tcpmm.errors.InputWarning")
def test_arcs_fed_in_along_a_semicircle_are_the_arcs_programmed():
    """A 220 deg arc fed in and out tangentially by semicircles read 225 deg: the last
    2.5 deg of the feed-in lie within 0.1 % of R, and on a machine without error the pair
    read a centre 14.8 um off and 9.4 um of backlash."""
    from tcpmm.analysis.diagnostics import circle_diagnostics

    run = _program_run(
        "G21 G90 G18\nG0 X0 Y0 Z0\nG2 X46.98463 Z-17.10101 I23.49232 K-8.55050 F3000\n"
        "G2 X-46.98463 Z-17.10101 I-46.98463 K17.10101\nG2 X0 Z0 I23.49232 K8.55050\n"
        "G3 X-46.98463 Z-17.10101 I-23.49232 K-8.55050\n"
        "G3 X46.98463 Z-17.10101 I46.98463 K17.10101\nG3 X0 Z0 I-23.49232 K8.55050\nM30\n",
        plane=("X", "Z"))
    res = analyse_circle(run, 0.05, plane=("X", "Z"))
    assert [round(p.arc_deg, 1) for p in res.passes] == [220.0, 220.0]
    d = circle_diagnostics(res, sensor="tcp")
    for name, (value, _) in d.terms.items():
        if value == value and not name.startswith(("cyclic_period", "radial", "circ")):
            assert abs(value) < 1e-9 + 1e-3 * abs(value), (name, value)


@pytest.mark.filterwarnings("ignore::tcpmm.errors.InputWarning")
def test_a_sensor_still_on_the_feed_in_when_its_command_joins_the_circle_is_cut_there():
    """Without feed-forward the axes run 2 mm behind their command at F5000: its first
    samples on the circle found the sensor still on the feed-in semicircle, and G read
    121 um where the lag alone makes a constant radial error. Here the sensor is the
    command 20 ms late: the same circle, so G is 0."""
    run = _program_run("G17 G21 G90\nG0 X0 Y0\nG3 X35 Y0 I17.5 J0 F5000\nG3 X35 Y0 I-35 J0\n"
                       "G3 X0 Y0 I-17.5 J0\nM30\n", lag_s=0.020)
    p = analyse_circle(run, R).passes[0]
    assert p.sensors["tcp"].circular_deviation < 0.05e-6
    assert p.sensors["tcp"].contour_error < 0.1e-6


@pytest.mark.filterwarnings("ignore::tcpmm.errors.InputWarning")
def test_samples_at_rest_on_the_circle_are_not_part_of_it():
    """A dwell at the start point holds 300 samples at one angle: an offset during it
    (play not yet taken up) read as a 0.33 um cyclic error and 1.7 um of lateral play."""
    from tcpmm.analysis.diagnostics import circle_diagnostics

    th = np.radians(45.0) + np.linspace(0.0, 2 * np.pi, 3601)
    one = R * np.c_[np.cos(th), np.sin(th)]
    rest = np.repeat(one[:1], 300, axis=0)
    p = np.vstack([rest, one[1:], one[-2::-1]])
    q = p.copy()
    q[:300, 0] += 1.5e-6
    res = analyse_circle(make_run(p, q), R)
    assert [x.direction for x in res.passes] == ["ccw", "cw"]
    d = circle_diagnostics(res, sensor="tcp")
    for name, (value, _) in d.terms.items():
        if value == value and not name.startswith(("cyclic_period", "radial", "circ")):
            assert abs(value) < 1e-9 + 1e-3 * abs(value), (name, value)


def test_a_gap_in_the_log_is_said_to_be_one(tmp_path):
    """Bench C's CCW circle with 0.3 s of its rows gone (a logger that broke off): the
    warning said the circle "starts or ends at quadrant point D" and told the user to
    start it between quadrant points. It says where the samples break off, and why D has
    no spike; the whole circle says neither."""
    import pandas as pd

    from conftest import bench_path
    from tcpmm.io.runfile import read_run

    path = bench_path("c") / "circle_ccw_meas.csv"
    pd.read_csv(path).drop(index=range(2000, 2300)).to_csv(tmp_path / "gap.csv", index=False)
    with pytest.warns(InputWarning) as said:
        analyse_circle(read_run(tmp_path / "gap.csv"), 0.035)
    text = [str(w.message) for w in said]
    assert any("samples break off (0.301 s from 238.4 to 279.5 deg)" in m for m in text)
    assert any("at quadrant point D (270 deg)" in m and "break off" in m for m in text)
    assert not any("start the circle between" in m for m in text)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        analyse_circle(read_run(path), 0.035)


def test_a_gap_under_a_time_that_runs_on_evenly_is_said_to_be_one(tmp_path):
    """Bench C's CCW circle with 40 rows gone just after B and its time stamped again n / 1
    kHz, as loggers that count samples do: spike B read 32.96 for 37.13 um with no word.
    The command's leap of 41 of its steps in one sample is said; the same leap held over
    several samples, as an interpolator's command logged faster than it moves, is not."""
    import pandas as pd

    from conftest import bench_path
    from tcpmm.analysis.circle_gaps import angle_jumps
    from tcpmm.io.runfile import read_run

    a = pd.read_csv(bench_path("c") / "circle_ccw_meas.csv")
    b = int(np.argmax(np.degrees(np.unwrap(np.arctan2(a.y_cmd_mm, a.x_cmd_mm))) >= 90))
    g = a.drop(index=range(b + 5, b + 45)).reset_index(drop=True)
    g.assign(time_s=np.arange(len(g)) * 1e-3).to_csv(tmp_path / "gap.csv", index=False)
    with pytest.warns(InputWarning) as said:
        analyse_circle(read_run(tmp_path / "gap.csv"), 0.035)
    text = [str(w.message) for w in said]
    assert any("leaps between two samples" in m and "from 90.6 to 96.2 deg" in m
               for m in text), text
    stairs = np.repeat(np.linspace(0.0, 2 * np.pi, 500), 8)
    assert angle_jumps(stairs).size == 0
    assert list(angle_jumps(np.r_[stairs[:1000], stairs[1200:]])) == [999]


def test_a_command_compensated_at_its_reversals_is_still_one_circle():
    """A command compensated for the machine's error leads it by some 70 um at each
    reversal (a dense program of such a command, run on the machine, records it as its
    command): held to 35 um of the circle, the turn fell into arcs between the reversals,
    and no spike was reported at three of the four points. Its whole turn is taken within
    a sensor's tolerance and said so; the TCP's spike after B is read as on a plain
    circle."""
    p = circle_path()

    def lead(a):  # 70 um at each quadrant point, over some 3 deg
        return sum(70e-6 * np.exp(-0.5 * ((np.degrees(a) - q + 180) % 360 - 180) ** 2 / 9)
                   for q in (0, 90, 180, 270))

    def spike(a):  # +5 um 6 deg after B
        return 5e-6 * np.exp(-0.5 * (((np.degrees(a) - 96 + 180) % 360 - 180) / 1.5) ** 2)

    tcp = polar_perturb(p, (0, 0), spike)
    with pytest.warns(InputWarning, match="the command departs from the circle by more than "
                                          "35 um"):
        res = analyse_circle(make_run(polar_perturb(p, (0, 0), lead), tcp), R)
    [ps] = res.passes
    assert abs(ps.sensors["tcp"].angle_rad[-1] - ps.sensors["tcp"].angle_rad[0]) == \
        pytest.approx(2 * np.pi, abs=np.radians(0.5))
    assert ps.sensors["tcp"].spikes["B"] == pytest.approx(5e-6, rel=1e-3)
    assert all(abs(ps.sensors["tcp"].spikes[q]) < 1e-9 for q in "ACD")
    # a command within 35 um of the circle is held to it, and nothing is said
    with warnings.catch_warnings():
        warnings.simplefilter("error", InputWarning)
        assert analyse_circle(make_run(p, tcp), R).passes[0].sensors["tcp"].spikes["B"] == \
            pytest.approx(5e-6, rel=1e-3)


def test_a_circle_logged_too_sparsely_for_its_peaks_is_said(recwarn):
    """A 10 um spike some 6 ms wide after B on a 7.2 s turn: logged every 8 ms it read
    9.46 um, and every 16 ms under 1 um, with no word (the demo's circle every 8 ms read G
    14 % low); logged every millisecond the figures do not hang on single samples, and
    nothing is said."""
    def spike(a):
        return 10e-6 * np.exp(-0.5 * (((np.degrees(a) - 93 + 180) % 360 - 180) / 0.15) ** 2)

    p = circle_path()
    tcp = polar_perturb(p, (0, 0), spike)
    analyse_circle(make_run(p, tcp), R)
    assert not [w for w in recwarn if "single samples" in str(w.message)]
    every = slice(None, None, 8)
    run = Run(np.arange(len(p))[every] * 1e-3,
              {a: AxisRun(cmd=p[every, i], tcp=tcp[every, i]) for i, a in enumerate("XY")})
    with pytest.warns(InputWarning, match=r"figures hang on single samples: left out every "
                                          r"other of its samples, 8 ms apart, tcp contour "
                                          r"error \d\.\d\d by \d\.\d\d µm, tcp G"):
        analyse_circle(run, R)


def test_the_sparse_log_check_judges_the_samples_the_table_gives(recwarn):
    """A TCP 12 ms behind its command, which enters the circle along a tangent: over the
    command's turn, the TCP's first samples are still on the tangent. The table takes the
    TCP's own samples of the turn (0.01 um); the check on a sparse log took the command's,
    and said "tcp contour error 25.39 by 19.04 um" of a circle that has none."""
    dt, v, lag = 4e-3, 10.0 / 60, 0.012
    w = v / R
    turn = 2 * np.pi / w

    def path(tt):
        tt = np.asarray(tt) - 0.2
        a = w * np.clip(tt, 0.0, turn)
        y = np.where(tt < 0, v * tt, np.where(tt > turn, v * (tt - turn), R * np.sin(a)))
        return R * np.cos(a), y

    t = np.arange(0.0, turn + 0.4, dt)
    (cx, cy), (tx, ty) = path(t), path(t - lag)
    res = analyse_circle(Run(t, {"X": AxisRun(cmd=cx, tcp=tx), "Y": AxisRun(cmd=cy, tcp=ty)}), R)
    assert res.passes[0].sensors["tcp"].contour_error < 0.05e-6
    assert not [m for m in recwarn if "single samples" in str(m.message)]


def test_a_ccw_and_a_cw_circle_at_other_feeds_are_no_pair():
    """A CCW circle at F5000 and a CW one twice as fast, with Y lagging by 1 ms: given as
    a pair they gave a servo mismatch angle of neither (3571 against 2381 and 4762 urad),
    a hysteresis and a G(b) of two feeds, exit 0. Each circle keeps its own terms, and the
    pair's diagnostics are refused, naming both feeds."""
    from tcpmm.analysis.diagnostics import circle_diagnostics

    def lagged(direction, speed):
        p = circle_path(direction)
        t = np.arange(len(p)) * 1e-3 / speed
        lag_y = np.interp(t - 1e-3, t, p[:, 1])
        return Run(t, {"X": AxisRun(cmd=p[:, 0], tcp=p[:, 0]),
                       "Y": AxisRun(cmd=p[:, 1], tcp=lag_y)})

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", InputWarning)
        ccw, cw_fast, cw = (analyse_circle(lagged(d, s), R)
                            for d, s in (("ccw", 1.0), ("cw", 2.0), ("cw", 1.0)))
        two = CircleResult(R, ccw.centre, ccw.passes + cw_fast.passes)  # as `circle` joins
        with pytest.raises(InputError, match=r"F1833 \(.*rad/s\) and the CW circle at F3665"):
            circle_diagnostics(two)
        assert two.passes[0].sensors["tcp"].pair is None  # its spikes after its own terms
        near = analyse_circle(lagged("cw", 1.02), R)  # 2 %: a servo mismatch angle 1 % off
        with pytest.raises(InputError, match="hold at one feed"):
            circle_diagnostics(CircleResult(R, ccw.centre, ccw.passes + near.passes))
        one = CircleResult(R, ccw.centre, ccw.passes + cw.passes)
        assert one.passes[0].sensors["tcp"].pair is not None
        mismatch = circle_diagnostics(one).terms["servo_mismatch"][0]
    assert mismatch == pytest.approx(1e-3, rel=0.01)


def test_a_spike_the_raw_figures_hide_under_a_servo_mismatch_is_said():
    """Measured = predicted + a 5 um bump 5 deg after each quadrant point, both with Y 1 ms
    behind X: the raw e - b of both takes its extreme at the window's end, on the servo's
    ellipse, and Table 2 read 0.01-0.08 um. The spikes after the pair's terms differ by
    5 um, and the comparison says so, point by point."""
    from tcpmm.analysis.circle_spikes import QUADRANTS

    def run(direction, bump):
        p = circle_path(direction, start_deg=45.0)
        t = np.arange(len(p)) * 1e-3 / 2.728  # F5000 on R 35 mm
        p = np.column_stack([p[:, 0], np.interp(t - 1e-3, t, p[:, 1])])
        quads = np.radians([0.0, 90.0, 180.0, 270.0])
        sgn = 1.0 if direction == "ccw" else -1.0

        def de(a):
            d = np.angle(np.exp(1j * (a[:, None] - quads[None, :] - sgn * np.radians(5.0))))
            return bump * np.exp(-0.5 * (d / np.radians(2.0)) ** 2).sum(axis=1)

        sensed = polar_perturb(p, (0.0, 0.0), de)
        return Run(t, {"X": AxisRun(cmd=p[:, 0], tcp=sensed[:, 0]),
                       "Y": AxisRun(cmd=p[:, 1], tcp=sensed[:, 1])})

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", InputWarning)
        meas, pred = (CircleResult(R, (0.0, 0.0), analyse_circle(run("ccw", b), R).passes
                                   + analyse_circle(run("cw", b), R).passes)
                      for b in (5e-6, 0.0))
        cmp = compare_circles(meas, pred)
    assert max(abs(r[f"spike_{q}_um"]) for r in cmp.rows for q in QUADRANTS) < 1.0
    assert {(h["direction"], h["point"]) for h in cmp.hidden} == {
        (d, q) for d in ("CCW", "CW") for q in QUADRANTS}
    assert all(h["after_terms_um"] == pytest.approx(5.0, abs=0.3) for h in cmp.hidden)
    assert any("hide where measurement and prediction part" in n for n in cmp.notes())
    assert compare_circles(pred, pred).hidden == []


def test_the_ring_labels_lie_under_the_measured_trace():
    """The rings' labels ("-100 µm", "0 µm") sat in white boxes over the measured trace
    and blanked part of it, which read as a gap in the path: they lie under the traces."""
    import matplotlib

    matplotlib.use("Agg")
    p = circle_path()
    fig = analyse_circle(make_run(p, polar_perturb(p, (0.0, 0.0), lambda a: 20e-6 * np.cos(
        2 * a))), R).plot()
    for ax in fig.axes:
        labels = [t for t in ax.texts if isinstance(t, matplotlib.text.Annotation)
                  and t.get_text().endswith("µm")]
        traces = [ln for ln in ax.lines if ln.get_linestyle() == "-"]
        if labels and traces:
            assert max(t.get_zorder() for t in labels) < min(ln.get_zorder() for ln in traces)
            return
    raise AssertionError("no ring label beside a trace")


def test_spikes_after_terms_are_compared_only_between_runs_fitted_alike():
    """Bench C's CCW circle analysed with its CW circle (the pair's terms) against the same
    CCW circle alone (one direction's terms): every raw spike differs by 0, yet "after the
    terms" read differences up to 10 um, said to be hidden by the raw ones. Spikes after
    different fits are not compared."""
    from conftest import bench_path
    from tcpmm.io.runfile import read_run

    def circle(*dirs):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", InputWarning)
            return CircleResult(0.035, (0.0, 0.0), [
                p for d in dirs for p in analyse_circle(
                    read_run(bench_path("c") / f"circle_{d}_meas.csv"), 0.035).passes])

    pair, ccw = circle("ccw", "cw"), circle("ccw")
    cmp = compare_circles(pair, ccw)
    assert all(r[f"spike_{q}_um"] == 0.0 for r in cmp.rows for q in "ABCD")
    assert cmp.hidden == []
    assert compare_circles(ccw, pair).hidden == []


def test_a_command_about_another_centre_is_said_with_the_centre_to_give(tmp_path):
    """Bench C's CCW circle with every X moved by 20 um and by 0.2 mm, analysed about
    (0, 0): the raw spikes read up to 24 um off (20 um) and the shift was blamed on a
    compensated command (0.2 mm), and compare took a prediction of the unshifted command
    as of the same test. The command's centre is said with the --centre to give, refused
    where the passes were found only within a sensor's tolerance, and compare refuses the
    prediction as of another command."""
    import pandas as pd

    from conftest import bench_path
    from tcpmm.io.runfile import read_run

    path = bench_path("c") / "circle_ccw_meas.csv"
    a = pd.read_csv(path)
    for shift in (0.02, 0.2):
        b = a.copy()
        for k in [c for c in a.columns if c.startswith("x_")]:
            b[k] += shift
        b.to_csv(tmp_path / f"s{shift}.csv", index=False)
    with pytest.warns(InputWarning, match=r"about \(0\.0200, 0\.0000\) mm, 20\.0 µm .*"
                                          r"give --centre 0\.0200,0\.0000"):
        moved = analyse_circle(read_run(tmp_path / "s0.02.csv"), 0.035)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        analyse_circle(read_run(tmp_path / "s0.02.csv"), 0.035, (20e-6, 0.0))
    with pytest.raises(InputError, match=r"200\.0 µm .* give --centre 0\.2000,0\.0000"):
        analyse_circle(read_run(tmp_path / "s0.2.csv"), 0.035)
    with pytest.raises(InputError, match=r"20\.0 µm from the predicted one's .* another"):
        compare_circles(moved, analyse_circle(read_run(path), 0.035))


@pytest.mark.parametrize("arc", [False, True], ids=["circle", "arc"])
def test_a_gap_in_the_measured_log_is_not_compared(arc):
    """The measured run with its samples from 90 to 100 deg gone (a logger that broke
    off), over a bump of 3 um at 95 deg that the prediction holds too: the point-by-point
    difference drew a straight line across the gap and read 3 um where nothing is
    measured. It compares the angles both runs hold, and finds nothing between them (the
    bump, of 3 deg standard deviation, interpolates within 1 nm between 0.05 deg
    samples)."""
    def bump(a):
        return 3e-6 * np.exp(-0.5 * ((np.degrees(a) % 360 - 95.0) / 3.0) ** 2)

    p = arc_path("ccw", 30.0, 300.0) if arc else circle_path()
    run = make_run(p, polar_perturb(p, (0, 0), bump))
    deg = np.degrees(np.arctan2(p[:, 1], p[:, 0])) % 360
    keep = ~((deg > 90.0) & (deg < 100.0) & (np.hypot(p[:, 0], p[:, 1]) > 0.9 * R))
    cut = Run(run.time_s[keep], {k: AxisRun(cmd=a.cmd[keep], tcp=a.tcp[keep])
                                 for k, a in run.axes.items()})
    with warnings.catch_warnings():  # the gap and the arc's quadrant points: said
        warnings.simplefilter("ignore", InputWarning)
        row = compare_circles(analyse_circle(cut, R), analyse_circle(run, R)).rows[0]
    assert row["radial_max_um"] < 0.01 and row["radial_rms_um"] < 0.005


@pytest.mark.parametrize("every", [1, 4])
def test_runs_logged_at_other_periods_are_said_to_be(every):
    """A run compared with itself logged every 4 ms: its spikes are the extremes of fewer
    samples, and the difference point by point interpolates between them; on a simulated
    circle the TCP read spikes up to 0.76 um apart under no word. Where the periods differ
    by more than half, a warning says so and how to simulate at the measured one's."""
    from tcpmm.analysis.compare import cut_alike

    p = circle_path()
    run = make_run(p, polar_perturb(p, (0, 0), lambda a: 1e-6 * np.cos(3 * a)))
    sparse = Run(run.time_s[::every], {k: AxisRun(cmd=a.cmd[::every], tcp=a.tcp[::every])
                                       for k, a in run.axes.items()})
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        cut_alike(sparse, run)
    text = [str(w.message) for w in said]
    told = [m for m in text if "logged every" in m]
    if every == 1:
        assert not told
        return
    assert told == [told[0]] and "the measured run is logged every 4 ms, the predicted every " \
        "1 ms" in told[0] and "--record-period-s 0.004" in told[0]
