"""The progress of the controller-side compensation (``tcpmm compensate --controller-out``,
most of a minute on a bench's circle): the core calls ``progress`` as many times as
:func:`controller_steps` announces, whichever guard ends a pulse's characteristic early,
and the command learned with the parameters as many times as :func:`combined_steps` does;
on a terminal one bar is told the sum and filled over both; in a pipe nothing of it is
written, and the output is the same as without a bar."""

from __future__ import annotations

import io
import json
import math
from contextlib import contextmanager

import pytest
from rich.console import Console
from rich.progress import Progress

from conftest import run_cli
from tcpmm.cli import _app
from tcpmm.cli import compensate as cli_compensate
from tcpmm.compensate import combined
from tcpmm.compensate.adaptation import adaptation_steps
from tcpmm.compensate.combined import combined_compensation, combined_steps
from tcpmm.compensate.controller import (
    AxisController,
    controller_compensation,
    controller_steps,
    coulomb_current,
)
from tcpmm.machines.builtin import builtin_machine
from tcpmm.model import AxisUncertainty
from tcpmm.path import write_command_csv
from tcpmm.path.circle import circle_command

R = 0.01  # [m]


def _xy(machine):
    return machine.model_copy(update={"axes": {a: machine.axes[a] for a in ("X", "Y")}})


def _circle():
    return circle_command(R, 5000 / 60e3, turns=1.0, start_angle_rad=math.pi / 4)


def _uncertain(machine):
    """The machine with an uncertainty on X: the characteristic is checked on draws [-]."""
    x = machine.axes["X"]
    return machine.with_axis("X", x.replace(uncertainty=AxisUncertainty(
        mechanics={"M_t": 0.02 * x.mechanics.M_t, "K_t": 0.05 * x.mechanics.K_t})))


def _counted(machine, draws):
    calls = []
    cc = controller_compensation(machine, _circle(), R, adapt_draws=draws,
                                 progress=lambda *a: calls.append(a))
    return cc, calls


@pytest.mark.parametrize("draws", [None, 0, 1])
def test_the_core_calls_progress_as_often_as_it_announces(draws):
    """One call for the figures before, one per axis for its pulse, the characteristic's
    overrides and draws, one for the figures after; each without an argument."""
    m = _uncertain(_xy(builtin_machine()))
    announced = controller_steps(m, _circle(), ("X", "Y"), draws)
    per_axis = 1 + (0 if draws is None else 3 + 5 * (1 + draws))
    assert announced == 2 + 2 * per_axis
    cc, calls = _counted(m, draws)
    assert len(calls) == announced and set(calls) == {()}
    if draws == 0:  # the same parameters and figures as without a progress
        alone = controller_compensation(m, _circle(), R, adapt_draws=draws)
        assert json.dumps(cc.to_dict()) == json.dumps(alone.to_dict())


def test_a_guard_that_ends_the_characteristic_early_still_fills_the_bar():
    """Without friction no pulse is kept: the characteristic is never computed, its steps
    are counted all the same; a model without uncertainty draws no machine."""
    m = _xy(builtin_machine())
    smooth = m.model_copy(update={"axes": {a: x.replace(friction=None)
                                           for a, x in m.axes.items()}})
    assert adaptation_steps(smooth, 6) == 3 + 5  # the model alone at each override
    cc, calls = _counted(smooth, 6)
    assert all(c.pulse_A == 0.0 for c in cc.axes.values())
    assert len(calls) == controller_steps(smooth, _circle(), ("X", "Y"), 6)


def _pulses(machine, share: float):
    """A pulse of ``share`` times each axis's Coulomb current, decaying in 30 ms [-]."""
    return {a: AxisController(share * coulomb_current(machine.axes[a]), 0.03, 0.0, 0.0)
            for a in ("X", "Y")}


@pytest.mark.filterwarnings("ignore::tcpmm.errors.InputWarning")
@pytest.mark.parametrize(("share", "draws"), [(1.0, 0), (1.0, 1), (4.0, 1)])
def test_the_learning_with_the_parameters_calls_progress_as_often_as_it_announces(
        share, draws):
    """Per share of the parameters a call per learning step and axis; with draws also
    one per share of the correction and machine, one per combination of shares judged
    and the rounds of the regions' shares, those a choice leaves out at once; each
    without an argument, and the same compensation as without a progress."""
    m, iterations = _xy(builtin_machine()), 2
    calls, params = [], _pulses(m, share)
    kw = {"iterations": iterations, "n_draws": draws, "radius_m": R}
    comp = combined_compensation(m, _circle(), params, progress=lambda *a: calls.append(a),
                                 **kw)
    learning = 2 * (iterations + 1)
    assert combined_steps(_circle(), iterations, draws) == (
        learning if draws == 0 else 3 * (learning + 5 * (1 + draws) + 5 ** 2) + 12)
    assert len(calls) == combined_steps(_circle(), iterations, draws) and set(calls) == {()}
    alone = combined_compensation(m, _circle(), params, **kw)
    assert json.dumps(comp.to_dict()) == json.dumps(alone.to_dict())


def _cli(tmp_path, *extra):
    src = tmp_path / "circle.csv"
    write_command_csv(_circle(), src)
    return ["compensate", "builtin:vmc", "--command", src, "-o", tmp_path / "c.csv",
            "--draws", "0", "--iterations", "3", "--radius", "10",
            "--controller-out", tmp_path / "ctl.yaml", *extra]


def test_on_a_terminal_the_bar_is_told_its_total_and_filled(tmp_path, capsys, monkeypatch):
    """The bar's total is the core's count of its steps, the tuning's and the learning's
    with its parameters, and it is filled to it, the learning's part while it learns."""
    screen = Console(file=io.StringIO(), force_terminal=True, color_system=None, width=200)

    @contextmanager
    def on_terminal(total, description):
        # the terminal for the bar alone: a command module imported meanwhile would keep
        # this console for the rest of the session
        with monkeypatch.context() as m:
            m.setattr(_app, "console", screen)
            with _app.progress_bar(total, description) as advance:
                yield advance

    monkeypatch.setattr(cli_compensate, "progress_bar", on_terminal)
    seen, add, update = {"advanced": 0, "named": set()}, Progress.add_task, Progress.update

    def add_task(self, description, *args, **kw):
        seen.update(description=description, total=kw.get("total"))
        return add(self, description, *args, **kw)

    def updated(self, task, **kw):
        seen["advanced"] += kw.get("advance") or 0
        seen["named"].add(kw.get("description"))
        return update(self, task, **kw)

    def learning(*args, **kw):
        at = seen["advanced"]
        got = combined_compensation(*args, **kw)
        seen["learning"] = seen["advanced"] - at
        return got

    monkeypatch.setattr(Progress, "add_task", add_task)
    monkeypatch.setattr(Progress, "update", updated)
    monkeypatch.setattr(combined, "combined_compensation", learning)
    code, _, _ = run_cli(capsys, *_cli(tmp_path))
    assert code == 0 and seen["description"] == "controller-side compensation"
    assert seen["learning"] == 2 * (3 + 1)  # --iterations 3, --draws 0, two axes
    assert seen["total"] == seen["advanced"] == 2 + 2 * (1 + 3 + 5) + seen["learning"]
    # the learning's steps say what the bar waits for now
    assert "controller-side compensation: the command learned with the parameters" in seen[
        "named"]
    assert "controller-side compensation" in screen.file.getvalue()  # drawn there


@pytest.mark.parametrize("as_json", [False, True])
def test_in_a_pipe_the_output_is_that_without_a_bar(tmp_path, capsys, monkeypatch, as_json):
    """Nothing of the bar in the text or the JSON, and the same bytes as a run whose
    bar does nothing."""
    extra = ("--json",) if as_json else ()
    got = run_cli(capsys, *_cli(tmp_path, *extra))
    params = (tmp_path / "ctl.yaml").read_bytes()

    @contextmanager
    def no_bar(total, description):
        yield lambda *_: None

    monkeypatch.setattr(cli_compensate, "progress_bar", no_bar)
    assert run_cli(capsys, *_cli(tmp_path, *extra)) == got
    assert (tmp_path / "ctl.yaml").read_bytes() == params
    code, out, err = got
    assert code == 0 and "━" not in out + err and "controller-side compensation:" not in err
    if as_json:
        assert "controller" in json.loads(out)
