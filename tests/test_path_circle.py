"""Circular test command: geometry, feed, limits, filter, and the G-code example."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from tcpmm.errors import InputError
from tcpmm.path import circle_command, circle_settings, program_to_command

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "circle_r35_f5000.nc"
R = 0.035  # [m]
F = 5000e-3 / 60  # [m/s]


def _plane(cmd):
    a, b = cmd.meta["plane_axes"]
    return cmd.positions[a], cmd.positions[b]


def test_example_equals_circle_command_ccw_then_cw():
    g = program_to_command(EXAMPLE, circle_settings())
    ccw = circle_command(R, F, direction="ccw")
    cw = circle_command(R, F, direction="cw")
    for ax in "XY":
        # the reversal at the centre is a stop: CW starts on the sample where CCW rests
        expected = np.concatenate([ccw.positions[ax], cw.positions[ax][1:]])
        assert g.positions[ax].shape == expected.shape
        assert np.abs(g.positions[ax] - expected).max() < 1e-9


@pytest.mark.parametrize("smoothing", ["linear", "bell"])
def test_example_equals_circle_command_with_a_filter(smoothing):
    st = circle_settings(smoothing_time_s=0.024, smoothing=smoothing)
    g = program_to_command(EXAMPLE, st)
    ccw = circle_command(R, F, direction="ccw", smoothing_time_s=0.024, smoothing=smoothing)
    cw = circle_command(R, F, direction="cw", smoothing_time_s=0.024, smoothing=smoothing)
    for ax in "XY":
        expected = np.concatenate([ccw.positions[ax], cw.positions[ax][1:]])
        assert np.abs(g.positions[ax] - expected).max() < 1e-9


def test_example_reaches_the_feed_and_keeps_the_radius():
    g = program_to_command(EXAMPLE, circle_settings())
    ccw = circle_command(R, F, direction="ccw")
    first, stop = ccw.meta["circle_index_range"]
    n = ccw.time_s.size
    for lo, hi in [(first, stop), (n - 1 + first, n - 1 + stop)]:  # CCW, then CW
        x, y = g.positions["X"][lo:hi], g.positions["Y"][lo:hi]
        radial = np.hypot(x, y) - R
        assert np.abs(radial).max() < 1e-7  # below 0.1 um (it is at rounding level)
        speed = np.hypot(np.diff(x), np.diff(y)) / g.period_s
        # chords of an arc at constant feed: F * sinc(omega*dt/2), 2.4e-7 below F
        chord = F * math.sin(F / R * g.period_s / 2) / (F / R * g.period_s / 2)
        assert speed == pytest.approx(np.full(speed.size, chord), rel=1e-9)
        turn = np.unwrap(np.arctan2(y, x))
        assert abs(turn[-1] - turn[0]) > 2 * math.pi - 2 * F / R * g.period_s


@pytest.mark.parametrize("direction", ["ccw", "cw"])
@pytest.mark.parametrize("plane_axes", [("X", "Y"), ("Z", "X"), ("Y", "Z"), ("X", "Z")])
@pytest.mark.parametrize("start_angle_deg", [0.0, 90.0, 217.0])
def test_geometry_in_every_plane_and_direction(direction, plane_axes, start_angle_deg):
    phi = math.radians(start_angle_deg)
    centre = (0.01, -0.02)
    cmd = circle_command(0.02, 0.05, centre_m=centre, direction=direction,
                         start_angle_rad=phi, plane_axes=plane_axes)  # fmt: skip
    a, b = _plane(cmd)
    a0, b0 = a - centre[0], b - centre[1]
    # at rest at the centre at both ends
    assert (a0[0], b0[0], a0[-1], b0[-1]) == pytest.approx((0, 0, 0, 0), abs=1e-15)
    for other in set(cmd.positions) - set(plane_axes):
        assert np.all(cmd.positions[other] == 0.0)
    first, stop = cmd.meta["circle_index_range"]
    r = np.hypot(a0, b0)
    assert np.abs(r[first:stop] - 0.02).max() < 1e-15
    turn = np.unwrap(np.arctan2(b0[first:stop], a0[first:stop]))
    sense = 1.0 if direction == "ccw" else -1.0
    assert np.all(np.diff(turn) * sense > 0)
    step = 0.05 / 0.02 * cmd.period_s  # angle per sample [rad]
    start = phi + 2 * math.pi * round((turn[0] - phi) / 2 / math.pi)
    assert 0 <= (turn[0] - start) * sense <= step
    # feed-in: semicircle of radius R/2 about the midpoint of centre and start point
    cin = 0.01 * np.array([math.cos(phi), math.sin(phi)])
    rin = np.hypot(a0[:first] - cin[0], b0[:first] - cin[1])
    assert np.abs(rin - 0.01).max() < 1e-15
    # the feed-in turns the same way as the circle
    tin = np.unwrap(np.arctan2(b0[1:first] - cin[1], a0[1:first] - cin[0]))
    assert (tin[-1] - tin[0]) * sense > 0.9 * math.pi
    # feed-out: semicircle back to the centre
    rout = np.hypot(a0[stop:] - cin[0], b0[stop:] - cin[1])
    assert np.abs(rout - 0.01).max() < 1e-15
    meta = cmd.meta
    assert meta["radius_m"] == 0.02 and meta["centre_m"] == centre
    assert meta["direction"] == direction and meta["plane_axes"] == plane_axes
    assert meta["start_angle_rad"] == phi


@pytest.mark.parametrize("turns", [0.5, 1.0, 1.5, 2.0, 3.25])
def test_turns_are_swept(turns):
    cmd = circle_command(R, F, turns=turns, start_angle_rad=0.3)
    x, y = _plane(cmd)
    first, stop = cmd.meta["circle_index_range"]
    turn = np.unwrap(np.arctan2(y[first:stop], x[first:stop]))
    step = F / R * cmd.period_s
    # the samples on the circle miss less than one step at either end
    assert 2 * math.pi * turns - 2 * step < turn[-1] - turn[0] <= 2 * math.pi * turns
    assert x[-1] == pytest.approx(0.0, abs=1e-15) and y[-1] == pytest.approx(0.0, abs=1e-15)


def test_no_feed_in_and_dwell():
    cmd = circle_command(R, F, feed_in=False, dwell_s=0.1)
    x, y = _plane(cmd)
    assert np.all(x[:101] == R) and np.all(y[:101] == 0.0)  # 100 periods at rest
    assert y[101] > 0.0
    assert x[-1] == pytest.approx(R) and np.all(x[-101:] == x[-1])
    assert np.abs(np.hypot(x, y) - R).max() < 1e-15


@pytest.mark.parametrize("accel", [0.2, 1.0, 3.0])
def test_tangential_and_axis_acceleration_limits(accel):
    cmd = circle_command(R, F, accel_limit_m_per_s2=accel)
    s = cmd.meta["path_s_m"]
    dt = cmd.period_s
    acc = np.diff(s, 2) / dt**2
    noise = 64 * np.finfo(float).eps * s.max() / dt**2
    assert np.abs(acc).max() <= accel * (1 + 1e-9) + noise
    assert np.abs(acc).max() == pytest.approx(accel, rel=1e-6)  # the limit is used
    x, y = _plane(cmd)
    a_xy = np.hypot(np.diff(x, 2), np.diff(y, 2)) / dt**2
    # tangential and centripetal acceleration each at most the limit
    assert a_xy.max() <= math.sqrt(2) * accel * (1 + 1e-9) + noise
    assert np.diff(s).max() / dt <= F * (1 + 1e-12)


def test_jerk_limit_gives_an_s_curve():
    jerk = 20.0
    cmd = circle_command(R, F, jerk_limit_m_per_s3=jerk)
    s = cmd.meta["path_s_m"]
    dt = cmd.period_s
    j = np.diff(s, 3) / dt**3
    noise = 64 * np.finfo(float).eps * s.max() / dt**3
    assert np.abs(j).max() <= jerk * (1 + 1e-9) + noise
    assert np.abs(j).max() > 0.9 * jerk
    trap = circle_command(R, F)
    assert np.abs(np.diff(trap.meta["path_s_m"], 3)).max() / dt**3 > 10 * jerk


@pytest.mark.parametrize(("smoothing", "taps"), [("linear", [20]), ("bell", [10, 10])])
def test_smoothing_shrinks_the_radius_as_a_moving_average_does(smoothing, taps):
    cmd = circle_command(R, F, smoothing_time_s=0.02, smoothing=smoothing)
    x, y = _plane(cmd)
    first, stop = cmd.meta["circle_index_range"]
    m = sum(taps) - len(taps)  # samples the filter needs to forget the feed-in
    r = np.hypot(x[first + m : stop - m], y[first + m : stop - m])
    # amplitude of a rotating vector through moving averages of n taps: sin(n w/2)/(n sin(w/2))
    w = F / R * cmd.period_s
    gain = np.prod([math.sin(n * w / 2) / (n * math.sin(w / 2)) for n in taps])
    assert r == pytest.approx(np.full(r.size, R * gain), abs=1e-12)
    assert R * (1 - gain) > 1e-6  # micrometres: the effect is real
    assert cmd.meta["filter_delay_s"] == pytest.approx(sum(n - 1 for n in taps) / 2 * 1e-3)
    # the command still starts and ends at rest at the centre
    assert x[0] == 0.0 and abs(x[-1]) < 1e-15 and abs(y[-1]) < 1e-15


@pytest.mark.parametrize(
    ("kw", "msg"),
    [
        (dict(radius_m=0.0), "radius_m"),
        (dict(feed_m_per_s=-1.0), "feed_m_per_s"),
        (dict(direction="up"), "direction"),
        (dict(plane_axes=("X", "X")), "plane_axes"),
        (dict(plane_axes=("X", "Q")), "plane_axes"),
        (dict(turns=0.0), "turns"),
        (dict(smoothing="cubic"), "smoothing"),
        (dict(smoothing_time_s=-0.1), "smoothing_time_s"),
        (dict(accel_limit_m_per_s2=0.0), "accel_limit"),
        (dict(jerk_limit_m_per_s3=0.0), "jerk_limit"),
        (dict(period_s=0.0), "period_s"),
        (dict(dwell_s=-1.0), "dwell_s"),
        (dict(centre_m=(0.0,)), "centre_m"),
    ],
)
def test_bad_arguments_raise_input_error(kw, msg):
    args = dict(radius_m=R, feed_m_per_s=F) | kw
    with pytest.raises(InputError, match=msg):
        circle_command(**args)
