"""A U-turn of a zig-zag whose step-over is shorter than the corner span is one corner: the
span over which each of its two turns is taken holds the other, so they are one bend at
the finder's resolution. It was reported as two corners of 90-160 deg a few tenths of a
millimetre apart, each settling "until the next corner", which was the other half of the
same U-turn."""

import itertools

import numpy as np
import pytest

from tcpmm.analysis.corners import CornerFinder, find_corners, path_length

SPAN = 0.5e-3


def zigzag(step_m, passes=4, length_m=5e-3, ds=1e-5):
    """A zig-zag of ``passes`` passes along X, ``step_m`` apart in Y, sampled every
    ``ds`` [m]."""
    pts, x, y, d = [(0.0, 0.0)], 0.0, 0.0, 1.0
    for k in range(passes):
        x += d * length_m
        pts.append((x, y))
        if k < passes - 1:
            y += step_m
            pts.append((x, y))
            d = -d
    out = []
    for a, b in itertools.pairwise(pts):
        n = max(round(np.hypot(b[0] - a[0], b[1] - a[1]) / ds), 1)
        t = np.arange(n)[:, None] / n
        out.append(np.asarray(a) + t * (np.asarray(b) - np.asarray(a)))
    return np.vstack([*out, [pts[-1]]])


def in_pieces(p, rows):
    """The corners of ``p`` fed ``rows`` vertices at a time, the polyline trimmed as a
    stream trims it [-]."""
    f, out, off, q, s = CornerFinder(span_m=SPAN), [], 0, None, None
    for a in range(0, len(p), rows):
        piece = p[a:a + rows]
        if q is None:
            q, s = piece, path_length(piece)
        else:
            s = np.concatenate([s, path_length(np.vstack([q[-1:], piece]), s[-1])[1:]])
            q = np.vstack([q, piece])
        final = a + rows >= len(p)
        out += f.step(q, s, off, final)
        if not final:
            k = f.keep(q, s, off)
            q, s, off = q[k - off:], s[k - off:], k
    return out


def same(a, b) -> bool:
    """The same corners, to the bit; the end's NaN turn equal to itself [-]."""
    return len(a) == len(b) and all(
        i == j and (t == u or (t != t and u != u)) for (i, t), (j, u) in zip(a, b, strict=True))


@pytest.mark.parametrize("step_mm", [0.05, 0.1, 0.15, 0.3, 0.5])
def test_a_u_turn_within_the_span_is_one_corner_at_its_middle(step_mm):
    p = zigzag(step_mm * 1e-3)
    corners = find_corners(p, span_m=SPAN)
    assert len(corners) == 4  # three U-turns and the end
    for n, (i, turn) in enumerate(corners[:-1]):
        assert np.degrees(turn) == pytest.approx(180.0, abs=1.0)
        # half-way along the step-over, at the end of the pass it turns from
        assert p[i][0] == pytest.approx(5e-3 if n % 2 == 0 else 0.0, abs=1e-9)
        assert p[i][1] == pytest.approx((n + 0.5) * step_mm * 1e-3, abs=2e-5)
    for rows in (1, 7, 37, 1000):
        assert same(in_pieces(p, rows), corners)


def test_corners_further_apart_than_the_span_stay_two():
    p = zigzag(2e-3)
    corners = find_corners(p, span_m=SPAN)
    assert len(corners) == 7
    assert all(np.degrees(t) == pytest.approx(90.0, abs=1.0) for _, t in corners[:-1])
    assert same(in_pieces(p, 37), corners)


def test_a_square_notch_bottom_turns_by_its_own_180_degrees():
    """A square notch 0.3 mm wide and deep: its bottom's two turns are one bend, whose turn
    was taken over chords reaching past the notch's top corners and read 74 deg; it is the
    down-leg's to the up-leg's, 180 deg."""
    w = 0.3e-3
    pts = [(0.0, 0.0), (10e-3, 0.0), (10e-3, -w), (10e-3 + w, -w), (10e-3 + w, 0.0),
           (20e-3, 0.0)]
    p = np.vstack([np.linspace(a, b, max(round(np.hypot(*np.subtract(b, a)) / 1e-5), 1),
                               endpoint=False) for a, b in itertools.pairwise(pts)]
                  + [[pts[-1]]])
    corners = find_corners(p, span_m=SPAN)
    bottom = [(i, t) for i, t in corners if p[i][1] < -0.5 * w]
    assert len(bottom) == 1
    assert np.degrees(bottom[0][1]) == pytest.approx(180.0, abs=1.0)
    assert same(in_pieces(p, 23), corners)


def test_a_u_turn_on_a_small_arc_is_a_corner():
    """A zig-zag whose passes are joined by G3/G2 arcs of 0.1 mm turns back within the
    span (154 deg over it), but evenly (72 deg over a quarter of it), and had no corner at
    all, where the same U-turn of two G1 moves had one; it is one corner at the arc's apex
    now. An arc of 2 mm radius is still none."""
    import warnings

    from tcpmm.path.program import program_to_command

    def corners_of(r_mm):
        lines = ["G21 G90 G17", "G1 X0 Y0 F3000"]
        for k in range(4):
            x = 20.0 if k % 2 == 0 else 0.0
            y = 2 * r_mm * k
            lines += [f"G1 X{x:.4f} Y{y:.4f}",
                      f"G{3 if k % 2 == 0 else 2} X{x:.4f} Y{y + 2 * r_mm:.4f} R{r_mm}"]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            cmd = program_to_command("\n".join([*lines, "G1 X10", "M30"]) + "\n")
        p = np.c_[cmd.positions["X"], cmd.positions["Y"]]
        return p, find_corners(p, span_m=SPAN)

    p, corners = corners_of(0.1)
    turns = corners[:-1]
    assert len(turns) == 4
    for n, (i, t) in enumerate(turns):  # at the apex, 0.1 mm beyond the pass's end
        assert p[i][0] == pytest.approx(20.1e-3 if n % 2 == 0 else -0.1e-3, abs=2e-6)
        assert np.degrees(t) > 140.0
    assert same(in_pieces(p, 29), corners)
    _, wide = corners_of(2.0)
    assert all(t != t for _, t in wide)  # only the end


def back_and_forth(turns_mm, ds=1e-5, dither=0):
    """A line along Y from 0 turning back at each of ``turns_mm`` in turn, then on to the
    last, sampled every ``ds``; ``dither`` samples of 1 µm back and forth at each turning
    point (a measured command about its stop) [m]."""
    ys, y = [0.0], 0.0
    for t in (v * 1e-3 for v in turns_mm):
        n = max(round(abs(t - y) / ds), 1)
        ys += list(y + (t - y) * np.arange(1, n + 1) / n)
        ys += [t - 1e-6 * np.sign(t - y) * (k % 2) for k in range(1, 2 * dither + 1)]
        y = t
    return np.column_stack([np.full(len(ys), 5e-3), ys, np.zeros(len(ys))])


@pytest.mark.parametrize("turns", [(2.5, 2.2, 3.0), (2.5, 2.0, 3.0), (2.5, 2.1, 3.0)])
@pytest.mark.parametrize("dither", [0, 3])
def test_two_reversals_within_a_span_are_each_at_its_turning_point(turns, dither):
    """Y up to 2.5 mm, back to 2.2 (2.0, 2.1), on to 3: the second reversal was placed at
    Y 2.442, on the way up past it (the vertex furthest from the run's first), and at 0.5
    mm apart the first was left out. Each is at its turning point, also where the command
    dithers by 1 µm about it, whole or fed in pieces. (Within half a span, 0.25 mm, the
    path seen over the span runs straight on: at the finder's resolution, no corner.)"""
    p = back_and_forth(turns, dither=dither)
    for found in (find_corners(p, span_m=SPAN), in_pieces(p, 37)):
        at = [p[i, 1] * 1e3 for i, _ in found if np.isfinite(_)]
        assert at == pytest.approx(list(turns[:2]), abs=2e-3), at
