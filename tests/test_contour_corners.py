"""Corner figures of NC programs on the built-in machine, where the figures of one corner
must not depend on what the program does after it: the dwell that ends it, and the move
that follows the leg. The streamed contour gives each the whole run's to the bit."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from tcpmm.analysis.contour import contour_error
from tcpmm.io.runfile import read_run
from tcpmm.path.program import program_to_command
from tcpmm.sim.simulate import simulate

SENSORS = ("motor", "scale", "tcp")


def same(a: dict, b: dict) -> bool:
    """One sensor's figures at two corners equal to the bit, NaN to NaN."""
    return a.keys() == b.keys() and np.array_equal(list(a.values()), list(b.values()),
                                                   equal_nan=True)


def assert_same_corners(got, want):
    """Every figure of every corner equal to the bit, NaN to NaN."""
    assert len(got) == len(want)
    for g, w in zip(got, want, strict=True):
        for s in SENSORS:
            assert same(g[s], w[s]), (w["number"], s, g[s], w[s])


def corners_of(vmc, tmp_path, lines):
    """The corners of a program run on ``vmc`` (its run file), whole and streamed in
    chunks of 97 rows (which must agree to the bit); those of its G0 rapids counted too."""
    from tcpmm.analysis.contour_stream import stream_contour

    text = "\n".join(["G21 G17 G90", *lines, "M30"]) + "\n"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        path = tmp_path / f"run{len(list(tmp_path.iterdir()))}.parquet"
        simulate(vmc, program_to_command(text)).write(path)
        whole = contour_error(read_run(path), rapids=True)
        streamed = stream_contour(path, whole.axes, whole.signed, rows=97, rapids=True)
    assert_same_corners(streamed.corners, whole.corners)
    return whole.corners


def test_a_corner_and_the_end_do_not_depend_on_the_closing_dwell(vmc, tmp_path):
    """X30 then Y30 at F3000 and a dwell of 0.5 s or 2 s: the motion up to the end point is
    the same, and so must be the corner's figures (its samples end halfway along the
    15 mm leg; a boundary taken halfway to the end of the dwell gave the corner the stop
    at the end point: tcp 213 ms and 1310 ms / 30 mm), and the end's settling counted
    from the command's arrival (scale 98 ms, and 675 ms with the 2 s dwell)."""
    got = {d: corners_of(vmc, tmp_path, ["G0 X0 Y0", "G1 X30 F3000", "Y30", f"G4 P{d}"])
           for d in (0.5, 2.0)}
    short, long = got[0.5], got[2.0]
    assert len(short) == len(long) == 2 and np.isnan(long[1]["turn_rad"])
    for s in SENSORS:
        assert same(short[0][s], long[0][s]), (s, short[0][s], long[0][s])
        assert not long[0][s]["settle_m"] > 0.015  # settled within its half of the leg
    for s in ("motor", "scale"):
        assert long[1][s]["settle_s"] == pytest.approx(short[1][s]["settle_s"], abs=2e-3)
        assert long[1][s]["settle_s"] < 0.15


def test_a_dwell_on_the_next_corner_is_no_part_of_a_corners_stretch(vmc, tmp_path):
    """The same corner with a dwell of 1 s on the next one or none: its figures are the
    same (halfway to the command's leaving the next corner, the stretch took in the stop
    there)."""
    got = [corners_of(vmc, tmp_path, ["G0 X0 Y0", "G1 X30 F3000", "Y30", *dwell, "X0",
                                      "G4 P0.5"]) for dwell in ([], ["G4 P1"])]
    assert len(got[0]) == len(got[1]) == 3
    for s in SENSORS:
        assert same(got[0][0][s], got[1][0][s]), (s, got[0][0][s], got[1][0][s])


def _corner_and_leg(leg: int, ring):
    """A command along X for 1 s, a rest of 0.1 s on the corner, along Y for ``leg``
    samples and a rest of 0.3 s at the end (1 kHz, 50 mm/s), and a run whose every sensor
    is off the command along X by ``ring(u)``, ``u`` the time since the command left the
    corner [m]."""
    from tcpmm.result import AxisRun, Run

    def ramp(n, a, b):
        return a + (b - a) * np.arange(1, n + 1) / n

    x = np.r_[0.0, ramp(1000, 0.0, 0.05), np.full(100 + leg + 300, 0.05)]
    y = np.r_[np.zeros(1101), ramp(leg, 0.0, leg * 5e-5), np.full(300, leg * 5e-5)]
    t = np.arange(x.size) * 1e-3
    u = np.clip(t - t[1100], 0.0, None)
    off = np.where(t > t[1100], ring(u), 0.0)
    sensors = {s: x + off for s in SENSORS}
    run = Run(t, {"X": AxisRun(cmd=x, **sensors), "Y": AxisRun(cmd=y, **dict.fromkeys(
        SENSORS, y))})
    return contour_error(run, plane="XY")


def _on_disk(monkeypatch):
    """Settling stretches kept on disk and read back 7 rows at a time."""
    from tcpmm.analysis import contour_corners, tape

    monkeypatch.setattr(tape, "SPILL_ROWS", 50)
    monkeypatch.setattr(contour_corners, "_BACK_ROWS", 7)


@pytest.mark.parametrize("disk", [False, True])
@pytest.mark.parametrize("leg", [1000, 1004, 1010, 1016])
def test_a_ringing_to_the_end_of_the_stretch_is_not_settled(leg, disk, monkeypatch):
    """A ringing of 3 um at 50 Hz that lasts all along the outgoing leg is not settled in
    a 1 um band, whatever the phase of the stretch's last sample (which fell in the band
    or out of it by chance: settled at 497 ms, or n/a)."""
    if disk:
        _on_disk(monkeypatch)
    res = _corner_and_leg(leg, lambda u: 3e-6 * np.sin(2 * np.pi * 50 * u))
    corner = res.corners[0]["tcp"]
    assert np.isnan(corner["settle_s"]) and np.isnan(corner["settle_m"])


@pytest.mark.parametrize("disk", [False, True])
def test_a_ringing_that_dies_out_settles_at_its_last_exit_from_the_band(disk, monkeypatch):
    """The same ringing decaying with a time constant of 0.1 s: settled from its last
    exit from the 1 um band about 0, before the last quarter of the stretch."""
    def ring(u):
        return 3e-6 * np.exp(-u / 0.1) * np.sin(2 * np.pi * 50 * u)

    if disk:
        _on_disk(monkeypatch)
    res = _corner_and_leg(1000, ring)
    u = np.arange(0, 0.5, 1e-3)
    want = u[np.flatnonzero(np.abs(ring(u)) > 1e-6)[-1] + 1]
    corner = res.corners[0]["tcp"]
    assert corner["settle_s"] == pytest.approx(want, abs=1e-9)
    assert corner["settle_m"] == pytest.approx(want * 0.05, abs=1e-9)


def test_like_corners_of_a_zigzag_settle_alike(vmc, tmp_path):
    """Passes of 50 mm at F3000 a step of 1 mm apart: every corner into a pass has the
    same geometry and speeds, and the tcp rings at the headstock's modes (50 and 35 Hz,
    about 3 um) past the halfway point of the pass; every one is not settled (some read
    524 ms, the halfway point, where the last sample fell in the band)."""
    lines, y = ["G0 X0 Y0", "G1 F3000"], 0
    for i in range(8):
        x = 50 if i % 2 == 0 else 0
        lines += [f"X{x} Y{y}", f"X{x} Y{y + 1}"]
        y += 1
    corners = corners_of(vmc, tmp_path, [*lines, "G4 P0.5"])
    into_pass = corners[1:-1:2]
    assert len(into_pass) == 7
    assert all(np.isnan(c["tcp"]["settle_s"]) for c in into_pass)
    # the scale has settled in each, alike
    scale = [c["scale"]["settle_s"] for c in into_pass]
    assert max(scale) - min(scale) <= 2e-3 and max(scale) < 0.1


@pytest.mark.parametrize("feed", [3000, 6000])
def test_the_sag_across_a_leg_is_no_overshoot_whatever_follows_the_leg(vmc, tmp_path,
                                                                        feed):
    """A plunge along -Z turned to X: the Z head's static sag under its weight is the
    datum its TCP is read from, and what the tcp swings past the corner, about 3.7 um, is
    the same with or without a dwell after the leg, at either feed along it (the sag had
    been taken off only where the ringing had died within 1 um by the stretch's end)."""
    got = []
    for dwell in ([], ["G4 P0.3"]):
        corners = corners_of(vmc, tmp_path, ["G0 X0 Y0 Z5", "G1 Z0 F500",
                                             f"G1 X30 F{feed}", *dwell, "G0 Z5", "G4 P0.5"])
        assert len(corners) == 4
        got.append(corners[1])
    assert same(got[0]["tcp"], got[1]["tcp"]), (got[0]["tcp"], got[1]["tcp"])
    assert 3.0e-6 < got[0]["tcp"]["overshoot_m"] < 4.5e-6


def test_the_corner_caption_says_none_overshoots_where_none_does():
    """A zig-zag of 41 corners none of which overshoots: the caption said "the 20 of
    largest overshoot shown", over a table of 0.00 µm; it says none overshoots and which
    are shown."""
    from tcpmm.cli.contour import CORNER_ROWS, _shown_corners

    flat = [{"tcp": {"overshoot_m": 0.0}} for _ in range(41)]
    shown, caption = _shown_corners(flat, "tcp")
    assert shown == flat[:CORNER_ROWS]
    assert f"none overshoots, the first {CORNER_ROWS} shown" in caption
    some = [{"tcp": {"overshoot_m": 2e-6 if k in (5, 30) else 0.0}} for k in range(41)]
    shown, caption = _shown_corners(some, "tcp")
    assert some[30] in shown and "the 2 that overshoot and the first of the others" in caption
    most = [{"tcp": {"overshoot_m": (k + 1) * 1e-6}} for k in range(41)]
    shown, caption = _shown_corners(most, "tcp")
    assert shown == most[-CORNER_ROWS:] and f"the {CORNER_ROWS} of largest overshoot" in caption
