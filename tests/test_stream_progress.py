"""The progress bar of a streamed program (``tcpmm simulate --gcode ... -o RUN.parquet``,
``tcpmm path --chunk-blocks``): it counts the program's lines and says so, comment and
blank lines among them, moves within a chunk as the results come, never back and never
past the file's lines, where it ends; and it changes no byte of what is written."""

from __future__ import annotations

import dataclasses
import io
import warnings

import numpy as np
import pytest
from rich.console import Console
from rich.progress import Progress

from conftest import run_cli
from tcpmm.cli import _stream
from tcpmm.result import AxisRun
from tcpmm.sim import streamrun


def program(moves: int = 40) -> str:
    """Long moves (a thousand samples each) among tape, comment and blank lines."""
    lines = ["%", "(a header: the part, the tool)", "; the set-up", "", "G21 G90",
             "G1 X0 Y0 F1200"]
    for i in range(1, moves + 1):
        lines.append(f"G1 X{20 * (i % 2)} Y{i}")
        lines.append("(the next pass)" if i % 2 else "")
    return "\n".join([*lines, "M30", "%"]) + "\n"


@pytest.fixture
def drawn(monkeypatch):
    """The bar drawn as on a terminal, into a string (``screen``), its total and every
    count it is set to (``done``) recorded."""
    seen = {"done": [], "screen": Console(file=io.StringIO(), force_terminal=True,
                                          color_system=None, width=200)}
    monkeypatch.setattr(_stream, "console", seen["screen"])
    add, update = Progress.add_task, Progress.update

    def add_task(self, description, *args, **kw):
        seen["total"] = kw.get("total")
        return add(self, description, *args, **kw)

    def updated(self, task, **kw):
        if kw.get("completed") is not None:
            seen["done"].append(kw["completed"])
        return update(self, task, **kw)

    monkeypatch.setattr(Progress, "add_task", add_task)
    monkeypatch.setattr(Progress, "update", updated)
    return seen


def _ran(capsys, tmp_path, command: str, chunk: int) -> tuple[int, str]:
    """Lines of the program and stdout, after running ``command`` on it streaming."""
    prog = tmp_path / "p.nc"
    prog.write_text(program())
    args = (["simulate", "builtin:vmc", "--gcode", prog, "-o", tmp_path / "run.parquet"]
            if command == "simulate" else ["path", prog, "-o", tmp_path / "cmd.csv"])
    code, out, err = run_cli(capsys, *args, "--chunk-blocks", chunk)
    assert code == 0, err
    return len(prog.read_text().splitlines()), out


@pytest.mark.parametrize("command", ["simulate", "path"])
@pytest.mark.parametrize("chunk", [5, 1000])
def test_the_bar_counts_lines_never_back_and_ends_at_the_files(tmp_path, capsys, drawn,
                                                                command, chunk):
    lines, _ = _ran(capsys, tmp_path, command, chunk)
    done = drawn["done"]
    assert drawn["total"] == lines  # comment, blank and tape lines among them
    assert done == sorted(done) and done[-1] == lines  # never back, the end at the total
    text = drawn["screen"].file.getvalue()
    assert f"{lines}/{lines} lines" in text and "blocks" not in text  # the unit said


@pytest.mark.parametrize("command", ["simulate", "path"])
def test_the_bar_moves_within_a_chunk(tmp_path, capsys, drawn, command):
    """One chunk, the whole program: the bar was set once, at the end of it."""
    lines, _ = _ran(capsys, tmp_path, command, 1000)
    inside = sorted({d for d in drawn["done"] if 0 < d < lines})
    assert len(inside) >= 2, drawn["done"]


@pytest.mark.parametrize("command, output", [("simulate", "run.parquet"),
                                             ("path", "cmd.csv")])
@pytest.mark.parametrize("chunk", [5, 1000])
def test_the_bar_changes_no_byte_written(tmp_path, capsys, monkeypatch, command, output,
                                         chunk):
    """On a terminal the axes run and the rows are written a part of a piece at a time:
    the file and stdout are those of a pipe, where nothing is drawn."""
    _, said = _ran(capsys, tmp_path, command, chunk)
    piped = (tmp_path / output).read_bytes()
    monkeypatch.setattr(_stream, "console", Console(file=io.StringIO(), force_terminal=True))
    assert _ran(capsys, tmp_path, command, chunk)[1] == said
    assert (tmp_path / output).read_bytes() == piped


@pytest.mark.parametrize("threads", [1, 2, 4])
@pytest.mark.parametrize("chunk", [3, 1000])
def test_axes_run_a_part_at_a_time_give_the_same_records(vmc, monkeypatch, threads, chunk):
    """Parts of a few hundred samples, cut across the velocity loop's steps and the
    records' period, whichever thread runs the axis."""
    monkeypatch.setattr(streamrun, "PART_SAMPLES", 333)

    def runs(progress):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return list(streamrun.stream_simulate(vmc, program(8), chunk_blocks=chunk,
                                                  record_period_s=0.002, threads=threads,
                                                  progress=progress))

    told = []
    whole, parts = runs(None), runs(told.append)
    assert len(told) > 3 * len(parts) and told == sorted(set(told))
    assert [r.time_s.size for r in parts] == [r.time_s.size for r in whole]
    for p, w in zip(parts, whole, strict=True):
        assert np.array_equal(p.time_s, w.time_s) and np.array_equal(p.nc_line, w.nc_line)
        for a in vmc.axes:
            for f in dataclasses.fields(AxisRun):
                assert np.array_equal(getattr(p.axes[a], f.name),
                                      getattr(w.axes[a], f.name)), (a, f.name)
