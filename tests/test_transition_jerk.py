"""Jerk at block transitions where the curvature steps (``transition_jerk_m_per_s3``,
:mod:`tcpmm.path.transitions`): at a tangent join of a line into an arc each axis's
acceleration steps by ``v^2 |delta kappa_axis|`` within one period, a jerk the path's
profile does not see (a line into a circle of R 35 mm at F5000: 147 m/s^3 for a sample
on X against an S-curve of 50)."""

import math

import numpy as np
import pytest
from pydantic import ValidationError

from tcpmm.cli import main
from tcpmm.path import InterpolatorSettings
from tcpmm.path.limits import derivative, peak
from tcpmm.path.program import program_to_command, program_to_interpolation
from tcpmm.path.speedlimits import JUNCTION_CAUSES, TRANSITION
from tcpmm.path.stream import stream_program
from tcpmm.path.transitions import transition_limits

J = 50.0  # the axes' jerk at a transition [m/s^3]
#: a line along the plane's second axis into a CCW circle of R 35 mm at F5000, then out
LEADIN = ("G21 {plane} G90\nG0 {a}35 {b}-20\nG1 {a}35 {b}0 F5000\n"
          "G3 {a}35 {b}0 {i}-35 {j}0\nG1 {a}35 {b}20\nM30\n")
PLANES = {"G17": ("X", "Y", "I", "J", 0), "G18": ("Z", "X", "K", "I", 2),
          "G19": ("Y", "Z", "J", "K", 1)}


def leadin(plane: str = "G17", feed: float = 5000.0) -> str:
    """:data:`LEADIN` in ``plane``: the plane's first axis carries the step [-]."""
    a, b, i, j, _ = PLANES[plane]
    return LEADIN.format(plane=plane, a=a, b=b, i=i, j=j).replace("F5000", f"F{feed:g}")


def settings(**kw) -> InterpolatorSettings:
    return InterpolatorSettings(profile="scurve", **{"transition_jerk_m_per_s3": J, **kw})


@pytest.mark.parametrize("plane", list(PLANES))
def test_the_cap_puts_the_axis_jerk_at_the_limit_exactly(plane):
    """At the line's join into the circle the speed limit is the one at which the step of
    X's (Z's, Y's) acceleration over the period is the limit, ``v^2 / r / T = j``, to
    rounding, in every G plane alike; the look-ahead runs the join at it and names it."""
    it = program_to_interpolation(leadin(plane), settings())
    T, r = 1e-3, 0.035
    cap = transition_limits(it.path, J, T)
    k = int(np.argmin(cap))
    assert cap[k] ** 2 / r / T == pytest.approx(J, rel=1e-9)
    assert np.isinf(np.delete(cap, [k, k + 1])).all()  # only the joins in and out of the arc
    assert it.junction_speed_m_per_s[k + 1] == pytest.approx(cap[k], rel=1e-12)
    assert JUNCTION_CAUSES[it.junction_cause[k + 1]] == "transition jerk (step of curvature)"
    assert math.sqrt(J * T * r) == pytest.approx(cap[k], rel=1e-9)


@pytest.mark.parametrize("plane", list(PLANES))
def test_the_sampled_command_keeps_the_jerk_at_the_join(plane):
    """The command's largest jerk of the axis that carries the step (X in G17), over
    20 ms about the join, is beyond the limit without the setting (147 m/s^3) and within
    it with: the third difference of an acceleration step ``a`` reads at most ``a / T``,
    and the S-curve's own jerk is along the path, the other axis at the join [-]."""
    axis, idx = PLANES[plane][0], PLANES[plane][4]
    for limit, beyond in ((None, True), (J, False)):
        it = program_to_interpolation(leadin(plane), settings(transition_jerk_m_per_s3=limit))
        cmd = it.command
        s = np.asarray(cmd.meta["path_s_m"])
        at = int(np.searchsorted(s, it.path.length[:2].sum()))  # the rapid, the line
        x = cmd.positions[axis]
        near = np.abs(derivative(x, 3, cmd.period_s))[at - 10:at + 10]
        assert bool(near.max() > 2 * J) is beyond, (limit, near.max())
        assert it.path.end[1, idx] == pytest.approx(0.035)


def test_no_cap_where_the_curvature_is_continuous():
    """A full circle's own blocks (four quadrants), collinear lines and a helix's blocks:
    no step of curvature, no limit (above 1e5 m/s: the rounding of the arcs' ends alone),
    and the command is the one without the setting, to the bit. The join of the rapid
    into the first block is an exact stop whatever its limit."""
    programs = [
        "G21 G17 G90\nG0 X35 Y0\nG3 X0 Y35 I-35 J0 F5000\nG3 X-35 Y0 I0 J-35\n"
        "G3 X0 Y-35 I35 J0\nG3 X35 Y0 I0 J35\nM30\n",
        "G21 G17 G90 G64\nG0 X0 Y0\nG1 X10 Y10 F5000\nG1 X20 Y20\nG1 X30 Y30\nM30\n",
        "G21 G17 G90\nG0 X20 Y0 Z0\nG3 X-20 Y0 Z2 I-20 J0 F5000\nG3 X20 Y0 Z4 I20 J0\n"
        "G3 X-20 Y0 Z6 I-20 J0\nM30\n"]
    for text in programs:
        it = program_to_interpolation(text, settings())
        p = it.path
        feed = ~(p.rapid[:-1] | p.rapid[1:])
        assert (transition_limits(p, J, 1e-3)[feed] > 1e5).all(), text
        assert TRANSITION not in it.junction_cause
        free = program_to_command(text, settings(transition_jerk_m_per_s3=None))
        for a, x in it.command.positions.items():
            assert np.array_equal(x, free.positions[a]), (text, a)


def test_a_helix_steps_by_its_own_curvature():
    """A line along a helix's start tangent into the helix: the curvature of a helix of
    radius ``r`` and rise ``c`` per radian is ``r / (r^2 + c^2)``, all of it radial, so
    the cap is ``sqrt(j T (r^2 + c^2) / r)`` on the radial axis (X at the start)."""
    r, c = 0.02, 0.004 / (2 * math.pi)  # 4 mm per turn
    # tangent at (20, 0, 0) of the CCW helix: (0, r, c) / |.|; a line of 10 mm along it
    t = np.array([0.0, r, c]) / math.hypot(r, c)
    p0 = -10e-3 * t + np.array([r, 0.0, 0.0])
    text = (f"G21 G17 G90\nG0 X{p0[0] * 1e3:.9f} Y{p0[1] * 1e3:.9f} Z{p0[2] * 1e3:.9f}\n"
            "G1 X20 Y0 Z0 F5000\nG3 X-20 Y0 Z2 I-20 J0\nG3 X20 Y0 Z4 I20 J0\nM30\n")
    it = program_to_interpolation(text, settings())
    cap = transition_limits(it.path, J, 1e-3)
    assert cap[1] == pytest.approx(math.sqrt(J * 1e-3 * (r**2 + c**2) / r), rel=1e-6)
    assert np.isinf(cap[[0, 2]]).all()  # the rapid's end; the helix's own blocks


def test_the_chunked_plan_is_the_whole_one():
    """Planned a block at a time (``tcpmm path --chunk-blocks``), the command with the
    limit is the whole program's, to the bit."""
    text = leadin()
    whole = program_to_command(text, settings())
    got = list(stream_program(text, settings(), chunk_blocks=1))
    for axis, x in whole.positions.items():
        assert np.array_equal(np.concatenate([p.positions[axis] for p in got]), x), axis


@pytest.mark.parametrize("bad", [0.0, -1.0, math.inf, math.nan, "fast"])
def test_the_setting_is_a_positive_number_or_none(bad):
    with pytest.raises(ValidationError, match="transition_jerk_m_per_s3"):
        InterpolatorSettings(transition_jerk_m_per_s3=bad)


@pytest.fixture(scope="module")
def scurve_model(tmp_path_factory):
    """The built-in machine with an S-curve of 50 m/s^3 and no transition limit [-]."""
    from tcpmm import builtin_machine, save_model

    vmc = builtin_machine()
    path = tmp_path_factory.mktemp("model") / "scurve.yaml"
    save_model(vmc.model_copy(update={"interpolation": {
        **(vmc.interpolation or {}), "profile": "scurve", "path_jerk_m_per_s3": J}}), path)
    return path


def test_compensate_keeps_the_jerk_at_a_line_into_an_arc(tmp_path, capsys, scurve_model):
    """The compensated command of a line into a circle keeps X's jerk within the S-curve's
    limit: the plan with headroom holds the join's speed to the jerk given times ``1 -
    headroom``, and the correction adds no more than the headroom. It went to 144 m/s^3
    against 50 (the plan's own 149), a warning put down to the step of curvature. The
    tolerance is the one the warnings use (``OVER_SHARE``, a file's rounding)."""
    from tcpmm.path import read_command_csv
    from tcpmm.path.limits import OVER_SHARE

    prog, out = tmp_path / "leadin.nc", tmp_path / "c.csv"
    prog.write_text(leadin())
    assert main(["compensate", str(scurve_model), "--gcode", str(prog), "-o", str(out),
                 "--draws", "0", "--iterations", "3"]) == 0
    err = capsys.readouterr().err
    cmd = read_command_csv(out)
    most = max(peak(x, 3, cmd.period_s, from_rest=True) for x in cmd.positions.values())
    assert most <= J * (1 + OVER_SHARE), most
    assert "jerk up to" not in err, err


def test_a_model_file_with_a_bad_setting_is_refused(tmp_path, capsys):
    """A negative transition jerk in a model file is an error naming the field, no
    traceback."""
    from tcpmm import builtin_machine, save_model

    vmc = builtin_machine()
    path = tmp_path / "bad.yaml"
    save_model(vmc, path)
    text = path.read_text().replace("transition_jerk_m_per_s3: null",
                                    "transition_jerk_m_per_s3: -5")
    path.write_text(text)
    prog = tmp_path / "p.nc"
    prog.write_text(leadin())
    assert main(["path", str(prog), "--model", str(path), "-o", str(tmp_path / "c.csv")]) != 0
    assert "transition_jerk_m_per_s3" in capsys.readouterr().err


@pytest.mark.parametrize("tol_mm", [0.01, 0.05])
def test_a_blend_runs_at_its_ends_speed(tol_mm):
    """A G64 square: each corner's blend steps the curvature by ``1 / r`` at both ends
    and runs at their limit all along, so the S-curve ramps on the lines, where the
    curvature is 0: every axis's jerk stays within the S-curve's 50 m/s^3 (the samples of
    a line along an axis read it exactly, hence ``OVER_SHARE``). Left to speed up inside
    the blend (24 µm radius), the ramp on so tight a curve read 81 m/s^3."""
    from tcpmm.path.geometry import BLEND
    from tcpmm.path.limits import OVER_SHARE

    text = (f"G21 G17 G90 G64 P{tol_mm:g}\nG0 X0 Y0\nG1 X40 Y0 F5000\nG1 X40 Y40\n"
            "G1 X0 Y40\nG1 X0 Y0\nM30\n")
    it = program_to_interpolation(text, settings())
    b = np.flatnonzero(it.path.kind == BLEND)
    assert b.size == 3
    v = it.junction_speed_m_per_s
    assert np.allclose(it.segment_peak_m_per_s[b], v[b], rtol=1e-9)
    cmd = it.command
    for a, x in cmd.positions.items():
        assert peak(x, 3, cmd.period_s, from_rest=True) <= J * (1 + OVER_SHARE), a
