"""A run made from an NC program records per sample the line of the block its command is
in and whether that is a G0 rapid; the contour error leaves the rapids out unless asked,
whole and streamed alike, and says how much it left out."""

from __future__ import annotations

import itertools
import json
import warnings

import numpy as np
import pytest

from conftest import run_cli
from tcpmm.analysis.contour import contour_error
from tcpmm.analysis.contour_stream import stream_contour
from tcpmm.io.runfile import read_run
from tcpmm.path.commandfile import read_command_csv
from tcpmm.path.program import program_to_command
from tcpmm.path.settings import InterpolatorSettings
from tcpmm.path.stream import stream_program
from tcpmm.path.ties import NEAR_ABS, NEAR_REL

#: feed passes along X joined by diagonal rapids, each rapid followed by a dwell in which
#: the servo settles from it (a dwell after a rapid counts as the rapid): the error of
#: the rapids (the axes' lags differ on a diagonal) is several times the passes'
PROGRAM = "\n".join(["G21 G90 G17", "G1 X10 F600", "G0 X40 Y25", "G4 P0.3", "G1 X50 F600",
                     "G0 X0 Y0", "G4 P0.3", "G1 X10 F600", "M30"]) + "\n"
#: the lines of PROGRAM in rapids: the G0s and the dwells after them
RAPID_LINES = {3, 4, 6, 7}


def quiet(fn, *args, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fn(*args, **kw)


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """The program's run as CSV (made whole) and as Parquet (streamed a block a chunk)."""
    d = tmp_path_factory.mktemp("rapids")
    (d / "p.nc").write_text(PROGRAM)
    model = d / "m.yaml"
    assert run_cli_plain("machine", "export", "vmc", "-o", model) == 0
    for name, extra in (("run.csv", []), ("run.parquet", ["--chunk-blocks", "1"])):
        assert run_cli_plain("simulate", model, "--gcode", d / "p.nc", "-o", d / name,
                             *extra) == 0
    return d / "run.csv", d / "run.parquet"


def same(a, b) -> bool:
    """Equal to the bit, NaN to NaN (corners and their figures; a streamed run's corners
    are a sequence, not a list) [-]."""
    return (json.dumps(list(a), sort_keys=True) == json.dumps(list(b), sort_keys=True)
            if not isinstance(a, dict) else
            json.dumps(a, sort_keys=True) == json.dumps(b, sort_keys=True))


def run_cli_plain(*args) -> int:
    from tcpmm.cli import main

    return quiet(main, [str(a) for a in args])


def test_a_program_run_records_the_line_and_the_rapids_of_each_sample(runs):
    csv, parquet = (read_run(p) for p in runs)
    assert np.array_equal(csv.nc_line, parquet.nc_line)
    assert np.array_equal(csv.rapid, parquet.rapid)
    lines = csv.nc_line[np.r_[0, np.flatnonzero(np.diff(csv.nc_line)) + 1]].tolist()
    assert lines == [2, 3, 4, 5, 6, 7, 8]  # every block in order, the header none
    for line in lines:
        flags = set(csv.rapid[csv.nc_line == line].tolist())
        assert flags == {int(line in RAPID_LINES)}, line


def test_a_run_without_the_columns_is_read_as_before(runs, tmp_path):
    """A measured run has no nc_line and no rapid; nothing is made up for it."""
    run = read_run(runs[0])
    bare = type(run)(run.time_s, run.axes, run.meta)
    bare.write(path := tmp_path / "bare.csv")
    back = read_run(path)
    assert back.nc_line is None and back.rapid is None
    assert "rapid" not in path.read_text().splitlines()[0]


@pytest.mark.parametrize("kind", ["linear", "bell"])
def test_the_rapid_flag_covers_the_filtered_rapid(kind):
    """Through a post-interpolation filter the command moves on after the unfiltered
    rapid ends: the flag holds while any sample the filter takes is in the rapid, so that
    every sample not flagged lies on a feed pass (Y 0 or 20, exactly), and the pieces of
    a program streamed a block a chunk give the whole command's flags."""
    text = "G21 G90 G17\nG1 X10 F3000\nG0 X10 Y20\nG1 X0 F3000\nM30\n"
    settings = InterpolatorSettings(filter_kind=kind, filter_time_s=0.016)
    cmd = program_to_command(text, settings)
    y, rapid = cmd.positions["Y"], cmd.meta["rapid"]
    assert y.size == rapid.size == cmd.meta["nc_line"].size
    on_pass = np.minimum(np.abs(y), np.abs(y - 0.02)) < 1e-12
    assert np.all(on_pass[rapid == 0]) and not np.all(on_pass)
    pieces = list(stream_program(text, settings, 1))
    assert np.array_equal(np.concatenate([p.rapid for p in pieces]), rapid)
    assert np.array_equal(np.concatenate([p.nc_line for p in pieces]), cmd.meta["nc_line"])


def test_contour_leaves_the_rapids_out_unless_asked(runs):
    run = read_run(runs[0])
    feed, every = contour_error(run, plane="XY"), contour_error(run, plane="XY", rapids=True)
    air = run.rapid == 1
    for s, e in every.errors.items():
        mine = np.abs(feed.errors[s])
        assert feed.summary()[s]["max_abs_m"] == float(np.max(mine[~air]))
        assert every.summary()[s]["max_abs_m"] == float(np.max(np.abs(e)))
        # out of the rapids each sample is measured from its own feed move alone, which
        # can only be further than the whole path, but for the segments that tie with the
        # closest (within NEAR_REL and NEAR_ABS), of which the whole path's may pick another
        assert np.all(mine[~air] >= np.abs(e[~air]) * (1 - NEAR_REL) - NEAR_ABS)
        assert np.array_equal(mine[air], np.abs(e[air]))
    top = every.summary()["tcp"]["max_abs_m"]
    assert top > 2.0 * feed.summary()["tcp"]["max_abs_m"]
    assert air[np.argmax(np.abs(every.errors["tcp"]))]  # the largest error is a rapid's
    table = feed.to_pandas()
    assert np.array_equal(table["nc_line"], run.nc_line)
    assert feed.rapids == {"counted": False, "samples": int(air.sum()),
                           "share": air.sum() / air.size, "corners": 4}
    assert every.rapids["counted"] and every.rapids["samples"] == int(air.sum())
    # the corners at the ends of the rapids are left out; the end of the path, on a
    # feed pass, stays
    assert len(every.corners) == 5 and [c["number"] for c in feed.corners] == [5]
    assert same(feed.corners[0], every.corners[-1])


def test_streamed_and_whole_leave_out_the_same(runs):
    whole = {r: contour_error(read_run(runs[1]), plane="XY", rapids=r) for r in (False, True)}
    for rows in (53, 97, 400, 10_000):
        for r, w in whole.items():
            got = stream_contour(runs[1], ("X", "Y"), True, rows=rows, rapids=r)
            assert got.rapids == w.rapids and same(got.corners, w.corners), rows
            for s, d in w.summary().items():
                g = got.summary()[s]
                assert [g[k] for k in ("max_abs_m", "max_m", "min_m")] == \
                    [d[k] for k in ("max_abs_m", "max_m", "min_m")], (rows, r, s)
                assert g["rms_m"] == pytest.approx(d["rms_m"], rel=1e-12)


def test_the_command_line_says_what_it_left_out(runs, capsys):
    csv, parquet = runs
    code, out, err = run_cli(capsys, "contour", csv, "--plane", "XY")
    assert code == 0 and "note: G0 rapids left out:" in err and "--rapids counts them" in err
    code, out, err = run_cli(capsys, "contour", csv, "--plane", "XY", "--rapids")
    assert code == 0 and "rapids" not in err
    got, notes = {}, {}
    for extra in ([], ["--chunk-rows", "97"]):
        for flag in ([], ["--rapids"]):
            code, out, said = run_cli(capsys, "contour", parquet, "--plane", "XY", "--json",
                                      *extra, *flag)
            got[bool(extra), bool(flag)] = json.loads(out)
            notes[bool(extra), bool(flag)] = said
    for counted in (False, True):
        w, s = got[False, counted], got[True, counted]
        assert w["rapids"] == s["rapids"] and w["rapids"]["counted"] is counted
        assert w["corners"] == s["corners"]
        assert w["rapids"]["corners"] == 4 and w["rapids"]["samples"] > 0
        # the share in per cent, as the note says it, under a key that says so
        assert "share" not in w["rapids"] and 0 < w["rapids"]["share_percent"] < 100
    share = got[False, False]["rapids"]["share_percent"]
    assert f"{share:.1f} % of the run" in notes[False, False]
    assert len(got[False, False]["corners"]) < len(got[False, True]["corners"])


def test_a_run_without_the_rapid_column_is_measured_whole(runs, tmp_path, capsys):
    """A measured run (no rapid column): every sample and corner counted, nothing said;
    --rapids changes nothing, and says so (it had been taken in silence, as if it had
    counted something)."""
    run = read_run(runs[0])
    bare = type(run)(run.time_s, run.axes, run.meta)
    bare.write(path := tmp_path / "measured.csv")
    res = contour_error(read_run(path), plane="XY")
    every = contour_error(run, plane="XY", rapids=True)
    assert res.rapids is None and res.summary() == every.summary()
    assert same(res.corners, every.corners)
    outs = []
    for flag in ([], ["--rapids"]):
        code, out, err = run_cli(capsys, "contour", path, "--plane", "XY", "--json", *flag)
        assert code == 0
        assert ("--rapids changes nothing here" in err) == bool(flag), err
        assert flag or "rapids" not in err
        outs.append(json.loads(out))
    assert outs[0] == outs[1] and outs[0]["rapids"] is None


def test_a_command_file_carries_the_blocks_to_contour(runs, tmp_path, capsys):
    """``tcpmm path`` writes nc_line and rapid (whole and streamed, the same text);
    ``--command`` of such a file gives a run that has no rapid column its rapids."""
    program = runs[0].parent / "p.nc"
    for name, extra in (("whole.csv", []), ("streamed.csv", ["--chunk-blocks", "1"])):
        code, _, _ = run_cli(capsys, "path", program, "-o", tmp_path / name, *extra)
        assert code == 0
    text = (tmp_path / "whole.csv").read_text()
    assert text == (tmp_path / "streamed.csv").read_text()
    assert text.splitlines()[0] == "time_s,x_mm,y_mm,nc_line,rapid"
    cmd = read_command_csv(tmp_path / "whole.csv")
    run = read_run(runs[0])
    assert np.array_equal(cmd.meta["rapid"], run.rapid[:cmd.time_s.size])
    type(run)(run.time_s, run.axes, run.meta).write(bare := tmp_path / "measured.csv")
    code, _, err = run_cli(capsys, "contour", bare, "--plane", "XY",
                           "--command", tmp_path / "whole.csv")
    assert code == 0 and f"G0 rapids left out: {int(run.rapid.sum())} samples" in err


def test_a_command_made_from_a_programs_of_other_samples_has_no_blocks(tmp_path):
    """A command made from a program's (compensation holds it longer at the end) keeps
    its meta; the blocks of the program's samples are not its own, and are not written."""
    from tcpmm.path import Command, write_command_csv

    cmd = program_to_command("G21 G90\nG1 X5 F3000\nG0 Y5\nM30\n")
    assert cmd.blocks() is not None
    t = cmd.time_s[0] + np.arange(cmd.time_s.size + 3) * cmd.period_s
    held = Command(t, {a: np.concatenate([p, np.full(3, p[-1])])
                       for a, p in cmd.positions.items()}, dict(cmd.meta))
    assert held.blocks() is None
    write_command_csv(held, path := tmp_path / "held.csv")
    assert path.read_text().splitlines()[0] == "time_s,x_mm,y_mm"


def test_the_samples_near_a_rapid_do_not_depend_on_the_chunks():
    """Rapids of a path with rests, each reaching the samples within the span of path
    length of it: the same intervals from the command whole and in chunks of every size,
    and those of their definition."""
    from tcpmm.analysis.rapids import RapidStretches

    rng = np.random.default_rng(3)
    step = np.where(rng.random(400) < 0.3, 0.0, rng.uniform(0.0, 2e-4, 400))
    p = np.column_stack([np.cumsum(step), np.zeros(400)])
    s = p[:, 0] - p[0, 0]
    flags = (np.arange(400) // 37 % 3 == 1).astype(np.int8)
    flags[[0, 398, 399]] = 1
    whole = RapidStretches(1e-3)
    whole.add_command(p, flags)
    for rows in range(1, 60):
        got = RapidStretches(1e-3)
        for k in range(0, 400, rows):
            got.add_command(p[k:k + rows], flags[k:k + rows])
        assert got.spans == whole.spans, rows
    near = np.array([whole.near(i) for i in range(400)])
    assert np.array_equal(whole.near_many(np.arange(400)), near)
    assert np.array_equal(whole.near_many(np.arange(400)[::-1]), near[::-1])
    assert not RapidStretches(1e-3).near_many([0, 5]).any()
    air = s[flags == 1]
    want = np.array([np.any(np.abs(air - x) <= 1e-3) for x in s])
    assert np.array_equal(near, want) and 0 < near.sum() < 400


def test_the_plane_is_that_of_the_feed_moves(tmp_path, capsys):
    """A program contouring in XY whose Z moves only in G0 (retract, step over, plunge)
    was measured in 3-D ("Z moves too, so the path is not plane"), its unsigned error
    mostly Z's sag, from the rapids it then left out; the plane is now taken from the feed
    moves, whole and streamed, and from every move with --rapids."""
    prog = tmp_path / "xy.nc"
    prog.write_text("G21 G91 G17\nG0 X5 Y5\nG1 X20 F3000\nG1 Y10\nG1 X-20\nG0 Z5\nG0 Y5\n"
                    "G0 Z-5\nG1 X20 F3000\nG1 Y10\nG0 Z5\nM30\n")
    for out in ("xy.csv", "xy.parquet"):
        assert run_cli(capsys, "simulate", "builtin:vmc", "--gcode", prog,
                       "-o", tmp_path / out)[0] == 0
    for args in (("xy.csv",), ("xy.parquet", "--chunk-rows", "100")):
        code, out, err = run_cli(capsys, "contour", tmp_path / args[0], *args[1:])
        assert code == 0 and "plane XY, taken from" in err, err
        assert "contour error in XY" in out
    code, out, err = run_cli(capsys, "contour", tmp_path / "xy.csv", "--rapids")
    assert code == 0 and "3D (unsigned)" in err
    # the Python function's plane="auto" (its default) as the command line's
    run = read_run(tmp_path / "xy.csv")
    assert contour_error(run).axes == ("X", "Y") and contour_error(run).signed
    assert contour_error(run, rapids=True).axes == ("X", "Y", "Z")


@pytest.mark.parametrize(("program", "plane"), [
    # two squares at two depths, Z moving only in G0 between them
    ("G0 X0 Y0 Z0\nG1 X50 F3000\nY50\nX0\nY0\nG0 Z-10\nG1 X50\nY50\nX0\nY0\n", "XY"),
    # two plunges, X moving only in G0 from one hole to the next
    ("G0 X10 Y10 Z5\nG1 Z-5 F300\nG0 Z5\nG0 X20\nG1 Z-5\nG0 Z5\n", None)])
def test_the_plane_is_that_in_which_the_feed_moves_travel(tmp_path, capsys, program, plane):
    """The plane was taken from the span of the feed samples: Z spans 10 mm over the two
    squares' samples, though no feed move moves it, and the squares read 3-D and unsigned;
    the X of two holes spans 10 mm, though it moves only in G0, and the plunges read as a
    ZX path (57.14 um, where the first hole alone reads 60.57 um in 3-D). The travel is
    now the largest within one feed move, whole and streamed alike."""
    prog = tmp_path / "p.nc"
    prog.write_text("G21 G90 G17\n" + program + "G4 P0.3\nM30\n")
    assert run_cli(capsys, "simulate", "builtin:vmc", "--gcode", prog,
                   "-o", tmp_path / "run.parquet")[0] == 0
    said = (f"plane {plane}, taken from" if plane else "3D (unsigned), taken from")
    got = []
    for extra in ([], ["--chunk-rows", "97"]):
        code, out, err = run_cli(capsys, "contour", tmp_path / "run.parquet", "--json", *extra)
        assert code == 0 and said in err, err
        got.append(json.loads(out)["sensors"])
    for sensor, whole in got[0].items():  # the rms is summed over other pieces
        assert [whole[k] for k in ("max_abs_um", "max_um", "min_um")] == \
            [got[1][sensor][k] for k in ("max_abs_um", "max_um", "min_um")]
        assert whole["rms_um"] == pytest.approx(got[1][sensor]["rms_um"], rel=1e-12)


@pytest.mark.parametrize("seed", range(5))
def test_the_travel_within_feed_moves_does_not_depend_on_the_chunks(seed):
    """MoveTravel fed whole and in chunks cut anywhere, moves running across the cuts,
    against each move's span taken directly."""
    from tcpmm.analysis.rapids import MoveTravel

    rng = np.random.default_rng(seed)
    for _ in range(60):
        n = int(rng.integers(1, 80))
        feed, x = rng.random(n) < 0.6, rng.normal(size=n).cumsum()
        edges = np.flatnonzero(np.diff(np.concatenate([[0], feed.astype(int), [0]])))
        want = max((float(np.ptp(x[a:b])) for a, b in edges.reshape(-1, 2)), default=0.0)
        cuts = np.sort(rng.choice(np.arange(1, n), min(n - 1, int(rng.integers(0, 6))),
                                  replace=False)) if n > 1 else np.zeros(0, int)
        for bounds in ([0, n], [0, *cuts.tolist(), n]):
            m = MoveTravel()
            for a, b in itertools.pairwise(bounds):
                m.add({"X": x[a:b]}, feed[a:b])
            assert m.travel()["X"] == want


def test_the_corners_near_a_rapid_taken_at_once_are_those_taken_one_by_one():
    """Spans that overlap, nest, touch and stand apart: each index near a span by the
    vectorised test as by the one a corner at a time."""
    from tcpmm.analysis.rapids import RapidStretches

    rng = np.random.default_rng(7)
    for _ in range(50):
        st = RapidStretches(1e-3)
        lo = np.sort(rng.integers(0, 300, rng.integers(1, 12)))
        st.spans = [[int(a), int(a + rng.integers(0, 60))] for a in lo]
        idx = rng.integers(-5, 400, 200)
        assert np.array_equal(st.near_many(idx), [st.near(int(i)) for i in idx])


def test_the_lag_a_rapid_carries_into_its_cut_is_measured_from_the_cut(tmp_path):
    """A diagonal G0 to a square's corner, then its first side at F5000: while the tool
    is still on the rapid's line the cut has begun, and the tool lies off the side by the
    rapid's lag. It read its distance to the rapid's line (2.6 um for 287 um off the side
    on a machine of a slower servo than this one's 40 um); it is measured from the side,
    whole and streamed alike."""
    prog = tmp_path / "sq.nc"
    prog.write_text("G21 G17 G90 G64 P0.01\nG0 X-20 Y-20\nG1 X20 Y-20 F5000\n"
                    "G1 X20 Y20\nG4 P0.3\nM30\n")
    for name in ("run.csv", "run.parquet"):
        assert run_cli_plain("simulate", "builtin:vmc", "--gcode", prog, "-o",
                             tmp_path / name) == 0
    run = read_run(tmp_path / "run.csv")
    res = quiet(contour_error, run, plane="XY")
    tcp = np.column_stack([run.axes[a].tcp for a in "XY"])
    cut = (run.rapid == 0) & (run.nc_line == 3) & (tcp[:, 0] > -20.0e-3)
    first = np.flatnonzero(cut)[:5]  # the side's first samples, still on the way
    off = tcp[first, 1] + 20.0e-3  # from the side y = -20 mm, the tool left of it
    assert np.all(np.abs(off) > 20e-6)
    np.testing.assert_allclose(np.abs(res.errors["tcp"][first]), np.abs(off), rtol=1e-9)
    assert res.summary()["tcp"]["max_abs_m"] >= np.max(np.abs(off))
    whole = quiet(contour_error, read_run(tmp_path / "run.parquet"), plane="XY")
    got = stream_contour(tmp_path / "run.parquet", ("X", "Y"), True, rows=97)
    for s, d in whole.summary().items():
        assert got.summary()[s]["max_abs_m"] == d["max_abs_m"]
        assert d["max_abs_m"] == pytest.approx(res.summary()[s]["max_abs_m"], rel=1e-6)


def test_a_tool_lagging_out_of_a_rapid_has_the_side_of_its_feed_move(tmp_path):
    """A G0 along the radius to a circle's start, then the circle CCW: the tool arrives
    some 55 um short, inside the circle, left of the travel (+). The rapid's last step ends
    on the circle's first vertex, was held in the feed move's window, and the tool read
    its side from the rapid's direction: -55 um for +55 um (the run's min), whole and
    streamed alike."""
    prog = tmp_path / "c.nc"
    prog.write_text("G21 G90 G17\nG0 X35 Y0\nG3 X35 Y0 I-35 J0 F3000\nG4 P0.5\nM30\n")
    assert run_cli_plain("simulate", "builtin:vmc", "--gcode", prog, "-o",
                         tmp_path / "run.parquet") == 0
    run = read_run(tmp_path / "run.parquet")
    res = quiet(contour_error, run, plane="XY")
    tcp = np.column_stack([run.axes[a].tcp for a in "XY"])
    inside = 35e-3 - np.hypot(*tcp.T)
    cut = np.flatnonzero(run.rapid == 0)[:10]  # the circle's first samples
    assert np.all(inside[cut] > 40e-6)
    assert np.all(res.errors["tcp"][cut] > 40e-6)
    assert res.summary()["tcp"]["min_m"] > -20e-6  # never 15 um outside it on the circle
    got = stream_contour(tmp_path / "run.parquet", ("X", "Y"), True, rows=97)
    assert got.summary()["tcp"]["min_m"] == res.summary()["tcp"]["min_m"]


def _feed_windows_reference(lo, hi, t_p, t_q, air):
    """The windows of :func:`feed_windows` by the feed move each sample is on, as it finds
    them where some vertex is in a rapid [-]."""
    from tcpmm.analysis.contour_windows import searched_feed_windows

    return searched_feed_windows(lo, hi, t_p, t_q, np.asarray(air) != 0)


@pytest.mark.parametrize("seed", range(4))
def test_windows_of_a_chunk_without_rapids_take_no_search(seed, monkeypatch):
    """A chunk of a run that records its rapids but has none (every chunk of a CAM
    finishing program) is one feed move: its windows are the time windows, the last
    reaching no further than the last segment, with no search of the samples' vertices
    (some 6 ms of every chunk of 200 000 samples); the same windows as the feed moves give,
    windows at the end and empty ones included."""
    from tcpmm.analysis.contour_windows import feed_windows

    rng = np.random.default_rng(seed)
    m, n = 50, 80
    t_p = np.cumsum(rng.uniform(0.5, 1.5, m))
    t_q = np.sort(rng.uniform(t_p[0] - 2, t_p[-1] + 2, n))
    lo = rng.integers(0, m + 1, n)
    hi = np.minimum(lo + rng.integers(-2, 12, n), m)
    air = np.zeros(m, np.int8)
    want = _feed_windows_reference(lo, hi, t_p, t_q, air)
    assert np.any(hi == m) and np.any(lo >= hi)

    def no_search(*args, **kwargs):
        raise AssertionError("searched")

    monkeypatch.setattr(np, "searchsorted", no_search)
    got = feed_windows(lo, hi, t_p, t_q, air)
    monkeypatch.undo()
    for g, w in zip(got, want, strict=True):
        np.testing.assert_array_equal(g, w)
    air[rng.integers(0, m)] = 1  # a rapid: the feed moves as before
    for g, w in zip(feed_windows(lo, hi, t_p, t_q, air),
                    _feed_windows_reference(lo, hi, t_p, t_q, air), strict=True):
        np.testing.assert_array_equal(g, w)
