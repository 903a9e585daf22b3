"""The corners of a streamed contour kept as columns (:mod:`tcpmm.analysis.corner_rows`):
read back, each is the dict it was, and a CAM program's corners take some 150 bytes each
instead of 1.6 kB."""

import json
import math

import numpy as np
import pytest

from tcpmm.analysis.corner_rows import CornerRows

NAMES = ("motor", "scale", "tcp")


def corner(k: int, fed: bool = True, d: int = 2) -> dict:
    """A corner as the stream gives it, with NaN, -0.0 and the float64 of a tape's
    figures among its values [-]."""
    row = {"number": k + 1, "index": 10 * k + 3, "point_m": [0.001 * k, -0.0, 2.5][:d],
           "turn_rad": math.pi / (k + 1)}
    if fed:
        for j, s in enumerate(NAMES):
            row[s] = {"overshoot_m": 1e-6 * (k + j), "rounding_m": np.float64(2e-6 * k),
                      "settle_s": math.nan if k % 3 else 0.004, "settle_m": -0.0}
    return row


def exact(a, b) -> bool:
    return json.dumps(list(a)) == json.dumps(list(b))


@pytest.mark.parametrize("d", [2, 3])
def test_corners_read_back_as_they_were(d):
    """Packed batches (fed and unfed mixed), a batch of another shape kept as it came:
    iterated, indexed from either end and sliced, the same dicts, keys in order."""
    rows = [corner(k, fed=k % 4 != 1, d=d) for k in range(40)]
    odd = [{**corner(40, d=d), "extra": 1}]
    table = CornerRows()
    table.extend(rows[:25])
    table.extend(odd)
    table.extend(rows[25:])
    want = rows[:25] + odd + rows[25:]
    assert len(table) == len(want) and exact(table, want)
    assert [list(c) for c in table] == [list(c) for c in want]
    assert table[0] == want[0] and table[-1] == want[-1] and table[25] == odd[0]
    assert exact(table[3:30:4], want[3:30:4])
    assert table.indices() == [c["index"] for c in want]
    with pytest.raises(IndexError):
        table[len(want)]


def test_corners_given_as_columns_read_back_as_packed_dicts():
    """Corners added as columns (numbered on from those before) read back as the same
    corners added as dicts; a figure of every corner read as a column, none where a
    corner has none."""
    rows = [corner(k, fed=k % 4 != 1) for k in range(12)]
    table, want = CornerRows(), CornerRows()
    table.extend(rows[:3])
    want.extend(rows)
    rest = rows[3:]
    figs = np.full((len(rest), len(NAMES), 4), np.nan)
    for k, r in enumerate(rest):
        if len(r) > 4:
            figs[k] = [list(r[s].values()) for s in NAMES]
    table.extend_columns([r["index"] for r in rest], [r["point_m"] for r in rest],
                         [r["turn_rad"] for r in rest], [len(r) > 4 for r in rest], figs,
                         NAMES)
    assert exact(table, want) and [list(c) for c in table] == [list(c) for c in want]
    assert table.figure("tcp", "overshoot_m") is None  # unfed corners among them
    fed = CornerRows()
    fed.extend_columns([1, 2], [[0.0, 1.0], [1.0, 2.0]], [0.5, 0.7], [True, True],
                       np.arange(24.0).reshape(2, 3, 4), NAMES)
    assert np.array_equal(fed.figure("scale", "rounding_m"), [5.0, 17.0])


def test_a_selection_keeps_the_corners_asked():
    rows = [corner(k, fed=k % 2 == 0) for k in range(30)]
    table = CornerRows()
    table.extend(rows[:10])
    table.extend(rows[10:])
    keep = [k % 3 != 0 for k in range(30)]
    assert exact(table.kept(keep), [c for c, k in zip(rows, keep, strict=True) if k])


def test_a_streamed_runs_corners_are_kept_as_columns(tmp_path):
    """The corners of a zig-zag of 400 U-turns, streamed: packed, under 300 bytes a
    corner, and the whole run's to the bit."""
    from tcpmm.analysis.contour import contour_error
    from tcpmm.analysis.contour_stream import stream_contour
    from tcpmm.io.runfile import read_run
    from tcpmm.result import AxisRun, Run

    t = np.arange(0.0, 40.0, 1e-3)
    x = 0.002 * np.abs(((t / 0.1) % 2.0) - 1.0)  # passes of 2 mm, 0.1 s each
    y = 5e-5 * np.floor(t / 0.1)
    lag = np.r_[x[:1], x[:-1]]
    run = Run(t, {"X": AxisRun(cmd=x, motor=lag, scale=lag, tcp=lag),
                  "Y": AxisRun(cmd=y, motor=y, scale=y, tcp=y)})
    run.write(path := tmp_path / "zigzag.parquet")
    got = stream_contour(path, ("X", "Y"), True, rows=5000).corners
    assert isinstance(got, CornerRows) and len(got) >= 300
    packed = [p for p in got._parts if isinstance(p, dict)]
    assert sum(len(p["number"]) for p in packed) == len(got)
    size = sum(v.nbytes for p in packed for v in p.values() if isinstance(v, np.ndarray))
    assert size / len(got) < 300
    assert exact(got, contour_error(read_run(path), plane=("X", "Y")).corners)
