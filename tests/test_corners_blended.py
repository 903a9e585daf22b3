"""Corners blended over more of the path than a quarter of the corner span turn as evenly
as a curve there, and are left out of the corners; the finder counts every such place
(``curves``) so that a table without them says so, and a longer span takes them in."""

from __future__ import annotations

import numpy as np
import pytest

from tcpmm.analysis.contour_corners import CornerStream


def rounded_square(side_m: float, radius_m: float, step_m: float = 10e-6) -> np.ndarray:
    """A square's outline, CCW from its lower left corner along a leg, each of its three
    inner corners rounded by an arc of ``radius_m`` (0: sharp), sampled every ``step_m``
    or finer [m]."""
    pts = [np.zeros(2)]
    corners = [(side_m, 0.0), (side_m, side_m), (0.0, side_m)]
    heading = 0.0
    for cx, cy in corners:
        d = np.array([np.cos(heading), np.sin(heading)])
        n = np.array([-d[1], d[0]])
        start = np.array([cx, cy]) - radius_m * d
        pts.append(start)
        if radius_m > 0:
            centre = start + radius_m * n
            a = np.linspace(0.0, np.pi / 2, max(int(radius_m * np.pi / 2 / step_m), 2) + 1)
            pts.extend(centre - radius_m * np.cos(a)[:, None] * n + radius_m
                       * np.sin(a)[:, None] * d)
        heading += np.pi / 2
    pts.append(np.zeros(2))
    out = [pts[0]]
    for p in pts[1:]:  # every leg sampled finely, as a command is
        k = max(int(np.linalg.norm(p - out[-1]) / step_m), 1)
        out.extend(out[-1] + (p - out[-1]) * np.arange(1, k + 1)[:, None] / k)
    return np.array(out)


def corners_and_curves(p, span_m: float = 0.5e-3, piece: int | None = None) -> tuple:
    """The corners' vertices and turns, and the count of curves, of the command ``p``,
    given whole or ``piece`` vertices at a time [-], [rad], [-]."""
    stream = CornerStream(span_m=span_m)
    tc = np.arange(p.shape[0]) * 1e-3
    step = piece or p.shape[0]
    for i in range(0, p.shape[0], step):
        stream.add_command(tc[i:i + step], p[i:i + step])
    rows = stream.finish()
    return [(c["index"], c["turn_rad"]) for c in rows], stream.finder.curves


@pytest.mark.parametrize("piece", [None, 7, 50, 333])
def test_corners_blended_over_a_quarter_span_are_counted_as_curves(piece):
    """A 20 mm square's corners rounded on 0.24 mm (a 90 deg corner under ``G64 P0.1``)
    turn evenly over the 0.5 mm span: no corner but the end, three curves; over a 2 mm
    span they are three corners of about 90 deg and no curve. Sharp corners and corners
    rounded on 0.02 mm are corners at 0.5 mm, and no curve. In pieces as whole."""
    blended = rounded_square(0.02, 0.24e-3)
    found, curves = corners_and_curves(blended, piece=piece)
    assert len(found) == 1 and np.isnan(found[0][1])  # the end alone
    assert curves == 3
    found, curves = corners_and_curves(blended, span_m=2e-3, piece=piece)
    assert curves == 0
    turns = np.degrees([t for _, t in found[:-1]])
    assert turns.size == 3 and np.all(np.abs(turns - 90.0) < 10.0), turns
    for r in (0.0, 0.02e-3):
        found, curves = corners_and_curves(rounded_square(0.02, r), piece=piece)
        assert len(found) == 4 and curves == 0, (r, found)


@pytest.mark.parametrize("radius_m, curves", [(35e-3, 0), (0.6e-3, 1)])
def test_a_circle_is_one_curve_where_it_turns_by_the_least_turn_over_the_span(radius_m,
                                                                             curves):
    """A full circle of R 35 mm turns by 1.6 deg over 0.5 mm: no curve; one of R 0.6 mm by
    48 deg, evenly: one curve all round, and no corner but the end [-]."""
    a = np.linspace(0.0, 2 * np.pi, int(2 * np.pi * radius_m / 10e-6) + 1)
    p = radius_m * np.c_[np.cos(a), np.sin(a)]
    found, got = corners_and_curves(p, piece=41)
    assert got == curves
    assert len(found) == 1 and np.isnan(found[0][1])


def test_the_command_line_says_what_the_corner_table_leaves_out(vmc, tmp_path, capsys):
    """A square under ``G64 P0.1`` run on the built-in machine: ``tcpmm contour`` lists
    the end alone and says that the command turns evenly at three places, naming the
    span that takes them in; with ``--corner-span-mm 2`` the three corners are listed and
    nothing is said; a run streamed in chunks gives the same."""
    import json
    import warnings

    from conftest import run_cli
    from tcpmm.path.program import program_to_command
    from tcpmm.sim.simulate import simulate

    text = ("G21 G17 G90 G64 P0.1\nG0 X0 Y0\nG1 X20 F5000\nY20\nX0\nY0\nG4 P0.5\nM30\n")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        path = tmp_path / "square.parquet"
        simulate(vmc, program_to_command(text)).write(path)
    code, out, err = run_cli(capsys, "contour", path)
    assert code == 0 and "evenly at 3 places" in err and "--corner-span-mm 2 " in err
    got = {}
    for chunks in ([], ["--chunk-rows", "97"]):
        for span in ("0.5", "2"):
            code, out, err = run_cli(capsys, "contour", path, "--json", "--corner-span-mm",
                                     span, *chunks)
            assert code == 0
            got[bool(chunks), span] = json.loads(out)
            assert ("evenly" in err) is (span == "0.5")
    for span in ("0.5", "2"):
        for k in ("corners", "curves"):
            assert got[False, span][k] == got[True, span][k]
    assert got[False, "0.5"]["curves"] == 3 and got[False, "2"]["curves"] == 0
    tcp = [c for c in got[False, "2"]["corners"] if c["sensor"] == "tcp"]
    assert [round(c["turn_deg"] or -1) > 80 for c in tcp] == [True, True, True, False]
