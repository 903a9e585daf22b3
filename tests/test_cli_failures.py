"""What the system refuses reaches the user as one line and exit code 2, and nothing of a
refused output is left: no traceback, no temporary file, an earlier file unchanged."""

import errno
import os
import signal
import tempfile

import numpy as np
import pytest

from tcpmm.cli import _exit_on_signals, _restore_signals, main
from tcpmm.io.atomic import atomic_path, write_text_atomic


def test_a_folder_that_refuses_writing_is_one_line(tmp_path, monkeypatch, capsys):
    def refuse(*args, **kwargs):
        raise PermissionError(errno.EACCES, "Permission denied")

    monkeypatch.setattr(tempfile, "mkstemp", refuse)
    out = tmp_path / "model.yaml"
    assert main(["machine", "export", "vmc", "-o", str(out)]) == 2
    cap = capsys.readouterr()
    err = cap.out + cap.err
    assert "cannot write the output (Permission denied)" in " ".join(err.split())
    assert "Traceback" not in err and not out.exists()


def test_a_full_disk_leaves_the_earlier_file_and_no_temporary_one(tmp_path, monkeypatch,
                                                                  capsys):
    out = tmp_path / "model.yaml"
    out.write_text("earlier\n")

    def full(src, dst):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(os, "replace", full)
    assert main(["machine", "export", "vmc", "-o", str(out)]) == 2
    cap = capsys.readouterr()
    err = cap.out + cap.err
    assert "No space left on device" in err and "free space" in " ".join(err.split())
    assert out.read_text() == "earlier\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["model.yaml"]


def test_an_unexpected_system_error_is_one_line(tmp_path, monkeypatch, capsys):
    from tcpmm.io import modelfile

    def broken(path):
        raise OSError(errno.EIO, "Input/output error", str(path))

    monkeypatch.setattr(modelfile, "read_machine", broken)
    assert main(["machine", "show", str(tmp_path / "m.yaml")]) == 2
    cap = capsys.readouterr()
    assert "Input/output error" in cap.out + cap.err and "Traceback" not in cap.err


@pytest.mark.skipif(not hasattr(signal, "SIGHUP"), reason="no SIGHUP on this system")
@pytest.mark.parametrize("name", ["SIGTERM", "SIGHUP"])
def test_a_termination_signal_during_a_write_leaves_nothing(tmp_path, name):
    sig = getattr(signal, name)
    out = tmp_path / "run.csv"
    before = _exit_on_signals()
    try:
        with pytest.raises(SystemExit) as stop, atomic_path(out) as tmp:
            tmp.write_text("half of a run\n")
            os.kill(os.getpid(), sig)
    finally:
        _restore_signals(before)
    assert stop.value.code == 128 + sig
    assert list(tmp_path.iterdir()) == []
    write_text_atomic(out, "whole\n")  # and the handlers are back as they were
    assert out.read_text() == "whole\n"


def test_an_unstable_loop_is_refused_unless_asked_for(tmp_path, capsys):
    from tcpmm.io.modelfile import write_machine
    from tcpmm.machines.builtin import builtin_machine

    m = builtin_machine()
    x = m.axes["X"]
    shaky = m.with_axis("X", x.replace(servo=x.servo.model_copy(update={
        "K_vp": 20 * x.servo.K_vp, "delay_samples": 3})))
    write_machine(shaky, tmp_path / "m.yaml")
    cmd = tmp_path / "cmd.csv"
    cmd.write_text("time_s,x_mm,y_mm\n0.000,0,0\n0.001,0,0\n0.002,0,0\n")
    run = tmp_path / "run.csv"
    args = ["simulate", str(tmp_path / "m.yaml"), "--command", str(cmd), "-o", str(run)]
    assert main(args) == 2 and not run.exists()
    cap = capsys.readouterr()
    assert "axis X" in cap.err and "--allow-unstable" in " ".join(cap.err.split())
    assert main([*args, "--allow-unstable"]) == 0 and run.exists()


def test_a_command_in_the_wrong_unit_is_named(tmp_path):
    import warnings

    from tcpmm.machines.builtin import builtin_machine
    from tcpmm.path.command import Command
    from tcpmm.sim.simulate import simulate

    t = np.arange(3) * 1e-3
    cmd = Command(time_s=t, positions={"X": np.full(3, 1e9)})  # 1e12 mm written as m
    with pytest.warns(Warning, match=r"axis X: the command goes to 1e\+12 mm"):
        with warnings.catch_warnings():
            warnings.simplefilter("always")
            simulate(builtin_machine(), cmd)


def test_a_one_axis_machine_runs_a_program_that_holds_the_other_axes_still(vmc):
    """A program of X moves on a one-axis rig: the interpolator writes the Y it names held
    at its start, and simulate refused it ('drives axis Y that the machine does not
    have'). An axis held still is left out; one that moves is still refused."""
    from tcpmm.errors import InputError
    from tcpmm.path.command import Command
    from tcpmm.sim.simulate import simulate

    rig = vmc.model_copy(update={"axes": {"X": vmc.axes["X"]}})
    t = np.arange(200) * 1e-3
    x = 1e-3 * np.sin(np.pi * t / t[-1])
    run = simulate(rig, Command(time_s=t, positions={"X": x, "Y": np.full(t.size, 5e-3)}))
    assert list(run.axes) == ["X"] and run.axes["X"].cmd.max() > 0.9e-3
    with pytest.raises(InputError, match="drives axis Y that the machine does not have"):
        simulate(rig, Command(time_s=t, positions={"X": x, "Y": x}))


def test_compiled_kernels_find_a_cache_when_nothing_of_the_user_is_writable(tmp_path,
                                                                          monkeypatch):
    import tempfile

    import numba

    from tcpmm import _numba_cache

    monkeypatch.setenv("NUMBA_CACHE_DIR", "")  # so that the test leaves it as it found it
    monkeypatch.delenv("NUMBA_CACHE_DIR")
    monkeypatch.setattr(numba.config, "CACHE_DIR", numba.config.CACHE_DIR)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    monkeypatch.setattr(tempfile, "gettempdir", lambda: str(tmp_path))
    monkeypatch.setattr(_numba_cache.os, "access", lambda path, mode: False)
    monkeypatch.setattr(_numba_cache, "FALLBACK", [])
    folder = _numba_cache.ensure_cache_dir()
    assert folder is not None and os.environ["NUMBA_CACHE_DIR"] == folder
    assert os.path.isdir(folder)
    assert numba.config.CACHE_DIR == folder


def test_a_writable_package_keeps_the_cache_beside_it(monkeypatch):
    from tcpmm import _numba_cache

    monkeypatch.setenv("NUMBA_CACHE_DIR", "")
    monkeypatch.delenv("NUMBA_CACHE_DIR")
    assert _numba_cache.ensure_cache_dir() is None  # the checkout is writable here


def test_version(capsys):
    from tcpmm import __version__

    assert main(["--version"]) == 0
    version, kernel, blas, loops = capsys.readouterr().out.strip().splitlines()
    assert version == f"tcpmm {__version__}"
    assert kernel.startswith(("kernel: compiled module ", "kernel: numba's kernels ("))
    assert blas.startswith("blas: OpenBLAS's ") or "figures may differ" in blas
    assert loops.startswith("numpy: numpy ") and "loops" in loops


def test_a_refused_command_leaves_no_output_folder(tmp_path, capsys):
    """The output's folders were made before the work, and stayed when the work was
    refused; they are made when something is written."""
    bad, good = tmp_path / "bad.nc", tmp_path / "good.nc"
    bad.write_text("G21 G90\nG1 X10 F1000 G2\nM30\n")
    good.write_text("G21 G90\nG1 X1 F1000\nM30\n")
    out = tmp_path / "nd" / "a" / "cmd.csv"
    assert main(["path", str(bad), "-o", str(out)]) == 2
    assert "line 2, column 14" in capsys.readouterr().err
    assert not (tmp_path / "nd").exists()
    assert main(["path", str(good), "-o", str(out)]) == 0
    assert out.is_file()


def test_an_output_folder_under_a_file_is_refused_before_the_work(tmp_path, capsys):
    (tmp_path / "f").write_text("")
    prog = tmp_path / "good.nc"
    prog.write_text("G21 G90\nG1 X1 F1000\nM30\n")
    assert main(["path", str(prog), "-o", str(tmp_path / "f" / "a" / "cmd.csv")]) == 2
    assert "is a file, so the output folder" in capsys.readouterr().err


def test_a_read_only_pycache_of_a_subpackage_moves_the_cache(tmp_path, monkeypatch, capsys):
    """The package folder writable but ``sim/__pycache__`` not, nor the home: numba would
    refuse at import ("no locator available") unless the cache moves."""
    import tempfile

    import numba

    from tcpmm import _numba_cache
    from tcpmm.cli import main

    monkeypatch.setenv("NUMBA_CACHE_DIR", "")
    monkeypatch.delenv("NUMBA_CACHE_DIR")
    monkeypatch.setattr(numba.config, "CACHE_DIR", numba.config.CACHE_DIR)
    monkeypatch.setattr(_numba_cache, "FALLBACK", [])
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "home"))
    monkeypatch.setattr(tempfile, "gettempdir", lambda: str(tmp_path))
    writable = _numba_cache.writable
    monkeypatch.setattr(_numba_cache, "writable", lambda p: writable(p) and not (
        p.name == "__pycache__" and p.parent.name == "sim") and "home" not in p.parts)
    folder = _numba_cache.ensure_cache_dir()
    assert folder is not None and os.environ["NUMBA_CACHE_DIR"] == folder
    assert main(["machine", "--help"]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "warning:" in err[0] and folder in err[0]


@pytest.mark.parametrize("content", [b"junk\n", b""])
@pytest.mark.parametrize("extra", [[], ["--chunk-rows", "100"]])
def test_contour_of_a_file_that_is_no_parquet_is_one_line(tmp_path, capsys, content, extra):
    """A .parquet that is junk or empty: contour printed a 49-line traceback and exited 1
    (circle said it in one line)."""
    bad = tmp_path / "run.parquet"
    bad.write_bytes(content)
    assert main(["contour", str(bad), *extra]) == 2
    err = capsys.readouterr().err
    assert "cannot read as Parquet" in err and "Traceback" not in err
    assert len(err.strip().splitlines()) == 1


def test_a_defect_is_one_line_and_exit_1_and_its_traceback_on_request(tmp_path, capsys,
                                                                      monkeypatch):
    """An exception no code expected reached the user as a traceback. It is one line
    naming it, exit 1; TCPMM_TRACEBACK=1 lets it through for a report."""
    import importlib

    run_cli = importlib.import_module("tcpmm.cli.run")  # tcpmm.cli.run: also a function

    def broken(*args, **kwargs):
        raise ZeroDivisionError("float division by zero")

    monkeypatch.setattr(run_cli, "positive", broken)
    args = ["circle", str(tmp_path / "none.csv"), "--radius", "35"]
    assert main(args) == 1
    err = " ".join(capsys.readouterr().err.split())
    assert "internal error, a defect of tcpmm (ZeroDivisionError: float division by zero)" \
        in err and "Traceback" not in err
    monkeypatch.setenv("TCPMM_TRACEBACK", "1")
    with pytest.raises(ZeroDivisionError):
        main(args)


def _refused(capsys, *args) -> str:
    assert main([str(a) for a in args]) == 2
    cap = capsys.readouterr()
    return " ".join((cap.out + cap.err).split())


def test_a_refusal_names_what_to_give_instead(tmp_path, capsys):
    """A missing model said only 'machine model not found', a folder given as the NC
    program 'cannot read the NC program: Is a directory', and a CCW run compared with a
    CW prediction 'the two runs share no circle direction and sensor to compare', naming
    neither run's direction."""
    from conftest import bench_path

    err = _refused(capsys, "simulate", tmp_path / "nomodel.yaml", "--gcode",
                   tmp_path / "p.nc", "-o", tmp_path / "r.csv")
    assert "machine model not found; give a model file tcpmm identify wrote" in err
    err = _refused(capsys, "path", tmp_path, "-o", tmp_path / "c.csv")
    assert "is a folder, not an NC program" in err
    d = bench_path("c")
    err = _refused(capsys, "compare", d / "circle_ccw_meas.csv", d / "circle_cw_meas.csv",
                   "--radius", "35")
    assert "the measured run holds CCW (" in err and "the predicted CW (" in err


def test_a_plot_in_a_plane_the_path_does_not_move_in_is_refused(tmp_path, capsys):
    """tcpmm path --plot --plane YZ of a square in XY drew the path as a line on an empty
    panel and exited 0; it is refused before anything is written."""
    nc = tmp_path / "square.nc"
    nc.write_text("G21 G90 G64\nG1 X0 Y0 F4000\nG1 X30\nG1 Y30\nG1 X0\nG1 Y0\nM30\n")
    out = tmp_path / "cmd.csv"
    err = _refused(capsys, "path", nc, "-o", out, "--plot", "--plane", "YZ")
    assert "does not move in the YZ plane" in err and not out.exists()
    assert main(["path", str(nc), "-o", str(out), "--plot", "--plane", "XY"]) == 0
    assert out.with_suffix(".png").exists()
