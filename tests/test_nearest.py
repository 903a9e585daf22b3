"""The compiled closest-segment search gives the contour error and its foot of measuring
every segment of the window in numpy, to the bit: on spirals, zig-zags, sharp corners,
arcs, paths that cross or come back on themselves, exact ties on a grid, resting
segments, one to seven axes and windows of any width."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tcpmm._rows import dot_rows as _dot
from tcpmm.analysis.contour import distance_to_polyline
from tcpmm.analysis.contour_windows import chord_sags, over_rests, whole_windows


def whole_window(q, p, t_q, t_p, window_s, signed):
    """:func:`distance_to_polyline` with every segment of each window measured."""
    seg = np.diff(p, axis=0)
    ln2 = _dot(seg, seg)
    moving = np.flatnonzero(ln2 > 0)
    nxt = moving[np.minimum(np.searchsorted(moving, np.arange(p.shape[0] - 1)),
                            moving.size - 1)]
    tdir = seg[nxt] / np.sqrt(ln2[nxt])[:, None]
    sag = chord_sags(seg, ln2, tdir)
    lo = np.searchsorted(t_p, t_q - window_s, side="left")
    hi = np.searchsorted(t_p, t_q + window_s, side="right")
    lo, hi = over_rests(lo, hi, t_p, t_q, ln2 > 0, window_s)  # no change without rests
    return whole_windows(q, p, seg, ln2, tdir, sag, np.sqrt(ln2), lo, hi, signed, t_q, t_p)


def same_to_the_bit(q, p, t_q, t_p, window_s, signed):
    fast = distance_to_polyline(q, p, t_q, t_p, window_s, signed)
    ref = whole_window(q, p, t_q, t_p, window_s, signed)
    np.testing.assert_array_equal(fast[0].view(np.int64), ref[0].view(np.int64))
    np.testing.assert_array_equal(fast[1], ref[1])


def shape(kind, n, rng):
    """Command vertices of a kind of path [m]."""
    s = np.linspace(0.0, 1.0, n)
    th = 2 * np.pi * s
    if kind == "spiral":
        return np.c_[(1e-3 + 0.01 * s) * np.cos(10 * th), (1e-3 + 0.01 * s) * np.sin(10 * th)]
    if kind == "figure_eight":
        return 0.01 * np.c_[np.sin(2 * th), np.sin(2 * th) * np.cos(2 * th)]
    if kind == "zigzag":
        return np.c_[np.abs((20 * s) % 2 - 1) * 0.01, s * 1e-3]
    if kind == "square":
        return np.round(0.01 * np.c_[np.clip(2 * np.sin(3 * th), -1, 1),
                                     np.clip(2 * np.cos(3 * th), -1, 1)], 6)
    if kind == "arc_back":  # out along an arc and back along the same arc
        a = np.pi * (1 - np.abs(2 * s - 1))
        return 0.01 * np.c_[np.cos(a), np.sin(a)]
    if kind == "grid_3d":  # exact ties on shared vertices, resting segments
        return np.cumsum(np.round(rng.normal(size=(n, 3)) * 2) * 1e-4, axis=0)
    return np.cumsum(rng.normal(size=(n, int(rng.integers(1, 8)))) * 1e-4, axis=0)


@pytest.mark.parametrize("kind", ["spiral", "figure_eight", "zigzag", "square", "arc_back",
                                  "grid_3d", "walk"])
@pytest.mark.parametrize("window_s", [0.002, 0.2, 5.0])
def test_the_same_as_every_segment_of_the_window(kind, window_s):
    rng = np.random.default_rng(len(kind))
    # 5 s spans the whole path (0.6 s), 0.2 s some 400 of its 1500 segments; the reference
    # it is held to measures every segment of the window, n^2 of them
    p = shape(kind, 600 if window_s > 1.0 else 1500, rng)
    t = np.arange(p.shape[0]) * 1e-3
    for scale in (0.0, 1e-7, 1e-5, 3e-3):  # on the path, near, on a neighbouring pass
        q = p + rng.normal(size=p.shape) * scale
        same_to_the_bit(q, p, t, t, window_s, p.shape[1] == 2)
        same_to_the_bit(np.round(q, 6), p, t, t, window_s, False)


@settings(max_examples=150, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(2, 400), nq=st.integers(1, 300),
       d=st.integers(1, 7), grid=st.booleans(), window_s=st.sampled_from([1e-4, 0.01, 0.1, 9.0]))
def test_random_paths_and_windows(seed, n, nq, d, grid, window_s):
    """Points near random vertices, at times off the command's, some before and after it."""
    rng = np.random.default_rng(seed)
    p = rng.normal(size=(n, d)) * 1e-2
    if grid:
        p = np.round(p * 1e3) * 1e-3
    if np.all(p[1:] == p[:-1]):
        p[-1] += 1e-3
    at = np.sort(rng.integers(0, n, nq))
    q = p[at] + (np.round(rng.normal(size=(nq, d))) * 1e-4 if grid else
                 rng.normal(size=(nq, d)) * 10.0 ** rng.uniform(-8, -2))
    t_p = np.arange(n) * 1e-2
    t_q = np.sort(at * 1e-2 + rng.normal(size=nq) * 0.05)
    same_to_the_bit(q, p, t_q, t_p, window_s, d == 2 and seed % 2 == 0)


def test_points_not_finite_are_measured_in_numpy():
    p = np.c_[np.linspace(0, 1e-2, 50), np.zeros(50)]
    q = p + 1e-6
    q[7, 0] = np.nan
    t = np.arange(50) * 1e-3
    same_to_the_bit(q, p, t, t, 0.01, True)
    assert np.isnan(distance_to_polyline(q, p, t, t, 0.01, True)[0][7])


@pytest.mark.parametrize("cores", [2, 3])
def test_paths_searched_in_threads_give_each_path_alone(cores, monkeypatch):
    """A run's three paths, together long enough to be searched in threads
    (``_THREADED``), each cut into as many runs of points as there are cores, each the
    same to the bit as that path searched alone in one piece; a path that is not finite
    goes to numpy beside them."""
    from tcpmm.analysis import contour_search
    from tcpmm.analysis.contour import distances_to_polyline
    from tcpmm.analysis.contour_search import _THREADED

    monkeypatch.setattr(contour_search, "usable_cores", lambda: cores)

    rng = np.random.default_rng(3)
    p = shape("spiral", 12_000, rng)
    t = np.arange(p.shape[0]) * 1e-3
    qs = {s: p + rng.normal(size=p.shape) * 10.0 ** -e for s, e in
          (("motor", 6), ("scale", 5), ("tcp", 4))}
    qs["bad"] = qs["tcp"].copy()
    qs["bad"][5, 1] = np.inf
    assert sum(q.shape[0] for q in qs.values()) >= _THREADED
    together = distances_to_polyline(qs, p, t, t, 0.2, True)
    assert list(together) == list(qs)
    for name, q in qs.items():
        alone = distance_to_polyline(q, p, t, t, 0.2, True)
        np.testing.assert_array_equal(together[name][0].view(np.int64),
                                      alone[0].view(np.int64))
        np.testing.assert_array_equal(together[name][1], alone[1])


def test_the_blocks_are_worked_out_once_for_every_path_and_thread(monkeypatch):
    """The command's blocks and boxes depend on the command alone: a chunk's three paths
    in two threads each take them from one call of ``search_blocks`` (they were worked
    out in each of the six searches), and each path's distances and feet are those of
    ``nearest_segments``, which works them out itself, to the bit."""
    from tcpmm import _compiled
    from tcpmm.analysis import contour_search
    from tcpmm.analysis.contour import distances_to_polyline
    from tcpmm.analysis.contour_distance import polyline

    monkeypatch.setattr(contour_search, "usable_cores", lambda: 2)
    calls = []
    blocks = _compiled.search_blocks
    monkeypatch.setattr(_compiled, "search_blocks", lambda *a: calls.append(1) or blocks(*a))
    rng = np.random.default_rng(5)
    p = shape("zigzag", 9_000, rng)
    t = np.arange(p.shape[0]) * 1e-3
    qs = {s: p + rng.normal(size=p.shape) * 10.0 ** -e for s, e in
          (("motor", 6), ("scale", 5), ("tcp", 4))}
    together = distances_to_polyline(qs, p, t, t, 0.2, True)
    assert len(calls) == 1
    seg, ln2, tdir, _, sag, seglen = polyline(p)
    lo = np.searchsorted(t, t - 0.2, side="left")
    hi = np.searchsorted(t, t + 0.2, side="right")
    for name, q in qs.items():
        alone = _compiled.nearest_segments(q, p, seg, ln2, tdir, sag, seglen, lo, hi, 1, t, t)
        np.testing.assert_array_equal(together[name][0].view(np.int64),
                                      alone[0].view(np.int64))
        np.testing.assert_array_equal(together[name][1], alone[1])


def _to_chords(x, start, chord):
    """Distance of points ``x`` (one per block) to each block's chord, in numpy [m]."""
    c2 = np.sum(chord * chord, axis=1)
    f = np.clip(np.divide(np.sum((x - start) * chord, axis=1), c2, out=np.zeros_like(c2),
                          where=c2 > 0), 0.0, 1.0)
    return np.sqrt(np.sum((x - start - f[:, None] * chord) ** 2, axis=1))


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(2, 60), st.integers(1, 7),
       st.sampled_from([1, 3, 8]))
def test_a_blocks_capsule_holds_its_segments(seed, n, d, block):
    """Every point of a block's segments (its vertices, and points along each segment)
    lies within the block's slack of its chord; the path length bounds the block's."""
    from tcpmm.path.nearest import block_capsules

    rng = np.random.default_rng(seed)
    p = np.cumsum(rng.normal(size=(n, d)) * 10.0 ** rng.uniform(-6, 0), axis=0)
    start, chord, _, slack, length = block_capsules(p, block)
    for i in range(n - 1):  # segment i lies in block i // block
        b = i // block
        for f in np.linspace(0.0, 1.0, 9):
            x = p[i] + f * (p[i + 1] - p[i])
            assert _to_chords(x[None, :], start[b:b + 1], chord[b:b + 1])[0] <= slack[b]
    for b in range(start.shape[0]):
        seg = np.diff(p[b * block:min(b * block + block, n - 1) + 1], axis=0)
        assert length[b] >= np.sum(np.sqrt(np.sum(seg * seg, axis=1)))


def test_a_straight_blocks_capsule_is_its_chord():
    """A straight pass's capsule is its chord (slack of rounding only), so a pass beside it
    0.05 mm away lies outside it; the corner's block holds the corner."""
    from tcpmm.path.nearest import block_capsules

    x = np.arange(0.0, 2e-3 + 1e-9, 2.5e-5)  # 2 mm in 0.025 mm steps along X
    p = np.r_[np.c_[x, np.zeros_like(x)], np.c_[x[::-1], np.full_like(x, 5e-5)]]
    slack = block_capsules(p, 8)[3]
    assert np.all(slack[:9] < 1e-12)  # the first pass's blocks
    # the turn's block: from (2, 0) mm up 0.05 mm and back 0.175 mm; the turn's outer
    # vertex lies furthest from that chord
    assert slack[10] == pytest.approx(0.05 * 0.175 / np.hypot(0.05, 0.175) * 1e-3, rel=1e-6)


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(2, 90), st.integers(1, 5), st.sampled_from([1, 3, 8]),
       st.sampled_from([1, 2, 4]))
def test_a_box_holds_its_blocks_segments(seed, n, d, block, per):
    """Every point of the segments of a box's blocks (its vertices, and points along each
    segment) lies within the box, in the first two coordinates; a path of one coordinate
    has no boxes."""
    from tcpmm.path.nearest import _box_far, block_boxes

    rng = np.random.default_rng(seed)
    p = np.cumsum(rng.normal(size=(n, d)) * 10.0 ** rng.uniform(-6, 0), axis=0)
    boxes = block_boxes(p, block, per)
    if d < 2:
        assert boxes[3].size == 0
        return
    for i in range(n - 1):  # segment i lies in box i // (block * per)
        for f in np.linspace(0.0, 1.0, 9):
            x = (p[i] + f * (p[i + 1] - p[i]))[None, :]
            assert _box_far(x, 0, *boxes, i // (block * per), 0.0) <= 0.0


def test_a_box_passes_over_the_next_pass_of_a_zigzag_at_any_angle():
    """A box of a zig-zag's pass, or of the U-turn between two, is as narrow as the passes
    lie apart, turned as they run: a point 0.1 mm beyond the second pass lies 0.05 mm and
    more outside every box at any angle."""
    from tcpmm.path.nearest import _box_far, block_boxes

    x = np.arange(0.0, 2e-3 + 1e-9, 2.5e-5)  # 2 mm in 0.025 mm steps
    p = np.r_[np.c_[x, np.zeros_like(x)], np.c_[x[::-1], np.full_like(x, 5e-5)]]
    for deg in (0.0, 30.0, 45.0):
        th = np.radians(deg)
        rot = np.array([[np.cos(th), -np.sin(th)], [np.sin(th), np.cos(th)]])
        boxes = block_boxes(p @ rot.T, 8, 4)
        far = (np.array([[1e-3, 1.5e-4]]) @ rot.T)  # 0.1 mm beyond the second pass
        for sb in range(boxes[3].size):
            assert _box_far(far, 0, *boxes, sb, 0.0) >= 0.05e-3 * (1 - 1e-6)


def test_a_tool_still_on_its_way_while_the_command_dwells_is_on_the_path():
    """The command runs along X to a corner and dwells there 0.5 s; the tool creeps on
    along the same line, 30 um short at the dwell's start, with a time constant of 0.15 s.
    Against the command within 0.2 s of it, the tool was measured against the corner alone
    once the leg was 0.2 s past: its lag along the path (8 um) read as contour error, and
    tcpmm compensate learned to overshoot the corner for it. The window reaches over the
    rest to 0.2 s of the command's motion: the tool is on the path, its error 0."""
    dt, v = 1e-3, 0.05
    t = np.arange(0.0, 1.0 + dt / 2, dt)
    x = np.minimum(v * t, 0.02)  # 0.4 s of motion, then the dwell at 20 mm
    p = np.c_[x, np.zeros_like(x)]
    creep = np.where(t > 0.4, 30e-6 * np.exp(-(t - 0.4) / 0.15), 0.0)
    q = np.c_[x - creep, np.zeros_like(x)]
    d, _ = distance_to_polyline(q, p, t, t, 0.2, True)
    assert np.max(np.abs(d)) < 1e-12
    same_to_the_bit(q, p, t, t, 0.2, True)


def test_the_reference_ties_as_the_compiled_search_does():
    """The numpy reference keeps its own copy of the tie's tolerances."""
    from tcpmm.analysis import contour_windows
    from tcpmm.path import nearest

    assert (contour_windows.NEAR_REL, contour_windows.NEAR_ABS) == (nearest.NEAR_REL,
                                                                    nearest.NEAR_ABS)


def test_a_chords_sag_on_an_arc_and_in_pieces():
    """On an arc of radius R sampled every L the sag is L^2 / 8R (to the small angle's
    order); a straight line has none; a piece of the path given the direction into it has
    the whole path's sags."""
    from tcpmm.analysis.contour_windows import travel

    R, L = 2e-3, 50e-6
    th = np.arange(200) * L / R
    p = R * np.c_[np.cos(th), np.sin(th)]
    seg, ln2, tdir, _ = travel(p)
    sag = chord_sags(seg, ln2, tdir)
    np.testing.assert_allclose(sag[1:-1], L**2 / (8 * R), rtol=1e-3)
    line = np.c_[np.linspace(0, 1e-3, 50), np.linspace(0, 2e-3, 50)]
    assert not np.any(chord_sags(*travel(line)[:3]))  # nor the rounding of its direction
    for cut in (1, 7, 120):
        seg2, ln22, tdir2, _ = travel(p[cut:])
        np.testing.assert_array_equal(chord_sags(seg2, ln22, tdir2, tdir[cut - 1]), sag[cut:])
        seg3, ln23, tdir3, _ = travel(p[:cut + 1])
        np.testing.assert_array_equal(chord_sags(seg3, ln23, tdir3, None, tdir[cut]),
                                      sag[:cut])
