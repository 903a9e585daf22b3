"""Programs as CAM writes them: G64 P corner blending, G61 and G9 exact stops, a long run
of short blocks at the programmed feed, what holds the feed back, and the interpolator
settings in the model file."""

import itertools
import math
import re
import warnings

import numpy as np
import pytest

from tcpmm.analysis.contour import distance_to_polyline
from tcpmm.cli import main
from tcpmm.errors import InputError, InputWarning
from tcpmm.io.modelfile import read_machine
from tcpmm.path import InterpolatorSettings, Line, parse_gcode
from tcpmm.path.blend import blend_corners
from tcpmm.path.geometry import evaluate, to_arrays
from tcpmm.path.limits import feed_limits
from tcpmm.path.program import program_to_interpolation
from tcpmm.path.segments import Arc, Blend
from tcpmm.path.speedlimits import BEND_TOL


def spiral(n=720, step_deg=2.0, head="G21 G90 G17 F3000"):
    """``n`` G1 blocks of ``step_deg`` each on a spiral from R10 to R40 mm, and its
    vertices [mm]."""
    pts = [(10.0, 0.0)]
    for k in range(1, n + 1):
        th, r = math.radians(step_deg * k), 10 + 30 * k / n
        pts.append((round(r * math.cos(th), 4), round(r * math.sin(th), 4)))
    body = "\n".join(f"X{x:.4f} Y{y:.4f}" for x, y in pts[1:])
    return f"{head}\nG0 X10 Y0\nG1\n{body}\nM30\n", np.array(pts)


def speed(interp):
    c = interp.command
    return np.gradient(np.asarray(c.meta["path_s_m"]), c.time_s)


def test_g64_p_is_a_contour_tolerance_and_g9_stops_one_block():
    segs = parse_gcode("G64 P0.01\nG1 X10 F100\nG9 X20\nX30\nG61 X40\nX50\nG64 X60\n"
                       "G20 G64 P0.001 X3\n")
    assert [s.tolerance_m for s in segs] == pytest.approx([1e-5] * 3 + [None] * 3 + [25.4e-6])
    assert [s.exact_stop for s in segs] == [False, True, False, True, True, False, False]
    with pytest.warns(InputWarning, match="Q ignored: the naive-CAM merging"):
        parse_gcode("G64 P0.01 Q0.005\nG1 X1 F100\n")
    for text, msg in (("G1 X1 F100 P2\n", "P is only used with G4"),
                      ("G61 P0.01\nG1 X1 F100\n", "P is only used with G4"),
                      ("G64 P-0.1\n", "must not be negative"),
                      ("G9\nG1 X1 F100\n", "G9 (exact stop) needs a move")):
        with pytest.raises(InputError, match=msg.replace("(", r"\(").replace(")", r"\)")):
            parse_gcode(text)


@pytest.mark.parametrize(("head", "fix"), [("G21", "in mm; write P0.01"),
                                           ("G20", "in inches under G20; write P0.0004")])
def test_a_contour_tolerance_of_more_than_10_mm_is_refused(head, fix):
    """``G64 P100`` (meant in µm, or P0.5 under G20, 12.7 mm) rounded a 10 mm square's
    corners by as much as its sides allow, with no word, where a model file's tolerance
    above 10 mm is refused. Read whole or streamed, the program is refused naming the
    word; 10 mm itself is taken."""
    from tcpmm.path.program import program_to_command
    from tcpmm.path.stream import stream_program

    p = "P100" if head == "G21" else "P0.5"
    text = f"{head} G90\nG1 X0 Y0 F1000\nG64 {p}\nG1 X10\nG1 Y10\n"
    for read in (lambda: program_to_command(text),
                 lambda: list(stream_program(text, chunk_blocks=1))):
        with pytest.raises(InputError, match=f"contour tolerance {p} is .* mm, above 10 mm") as e:
            read()
        assert fix in e.value.message
        assert (e.value.line, e.value.column) == (3, 5)
    program_to_command(text.replace(p, "P10" if head == "G21" else "P0.39"))


@pytest.mark.parametrize("turn_deg", [10.0, 90.0, 150.0])
def test_a_blend_passes_the_corner_at_the_tolerance_and_joins_tangentially(turn_deg):
    tol, th = 20e-6, math.radians(turn_deg)
    a = Line((0.0, 0.0, 0.0), (0.05, 0.0, 0.0), 0.05, tolerance_m=tol)
    end = (0.05 + 0.05 * math.cos(th), 0.05 * math.sin(th), 0.0)
    b = Line(a.end_m, end, 0.05)
    l1, arc, l2 = blend_corners([a, b])
    assert isinstance(arc, Blend) and arc.sweep_rad == pytest.approx(th, rel=1e-9)
    assert l1.end_m == arc.start_m and arc.end_m == l2.start_m and l2.end_m == end
    p = to_arrays([l1, arc, l2], (1.0, 1.0, 1.0))
    pts = evaluate(p, np.ones(20001, int), np.linspace(0, p.length[1], 20001))
    gap = np.linalg.norm(pts - np.array(a.end_m), axis=1).min()
    assert gap == pytest.approx(tol, rel=1e-6)  # the closest point is the arc's middle
    assert arc.radius_m == pytest.approx(math.dist(arc.end_m, arc.centre_m), rel=1e-12)
    assert np.allclose(pts[-1], arc.end_m, rtol=0, atol=1e-15)
    # tangent at both ends: the radius is normal to the line there
    for q, u in ((arc.start_m, (1, 0, 0)), (arc.end_m, (math.cos(th), math.sin(th), 0))):
        assert np.dot(np.subtract(q, arc.centre_m), u) == pytest.approx(0, abs=1e-15)


def test_corners_that_stay_sharp():
    o, x, xy = (0.0, 0.0, 0.0), (0.01, 0.0, 0.0), (0.01, 0.01, 0.0)
    tol = 1e-5
    assert len(blend_corners([Line(o, x, 0.1, tolerance_m=0.0), Line(x, xy, 0.1)])) == 2
    assert len(blend_corners([Line(o, x, 0.1, exact_stop=True, tolerance_m=tol),
                              Line(x, xy, 0.1)])) == 2
    assert len(blend_corners([Line(o, x, 0.1, tolerance_m=tol), Line(x, o, 0.1)])) == 2
    assert len(blend_corners([Line(o, x, 0.1, tolerance_m=tol), Arc(x, xy, (0.01, 0.005, 0),
                                                                    ("X", "Y"), "ccw", 0.1)])) == 2


def test_a_corner_in_any_orientation_is_blended_within_the_tolerance():
    o, x, skew = (0.0, 0.0, 0.0), (0.01, 0.0, 0.0), (0.02, 0.01, 0.01)
    tol = 1e-5
    segs = blend_corners([Line(o, x, 0.1, tolerance_m=tol), Line(x, skew, 0.1)])
    p = to_arrays(segs, (1.0, 1.0, 1.0))
    pts = evaluate(p, np.ones(20001, int), np.linspace(0, p.length[1], 20001))
    assert np.linalg.norm(pts - np.array(x), axis=1).min() == pytest.approx(tol, rel=1e-6)
    assert np.allclose(pts[[0, -1]], [segs[1].start_m, segs[1].end_m], rtol=0, atol=1e-15)
    # a 3-D polyline along a helix runs at its feed like the plane spiral
    pts = [(0.01 * math.cos(math.radians(2 * k)), 0.01 * math.sin(math.radians(2 * k)),
            -2e-5 * k) for k in range(361)]
    body = "\n".join(f"X{x * 1e3:.4f} Y{y * 1e3:.4f} Z{z * 1e3:.4f}" for x, y, z in pts[1:])
    res = program_to_interpolation(f"G64 P0.01\nG1 X10 Y0 Z0 F3000\n{body}\n")
    v, s = speed(res), np.asarray(res.command.meta["path_s_m"])
    on = (s > 0.02 + 0.05 * (s[-1] - 0.01)) & (s < s[-1] - 0.05 * (s[-1] - 0.01))
    assert np.ptp(v[on]) < 1e-4 * 0.05 and np.mean(v[on]) == pytest.approx(0.05, rel=1e-6)


def test_a_spiral_of_720_short_blocks_runs_at_the_programmed_feed_with_g64_p():
    text, verts = spiral(head="G21 G90 G17 G64 P0.01 F3000")
    res = program_to_interpolation(text)
    v = speed(res)
    s = np.asarray(res.command.meta["path_s_m"])
    on = (s > 0.05 * s[-1]) & (s < 0.95 * s[-1])  # away from the start and the end
    assert np.ptp(v[on]) < 0.01 * 0.05  # ripple under 1 % of F3000 = 0.05 m/s
    assert np.mean(v[on]) == pytest.approx(0.05, rel=1e-3)
    # and within the tolerance of the programmed polyline
    q = np.column_stack([res.command.positions["X"], res.command.positions["Y"]])
    k = np.flatnonzero(s > 0.011)  # after the rapid to the start
    d, _ = distance_to_polyline(q[k], verts * 1e-3, np.arange(k.size) / k.size,
                                np.linspace(0, 1, len(verts)), 2.0, False)
    assert np.max(d) <= 1e-5 * (1 + 1e-6)
    lim = feed_limits(res)
    assert lim.share_at_feed() > 0.98
    assert {r["cause"] for r in lim.summary()} <= {"exact stop", "path acceleration"}


def test_without_a_tolerance_the_corners_hold_the_spiral_back_and_say_so():
    text, _ = spiral()
    res = program_to_interpolation(text)
    v = speed(res)[np.asarray(res.command.meta["path_s_m"]) > 0.011]  # after the rapid
    assert v.max() == pytest.approx(0.05, rel=1e-6) and np.median(v) < 0.045  # the old ripple
    [top, *_] = feed_limits(res).summary()
    assert top["cause"] == "corner: axis acceleration"
    assert (top["first_line"], top["last_line"]) == (6, 722) and top["blocks"] > 600



def test_a_square_is_at_the_feed_where_its_samples_are(tmp_path, capsys):
    """Every side of a square reaches F3000, but each starts and ends at rest (exact stops):
    at 1 m/s^2 the feed is within 1 % from (0.99 * 0.05)^2 / 2 = 1.225 mm after a corner
    to as much before the next. Counted by the blocks' peaks it was 100 %."""
    program = "G21 G17 G90\nG0 X0 Y0\nG1 X50 Y0 F3000\nX50 Y50\nX0 Y50\nX0 Y0\nM30\n"
    lim = feed_limits(program_to_interpolation(program))
    assert not lim.held.any()  # every block reaches its feed
    ramp = (0.99 * 0.05) ** 2 / 2
    assert lim.feed_length_m == pytest.approx(0.2, rel=1e-9)
    assert lim.share_at_feed() == pytest.approx(1 - 8 * ramp / 0.2, abs=1e-3)  # a sample each
    assert lim.ramp_length_m() == pytest.approx(8 * ramp, abs=2e-4)
    d = lim.to_dict()
    assert d["length_at_feed_mm"] == pytest.approx(200 - 8e3 * ramp, abs=0.05)
    (tmp_path / "sq.nc").write_text(program)
    assert main(["path", str(tmp_path / "sq.nc"), "-o", str(tmp_path / "c.csv")]) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert "at the programmed feed (within 1 %) on 95.1 % of the path length" in out
    assert "speed up and slow down: 9.8 mm" in out  # 8 * ramp, to a sample


@pytest.mark.parametrize("program", ["G21 G90\nG0 X10 Y10\nG0 Z-5\nM30\n", "G4 P1\nM30\n"])
def test_a_program_without_feed_moves_is_not_at_its_feed(tmp_path, capsys, program):
    """Rapids and dwells alone were "at the programmed feed on 100.0 %" (0 of 0)."""
    assert math.isnan(feed_limits(program_to_interpolation(program)).share_at_feed())
    (tmp_path / "p.nc").write_text(program)
    assert main(["path", str(tmp_path / "p.nc"), "-o", str(tmp_path / "c.csv")]) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert "no feed moves" in out and "%" not in out

@pytest.mark.parametrize("kind", ["linear", "bell"])
def test_with_a_filter_the_share_at_feed_is_that_of_the_command_written(kind):
    """An interpolation filter slows the path at every corner it rounds; the share at the
    feed was taken from the samples before it (95.2 % on this square with a 50 ms bell
    filter, more than the 95.1 % without one, where the command written is at the feed on
    92.4 %). Now it is the written command's, each sample within 1 % of its feed."""
    program = "G21 G17 G90\nG0 X0 Y0\nG1 X50 Y0 F3000\nX50 Y50\nX0 Y50\nX0 Y0\nM30\n"
    s = InterpolatorSettings(filter_kind=kind, filter_time_s=0.05)
    res = program_to_interpolation(program, s)
    cmd = res.command
    P = np.column_stack(list(cmd.positions.values()))
    ds = np.sqrt(np.sum(np.diff(P, axis=0) ** 2, axis=1))
    at = ds >= 0.99 * 0.05 * cmd.period_s
    lim = feed_limits(res)
    assert lim.feed_length_m == pytest.approx(ds.sum(), rel=1e-9)
    assert lim.share_at_feed() == pytest.approx(ds[at].sum() / ds.sum(), abs=1e-9)
    assert lim.share_at_feed() < feed_limits(program_to_interpolation(program)).share_at_feed()


def test_the_limit_that_holds_a_block_back_is_named():
    s = InterpolatorSettings(axis_velocity_m_per_s={"X": 0.02})
    lim = feed_limits(program_to_interpolation("G1 X100 F3000\n", s))
    assert [r["cause"] for r in lim.summary()] == ["axis velocity"]
    assert lim.summary()[0]["lowest_m_per_s"] == pytest.approx(0.02)
    arc = "G1 X10 F20000\nG3 X10 Y0 I-5 J0\n"  # R5 at 20 m/min: v^2/R beyond 1 m/s^2
    causes = [r["cause"] for r in feed_limits(program_to_interpolation(arc)).summary()]
    assert "curvature (centripetal acceleration)" in causes
    scurve = InterpolatorSettings(profile="scurve", path_jerk_m_per_s3=1.0)
    table = feed_limits(program_to_interpolation("G1 X1 F3000\nX2\nX3\nX4\n",
                                                 scurve)).to_pandas()
    # four 1 mm blocks, too short to reach F3000 from rest and back with that jerk
    assert table["cause"].tolist() == ["exact stop", "path jerk", "path jerk", "exact stop"]


def test_a_block_is_held_back_by_its_own_limit_only_where_it_reaches_it():
    """A circle of R5 in 2 deg G3 arcs at F20000 from rest: every block's own limit (the
    centripetal acceleration) lies below the feed, but the blocks that speed up from rest
    and slow down to it stay far below that limit. Named after it, they made the
    curvature's 'peak feed as low as' a third of what the curvature allows; what holds them
    back is the path acceleration and the exact stops at the ends."""
    from tcpmm.path.speedlimits import SEGMENT_CAUSES

    arcs = "".join(
        f"G3 X{5 * math.cos(math.radians(k)):.5f} Y{5 * math.sin(math.radians(k)):.5f} "
        f"I{-5 * math.cos(math.radians(k - 2)):.5f} J{-5 * math.sin(math.radians(k - 2)):.5f}\n"
        for k in range(2, 362, 2))
    it = program_to_interpolation(f"G21 G90 G17\nG0 X5 Y0\nG1 F20000\n{arcs}M30\n")
    lim = feed_limits(it)
    vmax, peak = it.segment_vmax_m_per_s, it.segment_peak_m_per_s
    own = np.isin(lim.cause, [str(c) for c in SEGMENT_CAUSES[1:]])
    assert own.sum() > 100 and np.all(peak[own] >= 0.99 * vmax[own])
    rows = {r["cause"]: r for r in lim.summary()}
    assert set(rows) == {"curvature (centripetal acceleration)", "path acceleration",
                         "exact stop"}
    bound = vmax[lim.held & ~np.isin(lim.cause, ["exact stop"])].min()
    assert rows["curvature (centripetal acceleration)"]["lowest_m_per_s"] >= 0.99 * bound
    assert rows["path acceleration"]["lowest_m_per_s"] < 0.5 * bound


def test_machine_export_writes_the_interpolator_settings_and_path_reads_them(tmp_path,
                                                                             capsys):
    assert main(["machine", "export", "vmc", "-o", str(tmp_path / "m.yaml")]) == 0
    m = read_machine(tmp_path / "m.yaml")
    assert InterpolatorSettings.model_validate(m.interpolation) == InterpolatorSettings()
    text = (tmp_path / "m.yaml").read_text()
    assert "blend_tolerance_m: 0.0" in text
    (tmp_path / "e.yaml").write_text(text.replace("blend_tolerance_m: 0.0",
                                                  "blend_tolerance_m: 1.0e-05"))
    (tmp_path / "s.nc").write_text(spiral()[0])
    capsys.readouterr()
    for model, share in (("m.yaml", "1.7 %"), ("e.yaml", "99.")):
        code = main(["path", str(tmp_path / "s.nc"), "-o", str(tmp_path / "c.csv"),
                     "--model", str(tmp_path / model), "--plot"])
        out = " ".join(capsys.readouterr().out.split())
        assert code == 0 and f"at the programmed feed (within 1 %) on {share}" in out
    assert "held back by corner" not in out and (tmp_path / "c.png").is_file()
    (tmp_path / "bad.yaml").write_text(text.replace("blend_tolerance_m: 0.0",
                                                    "blend_tolerance_m: -1"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["path", str(tmp_path / "s.nc"), "-o", str(tmp_path / "c.csv"),
                     "--model", str(tmp_path / "bad.yaml")]) == 2
    assert "blend_tolerance_m" in capsys.readouterr().err


def test_feed_limits_and_the_command_plot_share_the_protocol(tmp_path):
    from tcpmm.plot import pyplot

    text, _ = spiral(n=90)
    res = program_to_interpolation(text)
    lim = feed_limits(res)
    table = lim.to_pandas()
    assert len(table) == res.path.n and set(table["cause"]) >= {"corner: axis acceleration"}
    import json

    json.dumps(lim.to_dict())
    assert lim.plot(path=tmp_path / "f.png").axes and (tmp_path / "f.png").stat().st_size > 0
    fig = pyplot().figure()
    axs = [fig.add_subplot(2, 2, k) for k in range(1, 5)]
    assert res.command.plot(ax=axs) is fig
    assert axs[3].get_title() == "feed along the path"
    with pytest.raises(ValueError, match="4 panels"):
        res.command.plot(ax=axs[:3])
    pyplot().close("all")


def _unit_reference(p, q):
    """The direction from ``p`` to ``q`` in Python floats, coordinates summed first to
    last [-]."""
    v = [q[i] - p[i] for i in range(3)]
    n = math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    return [x / n for x in v]


def _tangent_length_reference(a, b, tol):
    """The tangent length of one corner in Python floats (the module's formula)."""
    if not tol > 0.0 or a.exact_stop:
        return 0.0
    u1, u2 = _unit_reference(a.start_m, a.end_m), _unit_reference(b.start_m, b.end_m)
    c = min(max(u1[0] * u2[0] + u1[1] * u2[1] + u1[2] * u2[2], -1.0), 1.0)
    cr = [u1[1] * u2[2] - u1[2] * u2[1], u1[2] * u2[0] - u1[0] * u2[2],
          u1[0] * u2[1] - u1[1] * u2[0]]
    du = [u2[i] - u1[i] for i in range(3)]
    if (math.sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]) < 1e-12
            or math.sqrt(du[0] * du[0] + du[1] * du[1] + du[2] * du[2]) < BEND_TOL):
        return 0.0
    h = 0.5 * math.acos(c)
    s = math.sin(0.5 * h)
    d = min(tol * math.sin(h) / (2.0 * (s * s)), 0.5 * a.length_m, 0.5 * b.length_m)
    return d if d >= 1e-9 else 0.0


def _random_run(seed, n=400):
    """Straight blocks of random length: turns of every size, collinear runs, reversals,
    exact stops, and tolerances of a block's own, none or 0."""
    rng = np.random.default_rng(seed)
    pts, segs = [np.zeros(3)], []
    for _ in range(n):
        kind = rng.integers(4)
        step = (rng.normal(size=3) if kind == 0 else
                -(pts[-1] - pts[-2]) if kind == 1 and len(pts) > 1 else
                (pts[-1] - pts[-2]) if len(pts) > 1 else rng.normal(size=3))
        step = step / np.linalg.norm(step) * 10.0 ** rng.uniform(-5, -2)
        pts.append(pts[-1] + step)
        tol = [None, 0.0, 1e-5, 10.0 ** rng.uniform(-7, -3)][rng.integers(4)]
        segs.append(Line(tuple(pts[-2]), tuple(pts[-1]), 0.05 + 0.01 * rng.integers(3),
                         exact_stop=bool(rng.random() < 0.05), tolerance_m=tol))
    return segs


@pytest.mark.parametrize("seed", range(5))
def test_the_corners_of_a_long_run_taken_at_once_are_each_ones(seed):
    """Collinear runs, turns of every size, reversals, exact stops and tolerances of a
    block's own, none or 0: the tangent lengths worked out for all the corners at once
    are those of each corner alone, to the bit."""
    from tcpmm.path.blendrows import block_table, tangent_lengths

    segs = _random_run(seed)
    got = tangent_lengths(block_table(segs), 2e-6).tolist()
    want = [0.0] + [_tangent_length_reference(a, b, 2e-6 if a.tolerance_m is None
                                              else a.tolerance_m)
                    for a, b in itertools.pairwise(segs)] + [0.0]
    assert [v.hex() for v in got] == [float(v).hex() for v in want]
    assert sum(v > 0 for v in got) > 50


def _blended_reference(segs, d):
    """The blended path in Python floats, one block at a time (the module's formulas)."""
    out = []
    for i, s in enumerate(segs):
        if d[i] or d[i + 1]:
            u = _unit_reference(s.start_m, s.end_m)
            p = segs[i - 1].end_m if d[i] else s.start_m
            a = tuple(p[c] + d[i] * u[c] for c in range(3))
            b = tuple(s.end_m[c] - d[i + 1] * u[c] for c in range(3))
            gap = math.sqrt(sum((b[c] - a[c]) ** 2 for c in range(3)))
            span = math.sqrt(sum((s.end_m[c] - s.start_m[c]) ** 2 for c in range(3)))
            if gap > 1e-12 * max(span, 1e-3):
                out.append(Line(a, b, s.feed_m_per_s, s.exact_stop, s.line, s.tolerance_m))
        else:
            out.append(s)
        if d[i + 1]:
            nxt, dk, p = segs[i + 1], d[i + 1], s.end_m
            u1, u2 = u, _unit_reference(nxt.start_m, nxt.end_m)
            h = 0.5 * math.acos(min(max(u1[0] * u2[0] + u1[1] * u2[1] + u1[2] * u2[2],
                                        -1.0), 1.0))
            reach = dk / math.tan(h) / math.cos(h)
            bis = _unit_reference(u1, u2)
            out.append(Blend(tuple(p[c] - dk * u1[c] for c in range(3)),
                             tuple(p[c] + dk * u2[c] for c in range(3)),
                             tuple(p[c] + bis[c] * reach for c in range(3)),
                             min(s.feed_m_per_s, nxt.feed_m_per_s), line=nxt.line))
    return out


@pytest.mark.parametrize("seed", range(5))
def test_the_blends_of_a_long_run_taken_at_once_are_each_ones(seed):
    """The trimmed lines and blend arcs worked out for all the corners at once are those
    of each corner alone in Python floats, to the bit: no sum of a library that pairs the
    coordinates otherwise on another CPU, no vector unit's sine."""
    from tcpmm.path.blendrows import block_table, tangent_lengths

    segs = _random_run(seed)
    got = blend_corners(segs, 2e-6)
    want = _blended_reference(segs, tangent_lengths(block_table(segs), 2e-6).tolist())
    assert sum(type(s) is Blend for s in got) > 50
    assert got == want


def test_the_lines_a_limit_holds_back_are_a_line_or_a_span(tmp_path, capsys):
    """A limit that holds one block back names its line; one over several blocks the
    span of lines they lie in (other blocks among them): 'lines 16-16' and 'lines 4-15'
    (with line 14 held back by another limit) read as a run of lines."""
    arcs = "".join(f"G3 X20 Y{2 if k % 2 == 0 else 0} R1\n" for k in range(10))
    program = ("G21 G17 G90\nG1 X10 Y0 F2000\nG1 X20 Y0 F8000\n" + arcs
               + "G1 X30 Y0\nG2 X40 Y0 I5 J0 F20000\nG1 X50\n")
    (tmp_path / "fs.nc").write_text(program)
    assert main(["path", str(tmp_path / "fs.nc"), "-o", str(tmp_path / "c.csv")]) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert "in 11 blocks, between lines 4 and 15," in out and "in 1 block, line 16," in out
    assert "lines 16-16" not in out and "lines 4-15" not in out


def test_held_back_blocks_are_nc_blocks_not_blend_pieces(tmp_path, capsys):
    """A spiral of 2 deg G1 blocks under G64 P0.01: 'held back by path acceleration: 1.42 mm
    in 8 blocks, between lines 7 and 10' counted each line and its blend, four blocks as
    eight."""
    rows = []
    for k in range(720):
        r, th = 10.0 + 30.0 * k / 719, math.radians(2.0 * k)
        rows.append(f"G1 X{r * math.cos(th):.4f} Y{r * math.sin(th):.4f}\n")
    (tmp_path / "s.nc").write_text("G21 G90 G17\nG0 X10 Y0 Z0\nG64 P0.01\nG1 F3000\n"
                                   + "".join(rows[1:]))
    assert main(["path", str(tmp_path / "s.nc"), "-o", str(tmp_path / "c.csv")]) == 0
    out = " ".join(capsys.readouterr().out.split())
    held = [(int(n), int(a), int(b)) for n, a, b in re.findall(
        r"in (\d+) blocks, between lines (\d+) and (\d+)", out)]
    assert held and all(n <= b - a + 1 for n, a, b in held), out


def test_the_lines_between_a_blends_arcs_are_held_back_by_the_arcs(tmp_path, capsys):
    """A circle of R 10 mm as 628 chords under G64 P0.005 at F8000 runs at the 5045 mm/min
    its curvature allows; each chord is a short line between two blend arcs, and those
    lines were said held back by the path acceleration ('9.6 mm in 461 blocks', of 628),
    which changes nothing. Only the ramps at the start and the end are."""
    rows = "".join(f"G1 X{10 * math.cos(2 * math.pi * k / 628):.6f} "
                   f"Y{10 * math.sin(2 * math.pi * k / 628):.6f}\n" for k in range(1, 629))
    (tmp_path / "c.nc").write_text("G21 G90 G17\nG64 P0.005\nG0 X10 Y0\nG4 P0.3\nF8000\n"
                                   + rows + "G4 P0.5\nM30\n")
    assert main(["path", str(tmp_path / "c.nc"), "-o", str(tmp_path / "c.csv")]) == 0
    out = " ".join(capsys.readouterr().out.split())
    blocks = {c: int(n) for c, n in re.findall(r"held back by ([a-z ()]+): [\d.]+ mm in "
                                               r"(\d+) blocks?", out)}
    assert blocks["curvature (centripetal acceleration)"] > 500, out
    assert blocks["path acceleration"] < 120 and sum(blocks.values()) < 640, out


def test_path_says_where_a_sharp_corner_takes_an_axis_beyond_its_acceleration(tmp_path,
                                                                              capsys):
    """Under G64 without P the zig-zag's corners stay sharp, and their velocity step on
    top of the braking read 1.44 and 1.5 m/s2 against 1 with nothing said; with
    corner_step_share 0 (in the model file) every sharp corner stops and nothing is
    beyond the limit."""
    prog = tmp_path / "zig.nc"
    prog.write_text("G90 G17 G64 F5000\nG1 X20 Y0\nG1 X20 Y1\nG1 X0 Y1\nG1 X0 Y2\n"
                    "G1 X20 Y2\n")
    assert main(["path", str(prog), "-o", str(tmp_path / "c.csv")]) == 0
    said = " ".join(capsys.readouterr().out.split())
    assert "beyond an axis's acceleration for a period at sharp corners" in said
    assert re.search(r"X 1\.\d+ m/s² \(limit 1\), Y 1\.\d+ m/s² \(limit 1\)", said), said
    assert main(["machine", "export", "vmc", "-o", str(tmp_path / "m.yaml")]) == 0
    text = (tmp_path / "m.yaml").read_text()
    assert "corner_step_share: 1.0" in text
    (tmp_path / "s0.yaml").write_text(text.replace("corner_step_share: 1.0",
                                                   "corner_step_share: 0.0"))
    capsys.readouterr()
    assert main(["path", str(prog), "-o", str(tmp_path / "c.csv"), "--model",
                 str(tmp_path / "s0.yaml")]) == 0
    assert "beyond an axis's acceleration" not in capsys.readouterr().out


def test_a_program_interpolated_in_chunks_says_where_an_axis_goes_beyond_it(tmp_path,
                                                                          capsys):
    """With ``--chunk-blocks`` (and for every program of more than a million lines, which
    is always interpolated in chunks) the line naming the axes beyond their acceleration
    was left out; now it is the whole program's, to the digit."""
    prog = tmp_path / "zig.nc"
    prog.write_text("G90 G17 G64 F5000\nG1 X20 Y0\nG1 X20 Y1\nG1 X0 Y1\nG1 X0 Y2\n"
                    "G1 X20 Y2\n")
    said = {}
    for how in ([], ["--chunk-blocks", "2"]):
        assert main(["path", str(prog), "-o", str(tmp_path / "c.csv"), *how]) == 0
        said[bool(how)] = [ln for ln in capsys.readouterr().out.splitlines()
                           if "beyond an axis's acceleration" in ln]
    assert said[True] == said[False] and len(said[True]) == 1, said


@pytest.mark.parametrize("cuts", [[1], [2, 3], [5, 6, 7, 50], list(range(1, 60, 3))])
def test_the_running_peak_of_pieces_is_the_whole_commands(cuts):
    """The largest second and third difference per axis, the command given in pieces cut
    anywhere (a piece of one sample too), are the whole command's to the bit."""
    from tcpmm.path.limits import RunningPeak, peak

    rng = np.random.default_rng(3)
    x = {"X": np.cumsum(np.cumsum(rng.normal(size=64))), "Y": rng.normal(size=64)}
    for order in (2, 3):
        rp = RunningPeak(order, 1e-3)
        for a, b in zip([0, *cuts], [*cuts, 64], strict=True):
            rp.add({k: v[a:b] for k, v in x.items()})
        assert rp.most == {k: peak(v, order, 1e-3) for k, v in x.items()}


@pytest.mark.parametrize("tol_mm, aside_mm", [(0.005, 0.000005), (0.005, 0.000001),
                                               (0.05, 0.000001)])
def test_a_pass_and_back_beside_it_stays_sharp_at_its_reversal(tol_mm, aside_mm):
    """A 10 mm pass and back along it 1-5 nm aside turns back by 1e-7 to 5e-7 rad short
    of a reversal: the look-ahead stops there (its tangents' dot product is within
    ``REVERSAL_TOL`` of -1), where the blend of the tolerance made an arc of some 1e-12 m
    between tangent points a hair's breadth apart, to which no speed could be given, and
    the program was refused. The corner stays sharp: the command reaches X10 to the
    nanometre of its coordinates and turns back there."""
    from tcpmm.path.program import program_to_command

    text = (f"G21 G90 G64 P{tol_mm:g}\nG1 X0 Y0 F5000\nG1 X10. Y0\n"
            f"G1 X0 Y{aside_mm:.6f}\n")
    cmd = program_to_command(text)
    x = cmd.positions["X"]
    assert abs(np.max(x) - 0.01) <= 1e-12
    assert x[-1] == 0.0
