"""A curve posted as short G1 blocks under G64 without P (no blends) is held by its
curvature as its arc is (``shortblocks.chain_limits``): a circle of 0.02 mm chords at F20000 ran
at 5.6 times the axes' acceleration for 474 periods, each corner's velocity step within
the limit alone and several of them in one period. Its lines share the acceleration with
that centripetal acceleration as an arc does (``shortblocks.chain_tangential``): an ellipse of
0.05 mm chords, speeding up and slowing down along it, read 1.14 times X's limit for 884
periods."""

import math
import warnings

import numpy as np
import pytest

from tcpmm.cli import main
from tcpmm.compensate.headroom import planned_settings
from tcpmm.path import InterpolatorSettings, Line
from tcpmm.path.geometry import tangents, to_arrays
from tcpmm.path.interpolate import interpolate, interpolate_detailed
from tcpmm.path.program import program_to_command
from tcpmm.path.stream import stream_program

R_M, FEED = 0.02, 20000.0 / 6e4  # the circle of fast_short.nc: 20 mm at F20000
#: what an axis of a chain may read over its limit: the rounding of the sum of the
#: tangential and centripetal shares, and the curvature's change from block to block [-]
OVER = 1e-3


def chords(step_m: float, r: float = R_M, feed: float = FEED) -> list:
    """A full circle of radius ``r`` as G1 chords of about ``step_m`` [m]."""
    n = round(2.0 * math.pi * r / step_m)
    th = np.linspace(0.0, 2.0 * math.pi, n + 1)
    pts = np.column_stack([r * np.cos(th), r * np.sin(th), np.zeros(n + 1)])
    return [Line(tuple(pts[i]), tuple(pts[i + 1]), feed) for i in range(n)]


def gcode(step_mm: float, r_mm: float, feed: float, head: str = "G21 G90 G17 G64",
          r2_mm: float | None = None) -> str:
    """The circle (an ellipse of semi-axis ``r2_mm`` along Y) as a CAM writes it: G1
    chords, five decimals."""
    n = round(2.0 * math.pi * r_mm / step_mm)
    r2 = r_mm if r2_mm is None else r2_mm
    lines = [head, f"G0 X{r_mm:g} Y0"]
    lines += [f"G1 X{r_mm * math.cos(a):.5f} Y{r2 * math.sin(a):.5f} F{feed:g}"
              for a in 2.0 * math.pi * np.arange(1, n + 1) / n]
    return "\n".join([*lines, "M30"]) + "\n"


def steady(cmd):
    """Path speed [m/s] and the largest second difference per axis [m/s^2] of the middle
    half of the command (the start and stop ramps left out), and that of all of it."""
    x = np.column_stack(list(cmd.positions.values()))
    dt = cmd.period_s
    v = np.linalg.norm(np.diff(x, axis=0), axis=1) / dt
    acc = np.abs(np.diff(x, 2, axis=0)) / dt**2
    mid = slice(v.size // 4, 3 * v.size // 4)
    return v[mid], acc[mid].max(axis=0), acc.max(axis=0)


def arc_speed(settings=None) -> float:
    """Steady speed of the same circle as one G3 arc [m/s]."""
    cmd = program_to_command(f"G21 G90 G17\nG0 X20 Y0\nG3 X20 Y0 I-20 J0 F{FEED * 6e4:g}\n",
                             settings)
    return float(np.median(steady(cmd)[0]))


def test_a_circle_of_fine_chords_keeps_its_axes_within_their_acceleration():
    """0.02 mm chords at F20000: the command's second difference is the centripetal share
    (a/sqrt(2)) where the speed is steady, within the limit anywhere, and the circle runs
    at the G3 arc's 7135 mm/min (it ran at up to 20000 mm/min, 5.6 m/s2)."""
    v, acc_mid, acc_all = steady(interpolate(chords(2e-5)))
    a = InterpolatorSettings().axis_accel()[0]
    assert np.all(acc_mid <= a / math.sqrt(2.0) * 1.02), acc_mid
    assert np.all(acc_all <= a * (1 + OVER)), acc_all
    arc = arc_speed()
    assert arc * 6e4 == pytest.approx(7135, abs=1)
    assert v.min() >= 0.99 * arc and v.max() <= 1.01 * arc, (v.min() * 6e4, v.max() * 6e4)


def test_finer_chords_are_run_no_faster_than_the_arc():
    """The chain's limit does not depend on the chords' length: finer chords run as the
    arc, coarser ones no faster (0.2 and 0.5 mm: the corners' step rule, one corner or
    fewer per period, holds them lower; 0.01 mm ran at the feed before)."""
    arc = arc_speed()
    mean = {s: float(np.mean(steady(interpolate(chords(s)))[0]))
            for s in (1e-5, 2e-5, 1e-4, 2e-4, 5e-4)}
    assert all(m <= 1.01 * arc for m in mean.values()), mean
    assert mean[1e-5] == pytest.approx(mean[2e-5], rel=5e-3)
    assert mean[5e-4] <= mean[2e-4] <= mean[1e-4] <= mean[2e-5] * 1.005, mean


def test_behind_a_filter_coarser_chords_are_a_chain_too():
    """A bell filter of 16 ms spreads a corner's step over 8 ms: 0.5 mm chords at F20000
    fall several within it, and their steps added up to 4.6 m/s2 (in 1.029 s)."""
    st = InterpolatorSettings(filter_kind="bell", filter_time_s=0.016)
    cmd = program_to_command(gcode(0.5, 20.0, 20000.0), st)
    x = np.column_stack(list(cmd.positions.values()))
    assert np.abs(np.diff(x, 2, axis=0)).max() / cmd.period_s**2 <= 1.0 + OVER
    assert cmd.time_s[-1] > 1.4


def even_chords(step_mm: float, a_mm: float, b_mm: float, feed: float) -> str:
    """An ellipse as G1 chords of ``step_mm`` along it (not along its angle), six
    decimals."""
    t = np.linspace(0.0, 2.0 * math.pi, 200_001)
    pts = np.column_stack([a_mm * np.cos(t), b_mm * np.sin(t)])
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(pts, axis=0), axis=1))])
    at = np.append(np.arange(0.0, s[-1], step_mm), s[-1])
    x, y = np.interp(at, s, pts[:, 0]), np.interp(at, s, pts[:, 1])
    lines = ["G21 G90 G17", f"G0 X{x[0]:.6f} Y{y[0]:.6f}", "G64"]
    lines += [f"G1 X{xi:.6f} Y{yi:.6f} F{feed:g}" for xi, yi in zip(x[1:], y[1:], strict=True)]
    return "\n".join([*lines, "M30"]) + "\n"


def test_blocks_of_a_few_periods_keep_their_axes_within_the_limit_on_average():
    """An ellipse of 20 x 2.5 mm in 0.1 mm chords at F15000: near its ends a corner falls
    every two or three periods, each step held by the step rule alone, and the lines
    kept their whole acceleration: X read over its limit on average over 10 periods
    (1.068 times it; 61 periods over). A single corner's step may still read up to
    ``1 + corner_step_share`` for its period, as at any corner."""
    st = InterpolatorSettings()
    cmd = program_to_command(even_chords(0.1, 20.0, 2.5, 15000.0), st)
    x = np.column_stack(list(cmd.positions.values()))[:, :2]
    acc = np.diff(x, 2, axis=0) / cmd.period_s**2
    mean10 = np.array([np.convolve(acc[:, k], np.ones(10) / 10, "valid") for k in (0, 1)])
    assert np.abs(mean10).max() <= 1.0 + OVER, np.abs(mean10).max(axis=1)
    assert np.abs(acc).max() <= 1.0 + st.corner_step_share + OVER


@pytest.mark.parametrize("kind", ["none", "bell"])
def test_a_chain_speeding_up_and_slowing_down_keeps_its_axes_within_their_limit(kind):
    """An ellipse of 40 x 5 mm in 0.05 mm chords at F15000: its curvature changes along it,
    and so does the speed the chain allows. Where it sped up or slowed down, the lines'
    tangential acceleration (X's whole limit) came on top of the centripetal share: X read
    1.14 times its limit for 884 periods (1.12 behind the filter)."""
    st = InterpolatorSettings(filter_kind=kind, filter_time_s=0.016 * (kind != "none"))
    cmd = program_to_command(gcode(0.05, 40.0, 15000.0, r2_mm=5.0), st)
    x = np.column_stack(list(cmd.positions.values()))
    acc = np.abs(np.diff(x, 2, axis=0)).max(axis=0) / cmd.period_s**2
    a = np.asarray(st.axis_accel()[:2])
    assert np.all(acc <= a * (1 + OVER)), acc
    # the speed the chain keeps near the ends of the ellipse is still reached
    v = np.linalg.norm(np.diff(x, axis=0), axis=1) / cmd.period_s
    assert v.max() * 6e4 == pytest.approx(15000.0, rel=1e-3)


def test_the_chain_limit_is_the_arcs_for_any_chord_length():
    """``sqrt(a_n * r)`` at every junction of the chords of a circle, ``a_n = a/sqrt(2)``."""
    from tcpmm.path.speedlimits import chain_limits, normal_accel

    a_n = normal_accel((1.0, 1.0, 1.0), 1.0)
    assert a_n == pytest.approx([1 / math.sqrt(2.0)] * 3)
    for step in (2e-5, 5e-4, 2e-3):
        p = to_arrays(chords(step), (0.5, 0.5, 0.5))
        lim = chain_limits(p, tangents(p, True)[:-1], tangents(p, False)[1:], a_n)
        assert lim == pytest.approx(math.sqrt(R_M / math.sqrt(2.0)), rel=1e-3)


@pytest.mark.parametrize(("name", "text", "numbers"), [
    ("zigzag", "G90 G17 G64 F5000\nG1 X20 Y0\nG1 X20 Y1\nG1 X0 Y1\nG1 X0 Y2\nG1 X20 Y2\n",
     {"none": (1.089, 1.4992717066511767), "bell": (1.085, 1.0896475161731425)}),
    ("square", "G21 G90 G17 G64\nG1 X0 Y0 F3000\nG1 X10\nG1 Y10\nG1 X0\nG1 Y0\n",
     {"none": (0.995, 1.4999500000008326), "bell": (0.995, 1.0896441756509885)}),
    ("0.5 mm chords", gcode(0.5, 20.0, 20000.0), {"none": (2.995, 1.058916470631985)}),
])
def test_sharp_corners_between_long_blocks_keep_the_step_rule(name, text, numbers):
    """Duration and peak second difference as before the chain limit, within 1 %: a
    corner of long blocks (and the 0.5 mm chords without a filter) is still held by its
    velocity step; its lines give up only the mean centripetal acceleration of the steps
    (chain_tangential), 0.014 % of the acceleration on the square's 10 mm sides."""
    for kind, (duration, peak) in numbers.items():
        st = InterpolatorSettings(filter_kind=kind, filter_time_s=0.016 * (kind != "none"))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            cmd = program_to_command(text, st)
        x = np.column_stack(list(cmd.positions.values()))
        assert cmd.time_s[-1] == pytest.approx(duration, rel=1e-2), (name, kind)
        assert np.abs(np.diff(x, 2, axis=0)).max() / 1e-6 == pytest.approx(peak, rel=1e-2)


def test_the_headroom_holds_a_chain_as_it_holds_the_arc():
    """Planned with headroom 0.25 the chain's speed is the arc's planned with it:
    sqrt(0.75) of the full limits' (the step rule's smaller share alone let it run at
    15000 mm/min)."""
    st = planned_settings(InterpolatorSettings(), 0.25)
    v = steady(interpolate(chords(2e-5), st))[0]
    arc = arc_speed(st)
    assert arc == pytest.approx(math.sqrt(0.75) * arc_speed(), rel=1e-3)
    assert v.min() >= 0.99 * arc and v.max() <= 1.01 * arc


@pytest.mark.parametrize("settings", [
    InterpolatorSettings(), InterpolatorSettings(filter_kind="bell", filter_time_s=0.016)])
@pytest.mark.parametrize("chunk", [1, 7, 200])
@pytest.mark.parametrize("r2_mm", [None, 0.5])
def test_chunks_of_a_chain_plan_as_the_whole(settings, chunk, r2_mm):
    """The chain limit uses the two blocks at a junction only, and a line's share of the
    acceleration the corners at its two ends: streamed in chunks, a circle of 0.02 mm
    chords held by it (and an ellipse, whose speed changes along it) gives the whole
    program's command to the bit."""
    text = gcode(0.02, 2.0, 20000.0, r2_mm=r2_mm)
    ref = interpolate_detailed(chords(2e-5, 2e-3))
    assert np.any(ref.junction_cause == 4)  # JUNCTION_CAUSES: the curvature of short blocks
    whole = program_to_command(text, settings)
    got = list(stream_program(text, settings, chunk_blocks=chunk))
    for axis, x in whole.positions.items():
        assert np.array_equal(np.concatenate([p.positions[axis] for p in got]), x), axis


def test_path_says_the_curvature_of_short_blocks_holds_the_feed(tmp_path, capsys):
    """``tcpmm path`` names the curvature of short blocks as what holds most of the circle
    back (it said path acceleration: blocks too short to reach the feed)."""
    prog = tmp_path / "circle.nc"
    prog.write_text(gcode(0.02, 5.0, 20000.0))
    assert main(["path", str(prog), "-o", str(tmp_path / "c.csv")]) == 0
    said = capsys.readouterr().out
    held = [ln for ln in said.splitlines() if "held back by" in ln]
    assert "held back by curvature of short blocks" in held[0], said
    assert "runs as its arc would" in held[0]
