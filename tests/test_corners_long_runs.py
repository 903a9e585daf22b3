"""Corners of long runs with many of them (a CAM zig-zag: a corner every few millimetres):
each corner's geometry is looked up around it and takes down only the samples it owns, so
the work grows with the run, not with the run times its corners. The local look-ups give
the numbers of the whole-polyline ones to the bit."""

from __future__ import annotations

import math
from itertools import takewhile

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tcpmm._compiled import call
from tcpmm._rows import dot_rows, norm_rows
from tcpmm.analysis import corners as C
from tcpmm.analysis.contour import contour_error
from tcpmm.analysis.corner_store import CornerStore
from tcpmm.path.program import program_to_command
from tcpmm.sim.simulate import simulate


def _rest_start_whole(p, i):
    moved = np.flatnonzero(np.any(p[:i] != p[i], axis=1))
    return int(moved[-1]) + 1 if moved.size else 0


def _end_back_whole(p, s, first, least):
    """Where the chord into the end of the path starts: ``least``, or where the path
    before the end turns off its last moving segment's direction by more than 1 deg."""
    moved = [j for j in range(first) if not np.array_equal(p[j], p[first])]
    if not moved:
        return s[0]
    u = p[first] - p[moved[-1]]
    u = u / np.sqrt(dot_rows(u[None], u[None])[0])
    k = moved[-1]
    while k > 0 and s[k] > least:
        v = p[k] - p[k - 1]
        if np.any(v != 0.0) and dot_rows((v / np.sqrt(dot_rows(v[None], v[None])[0]))[None],
                                          u[None])[0] < math.cos(math.radians(1.0)):
            break
        k -= 1
    return s[k]


def _first_bend_whole(p, s, j0, t_out, after_m):
    seg = np.diff(p[j0:], axis=0)
    ln = norm_rows(seg)
    bent = (dot_rows(seg, t_out) < np.cos(np.radians(C._STRAIGHT_DEG)) * ln) & (ln > 0)
    bent &= s[j0:-1] > after_m
    k = np.flatnonzero(bent)
    return j0 + int(k[0]) if k.size else None


@st.composite
def polylines(draw):
    """A polyline of straight legs and rests (repeated points), up to a few thousand
    vertices, with legs long enough that blocks of 64 and more are crossed."""
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    pts, at = [np.zeros(2)], np.zeros(2)
    for _ in range(draw(st.integers(1, 12))):
        if rng.random() < 0.3:
            pts += [at.copy()] * int(rng.integers(1, 400))  # a rest
            continue
        step = rng.normal(size=2) * 1e-4
        for _ in range(int(rng.integers(1, 600))):
            at = at + step
            pts.append(at.copy())
    p = np.array(pts)
    return p, C.path_length(p)


@settings(max_examples=60, deadline=None)
@given(polylines(), st.data())
def test_looked_up_around_a_vertex_as_over_the_whole_polyline(ps, data):
    p, s = ps
    i = data.draw(st.integers(0, p.shape[0] - 1))
    assert C.rest_start(p, i) == _rest_start_whole(p, i)
    t_out = np.array([np.cos(data.draw(st.floats(0, 6.3))), 0.0])
    t_out[1] = np.sqrt(1 - t_out[0] ** 2)
    after = float(s[i]) + data.draw(st.floats(0, 1e-3))
    assert C.first_bend(p, s, i, t_out, after) == _first_bend_whole(p, s, i, t_out, after)
    # the compiled frame looks the chord before the end up around it, over the straight
    # stretch before it where that is shorter than the span
    span = data.draw(st.floats(1e-6, 1e-2))
    frame = call("corner_frames", p, s, np.arange(p.shape[0]) * 1e-3, np.array([i]),
                 np.array([np.nan]), span)[0]
    assert frame[0] == _rest_start_whole(p, i)
    x0 = max(s[i] - span, _end_back_whole(p, s, int(frame[0]), s[i] - span))
    v = p[i] - C._at(p, s, np.array([x0]))[0]
    t_in = v / (np.sqrt(dot_rows(v, v)) or 1.0)
    np.testing.assert_array_equal(frame[2:].view(np.int64),
                                  np.concatenate([t_in, t_in]).view(np.int64))


def zigzag(passes: int) -> str:
    """Passes of 2 mm in 0.1 mm blocks, 0.05 mm apart, blended (G64)."""
    lines, x, d = ["G21 G90 G17 G64 P0.01", "G1 X0 Y0 F3000"], 0.0, 1
    for k in range(passes):
        for _ in range(20):
            x += 0.1 * d
            lines.append(f"G1 X{x:.4f}")
        lines.append(f"G1 Y{(k + 1) * 0.05:.4f}")
        d = -d
    return "\n".join([*lines, "M30"]) + "\n"


@pytest.mark.filterwarnings("ignore")
def test_each_corner_takes_down_the_samples_it_owns(vmc, monkeypatch):
    run = simulate(vmc, program_to_command(zigzag(40)))
    rows = []
    add = CornerStore.add
    monkeypatch.setattr(CornerStore, "add", lambda self, g0, cuts, near, rowcut, block,
                        counts: (rows.append(len(block)),
                                 add(self, g0, cuts, near, rowcut, block, counts))[1])
    res = contour_error(run, plane=("X", "Y"))
    assert len(res.corners) >= 40  # the turn at each end of a pass is one corner
    # each sample is in the rows of the corner it settles after (and of the next, where
    # the two meet); taken down by every corner after which it came, the rows held about
    # a sample for each corner before it: some 40 times the run here
    assert rows and sum(rows) < 2 * run.time_s.size


@pytest.mark.filterwarnings("ignore")
def test_a_terminal_lists_the_corners_of_largest_overshoot(vmc, tmp_path, capsys,
                                                           monkeypatch):
    """Thousands of corners are no table to read: the command line lists those of the
    largest overshoots, says how many there are, and leaves them all to --json."""
    from tcpmm.cli import main
    from tcpmm.cli.contour import CORNER_ROWS

    simulate(vmc, program_to_command(zigzag(40))).write(tmp_path / "run.csv")
    assert main(["contour", str(tmp_path / "run.csv"), "--plane", "XY"]) == 0
    out = capsys.readouterr().out
    # the caption is one line in a pipe: a log is grepped for its figures
    assert any(line.startswith("turn: of the command") and "the 20 of largest "
               "overshoot shown (all with --json); overshoot median " in line
               for line in out.splitlines()), out
    # only those become rows: the rows of every corner and sensor of a 10 M-block
    # zig-zag (476 000 corners) took a gigabyte
    from tcpmm.analysis import contour as contour_module

    made, row = [], contour_module._corner_row
    monkeypatch.setattr(contour_module, "_corner_row", lambda *a: made.append(a) or row(*a))
    assert main(["contour", str(tmp_path / "run.csv"), "--plane", "XY"]) == 0
    assert len(made) == CORNER_ROWS and out == capsys.readouterr().out
    table = out[out.index("corners, tcp"):].splitlines()
    head = next(i for i, line in enumerate(table) if line and set(line) <= {"─"})
    rows = takewhile(lambda line: line.split()[0].isdigit(), table[head + 1:])
    assert len(list(rows)) == CORNER_ROWS
    assert main(["contour", str(tmp_path / "run.csv"), "--plane", "XY", "--json"]) == 0
    import json

    rows = json.loads(capsys.readouterr().out)["corners"]
    assert len([r for r in rows if r["sensor"] == "tcp"]) >= 40
