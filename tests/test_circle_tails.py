"""Terms that owe their value to where the reversals' transients are taken to end: fitted
again with 40 deg after each reversal left out instead of 20, a term whose radial size
moves by 0.1 um and 2 % of its own is reported uncertain by at least that much."""

import json
import re

import numpy as np
import pytest

from conftest import bench_path, run_cli
from tcpmm.analysis.circle_tail_terms import LINGER
from tcpmm.analysis.circle_tails import moving_line, moving_terms, radial_size
from tcpmm.analysis.circular import analyse_circle
from tcpmm.analysis.diagnostics import circle_diagnostics, diagnose_pair
from tcpmm.io.runfile import read_run
from test_circle_diagnostics import R, W, circle, diagnose, draw


def creeping(direction, err, seed, amp, decay_deg=30.0):
    """A circle whose radius creeps back after every quadrant point, as a slow position
    loop's or a flipping column's tail does: ``amp`` at the point, decaying over
    ``decay_deg`` along the travel [m, deg]."""
    a, e = circle(direction, err, seed)
    s = 1.0 if direction == "ccw" else -1.0
    past = (s * np.degrees(a)) % 90.0
    return a, e - amp * np.exp(-past / decay_deg)


def test_a_tail_past_the_window_makes_the_backlash_uncertain():
    """4 um of backlash X under a 2 um tail that creeps on past the 20 deg the fit leaves
    out read 2.6 um, and nothing said it was not firm. The fit's tail columns take most of
    it (3.75 um); this tail restarts at every quadrant point, unlike theirs, and what is
    left moves the term with 40 deg left out, towards the true value, which the
    diagnostics say, with both values."""
    err = {"b_x": 4e-6, "b_y": 6e-6}
    d = diagnose_pair(creeping("ccw", err, 1, 2e-6), creeping("cw", err, 2, 2e-6), R, (W, W))
    moving = moving_terms(d)
    assert "backlash_X" in moving
    now, wider = moving["backlash_X"]
    assert now == d["backlash_X"] and abs(wider - 4e-6) < abs(now - 4e-6)
    line = moving_line(d)
    assert f"backlash X {now * 1e6:.2f} -> {wider * 1e6:.2f} µm" in line
    assert d.to_dict()["tail_shift"]["backlash_X"] == pytest.approx(wider - now)


@pytest.mark.parametrize("seed", range(4))
def test_no_term_moves_on_circles_without_a_tail(seed):
    """Every error at once, drawn at random, with noise and no transient past the
    window: no term moves with it."""
    d = diagnose(draw(np.random.default_rng(seed)))
    assert moving_terms(d) == {} and moving_line(d) == ""
    assert set(d.tail_shift) >= {"backlash_X", "scale_mismatch", "centre_offset_Y"}


def test_radial_size_of_an_ellipse_is_half_its_axes_difference():
    """A squareness, scale or servo mismatch of ``v`` makes an ellipse of radial half
    amplitude ``R v / 2``; a length is its own; a time has none."""
    assert radial_size("scale_mismatch", -2e-4, 0.035) == pytest.approx(3.5e-6)
    assert radial_size("squareness_or_servo", 1e-4, 0.05) == pytest.approx(2.5e-6)
    assert radial_size("backlash_Y", -3e-6, 0.035) == 3e-6
    assert np.isnan(radial_size("servo_mismatch", 1e-3, 0.035))


def _pair(machine, fast):
    d = bench_path(machine)
    return [d / f"circle_{w}{fast}_meas.csv" for w in ("ccw", "cw")]


def test_an_independent_machines_tails_are_told_from_a_firm_circle(capsys):
    """Bench C at F10000 (a column that flips with the friction and rings at 31 Hz) read
    backlash Y 14.8 um with nothing to say it is 21.8 um with 40 deg left out. Bench D at
    F5000 reads backlash X 1.99 and Y 3.10 um, where its truth has no play: its transient
    lasts past the window (a step fits the samples past it as well as any tail), and the
    backlash is uncertain by more than its value, no squareness or centre at all. tcpmm
    circle prints the terms that move, --json each term's change."""
    res = [analyse_circle(read_run(f), 0.035) for f in _pair("c", "_fast")]
    moving = moving_terms(circle_diagnostics(*res, sensor="tcp"))
    assert moving["backlash_Y"][1] - moving["backlash_Y"][0] > 5e-6
    res = [analyse_circle(read_run(f), 0.035) for f in _pair("d", "")]
    d = circle_diagnostics(*res, sensor="tcp")
    moving = moving_terms(d)
    assert d.undetermined["reversal_tail_decay"].startswith(LINGER)
    assert all(abs(moving[f"backlash_{a}"][1] - d[f"backlash_{a}"]) > d[f"backlash_{a}"]
               for a in "XY")
    assert not {"squareness", "centre_offset_X"} & set(moving)
    code, out, _ = run_cli(capsys, "circle", *_pair("c", "_fast"), "--radius", 35)
    moved = re.search(r"uncertain by the reversals' tails: .*backlash Y "
                      r"(1\d\.\d\d) -> (2\d\.\d\d) µm", out)
    assert code == 0 and moved
    # the ranking marks them, and says what the mark means
    ranked = {line.split()[1] + " " + line.split()[2]: line for line in out.splitlines()
              if line.strip()[:1].isdigit() and len(line.split()) > 3}
    assert "backlash Y ~" in ranked["backlash Y"] and "~" not in ranked["lateral play"]
    assert "~: uncertain by the reversals' tails" in out
    code, out, _ = run_cli(capsys, "circle", *_pair("d", ""), "--radius", 35)
    ranked = {line.split()[1] + " " + line.split()[2]: line for line in out.splitlines()
              if line.strip()[:1].isdigit() and len(line.split()) > 3}
    # its transient lasts past the window: the scale mismatch moves with it, the play not
    assert code == 0 and "~" not in ranked["lateral play"]
    code, out, _ = run_cli(capsys, "circle", *_pair("c", "_fast"), "--radius", 35, "--json")
    terms = {t["term"]: t for t in json.loads(out)["diagnostics"]["terms"]}
    # the move the text gives, to its digits
    assert terms["backlash_Y"]["tail_shift"] == pytest.approx(
        float(moved[2]) - float(moved[1]), abs=0.011)
    assert terms["hysteresis"]["tail_shift"] is None
    # the flag itself, for a program reading --json
    assert terms["backlash_Y"]["uncertain_by_tails"] is True
    assert terms["lateral_play_X"]["uncertain_by_tails"] is False


def test_a_tail_longer_than_the_wider_window_is_flagged_by_what_it_moves():
    """A 2 um tail decaying over 60 deg, longer than both windows and than the longest
    tail searched: 4 um of backlash X read 2.64 um, moving by only 0.38 um with 40 deg left
    out. The transient lasts past the window, and the term is flagged by a move larger
    than its error, and the line says a longer transient moves it further still."""
    err = {"b_x": 4e-6, "b_y": 6e-6, "eps_x": 50e-6}
    d = diagnose_pair(creeping("ccw", err, 1, 2e-6, 60.0), creeping("cw", err, 2, 2e-6, 60.0),
                      R, (W, W))
    now, wider = moving_terms(d)["backlash_X"]
    assert d.undetermined["reversal_tail_decay"].startswith(LINGER)
    assert abs(wider - now) > abs(now - 4e-6)
    assert "moves them further still" in moving_line(d)


@pytest.mark.parametrize("lo, bow", [(-20.0, "str_y"), (70.0, "str_x"), (160.0, "str_y")])
def test_a_bow_the_arcs_determine_does_not_move_with_the_window(lo, bow):
    """220 deg arcs with the errors of a ballbar test and a bow of 2.3 um on the axis whose
    bow they determine: no transient, and no term moves with the window. The wider window
    used to leave the bow out, and the terms that share its shape took it over (a
    squareness of 44 um/m, a centre of 2.3 um), read as a transient past the window."""
    from test_circle_diagnostics import ARC_ERR, arc

    blind = "x" if bow == "str_y" else "y"
    err = {k: v for k, v in ARC_ERR.items() if k not in (f"p_{blind}", f"str_{blind}")}
    err[bow] = -2.3e-6
    d = diagnose_pair(arc("ccw", err, lo, 220, 1), arc("cw", err, lo, 220, 2), R, (W, W))
    assert moving_terms(d) == {} and moving_line(d) == ""
    assert d[f"straightness_{bow[-1].upper()}"] == pytest.approx(-2.3e-6, abs=0.1e-6)
    assert set(d.tail_shift) >= {"backlash_X", "squareness", "centre_offset_Y"}


def test_a_bow_the_arcs_cannot_determine_is_named_with_what_moves():
    """A bow of X over arcs from -20 deg, which they cannot tell from a centre and
    backlash: those terms depend on the window, and the line names the bow as a cause."""
    from test_circle_diagnostics import arc

    err = {"str_x": -2.3e-6}
    d = diagnose_pair(arc("ccw", err, -20.0, 220, 1), arc("cw", err, -20.0, 220, 2), R,
                      (W, W))
    assert "backlash_X" in moving_terms(d)
    assert moving_line(d).endswith("or an error the circles do not determine (lateral play "
                                   "X, straightness X) does")
