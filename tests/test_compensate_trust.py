"""The compensation's trust sample by sample: no sample is trusted where a machine the
draws span may see its error rise, though its region's largest error falls."""

from __future__ import annotations

import importlib
import json

import numpy as np
import pytest
from scipy.ndimage import maximum_filter1d

from tcpmm.cli import main
from tcpmm.compensate import compensate, machine_bounds, robust_factors
from tcpmm.compensate.cornerguard import CornerGuard
from tcpmm.compensate.headroom import program_with_headroom
from tcpmm.compensate.regional import composed_errors
from tcpmm.compensate.robust import contour, margin
from tcpmm.compensate.trust import RISE_WINDOW_S, local_rises, next_draw
from tcpmm.machines.builtin import builtin_machine
from tcpmm.path import Command

#: A 20 mm circle fed in along X and left along Y after a quarter turn more, as a ballbar
#: test runs it [mm].
CIRCLE = ("G21 G90 G17 G64\nG1 X10 Y0 F5000\nG1 X20 Y0\nG3 X20 Y0 I-20 J0\n"
          "G3 X0 Y20 I-20 J0\nG1 X0 Y21\nM30\n")


@pytest.fixture
def hunting(monkeypatch):
    """A correction learned also where the axes stand still, against the friction that
    holds them: it hunts there, and the model's own error rises after the lead-out's
    corner while every stretch's largest error falls
    (:data:`tcpmm.compensate.learning.REST_TIME_CONSTANTS`)."""
    monkeypatch.setattr(importlib.import_module("tcpmm.compensate.learning"),
                        "REST_TIME_CONSTANTS", np.inf)


def _path(n=1000, T=1e-3):
    t = np.arange(n) * T
    return Command(t, {"X": 1e-2 * t, "Y": np.zeros(n)})


def test_samples_are_not_trusted_where_the_model_itself_rises(hunting):
    """Where the model's own error rises though the largest error of every stretch falls,
    those samples are not trusted, and the rise is recorded."""
    from tcpmm.cli._app import interp_settings

    m = builtin_machine()
    _, cmd = program_with_headroom(CIRCLE, interp_settings(m), 0.25)
    comp = compensate(m, cmd, iterations=10, bounds=machine_bounds(m))
    robust_factors(m, comp, n_draws=3, seed=1)
    zero = {a: np.zeros_like(f) for a, f in comp.factors.items()}
    before = contour(composed_errors([m], comp, zero)[0], comp.target)
    after = contour(composed_errors([m], comp, comp.factors)[0], comp.target)
    env = maximum_filter1d(before, 2 * round(RISE_WINDOW_S / comp.target.period_s) + 1,
                           mode="nearest")
    rises = after > env + margin(env)
    assert rises.any()  # the case this test is about
    assert not (rises & comp.trusted).any()
    rise = comp.robustness["local_rise"]
    assert rise["share"] >= rises.mean() and rise["after_um"] > rise["before_um"]
    assert comp.robustness["trusted_share"] == pytest.approx(np.mean(comp.trusted))


def test_a_peak_moved_within_the_window_is_no_rise_and_a_new_one_is():
    path = _path()
    before = np.zeros((1, 1000))
    before[0, 100] = 10e-6
    after = np.zeros((1, 1000))
    after[0, 110] = 10e-6  # the same peak 10 ms later
    mask, summary = local_rises(before, after, path, margin)
    assert not mask.any() and summary["share"] == 0.0
    after[0, 500] = 1e-6  # where there was nothing
    mask, summary = local_rises(before, after, path, margin)
    assert np.flatnonzero(mask).tolist() == [500]
    assert summary["time_s"] == pytest.approx(0.5)
    assert summary["position_mm"]["X"] == pytest.approx(5.0)
    assert (summary["before_um"], summary["after_um"]) == pytest.approx((0.0, 1.0))


def test_draws_are_held_to_each_other_not_only_each_to_itself():
    """Each draw falls (5 -> 4.5 and 8 -> 7 µm), but a machine whose error before is the
    first's and after the second's rises: the draws cannot rule that out."""
    path = _path(n=200)
    before = np.array([np.full(200, 5e-6), np.full(200, 8e-6)])
    after = np.array([np.full(200, 4.5e-6), np.full(200, 7e-6)])
    assert np.all(after < before)
    mask, summary = local_rises(before, after, path, margin)
    assert mask.all()
    assert (summary["before_um"], summary["after_um"]) == pytest.approx((5.0, 7.0))


def test_next_draw_of_columns_is_that_of_each_column():
    x = np.random.default_rng(3).normal(size=(7, 5))
    assert np.array_equal(next_draw(x), [next_draw(c) for c in x.T])
    assert isinstance(next_draw(x[:, 0]), float)


def test_the_console_and_json_say_where_the_draws_cannot_rule_out_a_rise(tmp_path, capsys,
                                                                        hunting, monkeypatch):
    # the hunting correction also runs the TCP past the lead-out's end, where the corners'
    # guard would hold every share back: the guard off, the rises are what is left to say
    monkeypatch.setattr(CornerGuard, "holds", lambda self, *args: True)
    monkeypatch.setattr(CornerGuard, "rising", lambda self, *args: [])
    # nor is it judged as the circular test it is, whose spikes' guard would hold it too
    monkeypatch.setattr("tcpmm.analysis.circle_find.command_circle", lambda *args: None)
    prog = tmp_path / "circle.nc"
    prog.write_text(CIRCLE)
    args = ["compensate", "builtin:vmc", "--gcode", str(prog), "-o", str(tmp_path / "c.csv"),
            "--draws", "3", "--iterations", "10"]
    assert main(args) == 0
    out = capsys.readouterr().out
    assert "the draws cannot rule out a rise (not trusted)" in out
    assert main([*args, "--json"]) == 0
    rise = json.loads(capsys.readouterr().out)["robustness"]["local_rise"]
    assert 0.0 < rise["share"] < 1.0 and rise["window_s"] == RISE_WINDOW_S


def test_the_draws_measure_a_program_with_a_rapid_as_the_figures_do():
    """The draws measured each sample against the whole path within 0.1 s, a G0 rapid's
    too, where the figures before and after (tcpmm contour) leave the rapid out and
    measure a sample after it from its own feed move: on a rapid then arcs they read
    40.9 um on their worst draw against 57.4 um on the model, and a sample in the rapid
    was named as not trusted. A rapid's samples are 0 and the others are contour's."""
    from tcpmm.analysis.contour import contour_error
    from tcpmm.compensate.robust import contour
    from tcpmm.path import program_to_command
    from tcpmm.result import AxisRun, Run

    target = program_to_command("G21 G90 G17\nG0 X10 Y0\nG3 X0 Y10 I-10 J0 F2000\n"
                                "G2 X-10 Y0 I0 J-10\nG4 P0.3\nM30\n")
    rapid = target.blocks()[1]
    assert rapid.any() and not rapid.all()
    t = target.time_s
    lag = {a: p - np.interp(t - 0.003, t, p) for a, p in target.positions.items()}
    err = np.array([lag[a] for a in target.positions])
    run = Run(t, {a: AxisRun(cmd=p, tcp=p - lag[a]) for a, p in target.positions.items()},
              nc_line=target.blocks()[0], rapid=rapid)
    ours = contour(err, target, window_s=0.2)
    theirs = np.abs(contour_error(run, plane="XY", window_s=0.2).errors["tcp"])
    assert np.all(ours[rapid != 0] == 0.0)
    np.testing.assert_allclose(ours[rapid == 0], theirs[rapid == 0], rtol=1e-9, atol=1e-12)
    assert ours.max() == pytest.approx(theirs[rapid == 0].max(), rel=1e-9)
