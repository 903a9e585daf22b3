"""A path that comes back where it was within the search window: a closed contour's end
meets its start, a pass back along the way it came ties with the way out. Each sample is
measured against the pass being run, and the end of a closed contour has its overshoot."""

import numpy as np
import pytest

from tcpmm.analysis.contour import contour_error, distance_to_polyline
from tcpmm.result import AxisRun, Run
from test_contour import DT, square


@pytest.mark.parametrize("aside_m", [0.5e-6, -0.5e-6, 0.0])
def test_the_end_of_a_closed_square_overshoots_past_its_start(aside_m):
    """Once the command is back at (0, 0), the tool runs on along -Y by delta and comes
    back, ``aside_m`` off along X: where that is +X, the square's first leg lies closer to
    it than its last does, and the end read an overshoot of 0."""
    p = square(side=2e-3)  # from (0, 0) back to it, its motion (160 ms) within the window
    arrive = p.shape[0] - 101  # the command's first sample at the end point
    delta, tau = 5e-6, 0.005  # below 1e-10 m over the rest's last quarter
    u = np.clip((np.arange(p.shape[0]) - arrive) * DT, 0, None) / tau
    act = p.copy()
    act[:, 1] -= delta * u * np.exp(1 - u)
    act[arrive:, 0] += aside_m
    run = Run(np.arange(p.shape[0]) * DT,
              {a: AxisRun(cmd=p[:, i], tcp=act[:, i]) for i, a in enumerate("XY")})
    end = contour_error(run).corners[-1]
    assert np.isnan(end["turn_rad"])
    # less the level the tool comes to rest at (the bump's tail, below 1e-10 m)
    assert end["tcp"]["overshoot_m"] == pytest.approx(delta, abs=1e-10)
    assert end["tcp"]["rounding_m"] == pytest.approx(abs(aside_m), abs=1e-12)


@pytest.mark.parametrize("heading", [(1.0, 0.0), (1.0, 2.0)])
@pytest.mark.parametrize("offset_m", [1e-6, -1e-6])
def test_a_tool_on_its_way_back_is_measured_against_the_way_back(offset_m, heading):
    """Out along a line and back on the same samples within the window: the way out and
    the way back lie equally close to a tool beside them. On the way back the error takes
    the way back's sign (+: left of the travel) and its segment, not the way out's. Off
    the axes, the samples as a run file keeps them (ten significant digits of a mm) lie
    up to some 1e-13 m off the line, so that one pass lay nearer by rounding alone, and a
    tool on the way out was measured against the way back (its sign wrong on 52 of 113
    samples of a G1 X1 Y2, G1 X0 Y0 on the built-in machine)."""
    u = np.array(heading) / np.hypot(*heading)
    # back on samples of its own, between the way out's
    s = np.r_[np.linspace(0, 0.01, 101), np.linspace(0.01, 0, 101)[1:] + 3.7e-5]
    p = np.array([[float(f"{v:.10g}") * 1e-3 for v in row] for row in s[:, None] * u * 1e3])
    t = np.arange(s.size) * DT
    q = s[:, None] * u + offset_m * np.array([-u[1], u[0]])  # left of the way out
    d, foot = distance_to_polyline(q, p, t, t, 0.2, True)
    out, back = slice(10, 90), slice(110, 190)
    assert d[out] == pytest.approx(np.full(80, offset_m), abs=1e-12)
    assert d[back] == pytest.approx(np.full(80, -offset_m), abs=1e-12)
    assert (foot[out] < 100).all() and (foot[back] >= 100).all()


@pytest.mark.parametrize("offset_m", [2e-6, -2e-6])
@pytest.mark.parametrize("radius_m", [1e-3, 3e-3])
def test_a_tool_on_its_way_back_along_an_arc_is_measured_against_the_way_back(offset_m,
                                                                              radius_m):
    """Out along an arc and back along it at 1 ms samples that fall elsewhere on the arc:
    the two passes' chords lie apart by up to their sag (0.56 um at R 1 mm, 67 um a
    sample), and half the samples lay nearer the other pass's chord. A tool on the arc's
    circle ``offset_m`` outside reads, pass by pass, the error of the pass it is on: right
    of the travel (-) out, counterclockwise, and left (+) on the way back, within the
    chord's sag."""
    v, T = 4000 / 60e3, 1e-3
    t = np.arange(int(np.pi * radius_m / v / T) * 2 + 2) * T
    t_rev = (int(np.pi * radius_m / v / T) + 0.37) * T  # the reversal falls between samples
    theta = v / radius_m * np.where(t <= t_rev, t, 2 * t_rev - t)
    p = radius_m * np.c_[np.cos(theta), np.sin(theta)]
    q = (radius_m + offset_m) * np.c_[np.cos(theta), np.sin(theta)]
    d, _ = distance_to_polyline(q, p, t, t, 0.2, True)
    sag = (v * T) ** 2 / (8 * radius_m)
    away = np.abs(t - t_rev) > 5 * T  # the reversal itself has no side
    expected = np.where(t <= t_rev, -offset_m, offset_m)
    np.testing.assert_allclose(d[away], expected[away], rtol=0, atol=sag * 1.01)


def test_a_tool_beside_a_line_before_a_corner_is_measured_to_the_line():
    """A corner's last segment before it turns, of some sag, may lie within its sag of
    the closest distance while a straight segment between does not: it is the same pass,
    and the tool beside the line reads its distance to the line, not the corner's."""
    um = 1e-6
    p = np.array([(-10, 0), (-5, 0), (0, 0), (3.567, 0), (6.13, 0), (7.70, 0), (7.70, 3),
                  (7.70, 6), (7.70, 9)]) * um
    t = np.arange(p.shape[0]) * 1e-3
    q = np.array([[3.37, -15.55]]) * um
    d, foot = distance_to_polyline(q, p, np.array([4.5e-3]), t, 0.2, True)
    assert d[0] == pytest.approx(-15.55 * um, rel=1e-12) and foot[0] == 2


def test_the_end_of_a_slot_overshoots_along_the_direction_it_ends_in():
    """A path that ends on a small arc, a slot's end of R 0.1 mm turning back from +X to
    -X: the tool runs on past the end point along -X, the direction of travel there. The
    chord over the corner span (0.5 mm back, on the way in) points elsewhere, and the way
    in, along +X below the end point, lies beyond it in -X before the command is there."""
    line = np.c_[np.linspace(9e-3, 10e-3, 21)[:-1], np.zeros(20)]
    a = np.linspace(-np.pi / 2, np.pi / 2, 201)
    arc = np.c_[10e-3 + 0.1e-3 * np.cos(a), 0.1e-3 + 0.1e-3 * np.sin(a)]
    p = np.vstack([line, arc, np.repeat(arc[-1:], 400, axis=0)])
    arrive = line.shape[0] + arc.shape[0] - 1
    delta, tau = 5e-6, 0.01
    u = np.clip((np.arange(p.shape[0]) - arrive) * DT, 0, None) / tau
    act = p.copy()
    act[:, 0] -= delta * u * np.exp(1 - u)
    run = Run(np.arange(p.shape[0]) * DT,
              {ax: AxisRun(cmd=p[:, i], tcp=act[:, i]) for i, ax in enumerate("XY")})
    end = contour_error(run).corners[-1]
    assert np.isnan(end["turn_rad"])
    assert end["tcp"]["overshoot_m"] == pytest.approx(delta, rel=1e-3)


def test_an_arc_that_turns_back_onto_a_line_has_its_corner_at_the_cusp():
    """An arc of R 1 mm whose end turns back (166 deg) onto a line: the corner is the
    cusp, where the command turns, not the sharpest turn over the span, which lies on the
    line past it where the other side curves (8 to 32 um past it on such paths)."""
    u = np.linspace(0.0, 1.0, 200)
    th = np.pi + np.pi * (1 - (1 - u) ** 2)  # slowing down into the cusp
    arc = 1e-3 * np.c_[np.cos(th), np.sin(th)]
    v = np.linspace(0.0, 1.0, 300)[1:]
    line = np.c_[np.full(v.size, 1e-3), -3e-3 * v**2]
    p = np.vstack([arc, line, np.repeat(line[-1:], 300, axis=0)])
    run = Run(np.arange(p.shape[0]) * DT,
              {ax: AxisRun(cmd=p[:, i], tcp=p[:, i] + 2e-6) for i, ax in enumerate("XY")})
    corners = [c for c in contour_error(run).corners if c["turn_rad"] == c["turn_rad"]]
    assert len(corners) == 1 and np.degrees(corners[0]["turn_rad"]) > 150
    np.testing.assert_allclose(corners[0]["point_m"], [1e-3, 0.0], rtol=0, atol=1e-12)
