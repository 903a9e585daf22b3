"""A command's outputs: never one another's or an input's file, all written or none, with
names as long as the file system allows, and a stop by a signal said."""

from __future__ import annotations

import errno
from pathlib import Path

import numpy as np
import pytest
import typer

from conftest import run_cli
from tcpmm.errors import InputError
from tcpmm.ident.frf import FRF
from tcpmm.io.atomic import staged_folder, write_text_atomic
from tcpmm.io.frffile import write_frf_csv

NC = Path(__file__).parents[1] / "examples" / "circle_r35_f5000.nc"


def _frf(folder: Path) -> Path:
    f = np.geomspace(10.0, 1000.0, 200)
    s = 2j * np.pi * f
    h = 1.0 / (1 + s / (2 * np.pi * 100) + (s / (2 * np.pi * 300)) ** 2)
    return write_frf_csv(FRF(f, h, np.ones(f.size), 10, np.zeros(f.size), name="t"),
                         folder / "h.csv")


@pytest.mark.parametrize("outputs", [
    ("-o", "{d}/comp.csv", "--gcode-out", "{d}/p.nc"),
    ("-o", "{d}/out.csv", "--gcode-out", "{d}/out.csv"),
    ("-o", "{d}/comp.csv", "--report", "{d}/r.html", "--reference-out", "{d}/comp.csv"),
])
def test_compensate_refuses_an_output_on_an_input_or_on_another_output(capsys, tmp_path,
                                                                         outputs):
    """``compensate --gcode-out p.nc`` replaced the program it read, and ``-o out.csv
    --gcode-out out.csv`` lost the command file; both are refused before any work."""
    prog = tmp_path / "p.nc"
    prog.write_text(NC.read_text())
    (tmp_path / "out.csv").write_text("kept")
    code, out, err = run_cli(capsys, "compensate", "builtin:vmc", "--gcode", prog,
                             *[a.format(d=tmp_path) for a in outputs])
    assert code == 2, out + err
    assert "is also an input" in out + err or "given to both" in out + err
    assert prog.read_text() == NC.read_text() and (tmp_path / "out.csv").read_text() == "kept"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.csv", "p.nc"]


@pytest.mark.parametrize("args", [
    ("frf", "fit", "{d}/h.csv", "-o", "{d}/same.png", "--plot", "{d}/same.png"),
    ("frf", "fit", "{d}/h.csv", "-o", "{d}/f.yaml", "--model-fragment", "{d}/f.yaml"),
    ("circle", "{d}/run.csv", "--radius", "35", "--plot", "{d}/same.png",
     "--diag-plot", "{d}/same.png"),
])
def test_two_outputs_of_one_name_are_refused(capsys, tmp_path, args):
    """``frf fit -o same.png --plot same.png`` ended 0 with the fit's JSON replaced by
    the plot."""
    (tmp_path / "same.png").write_text("kept")
    code, out, err = run_cli(capsys, *[a.format(d=tmp_path) for a in args])
    assert code == 2, out + err
    assert "given to both" in out + err and "give each output its own name" in out + err
    assert (tmp_path / "same.png").read_text() == "kept"


def test_outputs_are_put_in_place_only_once_all_are_written(tmp_path):
    """A later output that failed (a full disk) left the earlier ones written, an earlier
    file of that name lost, under "nothing was written"."""
    from tcpmm.io.atomic import together

    first, new = tmp_path / "comp.csv", tmp_path / "sub" / "comp.nc"
    first.write_text("before")
    with pytest.raises(InputError, match="nothing was written"), together():
        write_text_atomic(first, "after")
        write_text_atomic(tmp_path / "sub" / "other.txt", "x")
        raise InputError("cannot write the output (No space left on device); nothing was "
                         "written", file=new)
    assert first.read_text() == "before"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["comp.csv"]


def test_an_exit_on_purpose_keeps_the_outputs_written(tmp_path):
    """``identify --strict`` ends with code 3 after writing the model: it is kept."""
    from tcpmm.cli._outputs import outputs_together

    with pytest.raises(typer.Exit), outputs_together():
        write_text_atomic(tmp_path / "m.yaml", "model")
        raise typer.Exit(3)
    assert (tmp_path / "m.yaml").read_text() == "model"


def test_frf_fit_leaves_no_fit_where_its_plot_cannot_be_written(capsys, tmp_path,
                                                                  monkeypatch):
    """``frf fit -o fit.json --plot fit.png`` on a full disk left fit.json behind while
    saying that nothing was written."""
    import matplotlib.figure

    def full(self, *a, **k):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", full)
    h = _frf(tmp_path)
    code, out, err = run_cli(capsys, "frf", "fit", h, "--poles", 2, "--delay", "none",
                             "-o", tmp_path / "fit.json", "--plot", tmp_path / "fit.png")
    assert code == 2, out + err
    assert "nothing was written" in out + err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["h.csv"]


@pytest.mark.parametrize("length", [240, 251])
def test_an_output_with_a_long_legal_name_is_written(tmp_path, length):
    """A name of 240-255 characters was refused as "File name too long": the temporary
    file's name was the output's with a suffix added."""
    path = tmp_path / ("a" * length + ".csv")
    write_text_atomic(path, "x\n")
    assert path.read_text() == "x\n"
    folder = tmp_path / ("b" * (length + 4))
    with staged_folder(folder) as tmp:
        write_text_atomic(tmp / "t.csv", "y\n")
    assert (folder / "t.csv").read_text() == "y\n"


def test_a_staged_folder_that_fails_leaves_no_folder_and_names_the_users(tmp_path):
    """``identify --report small/idrep`` and ``demo -o small/demo`` on a full disk left
    empty folders behind and named the temporary folder's file in the error."""
    out = tmp_path / "new" / "idrep"
    with pytest.raises(InputError) as got, staged_folder(out) as tmp:
        raise InputError("cannot write the output (No space left on device); nothing was "
                         "written", file=tmp / "sweep_X.png")
    assert got.value.file == str(out)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("stop, code, name", [(KeyboardInterrupt, 130, "SIGINT"),
                                              (lambda: SystemExit(143), 143, "SIGTERM")])
def test_a_stop_by_a_signal_is_said(capsys, tmp_path, monkeypatch, stop, code, name):
    """Ctrl-C ended a command with 130 and nothing on stderr."""
    import tcpmm.path.program

    def stopped(*a, **k):
        raise stop()

    monkeypatch.setattr(tcpmm.path.program, "program_to_interpolation", stopped)
    got, out, err = run_cli(capsys, "path", NC, "-o", tmp_path / "cmd.csv")
    assert got == code
    assert f"stopped ({name}): nothing was written" in out + err
    assert list(tmp_path.iterdir()) == []
