"""Interpolator properties on random programs: geometry, feed, limits, corners, filter."""

from __future__ import annotations

import math
import time

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from tcpmm.errors import InputError
from tcpmm.path import (
    InterpolatorSettings,
    Line,
    interpolate,
    interpolate_detailed,
    parse_gcode,
)
from tcpmm.path.speedlimits import BEND_TOL

PLANE = {17: (0, 1), 18: (2, 0), 19: (1, 2)}  # G17 XY, G18 ZX, G19 YZ
CENTRE_LETTER = "IJK"
AXIS_LETTER = "XYZ"


def _mm(x):
    """Round a length [m] as the program writes it (6 decimals in mm) [m]."""
    return round(x * 1e3, 6) * 1e-3


@st.composite
def programs(draw, max_moves=6, arcs=True, lines=True, helix=True, min_len_mm=0.5):
    """A random program and its geometry, written independently of the parser.

    Returns the G-code text and a list of moves: dicts with start, end [m], feed [m/s],
    and for arcs the plane indices, centre [m] and signed sweep [rad].
    """
    pos = np.zeros(3)
    text = ["G21 G90"]
    moves = []
    kinds = (["line"] if lines else []) + (["arc"] if arcs else [])
    for _ in range(draw(st.integers(1, max_moves))):
        feed_mm_min = round(draw(st.floats(1000.0, 9000.0)), 3)
        feed = feed_mm_min * 1e-3 / 60.0
        if draw(st.sampled_from(kinds)) == "line":
            d = np.array([draw(st.floats(-1.0, 1.0)) for _ in range(3)])
            d = d / np.linalg.norm(d) if np.linalg.norm(d) > 1e-3 else np.array([1.0, 0, 0])
            length = draw(st.floats(min_len_mm * 1e-3 + 1e-5, 0.05))
            end = np.array([_mm(c) for c in pos + length * d])
            words = " ".join(f"{AXIS_LETTER[i]}{end[i] * 1e3:.6f}" for i in range(3))
            text.append(f"G1 {words} F{feed_mm_min:.3f}")
            moves.append(dict(kind="line", start=pos.copy(), end=end, feed=feed))
        else:
            plane = draw(st.sampled_from([17, 18, 19]))
            ia, ib = PLANE[plane]
            ih = 3 - ia - ib
            r = draw(st.floats(0.002, 0.04))
            alpha = draw(st.floats(-math.pi, math.pi))
            ccw = draw(st.booleans())
            full = draw(st.booleans()) and draw(st.booleans())
            sweep = 2 * math.pi if full else draw(st.floats(0.1, 2 * math.pi - 0.1))
            sweep = sweep if ccw else -sweep
            off = np.array([_mm(-r * math.cos(alpha)), _mm(-r * math.sin(alpha))])
            ca, cb = pos[ia] + off[0], pos[ib] + off[1]
            end = pos.copy()
            if not full:
                end[ia] = _mm(ca + r * math.cos(alpha + sweep))
                end[ib] = _mm(cb + r * math.sin(alpha + sweep))
            if helix and draw(st.booleans()):
                end[ih] = _mm(pos[ih] + draw(st.floats(-0.01, 0.01)))
            words = " ".join(f"{AXIS_LETTER[i]}{end[i] * 1e3:.6f}" for i in (ia, ib, ih))
            centre = f"{CENTRE_LETTER[ia]}{off[0] * 1e3:.6f} {CENTRE_LETTER[ib]}{off[1] * 1e3:.6f}"
            g = "G3" if ccw else "G2"
            text.append(f"G{plane} {g} {words} {centre} F{feed_mm_min:.3f}")
            moves.append(
                dict(kind="arc", start=pos.copy(), end=end, feed=feed, ia=ia, ib=ib, ih=ih,
                     ca=ca, cb=cb, sweep=sweep)
            )  # fmt: skip
        pos = end
    return "\n".join(text) + "\n", moves


def _arc_numbers(m):
    s, e = m["start"], m["end"]
    ia, ib, ih = m["ia"], m["ib"], m["ih"]
    r0 = math.hypot(s[ia] - m["ca"], s[ib] - m["cb"])
    r1 = math.hypot(e[ia] - m["ca"], e[ib] - m["cb"])
    th0 = math.atan2(s[ib] - m["cb"], s[ia] - m["ca"])
    th1 = math.atan2(e[ib] - m["cb"], e[ia] - m["ca"])
    dh = e[ih] - s[ih]
    # the sweep the rounded end point gives: nearest to the drawn one
    nominal = m["sweep"]
    sweep = nominal + math.remainder(th1 - th0 - nominal, 2 * math.pi)
    return r0, r1, th0, dh, sweep


def _length(m):
    if m["kind"] == "line":
        return float(np.linalg.norm(m["end"] - m["start"]))
    r0, r1, _, dh, sweep = _arc_numbers(m)
    return math.hypot(0.5 * (r0 + r1) * sweep, dh)


def _points(m, s):
    """Points at distances s along a move [m]."""
    f = np.asarray(s) / _length(m)
    if m["kind"] == "line":
        return m["start"] + f[:, None] * (m["end"] - m["start"])
    r0, r1, th0, dh, sweep = _arc_numbers(m)
    th = th0 + sweep * f
    r = r0 + (r1 - r0) * f
    p = np.empty((f.size, 3))
    p[:, m["ia"]] = m["ca"] + r * np.cos(th)
    p[:, m["ib"]] = m["cb"] + r * np.sin(th)
    p[:, m["ih"]] = m["start"][m["ih"]] + dh * f
    return p


def _xyz(cmd):
    n = cmd.time_s.size
    return np.column_stack([cmd.positions.get(a, np.zeros(n)) for a in "XYZ"])


def _expected(moves, path_s):
    cum = np.concatenate([[0.0], np.cumsum([_length(m) for m in moves])])
    seg = np.clip(np.searchsorted(cum, path_s, side="right") - 1, 0, len(moves) - 1)
    out = np.empty((path_s.size, 3))
    for i, m in enumerate(moves):
        k = seg == i
        out[k] = _points(m, path_s[k] - cum[i])
    return out, cum


def _settings(draw_profile, accel, jerk, **kw):
    return InterpolatorSettings(
        profile=draw_profile, path_accel_m_per_s2=accel, path_jerk_m_per_s3=jerk, **kw
    )


limits = st.tuples(
    st.sampled_from(["trapezoid", "scurve"]), st.floats(0.3, 5.0), st.floats(5.0, 300.0)
)


@settings(max_examples=40, deadline=None)
@given(prog=programs(), lim=limits)
def test_samples_lie_on_the_programmed_geometry(prog, lim):
    text, moves = prog
    cmd = interpolate(parse_gcode(text), _settings(*lim))
    p = _xyz(cmd)
    path_s = cmd.meta["path_s_m"]
    expected, cum = _expected(moves, path_s)
    # radius blend of rounded end points is at most ~1.5e-9 m; positions are exact
    assert np.abs(p - expected).max() < 1e-8
    # path length preserved; distance along the path runs from 0 to the end, never back
    assert cmd.meta["path_length_m"] == pytest.approx(cum[-1], rel=1e-12, abs=1e-15)
    assert path_s[0] == 0.0 and path_s[-1] == pytest.approx(cum[-1], rel=1e-12)
    assert np.all(np.diff(path_s) >= 0.0)
    chords = np.linalg.norm(np.diff(p, axis=0), axis=1).sum()
    assert chords <= cum[-1] * (1 + 1e-12)
    # from the start to the end point
    assert np.abs(p[0] - moves[0]["start"]).max() < 1e-15
    assert np.abs(p[-1] - moves[-1]["end"]).max() < 1e-8


@settings(max_examples=40, deadline=None)
@given(prog=programs(), lim=limits)
def test_feed_acceleration_and_jerk_limits_hold(prog, lim):
    text, moves = prog
    profile, accel, jerk = lim
    s = _settings(*lim)
    cmd = interpolate(parse_gcode(text), s)
    dt = s.period_s
    path_s = cmd.meta["path_s_m"]
    cum = np.concatenate([[0.0], np.cumsum([_length(m) for m in moves])])
    speed = np.diff(path_s) / dt
    # per segment: where both samples lie within one move, the speed is at most its F
    seg0 = np.searchsorted(cum, path_s[:-1], side="right") - 1
    seg1 = np.searchsorted(cum, path_s[1:], side="left") - 1
    same = seg0 == seg1
    feeds = np.array([m["feed"] for m in moves])
    assert np.all(speed[same] <= feeds[np.clip(seg0[same], 0, len(moves) - 1)] * (1 + 1e-9))
    assert speed.max() <= feeds.max() * (1 + 1e-9)
    # second/third differences are averages of the path acceleration/jerk
    noise = 16 * np.finfo(float).eps * max(path_s.max(), 1e-3)
    acc = np.diff(path_s, 2) / dt**2
    assert np.abs(acc).max() <= accel * (1 + 1e-9) + noise / dt**2
    if profile == "scurve":
        jrk = np.diff(path_s, 3) / dt**3
        assert np.abs(jrk).max() <= jerk * (1 + 1e-9) + noise / dt**3


@settings(max_examples=30, deadline=None)
@given(
    prog=programs(max_moves=1, lines=False),
    lim=limits,
    axis_acc=st.tuples(st.floats(0.2, 5.0), st.floats(0.2, 5.0), st.floats(0.2, 5.0)),
    axis_vel=st.tuples(st.floats(0.01, 0.2), st.floats(0.01, 0.2), st.floats(0.01, 0.2)),
)
def test_axis_limits_hold_on_arcs_and_helices(prog, lim, axis_acc, axis_vel):
    text, _ = prog
    s = _settings(
        *lim,
        axis_accel_m_per_s2=dict(zip("XYZ", axis_acc, strict=True)),
        axis_velocity_m_per_s=dict(zip("XYZ", axis_vel, strict=True)),
    )
    p = _xyz(interpolate(parse_gcode(text), s))
    dt = s.period_s
    vel = np.abs(np.diff(p, axis=0)) / dt
    acc = np.abs(np.diff(p, 2, axis=0)) / dt**2
    noise = 16 * np.finfo(float).eps * 0.1 / dt**2
    for a in range(3):
        assert vel[:, a].max() <= axis_vel[a] * (1 + 1e-9)
        assert acc[:, a].max() <= axis_acc[a] * (1 + 1e-9) + noise


@settings(max_examples=30, deadline=None)
@given(
    prog=programs(max_moves=6, arcs=False, min_len_mm=5.0),
    axis_acc=st.tuples(st.floats(0.5, 5.0), st.floats(0.5, 5.0), st.floats(0.5, 5.0)),
    jerk=st.floats(5.0, 300.0),
)
def test_corner_velocity_step_is_one_period_of_axis_acceleration(prog, axis_acc, jerk):
    text, moves = prog
    s = InterpolatorSettings(
        profile="scurve",
        path_jerk_m_per_s3=jerk,
        path_accel_m_per_s2=max(axis_acc),
        axis_accel_m_per_s2=dict(zip("XYZ", axis_acc, strict=True)),
    )
    res = interpolate_detailed(parse_gcode(text), s)
    v = res.junction_speed_m_per_s
    dt = s.period_s
    for i in range(1, len(moves)):
        u0 = moves[i - 1]["end"] - moves[i - 1]["start"]
        u1 = moves[i]["end"] - moves[i]["start"]
        step = v[i] * np.abs(u1 / np.linalg.norm(u1) - u0 / np.linalg.norm(u0))
        assert np.all(step <= np.array(axis_acc) * dt * (1 + 1e-9))
    # on the samples: the step plus a tangential acceleration that is zero at the corner
    # and rises by at most the jerk over two periods
    acc = np.abs(np.diff(_xyz(res.command), 2, axis=0)) / dt**2
    noise = 16 * np.finfo(float).eps * 0.1 / dt**2
    assert np.all(acc.max(axis=0) <= np.array(axis_acc) * (1 + 1e-9) + 2 * jerk * dt + noise)


def _two_lines_2nm_apart():
    """Two G1 moves along Z, the first 2 nm off in Y: a turn of 6.4e-8 rad [-]."""
    text = ("G21 G90\nG1 X0.000000 Y0.000002 Z31.250000 F1000.000\n"
            "G1 X0.000000 Y0.000002 Z62.500000 F1000.000\n")
    a, b, c = np.zeros(3), np.array([0.0, 2e-9, 0.03125]), np.array([0.0, 2e-9, 0.0625])
    return text, [{"kind": "line", "start": a, "end": b, "feed": 1.0 / 60.0},
                  {"kind": "line", "start": b, "end": c, "feed": 1.0 / 60.0}]


@settings(max_examples=30, deadline=None)
@given(
    prog=programs(max_moves=6, arcs=False, min_len_mm=5.0),
    axis_acc=st.tuples(st.floats(0.5, 5.0), st.floats(0.5, 5.0), st.floats(0.5, 5.0)),
    share=st.sampled_from([0.0, 0.25, 1.0]),
)
@example(prog=_two_lines_2nm_apart(), axis_acc=(1.0, 1.0, 1.0), share=0.0)
def test_corner_step_share_bounds_the_sampled_acceleration(prog, axis_acc, share):
    """A trapezoid brakes into a sharp corner at the axes' limits; the corner's velocity
    step comes on top, so the samples read at most ``1 + share`` times the limit. A join
    whose unit tangent changes by no more than ``BEND_TOL`` on an axis is a tangent join,
    not a corner (:mod:`tcpmm.path.speedlimits`): its step is at most the speed times that."""
    text, moves = prog
    s = InterpolatorSettings(path_accel_m_per_s2=max(axis_acc), corner_step_share=share,
                             axis_accel_m_per_s2=dict(zip("XYZ", axis_acc, strict=True)))
    res = interpolate_detailed(parse_gcode(text), s)
    v, dt = res.junction_speed_m_per_s, s.period_s
    for i in range(1, len(moves)):
        u0 = moves[i - 1]["end"] - moves[i - 1]["start"]
        u1 = moves[i]["end"] - moves[i]["start"]
        du = np.abs(u1 / np.linalg.norm(u1) - u0 / np.linalg.norm(u0))
        # the test's tangents and the interpolator's are rounded apart: a margin at the
        # boundary, where either may call the join tangent
        corner = du > BEND_TOL * (1 + 1e-6)
        limit = share * np.array(axis_acc) * dt * (1 + 1e-9) + 1e-15
        assert np.all(v[i] * du[corner] <= limit[corner])
        assert np.all(v[i] * du[~corner] <= v[i] * BEND_TOL * (1 + 1e-6) + limit[~corner])
    acc = np.abs(np.diff(_xyz(res.command), 2, axis=0)) / dt**2
    noise = 16 * np.finfo(float).eps * 0.1 / dt**2
    assert np.all(acc.max(axis=0) <= (1 + share) * np.array(axis_acc) * (1 + 1e-9) + noise)


@pytest.mark.parametrize("text", [
    "G1 X10 F3000\nG3 X20 Y10 I0 J10\n",  # a line into a tangent arc
    "G1 X3 Y7 F3000\nG1 X10 Y23.3333333\n",  # collinear to the 7th decimal
])
def test_corner_step_share_zero_keeps_tangent_joins_moving(text):
    """Share 0 stops at sharp corners only: a join whose tangent turns by rounding alone
    keeps the programmed speed."""
    res = interpolate_detailed(parse_gcode(text), InterpolatorSettings(corner_step_share=0.0))
    assert res.junction_speed_m_per_s[1] == pytest.approx(0.05)


def _to_segment(p, a, b):
    """Distance of points p from the segment a-b [m]."""
    ab = b - a
    f = np.clip((p - a) @ ab / (ab @ ab), 0.0, 1.0)
    return np.linalg.norm(p - a - f[:, None] * ab, axis=1)


def _corner(angle_deg, **kw):
    a = math.radians(angle_deg)
    text = f"G1 X50 F6000\nG1 X{50 + 50 * math.cos(a):.6f} Y{50 * math.sin(a):.6f}\n"
    res = interpolate_detailed(parse_gcode(text), InterpolatorSettings(**kw))
    p = np.column_stack([res.command.positions["X"], res.command.positions["Y"]])
    corner = np.array([0.05, 0.0])
    end = corner + 0.05 * np.array([math.cos(a), math.sin(a)])
    dist = np.minimum(_to_segment(p, np.zeros(2), corner), _to_segment(p, corner, end))
    assert p[-1] == pytest.approx(end, abs=1e-9)
    return res, dist


@pytest.mark.parametrize("profile", ["trapezoid", "scurve"])
@pytest.mark.parametrize("kind", ["linear", "bell"])
@pytest.mark.parametrize("angle_deg", [10.0, 30.0, 90.0, 150.0])
def test_filter_cuts_a_corner_by_less_than_the_tolerance(profile, kind, angle_deg):
    tol = 5e-6
    res, dist = _corner(
        angle_deg, filter_kind=kind, filter_time_s=0.01, corner_tolerance_m=tol,
        profile=profile, path_jerk_m_per_s3=20.0, path_accel_m_per_s2=0.5,
        axis_accel_m_per_s2={"X": 5.0, "Y": 5.0},
    )  # fmt: skip
    assert res.junction_speed_m_per_s[1] > 0.0  # the corner is not an exact stop
    assert dist.max() <= tol
    assert dist.max() > 0.1 * tol  # the filter does round the corner; the limit is not lax


def test_corner_the_filter_would_cut_too_much_becomes_an_exact_stop():
    tol = 5e-6
    res, dist = _corner(90.0, filter_kind="linear", filter_time_s=0.03, corner_tolerance_m=tol,
                        path_accel_m_per_s2=2.0)  # fmt: skip
    assert res.junction_speed_m_per_s[1] == 0.0
    assert dist.max() < 1e-9  # the next move waited until the filter settled


@pytest.mark.parametrize("kind", ["linear", "bell"])
def test_filter_radius_loss_on_an_arc_stays_within_tolerance(kind):
    tol = 2e-6
    s = InterpolatorSettings(filter_kind=kind, filter_time_s=0.04, corner_tolerance_m=tol)
    cmd = interpolate(parse_gcode("G1 X20 F10000\nG3 X20 Y0 I-20 J0\n"), s)
    x, y = cmd.positions["X"], cmd.positions["Y"]
    on_circle = cmd.meta["path_s_m"] > 0.02 + 0.005
    r = np.hypot(x, y)[on_circle & (cmd.meta["path_s_m"] < cmd.meta["path_s_m"][-1])]
    assert np.abs(r - 0.02).max() <= tol * 1.05
    # the limit is active: programmed 10 m/min is reduced on the arc
    v = np.hypot(np.diff(x), np.diff(y)) / s.period_s
    assert v.max() < 10.0 / 60.0 * 0.9


def test_rapid_uses_per_axis_speed_and_stops_at_both_ends():
    s = InterpolatorSettings(rapid_m_per_s={"X": 0.5, "Y": 0.25, "Z": 0.1},
                             path_accel_m_per_s2=5.0)  # fmt: skip
    res = interpolate_detailed(parse_gcode("G0 X500 Y500\nG1 X600 F6000\nG0 Z-100\n"), s)
    p = _xyz(res.command)
    vel = np.abs(np.diff(p, axis=0)) / s.period_s
    assert vel[:, 0].max() <= 0.5 * (1 + 1e-9)
    assert vel[:, 1].max() <= 0.25 * (1 + 1e-9)
    assert vel[:, 2].max() <= 0.1 * (1 + 1e-9)
    # the diagonal rapid runs as fast as Y allows
    assert vel[:, 1].max() == pytest.approx(0.25, rel=1e-6)
    assert vel[:, 2].max() == pytest.approx(0.1, rel=1e-6)
    assert np.all(res.junction_speed_m_per_s == 0.0)


def test_dwell_holds_for_whole_periods_and_exact_stop_mode_stops():
    s = InterpolatorSettings()
    res = interpolate_detailed(parse_gcode("G1 X10 F1000\nG4 P0.2505\nG61 G1 X20\nX30\n"), s)
    x = res.command.positions["X"]
    at_ten = np.flatnonzero(np.isclose(x, 0.01, atol=0.0, rtol=0.0))
    assert at_ten.size == 252  # end sample of the move, 251 periods of dwell (rounded up)
    assert res.junction_speed_m_per_s[3] == 0.0  # G61: stop between X20 and X30


def test_moves_start_on_a_sample_so_history_does_not_change_them():
    s = InterpolatorSettings(profile="scurve")
    move = "G1 X10 Y5 F3000\nG1 X20 Y0\n"
    alone = interpolate(parse_gcode(move), s)
    after = interpolate(parse_gcode("G1 X-3.3337 F777\nG1 X0\nG4 P0.0123\n" + move), s)
    n = alone.time_s.size
    for a in "XY":
        np.testing.assert_array_equal(after.positions[a][-n:], alone.positions[a])


def test_settings_are_a_plain_strict_model():
    s = InterpolatorSettings.model_validate(
        {"period_s": 0.0005, "axis_accel_m_per_s2": {"x": 2.0}, "filter_kind": "bell"}
    )
    assert s.axis_accel() == (2.0, 1.0, 1.0)
    assert InterpolatorSettings.model_validate(s.model_dump()) == s
    with pytest.raises(ValueError, match="extra"):
        InterpolatorSettings(period=1e-3)
    with pytest.raises(ValueError, match="unknown axis"):
        InterpolatorSettings(axis_velocity_m_per_s={"Q": 1.0})
    with pytest.raises(ValueError, match="positive"):
        InterpolatorSettings(axis_accel_m_per_s2={"X": 0.0})


def test_bad_segment_lists_raise_input_error():
    with pytest.raises(InputError, match="continuous"):
        interpolate([Line((0, 0, 0), (1, 0, 0), 0.1), Line((2, 0, 0), (3, 0, 0), 0.1)])
    with pytest.raises(InputError, match="feed"):
        interpolate([Line((0, 0, 0), (1, 0, 0), 0.0)])
    with pytest.raises(InputError, match="empty"):
        interpolate([])
    with pytest.raises(InputError, match="samples"):
        interpolate([Line((0, 0, 0), (1, 0, 0), 1e-6)])
    with pytest.raises(InputError, match="axes stand"):
        interpolate([Line((0, 0, 0), (1, 0, 0), 0.1)], start_position_m=(1, 0, 0))


def test_100k_short_blocks_interpolate_quickly():
    n = 100_000
    phi = np.linspace(0.0, 200 * math.pi, n + 1)
    r = 0.005 + 0.045 * phi / phi[-1]
    pts = np.column_stack([r * np.cos(phi), r * np.sin(phi), np.zeros_like(phi)])
    pts = [tuple(p) for p in pts.tolist()]
    segs = [Line(pts[k], pts[k + 1], 0.05) for k in range(n)]
    interpolate(segs[:3])  # compiled code is cached; keep any compile out of the timing
    t0 = time.perf_counter()
    cmd = interpolate(segs, InterpolatorSettings(filter_kind="linear", filter_time_s=0.02))
    elapsed = time.perf_counter() - t0
    assert elapsed < 10.0
    assert cmd.meta["path_length_m"] == pytest.approx(
        np.linalg.norm(np.diff(np.array(pts), axis=0), axis=1).sum(), rel=1e-12
    )


def test_a_segment_the_doubles_cannot_resolve_is_named():
    """An arc's centre of infinity (a radius of 1e200 mm squared) gave a speed limit of
    NaN and an AssertionError traceback; it is an input error naming the line."""
    from dataclasses import replace

    from tcpmm.path import Arc
    from tcpmm.path.filters import filter_shape
    from tcpmm.path.geometry import to_arrays
    from tcpmm.path.speedlimits import segment_limits

    arc = Arc((0.0, 0.0, 0.0), (0.01, 0.0, 0.0), (0.005, math.inf, 0.0), ("X", "Y"), "cw",
              0.01, line=2)
    with pytest.raises(InputError, match="arc centres must be finite") as e:
        interpolate([arc])
    assert e.value.line == 2
    p = to_arrays([replace(arc, centre_m=(0.005, 1.0, 0.0))], (0.5, 0.5, 0.5))
    p = replace(p, length=np.array([math.nan]))
    with pytest.raises(InputError, match="no speed limit can be computed") as e:
        segment_limits(p, (1.0, 1.0, 1.0), (1.0, 1.0, 1.0), 1.0,
                       filter_shape("none", 0.0, 1e-3, 1e-5))
    assert e.value.line == 2
    # the interpolator's own count of segments (blends, runs, a chunk's) is no place in
    # the program: the line alone names it, the same whole and streamed
    assert "segment" not in e.value.message


def test_a_feed_above_the_rapid_traverse_is_held_to_it():
    """A control feeds no axis faster than it traverses: G1 X500 F100000 ran at 42.4 m/min
    on axes of 30 m/min rapid (1.415 s instead of 1.0 + 0.5 s of acceleration)."""
    from tcpmm.path import program_to_command

    cmd = program_to_command("G21 G90\nG1 X500 F100000\nM30\n")
    v = np.abs(np.diff(cmd.positions["X"])) / np.diff(cmd.time_s)
    assert v.max() <= 0.5 * (1 + 1e-9)
    assert cmd.time_s[-1] - cmd.time_s[0] == pytest.approx(1.5, abs=2e-3)


def test_the_built_in_machine_names_a_command_faster_than_its_rapid_as_its_file_does(tmp_path):
    """builtin:vmc had no interpolation settings, so a command at 42 m/min passed without a
    word while the same machine exported to a file was warned about."""
    import warnings

    from tcpmm import builtin_machine, simulate
    from tcpmm.errors import InputWarning
    from tcpmm.path.command import Command

    t = np.arange(0, 0.2, 1e-3)
    cmd = Command(t, {"X": 0.7 * t, "Y": 0.0 * t, "Z": 0.0 * t})
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        simulate(builtin_machine(), cmd)
    assert any("faster than the rapid traverse" in str(w.message) for w in got
               if issubclass(w.category, InputWarning))
