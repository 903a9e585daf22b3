"""Backlash taken up as a dead band: the table stands at a reversal until the motor has
crossed the play, so the lost motion goes from one side to the other over the backlash's
own travel after it, not at once. The reversal spikes after the terms must read the
transient alone whichever way the play is taken up, and the take-up's width is reported
(docs/circle_diagnostics.md, "Model").

The circles are those of ``test_circle_diagnostics`` (each error injected as the position
error it is), with each axis' backlash applied as a dead band on its own position.
"""

from pathlib import Path

import numpy as np
import pytest

from tcpmm.analysis.circular import analyse_circle
from tcpmm.analysis.diagnostics import circle_diagnostics, diagnose_pair
from tcpmm.api import as_command, load_model, simulate
from test_circle_diagnostics import (
    ALL,
    DT,
    NOISE,
    START,
    R,
    W,
    assert_recovered,
    circle,
    expected,
)

PROGRAM = Path(__file__).resolve().parents[1] / "examples" / "circle_r35_f5000.nc"


def dead_band(pos, b, first):
    """``pos`` seen through a play of ``b``: the table stands until the motor has taken
    it up, and starts with it taken up against the first motion ``first`` (+1, -1) [m]."""
    out = np.empty_like(pos)
    out[0] = pos[0] - first * b / 2
    for i in range(1, pos.size):
        out[i] = min(max(out[i - 1], pos[i] - b / 2), pos[i] + b / 2)
    return out


def dead_band_circle(direction, err, seed=0, noise=NOISE, n=7200, start_deg=START):
    """:func:`test_circle_diagnostics.circle` with the backlashes ``b_x``, ``b_y`` of
    ``err`` taken up as dead bands on each axis' own (lagging) position [rad, m]."""
    s = 1.0 if direction == "ccw" else -1.0
    w = 2 * np.pi / (n * DT)
    rest = {k: v for k, v in err.items() if k not in ("b_x", "b_y")}
    a, e = circle(direction, rest, seed, start_deg=start_deg, noise=noise, n=n)
    th = np.radians(start_deg) + s * w * DT * np.arange(n + 1)
    x, y = (R + e) * np.cos(a), (R + e) * np.sin(a)
    for axis, tau, b in (("x", err.get("tau_x", 0.0), err.get("b_x", 0.0)),
                         ("y", err.get("tau_y", 0.0), err.get("b_y", 0.0))):
        own = th - s * w * tau
        pos = R * np.cos(own) if axis == "x" else R * np.sin(own)
        shift = dead_band(pos, b, np.sign(pos[1] - pos[0])) - pos
        x, y = (x + shift, y) if axis == "x" else (x, y + shift)
    return np.unwrap(np.arctan2(y, x)), np.hypot(x, y) - R


def diagnose_dead_band(err, noise=NOISE, n=7200):
    w = 2 * np.pi / (n * DT)
    return diagnose_pair(dead_band_circle("ccw", err, 1, noise, n),
                         dead_band_circle("cw", err, 2, noise, n), R, (w, w))


def spikes(diag):
    return {(d, q): diag[f"spike_{q}_{d}"] for d in ("ccw", "cw") for q in "ABCD"}


@pytest.mark.parametrize("how", ["dead band", "step"])
def test_backlash_alone_leaves_no_spike_after_the_terms(how):
    """4 and 6 um of backlash and nothing else: as a dead band the table's offset turns
    over 4 and 6 um of travel (0.9 and 1.1 deg after the quadrant points at R 35 mm), and a
    step at the reversal left a dip there that read spikes of -3.6 to -5.9 um; as a step
    it reads none either way. The width reads the backlash's own for the dead band, 0 for
    the step."""
    err = {"b_x": 4e-6, "b_y": 6e-6}
    diag = (diagnose_dead_band(err, noise=0.0) if how == "dead band" else
            diagnose_pair(circle("ccw", err, noise=0.0), circle("cw", err, noise=0.0), R,
                          (W, W)))
    for where, v in spikes(diag).items():
        assert abs(v) < 0.1e-6, (where, v)
    for axis, b in (("X", 4e-6), ("Y", 6e-6)):
        assert diag[f"backlash_{axis}"] == pytest.approx(b, rel=0.02)
        width, u95 = diag[f"take_up_width_{axis}"], 2 * diag.sigma[f"take_up_width_{axis}"]
        want = b if how == "dead band" else 0.0
        assert abs(width - want) <= max(u95, 0.03 * b), (axis, width, u95)
        assert u95 < 0.1 * b
    assert diag.terms["take_up_width_X"][1] == "m"


def test_a_spike_beside_a_dead_band_reads_its_own_height():
    """A 5 um spike 3 deg after every quadrant point beside dead bands of 4 and 6 um and
    0.05 um of noise: the dip of the play taken up after a step read -5.3 um at B where the
    spike is +5 (the dip's extreme is the larger). Tolerance of a spike: 4.5 noise rms,
    the extreme of the noise over its window."""
    spike = {(d, q): (5e-6, 3.0) for d in ("ccw", "cw") for q in "ABCD"}
    err = {"b_x": 4e-6, "b_y": 6e-6, "spikes": spike}
    diag = diagnose_dead_band(err)
    for where, v in spikes(diag).items():
        assert v == pytest.approx(5e-6, abs=4.5 * NOISE), where
    assert diag["backlash_X"] == pytest.approx(4e-6, rel=0.02)
    assert diag["backlash_Y"] == pytest.approx(6e-6, rel=0.02)


@pytest.mark.parametrize("height", [5e-6, -2e-6])
def test_a_transient_after_the_reversals_leaves_the_width_open(height):
    """A spike 3 deg after every quadrant point beside dead bands of 4 and 6 um: the
    transient lies in the samples the take-up is read from and reads as part of it (5 um
    read the widths 1.92 ± 0.07 and 3.51 ± 0.11 um, -2 um 5.73 and 7.65 um). The widths
    are open, saying why; the backlash, read past the window, stands. Without the spike
    they are read (test_backlash_alone_leaves_no_spike_after_the_terms)."""
    spike = {(d, q): (height, 3.0) for d in ("ccw", "cw") for q in "ABCD"}
    diag = diagnose_dead_band({"b_x": 4e-6, "b_y": 6e-6, "spikes": spike})
    for axis, points, b in (("X", "A and C", 4e-6), ("Y", "B and D", 6e-6)):
        assert np.isnan(diag[f"take_up_width_{axis}"])
        said = diag.undetermined[f"take_up_width_{axis}"]
        assert "transient" in said and (points in said or "lasts past the window" in said)
        assert diag[f"backlash_{axis}"] == pytest.approx(b, rel=0.02)


def pulsed_dead_band(direction, err, peak_deg, seed, height=5e-6):
    """:func:`dead_band_circle` with a pulse ``height (u / p) exp(1 - u / p)`` of radial
    error after each quadrant point, ``u`` the angle since it, ``p`` = ``peak_deg``: a
    loop's response that rises from the reversal, through the take-up [rad, m]."""
    a, e = dead_band_circle(direction, err, seed)
    s = 1.0 if direction == "ccw" else -1.0
    for at in (0.0, 90.0, 180.0, 270.0):
        u = (s * (np.degrees(a) - at)) % 360.0 / peak_deg
        e = e + np.where(u * peak_deg < 90.0, height * u * np.exp(1.0 - u), 0.0)
    return a, e


def test_a_spike_within_the_take_up_holds_its_height_in_its_pm():
    """A 5 um pulse peaking 0.5 deg after each point, within the 0.9 and 1.1 deg the dead
    bands of 4 and 6 um take: the take-up took part of it, the spikes read 3.38 to 4.19
    um, their ±95% 0.19 um, though the widths were left open beside the transient. The
    spikes are read with the width that fits best; a width left open now widens their ±
    over every width it may be, as where the search itself leaves it open."""
    err = {"b_x": 4e-6, "b_y": 6e-6}
    diag = diagnose_pair(pulsed_dead_band("ccw", err, 0.5, 1),
                         pulsed_dead_band("cw", err, 0.5, 2), R, (W, W))
    assert np.isnan(diag["take_up_width_X"]) and np.isnan(diag["take_up_width_Y"])
    for (d, q), v in spikes(diag).items():
        u95 = diag.spike_u95[f"spike_{q}_{d}"]
        assert abs(v - 5e-6) <= u95, (d, q, v, u95)
    assert max(abs(v - 5e-6) for v in spikes(diag).values()) > 0.5e-6  # the case it is


def test_a_wide_dead_band_is_taken_up_at_the_axes_own_angle():
    """Dead bands of 100 and 60 um and nothing else. The circle is read at the tool's
    angle, which Y's lost motion turns from X's own by 30 um / R at A; X's travel, read
    there, ran 0.5 um off within the take-up: the widths read 97.1 and 56.2 um, and the
    rest read spikes of 0.45 to 0.74 um, +- 0.2 um, at every point, with none injected.
    The travel is now read at the axes' own angle."""
    diag = diagnose_dead_band({"b_x": 100e-6, "b_y": 60e-6})
    for where, v in spikes(diag).items():
        assert abs(v) <= 4.5 * NOISE, (where, v)
    for axis, b in (("X", 100e-6), ("Y", 60e-6)):
        assert diag[f"backlash_{axis}"] == pytest.approx(b, rel=0.002)
        width, u95 = diag[f"take_up_width_{axis}"], 2 * diag.sigma[f"take_up_width_{axis}"]
        assert abs(width - b) <= u95 < 0.03 * b, (axis, width, u95)


def test_a_bench_whose_transient_lasts_past_the_window_reads_no_width():
    """Bench D at F5000 (no play in its truth): at the TCP a transient lasts past the
    window, through the samples the take-up is read from, and the widths read 5.14 ± 0.75
    and 7.05 ± 0.65 um for backlashes of 1.99 and 3.10 um. They are open, saying why; the
    backlashes keep their values."""
    from conftest import bench_path
    from tcpmm.io.runfile import read_run

    files = [bench_path("d") / f"circle_{w}_meas.csv" for w in ("ccw", "cw")]
    diag = circle_diagnostics(*[analyse_circle(read_run(f), 0.035) for f in files],
                              sensor="tcp")
    assert diag.tails == "lingers"
    for axis in "XY":
        assert np.isnan(diag[f"take_up_width_{axis}"])
        assert "lasts past the window" in diag.undetermined[f"take_up_width_{axis}"]
        assert np.isfinite(diag[f"backlash_{axis}"])


def test_one_direction_leaves_its_width_open_beside_a_transient():
    """One direction has no spikes' ±95%: a spike beyond 4.5 times what its fit leaves
    (rms) is a transient, and the width beside it is open; without it the width is the
    dead band's."""
    from tcpmm.analysis.circle_single import diagnose_single

    for height in (0.0, 5e-6):
        spike = {("ccw", q): (height, 3.0) for q in "ABCD"}
        a, e = dead_band_circle("ccw", {"b_x": 4e-6, "b_y": 6e-6, "spikes": spike}, 1, NOISE,
                                7200)
        diag = diagnose_single(a, e, "ccw", R)
        for axis, b in (("X", 4e-6), ("Y", 6e-6)):
            if height:
                assert np.isnan(diag[f"take_up_width_{axis}"])
                assert "transient" in diag.undetermined[f"take_up_width_{axis}"]
            else:
                assert diag[f"take_up_width_{axis}"] == pytest.approx(b, rel=0.03)
            assert diag[f"backlash_{axis}"] == pytest.approx(b, rel=0.02)


@pytest.mark.parametrize("tau_y", [0.0, 1e-3])
def test_every_error_with_dead_band_backlash_is_recovered(tau_y):
    """Every error of ``test_circle_diagnostics.ALL`` at once, the backlash a dead band
    of the same size (a dead band's play is positive) and one spike of 5 um 4 deg after B
    (ALL's, 8-20 um, would hide the dip a step leaves), with and without Y lagging X by
    1 ms: each term within 2 % or 0.1 um of radial error, and each spike within 4.5 noise
    rms of its own (the dip read -5.3 to -7.6 um)."""
    err = dict(ALL, b_x=abs(ALL["b_x"]), b_y=abs(ALL["b_y"]), tau_x=0.0, tau_y=tau_y,
               spikes={("ccw", "B"): (5e-6, 4.0)})
    assert_recovered(diagnose_dead_band(err), expected(err))


def test_a_backlash_in_the_noise_has_no_width():
    """0.02 um of play under 0.05 um of noise: any take-up fits as well, so the width is
    n/a and says why; the spikes after the terms are the noise's."""
    diag = diagnose_dead_band({"b_x": 0.02e-6, "b_y": 0.02e-6})
    for axis in "XY":
        assert np.isnan(diag[f"take_up_width_{axis}"])
        assert "do not tell how its backlash is taken up" in diag.undetermined[
            f"take_up_width_{axis}"]
    assert max(abs(v) for v in spikes(diag).values()) < 4.5 * NOISE


@pytest.mark.filterwarnings("ignore::tcpmm.errors.InputWarning")  # no spike at A, its start
def test_nut_backlash_on_an_encoder_fed_axis_leaves_the_spikes_alone():
    """The built-in machine with X on its motor's encoder, with and without 8 um of play
    in its nut, on the example circle: the backlash term takes the lost motion (8 um more)
    and the spikes after the terms stay the transient's (C read -11.3 um for +6.4 without
    the play, the dip of the play taken up after a step). Its take-up width, read from
    the samples after the reversal that a transient lasting past the window shares, is
    open: it read 10.38 ± 3.10 um, for 10.9 um of lost motion, but on the same kind of
    samples the benches, without play, read 5.14 ± 0.75 to 26.5 ± 1.4 um."""
    base = load_model("builtin:vmc")
    x = base.axes["X"]
    x = x.replace(servo=x.servo.model_copy(update={"position_feedback": "encoder"}))
    diags = {}
    for play in (0.0, 8e-6):
        axis = x.replace(friction=x.friction.model_copy(update={"backlash": play}))
        machine = base.with_axis("X", axis)
        run = simulate(machine, as_command(PROGRAM, machine))
        diags[play] = circle_diagnostics(analyse_circle(run, R), sensor="tcp")
    without, played = diags[0.0], diags[8e-6]
    assert played["backlash_X"] - without["backlash_X"] == pytest.approx(8e-6, rel=0.02)
    for where, v in spikes(played).items():
        if np.isfinite(v):
            assert v == pytest.approx(spikes(without)[where], abs=0.2e-6), where
    # the play's dead band and the screw's own lost motion are taken up as it winds up,
    # into the reversal's transient: the width, read from the samples it shares, is open
    assert np.isnan(played["take_up_width_X"])
    assert "transient" in played.undetermined["take_up_width_X"]


def test_one_direction_reads_its_dead_band_as_backlash_not_as_spikes():
    """One circle alone fits its backlash too: a dead band of 4 and 6 um read spikes of
    -4 and -6 um after its own terms, the whole play."""
    from tcpmm.analysis.circle_single import diagnose_single

    diag = diagnose_single(*dead_band_circle("ccw", {"b_x": 4e-6, "b_y": 6e-6}, 1, 0.0),
                           "ccw", R)
    for q in "ABCD":
        assert abs(diag[f"spike_{q}_ccw"]) < 0.1e-6, q
    assert diag["take_up_width_Y"] == pytest.approx(6e-6, rel=0.03)


#: Started on quadrant point A, half a sample off it: a sample on a reversal has no side
ON_A = 0.5 * np.degrees(W * DT)


def _pair_from(start_deg, err, noise):
    w = 2 * np.pi / (7200 * DT)
    return diagnose_pair(dead_band_circle("ccw", err, 1, noise, start_deg=start_deg),
                         dead_band_circle("cw", err, 2, noise, start_deg=start_deg), R, (w, w))


@pytest.mark.filterwarnings("ignore::tcpmm.errors.InputWarning")  # no spike at A, its start
def test_circles_started_on_a_quadrant_point_take_no_take_up_from_their_start():
    """A G02/G03 circle started at (R, 0): the axis starts from rest at its quadrant point,
    its play taken up before the record, and no reversal happens there. Counted as one,
    its start put X's width at 2.5 um (dead band 4 um) and read spike C -1.18 um
    after the terms where there is none."""
    diag = _pair_from(ON_A, {"b_x": 4e-6, "b_y": 6e-6}, 0.0)
    for axis, b in (("X", 4e-6), ("Y", 6e-6)):
        assert diag[f"take_up_width_{axis}"] == pytest.approx(b, rel=0.03), axis
    assert max(abs(v) for v in spikes(diag).values() if np.isfinite(v)) < 0.1e-6


@pytest.mark.filterwarnings("ignore::tcpmm.errors.InputWarning")
def test_a_take_up_the_reversals_leave_loose_widens_its_spikes():
    """Every error at once with Y lagging X by 1 ms, started on a quadrant point: X's width
    is read from its C reversals alone and comes out loose; the spike at C, which moves
    with it (1.9 um, none injected), carries that in its 95 % uncertainty."""
    err = dict(ALL, b_x=4e-6, b_y=6e-6, tau_x=0.0, tau_y=1e-3, spikes={})
    diag = _pair_from(ON_A, err, NOISE)
    for (d, q), v in spikes(diag).items():
        if np.isfinite(v):
            assert abs(v) <= diag.spike_u95[f"spike_{q}_{d}"] + 4.5 * NOISE, (d, q)


def test_a_backlash_one_direction_cannot_place_has_no_width():
    """One CW direction with Y lagging 1 ms: the ellipse, were it a servo mismatch, moves
    the reversals by a sample and the backlash is left open; its take-up width, which
    read 11.75 +- 1.78 um for a dead band of 6 um, is open with it."""
    from tcpmm.analysis.circle_single import diagnose_single

    err = {"b_x": 4e-6, "b_y": 6e-6, "tau_x": 0.0, "tau_y": 1e-3}
    a, e = dead_band_circle("cw", err, 3, NOISE)
    diag = diagnose_single(a, e, "cw", R)
    for axis in "XY":
        if np.isnan(diag[f"backlash_{axis}"]):
            assert np.isnan(diag[f"take_up_width_{axis}"])
            assert "the backlash it takes up is open" in diag.undetermined[
                f"take_up_width_{axis}"]
