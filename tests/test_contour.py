"""Contour error along any path: known offsets with their sign, a corner with a known
overshoot and settling, and a square end to end on the built-in machine."""

import itertools
import json

import numpy as np
import pytest

from tcpmm.analysis.contour import contour_error, distance_to_polyline
from tcpmm.analysis.corners import find_corners
from tcpmm.cli import main
from tcpmm.errors import InputError
from tcpmm.result import AxisRun, Run

DT = 1e-3


def make_run(cmd, act, sensors=("motor", "scale", "tcp")):
    """A run of the axes of ``cmd``: every sensor at ``act`` [m]."""
    t = np.arange(len(next(iter(cmd.values())))) * DT
    axes = {a: AxisRun(cmd=cmd[a], **{s: act[a] for s in sensors}) for a in cmd}
    return Run(t, axes)


def circle(r, turns=1.0, n=4000, ccw=True):
    th = np.linspace(0, 2 * np.pi * turns, n) * (1 if ccw else -1)
    return r * np.cos(th), r * np.sin(th)


@pytest.mark.parametrize("ccw", [True, False])
def test_a_circle_offset_inwards_is_left_of_a_ccw_travel(ccw):
    x, y = circle(0.02, ccw=ccw)
    d = 3e-6
    k = 1 - d / 0.02
    res = contour_error(make_run({"X": x, "Y": y, "Z": 0 * x}, {"X": k * x, "Y": k * y,
                                                              "Z": 0 * x}))
    assert res.axes == ("X", "Y") and res.signed
    sign = 1.0 if ccw else -1.0  # inside: left of a CCW travel, right of a CW one
    for e in res.errors.values():
        # chords of 31 um sag 6e-9 um: the polyline is the circle within that
        assert e == pytest.approx(sign * d, abs=1e-11)
    [end] = res.corners  # no corner on a circle; its end is where a step test stops
    assert end["index"] == x.size - 1 and np.isnan(end["turn_rad"])


def test_a_line_offset_to_either_side_and_in_3d():
    x = np.linspace(0, 0.05, 2000)
    z = np.zeros_like(x)
    d = 5e-6
    left = contour_error(make_run({"X": x, "Y": z}, {"X": x, "Y": z + d}), plane="XY")
    right = contour_error(make_run({"X": x, "Y": z}, {"X": x, "Y": z - d}), plane="XY")
    np.testing.assert_allclose(left.errors["tcp"], d, atol=1e-15)
    np.testing.assert_allclose(right.errors["tcp"], -d, atol=1e-15)
    seen = contour_error(make_run({"X": x, "Y": z}, {"X": x, "Y": z - d}), plane="YX")
    np.testing.assert_allclose(seen.errors["tcp"], d, atol=1e-15)  # seen from -Z
    run = make_run({"X": x, "Y": z, "Z": z}, {"X": x, "Y": z + 0.6 * d, "Z": z - 0.8 * d})
    res = contour_error(run, plane=None)
    assert not res.signed and res.axes == ("X", "Y", "Z")
    np.testing.assert_allclose(res.errors["tcp"], d, rtol=1e-12)
    # a table in the run-file layout gives the same
    assert contour_error(run.to_pandas(), plane="3D").errors["tcp"] == pytest.approx(
        res.errors["tcp"], abs=1e-12)


def square(side=0.05, v=0.05, rest=100):
    """A CCW square at speed ``v`` with an exact stop of ``rest`` samples at each corner."""
    pts = np.array([(0, 0), (side, 0), (side, side), (0, side), (0, 0)], float)
    out = [pts[:1]]
    for a, b in itertools.pairwise(pts):
        n = round(side / v / DT)
        f = np.arange(1, n + 1)[:, None] / n
        out += [a + f * (b - a), np.repeat(b[None], rest, axis=0)]
    return np.vstack(out)


def test_a_known_overshoot_rounding_and_settling_at_a_corner():
    p = square()
    corners = find_corners(p)
    assert [p[i].tolist() for i, _ in corners] == [[0.05, 0], [0.05, 0.05], [0, 0.05], [0, 0]]
    assert all(t == pytest.approx(np.pi / 2, abs=1e-6) for _, t in corners[:3])
    assert corners[3][0] == p.shape[0] - 1 and np.isnan(corners[3][1])
    # at the first corner the X axis runs past it by delta, up and back down smoothly
    i = corners[0][0]
    first = i - 99  # the first sample at rest on the corner
    delta, tau = 8e-6, 0.03
    u = np.clip((np.arange(p.shape[0]) - first) * DT, 0, None) / tau
    bump = delta * u * np.exp(1 - u)
    act = p.copy()
    act[:, 0] += bump
    res = contour_error(make_run({"X": p[:, 0], "Y": p[:, 1]}, {"X": act[:, 0],
                                                                "Y": act[:, 1]}),
                        settle_tol_m=1e-6)
    c1 = res.corners[0]["tcp"]
    assert c1["overshoot_m"] == pytest.approx(delta, rel=1e-6)
    assert c1["rounding_m"] == pytest.approx(0.0, abs=1e-12)  # it reaches the corner
    # past a left turn is to the right of the travel on: negative
    assert res.errors["tcp"].min() == pytest.approx(-delta, rel=1e-6)
    # the bump falls below 1 um at u* with u* exp(1 - u*) = 1/8, after the command leaves
    uu = np.linspace(1, 20, 2_000_001)
    u_star = uu[np.argmax(uu * np.exp(1 - uu) < 1e-6 / delta)]
    want = first * DT + u_star * tau - i * DT
    assert c1["settle_s"] == pytest.approx(want, abs=1.5 * DT)
    assert c1["settle_m"] == pytest.approx(want * 0.05, abs=1.5 * DT * 0.05)
    for c in res.corners[1:3]:
        assert c["tcp"]["overshoot_m"] == 0 and c["tcp"]["settle_s"] == pytest.approx(DT, abs=DT)
    d = res.to_dict()
    assert d["corners"][0]["overshoot_um"] == pytest.approx(8.0, rel=1e-6)
    json.dumps(d)


def test_a_path_run_twice_each_way_is_matched_with_the_pass_being_run():
    x1, y1 = circle(0.01, n=3000, ccw=True)
    x2, y2 = circle(0.01, n=3000, ccw=False)
    x, y = np.r_[x1, x2], np.r_[y1, y2]
    k = 1 - 2e-6 / 0.01  # inside throughout
    res = contour_error(make_run({"X": x, "Y": y}, {"X": k * x, "Y": k * y}), window_s=0.2)
    e = res.errors["tcp"]
    assert e[100:2900] == pytest.approx(2e-6, abs=1e-10)
    assert e[3100:5900] == pytest.approx(-2e-6, abs=1e-10)


def test_bad_input_is_an_input_error():
    x = np.linspace(0, 1, 10)
    with pytest.raises(InputError, match="does not move"):
        distance_to_polyline(np.zeros((3, 2)), np.zeros((4, 2)), np.arange(3.0),
                             np.arange(4.0), 1.0, True)
    with pytest.raises(InputError, match="window_s must be a positive"):
        contour_error(make_run({"X": x, "Y": x}, {"X": x, "Y": x}), window_s=0)
    with pytest.raises(InputError, match="no axis Z"):
        contour_error(make_run({"X": x, "Y": x}, {"X": x, "Y": x}), plane="XZ")


def test_a_square_on_the_builtin_machine_from_the_cli(tmp_path, capsys):
    (tmp_path / "sq.nc").write_text("G21 G17 G90\nG0 X0 Y0\nG1 X50 Y0 F3000\nX50 Y50\n"
                                    "X0 Y50\nX0 Y0\nG4 P0.5\nM30\n")
    for args in (["path", tmp_path / "sq.nc", "-o", tmp_path / "cmd.csv"],
                 ["simulate", "builtin:vmc", "--command", tmp_path / "cmd.csv", "-o",
                  tmp_path / "run.csv"]):
        assert main([str(a) for a in args]) == 0
    capsys.readouterr()
    code = main(["contour", str(tmp_path / "run.csv"), "--json", "--plot",
                 str(tmp_path / "c.png")])
    cap = capsys.readouterr()
    assert code == 0, cap.err
    assert "plane XY, taken from" in cap.err
    res = json.loads(cap.out)
    assert res["axes"] == "XY" and set(res["sensors"]) == {"motor", "scale", "tcp"}
    rows = [r for r in res["corners"] if r["sensor"] == "scale"]
    at = [v for r in rows for v in (r["x_mm"], r["y_mm"])]
    assert at == pytest.approx([50, 0, 50, 50, 0, 50, 0, 0], abs=1e-3)  # samples pass by
    assert all(r["turn_deg"] == pytest.approx(90, abs=0.01) for r in rows[:3])
    assert rows[3]["turn_deg"] is None  # the end
    # a servo that follows within tens of um and settles within a second, at the end
    # within the dwell
    assert 0 < res["sensors"]["scale"]["max_abs_um"] < 200
    assert all(r["rounding_um"] < 200 and 0 < r["settle_ms"] < 1000 for r in rows)
    assert (tmp_path / "c.png").is_file()
    code = main(["contour", str(tmp_path / "run.csv"), "--plane", "3d"])
    text = " ".join(capsys.readouterr().out.split())
    assert code == 0 and "contour error in XYZ" in text
    assert "unsigned: the distance in XYZ (3D)" in text


def test_a_long_run_name_stays_on_one_line_and_cmd_is_no_sensor(tmp_path, capsys):
    """In a pipe no line is wrapped: the run's name, a table's title, was wrapped to the
    table's width in the middle of a long name. --sensor cmd said 'the run has no cmd
    signals' of a run that has them: the error is measured from the command."""
    name = "a_rather_long_run_file_name_from_the_cam_system_2024_v3_final.csv"
    cmd = tmp_path / "cmd.csv"
    (tmp_path / "sq.nc").write_text("G21 G17 G90\nG0 X0 Y0\nG1 X20 Y0 F3000\nX20 Y20\nM30\n")
    assert main(["path", str(tmp_path / "sq.nc"), "-o", str(cmd)]) == 0
    assert main(["simulate", "builtin:vmc", "--command", str(cmd), "-o",
                 str(tmp_path / name)]) == 0
    capsys.readouterr()
    assert main(["contour", str(tmp_path / name)]) == 0
    first = capsys.readouterr().out.splitlines()[0]
    assert first == f"{tmp_path / name}: contour error in XY [µm]"
    # the command has no error from itself: --help does not offer it, and it is refused
    assert main(["contour", str(tmp_path / name), "--sensor", "cmd"]) == 2
    assert "'cmd' is not one of 'tcp', 'scale', 'motor'" in capsys.readouterr().err
    assert main(["contour", "--help"]) == 0
    assert "<tcp|scale|motor>" in capsys.readouterr().out


def test_a_step_along_one_axis_overshoots_and_settles_at_its_end(capsys, tmp_path):
    """A move of 10 mm along X and a rest: the end overshoots by delta and rings down."""
    n_move, n_rest = 200, 300
    x = np.r_[np.linspace(0, 0.01, n_move), np.full(n_rest, 0.01)]
    delta, tau, w = 5e-6, 0.02, 2 * np.pi * 25
    u = np.clip(np.arange(x.size) - (n_move - 1), 0, None) * DT
    ring = np.exp(-u / tau) * np.sin(w * u)
    ring *= delta / ring.max()
    act = x + ring
    run = make_run({"X": x, "Y": 0 * x, "Z": 0 * x}, {"X": act, "Y": 0 * x, "Z": 0 * x})
    res = contour_error(run)  # one axis moves: 3-D, unsigned
    assert not res.signed
    [end] = res.corners
    m = end["tcp"]
    assert m["overshoot_m"] == pytest.approx(delta, rel=1e-12)
    # settled once the distance to the end point stays within 1 um
    k = np.flatnonzero(np.abs(ring) > 1e-6)[-1] + 1
    assert m["settle_s"] == pytest.approx(u[k], abs=1e-12)
    assert m["settle_m"] == 0.0  # the command stands still meanwhile
    run.to_pandas().to_csv(tmp_path / "run.csv", index=False)
    assert main(["contour", str(tmp_path / "run.csv")]) == 0
    cap = capsys.readouterr()
    assert "3D (unsigned), taken from" in " ".join(cap.err.split())
    assert "end" in cap.out
    # --chunk-rows does nothing to a CSV run, and says so
    assert main(["contour", str(tmp_path / "run.csv"), "--chunk-rows", "100"]) == 0
    again = capsys.readouterr()
    assert "--chunk-rows reads a Parquet run in chunks; " in " ".join(again.err.split())
    assert again.out == cap.out


def test_the_result_shares_the_protocol(tmp_path):
    import pandas as pd

    from tcpmm.plot import pyplot

    p = square()
    res = contour_error(make_run({"X": p[:, 0], "Y": p[:, 1]}, {"X": p[:, 0], "Y": p[:, 1]}))
    assert isinstance(res.to_pandas(), pd.DataFrame) and len(res.to_pandas()) == p.shape[0]
    assert len(res.corners_table()) == 4 * 3  # corners and the end, per sensor
    json.dumps(res.to_dict())
    fig = res.plot(path=tmp_path / "c.png")
    assert (tmp_path / "c.png").stat().st_size > 0 and len(fig.axes) == 3  # + colour bar
    fig = pyplot().figure()
    axs = [fig.add_subplot(1, 2, k) for k in (1, 2)]
    assert res.plot(ax=axs) is fig
    assert res.plot(ax=axs[0], sensor="scale") is fig  # the coloured path alone
    pyplot().close("all")


def _spiral_program(n=500, turns=3, r0=0.2, r1=20.2) -> str:
    th = np.linspace(0, 2 * np.pi * turns, n + 1)
    r = np.linspace(r0, r1, n + 1)
    pts = "\n".join(f"X{a:.4f} Y{b:.4f}" for a, b in zip(r * np.cos(th), r * np.sin(th),
                                                          strict=True))
    return f"G21 G17 G90 G64 P0.01\nG0 X0 Y0\nG1 F3000\n{pts}\nG4 P0.3\nM30\n"


@pytest.mark.parametrize("program", [
    _spiral_program(),
    "G21 G18 G90\nG2 X0 Z0 I20 K0 F3000\nG4 P0.3\nM30\n",
    "G21 G19 G90\nG3 Y0 Z0 J0 K20 F3000\nG4 P0.3\nM30\n",
], ids=["spiral", "G18", "G19"])
def test_a_curve_has_no_corner_and_its_end_no_overshoot_of_its_size(program, tmp_path,
                                                                   capsys):
    """A spiral of 500 blended blocks turns tightly inside but evenly: no corner. A circle
    ends where it started: the end's overshoot is measured near the end, not across the
    circle (which gave the radius, 20 000 um, and on the spiral 13 000 um)."""
    (tmp_path / "p.nc").write_text(program)
    for args in (["path", tmp_path / "p.nc", "-o", tmp_path / "cmd.csv"],
                 ["simulate", "builtin:vmc", "--command", tmp_path / "cmd.csv", "-o",
                  tmp_path / "run.csv"]):
        assert main([str(a) for a in args]) == 0
    capsys.readouterr()
    assert main(["contour", str(tmp_path / "run.csv"), "--json"]) == 0
    res = json.loads(capsys.readouterr().out)
    assert [r["turn_deg"] for r in res["corners"]] == [None] * len(res["sensors"])
    for r in res["corners"]:
        # within the sensor's own contour error, which is tens of um
        assert 0 <= r["overshoot_um"] <= res["sensors"][r["sensor"]]["max_abs_um"]
        assert r["overshoot_um"] < 15


def test_a_blended_corner_s_turn_is_said_to_be_over_the_span(tmp_path, capsys):
    """A square's 90 deg corners blended under G64 P0.01 turn by 88 deg over the 0.5 mm
    the corners are taken over; the table said 88 deg with nothing to say it is not the
    programmed corner. The caption says over what the turn is taken."""
    (tmp_path / "sq.nc").write_text("G21 G17 G90 G64 P0.01\nG0 X0 Y0\nG1 X20 Y0 F3000\n"
                                    "X20 Y20\nX0 Y20\nX0 Y0\nG4 P0.3\nM30\n")
    assert main(["simulate", "builtin:vmc", "--gcode", str(tmp_path / "sq.nc"), "-o",
                 str(tmp_path / "run.csv")]) == 0
    capsys.readouterr()
    assert main(["contour", str(tmp_path / "run.csv")]) == 0
    out = capsys.readouterr().out
    assert " 88° " in out
    assert "turn: of the command over 0.5 mm before and after" in " ".join(out.split())


@pytest.mark.parametrize("suffix", ["csv", "parquet"])
def test_a_plane_the_path_does_not_run_in_is_refused(suffix, tmp_path, capsys):
    """A G18 circle taken in XY read a contour error of 0.00 um on every sensor, with a
    corner, exit 0: the error of the line X runs along, Y never moving. The plane is
    refused with the one the path runs in; that one, and XY of a helix (Z moving a
    little beside X and Y), are measured."""
    progs = {"g18": "G21 G18 G90\nG2 X0 Z0 I20 K0 F3000\nG4 P0.3\nM30\n",
             "helix": "G21 G17 G90\nG1 X-20 Y0 F3000\nG2 X-20 Y0 Z-1 I20 J0\nG4 P0.3\nM30\n"}
    for name, prog in progs.items():
        (tmp_path / f"{name}.nc").write_text(prog)
        assert main(["simulate", "builtin:vmc", "--gcode", str(tmp_path / f"{name}.nc"),
                     "-o", str(tmp_path / f"{name}.{suffix}")]) == 0
    capsys.readouterr()
    code = main(["contour", str(tmp_path / f"g18.{suffix}"), "--plane", "XY"])
    err = " ".join(capsys.readouterr().err.split())
    assert code == 2 and "the plane XY leaves out Z, which moves 40 mm" in err
    assert "the path runs in the ZX plane" in err and "Traceback" not in err
    for run, plane in (("g18", "ZX"), ("helix", "XY")):
        assert main(["contour", str(tmp_path / f"{run}.{suffix}"), "--plane", plane,
                     "--json"]) == 0
        res = json.loads(capsys.readouterr().out)
        assert res["sensors"]["tcp"]["max_abs_um"] > 1.0


@pytest.mark.parametrize("turn_deg", [45.0, 135.0])
def test_a_corner_of_any_turn_overshoots_across_its_outgoing_leg(turn_deg):
    """A followed path has no overshoot at a 45 or 135 degree corner (along the incoming
    direction, the outgoing leg of a 45 degree turn runs on 'past' the corner); a bump
    outwards across the outgoing leg right after the corner is the overshoot."""
    a = np.radians(turn_deg)
    t_out = np.array([np.cos(a), np.sin(a)])
    leg = np.linspace(0, 0.02, 400)[1:, None]
    p = np.vstack([np.c_[np.linspace(-0.02, 0, 400), np.zeros(400)],
                   np.repeat([[0.0, 0.0]], 50, axis=0), leg * t_out])
    run = make_run({"X": p[:, 0], "Y": p[:, 1]}, {"X": p[:, 0], "Y": p[:, 1]})
    [corner, _] = contour_error(run).corners
    assert np.degrees(corner["turn_rad"]) == pytest.approx(turn_deg, abs=0.1)
    assert corner["tcp"]["overshoot_m"] == 0 and corner["tcp"]["rounding_m"] == 0
    delta = 4e-6
    n_out = np.array([np.sin(a), -np.cos(a)])  # right of the outgoing leg: outside
    u = np.clip(np.arange(p.shape[0]) - 460, 0, None) * DT / 0.02
    act = p + (delta * u * np.exp(1 - u))[:, None] * n_out
    res = contour_error(make_run({"X": p[:, 0], "Y": p[:, 1]}, {"X": act[:, 0],
                                                                "Y": act[:, 1]}))
    assert res.corners[0]["tcp"]["overshoot_m"] == pytest.approx(delta, rel=1e-3)
    assert res.errors["tcp"].min() == pytest.approx(-delta, rel=1e-3)


@pytest.mark.parametrize("direction", [(1.0, 0.0), (0.6, -0.8)])
def test_a_reversal_is_its_turning_point(direction):
    """Out along a line and back (a plunge and retract, a step test out and back): every
    point within half a span of the turning point turns by 180 degrees over the span; the
    corner is the turning point, and a point that turns back short of it by delta has a
    rounding of delta."""
    u = np.array(direction)
    t = np.arange(2001) * DT
    x = 0.01 * (1 - np.cos(np.pi * t / 1.0))  # 0 -> 20 mm -> 0, at rest at the turn
    p = x[:, None] * u
    delta = 30e-6
    act = (x * (1 - delta / 0.02))[:, None] * u
    res = contour_error(make_run({"X": p[:, 0], "Y": p[:, 1]}, {"X": act[:, 0],
                                                                "Y": act[:, 1]}))
    [corner, end] = res.corners
    assert corner["index"] == 1000 and np.isnan(end["turn_rad"])
    assert corner["turn_rad"] == pytest.approx(np.pi, abs=1e-6)
    assert corner["tcp"]["rounding_m"] == pytest.approx(delta, rel=1e-6)
    assert corner["tcp"]["overshoot_m"] == pytest.approx(0.0, abs=1e-15)


def test_a_reversal_is_its_turning_point_where_the_samples_are_sparse():
    """An interpolated reversal (F5000 to 20 mm and back at 1 m/s^2): the samples lie
    0.02 mm apart half a span before the turn and crowd at it, so the vertex halfway along
    the path between the first and the last that turn back lay 4.5 um short of the
    turning point, and a tool that turned back 30 um short of it read 25.5 um."""
    from tcpmm.path import program_to_command

    cmd = program_to_command("G21 G90 G17\nG1 X20 F5000\nG1 X0\nM30\n")
    x = cmd.positions["X"]
    delta = 30e-6
    act = x * (1 - delta / x.max())
    zero = np.zeros_like(x)
    assert cmd.time_s[1] - cmd.time_s[0] == pytest.approx(DT)
    res = contour_error(make_run({"X": x, "Y": zero}, {"X": act, "Y": zero}))
    [corner, _] = res.corners
    assert corner["point_m"][0] == x.max()
    assert corner["tcp"]["rounding_m"] == pytest.approx(delta, rel=1e-6)


def test_a_sag_across_the_outgoing_leg_is_no_overshoot():
    """A square in XZ whose tool hangs a constant 50 um low (under its weight): past the
    corner where the -Z plunge turns to -X the tool lies 50 um outside the path all along
    the leg; that is contour error, not overshoot. A bump on top of it is the overshoot."""
    leg = np.linspace(0, 0.02, 401)
    p = np.vstack([np.c_[leg, np.zeros(401)], np.c_[np.full(400, 0.02), -leg[1:]],
                   np.c_[0.02 - leg[1:], np.full(400, -0.02)]])
    sag = np.array([0.0, -50e-6])
    i = 800  # the corner at (20, -20) mm
    u = np.clip(np.arange(p.shape[0]) - i, 0, None) * DT / 0.01  # settled by halfway on
    delta = 5e-6
    for bump, want in ((0.0, 0.0), (delta, delta)):
        act = p + sag + (bump * u * np.exp(1 - u))[:, None] * np.array([0.0, -1.0])
        res = contour_error(make_run({"X": p[:, 0], "Z": p[:, 1]}, {"X": act[:, 0],
                                                                    "Z": act[:, 1]}))
        second = res.corners[1]
        assert second["index"] == i
        assert second["tcp"]["overshoot_m"] == pytest.approx(want, abs=1e-9)
        assert abs(res.errors["tcp"][-100:]).min() == pytest.approx(50e-6, rel=1e-9)


def stopping(tail_s, noise_m=0.0, seed=0, lag_s=0.01):
    """A move of 20 mm along X at 10 mm/s whose tool follows as a first-order lag of
    ``lag_s`` (100 um behind at speed for 10 ms), recorded ``tail_s`` past the command's
    arrival, with noise of ``noise_m`` rms on X and Y [m]."""
    xc = np.r_[np.linspace(0.0, 0.02, 2001), np.full(round(tail_s / DT), 0.02)]
    a = np.exp(-DT / lag_s)
    x = np.zeros_like(xc)
    for k in range(1, x.size):
        x[k] = a * x[k - 1] + (1 - a) * xc[k - 1]
    rng = np.random.default_rng(seed)
    y = noise_m * rng.standard_normal(x.size)
    x = x + noise_m * rng.standard_normal(x.size)
    return make_run({"X": xc, "Y": 0 * xc}, {"X": x, "Y": y})


@pytest.mark.parametrize("lag_s", [0.01, 0.1])
def test_a_run_that_stops_on_the_way_to_the_end_leaves_the_end_unmeasured(tmp_path, capsys,
                                                                          lag_s):
    """A run that stops as the command arrives at the end, the tool still 100 um behind:
    its closest approach was where the run stopped, no rounding of the machine's, so the
    end's overshoot and rounding are n/a, and the command line says why and how far. A tool
    1 mm behind never came near enough to be measured there: the same (it read n/a
    without a word)."""
    run = stopping(0.0, lag_s=lag_s)
    res = contour_error(run, plane="XY")
    [end] = res.corners
    short = 0.02 - run.axes["X"].tcp[-1]
    assert short > 9 * lag_s * 1e-3
    assert res.unreached == pytest.approx(dict.fromkeys(("motor", "scale", "tcp"), short),
                                          rel=1e-12)
    for s in res.errors:
        assert all(np.isnan(v) for v in end[s].values()), s
    assert res.to_dict()["end_unreached_um"]["tcp"] == pytest.approx(short * 1e6, rel=1e-12)
    run.to_pandas().to_csv(tmp_path / "run.csv", index=False)
    assert main(["contour", str(tmp_path / "run.csv"), "--plane", "XY"]) == 0
    cap = capsys.readouterr()
    err = " ".join(cap.err.split())
    assert ("the run stops before the machine comes to rest at the path's end point (at "
            f"the last sample motor {short * 1e6:.2f} µm") in err
    assert "G4 P0.5), or a longer one than it has" in err
    assert cap.out.splitlines()[-2].split()[-5:] == ["end", "n/a", "n/a", "n/a", "n/a"]


@pytest.mark.parametrize("seed", range(4))
def test_a_run_that_records_the_rest_has_its_end_measured_noise_and_all(seed):
    """The same move recorded 0.3 s on (30 lags): the tool arrives, its rounding at the end
    is its distance there; with noise of 2 um about the end point (above the 1 um band:
    never settled) the end is still measured, for the tool came close before the last
    sample."""
    res = contour_error(stopping(0.3), plane="XY")
    assert res.unreached == {}
    assert res.corners[-1]["tcp"]["rounding_m"] < 1e-9
    noisy = contour_error(stopping(0.3, 2e-6, seed), plane="XY")
    end = noisy.corners[-1]["tcp"]
    assert noisy.unreached == {} and np.isnan(end["settle_s"])
    assert 0 <= end["rounding_m"] < 2e-6 and np.isfinite(end["overshoot_m"])


def test_a_tool_ringing_on_the_way_or_about_a_deflection():
    """The tool's column rings at 7 Hz (5 um) about its motor. Where the run stops as the
    command arrives, the motor still 100 um behind, the tool's closest approach came before
    its last sample, yet no figure at the end is the machine's: all n/a. Where the run goes
    on 0.5 s, the motor at rest and the tool ringing about a deflection of 45 um short
    (never within the band: not settled), the tool came closer between: measured."""
    for tail_s, cut in ((0.0, True), (0.5, False)):
        run = stopping(tail_s)
        x = run.axes["X"].motor
        t = run.time_s
        ring = 5e-6 * np.sin(2 * np.pi * 7 * t) - 45e-6 * (t > 2.0)
        axes = {"X": AxisRun(cmd=run.axes["X"].cmd, motor=x, tcp=x + ring),
                "Y": run.axes["Y"]}
        res = contour_error(Run(t, axes), plane="XY")
        end = res.corners[-1]
        assert set(res.unreached) == ({"motor", "tcp"} if cut else set())
        assert np.isnan(end["tcp"]["rounding_m"]) == cut
        if not cut:
            assert np.isnan(end["tcp"]["settle_s"])
            assert end["tcp"]["rounding_m"] == pytest.approx(40e-6, abs=0.1e-6)


def test_a_circle_run_twice_in_one_place_has_its_end_measured_at_the_end():
    """A circle that ends on its start, followed with a lag and a static deflection along
    the last direction: the start's samples lie 'past' the end along the incoming direction
    by up to the radius, and the deflection is where it rests, not an overshoot."""
    x, y = circle(0.02, n=4000)
    x, y = np.r_[x, np.full(300, x[-1])], np.r_[y, np.full(300, y[-1])]
    lag = 5
    ax, ay = np.r_[np.full(lag, x[0]), x[:-lag]], np.r_[np.full(lag, y[0]), y[:-lag]] + 3e-6
    [end] = contour_error(make_run({"X": x, "Y": y}, {"X": ax, "Y": ay})).corners
    assert np.isnan(end["turn_rad"])
    assert end["tcp"]["overshoot_m"] == 0
    assert end["tcp"]["rounding_m"] == pytest.approx(3e-6, rel=1e-6)


def test_an_offset_held_throughout_a_move_along_one_axis_is_said(tmp_path, capsys):
    """A move along X alone is measured in 3-D: a sensor of Z, standing still, that holds
    an offset (a measured TCP zeroed elsewhere, say) is in every figure, and is said. The
    built-in Z's sag under its weight is the datum its sensors are read from, no offset."""
    import warnings

    from tcpmm import builtin_machine, simulate
    from tcpmm.path import program_to_command

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        run = simulate(builtin_machine(), program_to_command(
            "G21 G90 G17\nG0 X0 Y0\nG1 X20 F2000\nG4 P0.5\nG1 X0\nG4 P0.5\nM30\n"))
    run.write_csv(tmp_path / "x.csv")
    assert main(["contour", str(tmp_path / "x.csv"), "--json"]) == 0
    out = capsys.readouterr()
    assert json.loads(out.out)["sensors"]["tcp"]["max_abs_um"] < 5.0
    assert "never falls below" not in out.err
    run.axes["Z"].tcp = run.axes["Z"].tcp - 50.7e-6
    run.write_csv(tmp_path / "x.csv")
    assert main(["contour", str(tmp_path / "x.csv")]) == 0
    err = " ".join(capsys.readouterr().err.split())
    assert "note: tcp: the error never falls below 50." in err
    assert main(["contour", str(tmp_path / "x.csv"), "--plane", "XY"]) == 0
    assert "never falls below" not in capsys.readouterr().err


@pytest.mark.parametrize("deg", [180.0, 200.0])
def test_a_corner_of_180_deg_or_more_is_refused(tmp_path, capsys, deg):
    """--corner-deg 200 was taken and found no corner, silently: no path turns further
    than back on itself."""
    x = np.linspace(0.0, 0.01, 200)
    run = make_run({"X": x, "Y": 0 * x}, {"X": x, "Y": 0 * x})
    with pytest.raises(InputError, match="corner_deg must be below 180"):
        contour_error(run, corner_deg=deg)
    run.write_csv(tmp_path / "r.csv")
    assert main(["contour", str(tmp_path / "r.csv"), "--corner-deg", str(deg)]) == 2
    assert "give less than 180" in " ".join(capsys.readouterr().err.split())


def test_a_largest_error_just_after_a_rapid_is_said_to_be_the_lag_it_carries(tmp_path,
                                                                            capsys):
    """A G0 to the start of a circle, then the circle at F1000 and at F5000: both read the
    same largest error, 46 um, 0.39 s into the run, the lag the servo carries from the
    rapid into the first feed move. The table gives when it lies, and a note says it
    lies just after a rapid; after a dwell that lets the lag settle the note is gone.
    The streamed run gives the same figures (its RMS is summed chunk by chunk)."""
    def run(name, prog):
        (tmp_path / f"{name}.nc").write_text(prog)
        assert main(["simulate", "builtin:vmc", "--gcode", str(tmp_path / f"{name}.nc"),
                     "-o", str(tmp_path / f"{name}.parquet")]) == 0
        capsys.readouterr()
        assert main(["contour", str(tmp_path / f"{name}.parquet")]) == 0
        text = capsys.readouterr()
        assert main(["contour", str(tmp_path / f"{name}.parquet"), "--json"]) == 0
        whole = json.loads(capsys.readouterr().out)["sensors"]
        assert main(["contour", str(tmp_path / f"{name}.parquet"), "--json",
                     "--chunk-rows", "700"]) == 0
        keys = ("max_abs_um", "max_abs_at_s", "max_abs_after_rapid_s")
        streamed = json.loads(capsys.readouterr().out)["sensors"]
        assert {s: [d[k] for k in keys] for s, d in streamed.items()} == {
            s: [d[k] for k in keys] for s, d in whole.items()}
        return " ".join(text.err.split()), text.out, whole

    circle = "G2 X35 Y0 I-35 J0\nM30\n"
    err, out, tcp = run("fast", f"G21 G17 G90\nG0 X35 Y0\nG1 F5000\n{circle}")
    assert "max |e| at s" in out and tcp["tcp"]["max_abs_after_rapid_s"] < 0.1
    assert "note: the largest error (motor" in err and "after a G0 rapid ends)" in err
    err, _, tcp = run("dwell", f"G21 G17 G90\nG0 X35 Y0\nG4 P0.5\nG1 F5000\n{circle}")
    assert "after a G0 rapid ends" not in err
    assert tcp["tcp"]["max_abs_after_rapid_s"] > 0.3 and tcp["tcp"]["max_abs_at_s"] > 0.8


def square_contour(tmp_path, capsys, period_s: float, *extra):
    """``tcpmm contour`` of a 50 mm square at F3000 (G64 P0.01) on the built-in machine
    recorded every ``period_s``: exit code, stdout and stderr [-]."""
    from conftest import run_cli

    prog = tmp_path / "sq.nc"
    prog.write_text("G21 G90 G17 G64 P0.01\nG0 X0 Y0\nG1 X50 F3000\nY50\nX0\nY0\nG4 P0.5\nM30\n")
    run = tmp_path / f"r{period_s}.csv"
    assert run_cli(capsys, "simulate", "builtin:vmc", "--gcode", prog, "-o", run,
                   "--record-period-s", period_s)[0] == 0
    return run_cli(capsys, "contour", run, *extra)


def test_corners_a_coarse_record_cuts_are_not_measured(tmp_path, capsys):
    """A 50 mm square at F3000 recorded every 50 ms (2.5 mm apart): the command's samples
    cut its corners by 223 um, and the corners read a rounding of 1133 um where a sample
    passed 51 um from the corner (38 um recorded every millisecond). Their overshoot and
    rounding are n/a, and the warning says why; the same run recorded every millisecond
    keeps them."""
    for period, coarse in ((0.05, True), (0.001, False)):
        code, out, err = square_contour(tmp_path, capsys, period, "--json")
        assert code == 0, err
        rows = [r for r in json.loads(out)["corners"] if r["sensor"] == "tcp"]
        rounded = [r["rounding_um"] for r in rows[:3]]
        if coarse:
            assert all(v is None for v in rounded), rounded
            assert "overshoot and rounding are not given" in " ".join(err.split())
        else:
            assert all(v is not None and 20.0 < v < 80.0 for v in rounded), rounded


def test_a_peak_read_on_too_few_samples_is_said(tmp_path, capsys):
    """The square at F3000 recorded every 5 ms read its TCP's largest contour error as
    48.0 um, the millisecond record 55.5 um, with no word (the chords' sag is small there).
    Where a sensor's largest error stands well above both its neighbouring samples, a
    warning says the peak between them may be higher; the millisecond record has none."""
    for period, said in ((0.005, True), (0.001, False)):
        code, _, err = square_contour(tmp_path, capsys, period)
        assert code == 0, err
        text = " ".join(err.split())
        assert ("largest error is read on samples whose neighbours lie well below it: "
                in text) == said, text
        assert not said or "tcp at" in text


def test_a_coarse_peak_said_is_the_summarys_largest_error(tmp_path, capsys):
    """G0 rapids round a square, then a slow feed arc, recorded every 5 ms: the rapids are
    left out of the figures, but the warning of a peak read on too few samples named the
    rapids' corners ('motor at 0.295 s (7.19 um)'), whose errors the summary leaves out,
    not its largest error (motor at 3.465 s). It names the summary's largest errors."""
    from conftest import run_cli

    prog, run = tmp_path / "rq.nc", tmp_path / "rq.csv"
    prog.write_text("G21 G90 G17\nG0 X20 Y0\nG0 X20 Y20\nG0 X0 Y20\nG0 X0 Y0\nG4 P0.3\n"
                    "G1 X10 F300\nG3 X10 Y0 I5 J0\nG4 P0.5\nM30\n")
    assert run_cli(capsys, "simulate", "builtin:vmc", "--gcode", prog, "-o", run,
                   "--record-period-s", 0.005)[0] == 0
    code, out, err = run_cli(capsys, "contour", run, "--json")
    assert code == 0, err
    sensors = json.loads(out)["sensors"]
    text = " ".join(err.split())
    assert "neighbours lie well below it" in text
    said = text.split("neighbours lie well below it: ")[1].split(";")[0]
    for part in said.split(", "):  # e.g. "tcp at 5.055 s (1.8 um)"
        sensor, _, at = part.split()[:3]
        assert float(at) == pytest.approx(sensors[sensor]["max_abs_at_s"], abs=5e-4), part
