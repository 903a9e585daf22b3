"""What the system around a command gives it: names in bytes no locale decodes, colour
asked for by the environment, standard streams closed or full, files the user may not
write, narrow terminals. A command writes what it can or refuses in one line, never ends
in a traceback, and never says it wrote what it did not."""

import json

import numpy as np
import pytest

from tcpmm.cli import main

#: What Python makes of "Maschine µ" typed in a C locale (PYTHONUTF8=0): the bytes of
#: "µ" as lone surrogates (PEP 383) [-].
C_LOCALE_TITLE = "Maschine \udcc2\udcb5"
#: A file name with a Latin-1 "ü" (byte 0xFC), which is no UTF-8, as Python gives it [-].
LATIN1_NAME = "r\udcfcn.csv"


def _circle_run(path):
    """A CCW circle of 35 mm radius with a small TCP deviation, written to ``path``."""
    from test_circle import filtered_circle, make_run, polar_perturb

    cmd, _ = filtered_circle(feed_m_s=5.0 / 60, window_s=0.040)
    tcp = polar_perturb(cmd, (0, 0), lambda a: 2e-6 * np.cos(2 * a))
    make_run(cmd, tcp).write_csv(path)
    return path


def test_a_report_is_written_for_names_no_locale_decodes(tmp_path, capsys):
    """A title and a run file name in undecoded bytes: the report is written, the title's
    bytes read as the UTF-8 they are, the Latin-1 byte of the name as U+FFFD."""
    run = _circle_run(tmp_path / LATIN1_NAME)
    out = tmp_path / "r.html"
    code = main(["report", "-o", str(out), "--run", str(run), "--radius", "35",
                 "--title", C_LOCALE_TITLE])
    assert code == 0, capsys.readouterr().err
    text = out.read_text(encoding="utf-8")
    assert "Maschine µ" in text and "r\ufffdn.csv" in text


def test_json_and_text_files_hold_names_in_undecoded_bytes(tmp_path):
    from tcpmm.io.atomic import write_columns_atomic, write_text_atomic
    from tcpmm.result import json_ready

    write_text_atomic(tmp_path / "t.txt", f"{C_LOCALE_TITLE} {LATIN1_NAME}\n")
    assert (tmp_path / "t.txt").read_text(encoding="utf-8") == "Maschine µ r\ufffdn.csv\n"
    data = json_ready({LATIN1_NAME: [C_LOCALE_TITLE]})
    assert json.loads(json.dumps(data)) == {"r\ufffdn.csv": ["Maschine µ"]}
    write_columns_atomic(tmp_path / "t.csv", {C_LOCALE_TITLE: [1.0]})
    assert (tmp_path / "t.csv").read_text(encoding="utf-8").startswith("Maschine µ\n")


def test_a_json_row_holds_names_in_undecoded_bytes():
    from tcpmm.cli._jsonrow import flat_row_json

    for ascii_only in (False, True):
        row = json.loads(flat_row_json({"run": LATIN1_NAME, C_LOCALE_TITLE: 1.0}, ascii_only))
        assert row == {"run": "r\ufffdn.csv", "Maschine µ": 1.0}


def test_json_stays_json_where_the_environment_forces_colour(tmp_path):
    """FORCE_COLOR=1 (as CI systems set it) on a standard output that is a file: the JSON
    is written without colour codes and parses. In a process of its own: rich reads the
    environment's colours when its console is made, at the import."""
    import os
    import subprocess
    import sys

    out = tmp_path / "x.json"
    env = {**os.environ, "FORCE_COLOR": "1", "TERM": "xterm-256color"}
    with open(out, "w") as fh:
        done = subprocess.run([sys.executable, "-c", "import sys; from tcpmm.cli import main; "
                               "sys.exit(main())", "machine", "show", "builtin:vmc", "--json"],
                              stdout=fh, stderr=subprocess.PIPE, env=env, timeout=120)
    assert done.returncode == 0, done.stderr
    text = out.read_text(encoding="utf-8")
    assert "\x1b[" not in text
    assert "X" in json.loads(text)


def test_only_a_stream_that_is_a_terminal_counts_as_one(monkeypatch):
    """A pipe is no terminal whatever FORCE_COLOR says; a pseudo-terminal is one, and a
    console made to be one (a test's screen) stays one."""
    import io
    import os
    import pty

    from rich.console import Console

    from tcpmm.cli._app import on_screen

    monkeypatch.setenv("FORCE_COLOR", "1")
    read, write = os.pipe()
    main_end, screen_end = pty.openpty()
    with open(write, "w") as pipe, open(screen_end, "w") as screen:
        assert Console(file=pipe).is_terminal and not on_screen(Console(file=pipe))
        assert on_screen(Console(file=screen))
    os.close(read)
    os.close(main_end)
    assert on_screen(Console(file=io.StringIO(), force_terminal=True))


def _nothing_writable(tmp_path, monkeypatch):
    """No folder for numba's cache: the package's and the home's not writable, and no
    temporary folder usable (a read-only container)."""
    import errno
    import os
    import tempfile

    import numba

    from tcpmm import _numba_cache

    def no_temporary_folder():
        raise FileNotFoundError(errno.ENOENT, "No usable temporary directory found")

    monkeypatch.setenv("NUMBA_CACHE_DIR", "")  # so that the test leaves it as it found it
    monkeypatch.delenv("NUMBA_CACHE_DIR")
    monkeypatch.setattr(numba.config, "CACHE_DIR", numba.config.CACHE_DIR)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    monkeypatch.setattr(tempfile, "gettempdir", no_temporary_folder)
    monkeypatch.setattr(_numba_cache.os, "access", lambda path, mode: False)
    monkeypatch.setattr(_numba_cache, "FALLBACK", [])
    monkeypatch.setattr(_numba_cache, "NO_CACHE", [], raising=False)
    return os


def test_no_writable_folder_at_all_is_no_traceback_at_import(tmp_path, monkeypatch):
    from tcpmm import _numba_cache

    os = _nothing_writable(tmp_path, monkeypatch)
    assert _numba_cache.ensure_cache_dir() is None
    assert "NUMBA_CACHE_DIR" not in os.environ and not _numba_cache.FALLBACK


def test_numba_without_a_cache_folder_is_one_line_with_the_fix(tmp_path, monkeypatch,
                                                               capsys):
    """Where numba's kernels must run and no folder takes their cache, numba refuses
    ("no locator available"): one line naming the folders and the fix, exit 2."""
    import tcpmm.cli as cli
    from tcpmm import _numba_cache

    _nothing_writable(tmp_path, monkeypatch)
    _numba_cache.ensure_cache_dir()

    def refused(argv):
        raise RuntimeError("cannot cache function 'run_axis': no locator available for "
                           "file 'kernel.py'")

    monkeypatch.setattr(cli, "register", refused)
    assert main(["simulate", "builtin:vmc"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "TMPDIR or NUMBA_CACHE_DIR" in err[0]
    assert "internal error" not in err[0] and "__pycache__" in err[0]


def test_a_read_only_install_uses_the_kernel_built_in_it(tmp_path, monkeypatch):
    """The package's __pycache__ holds the compiled module for this key but cannot be
    written: the module there is used, not built again in the user's cache."""
    from tcpmm import _compiled

    package = tmp_path / "package" / "__pycache__"
    package.mkdir(parents=True)
    monkeypatch.setenv("NUMBA_CACHE_DIR", "")
    monkeypatch.delenv("NUMBA_CACHE_DIR")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "home"))
    monkeypatch.setattr(_compiled, "_PKG", tmp_path / "package")
    monkeypatch.setattr(_compiled, "_key", lambda: "k")
    monkeypatch.setattr(_compiled, "writable", lambda folder: folder != package)
    name = _compiled.module_path().name
    assert _compiled.module_path().parent == tmp_path / "home" / "tcpmm" / "compiled"
    (package / name).write_bytes(b"built by whoever installed it")
    assert _compiled.module_path() == package / name


class _FillingDisk:
    """A file on a disk with ``room`` bytes left: a write takes what fits, the next one
    is refused (ENOSPC), as the system's write does on a disk that fills; ``buffered``
    false as ``python -u`` (PYTHONUNBUFFERED) has it."""

    def __new__(cls, room: int, buffered: bool = True):
        import errno
        import io

        class Raw(io.RawIOBase):
            def writable(self):
                return True

            def write(self, data):
                nonlocal room
                if room <= 0:
                    raise OSError(errno.ENOSPC, "No space left on device")
                taken = min(len(data), room)
                room -= taken
                return taken

        raw = Raw()
        return io.TextIOWrapper(io.BufferedWriter(raw) if buffered else raw,
                                encoding="utf-8", write_through=not buffered)


@pytest.mark.parametrize("buffered", [True, False])
def test_json_on_a_standard_output_that_fills_is_an_error(tmp_path, monkeypatch, capsys,
                                                          buffered):
    """The circle's JSON is larger than the room left and than the stream's buffer:
    exit 2 and one line, not a truncated file with exit 0."""
    import sys

    run = _circle_run(tmp_path / "run.csv")
    monkeypatch.setattr(sys, "stdout", _FillingDisk(12000, buffered))
    assert main(["circle", str(run), "--radius", "35", "--json"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1] == "error: No space left on device (standard output)"


def test_text_left_in_the_standard_output_s_buffer_is_checked_before_the_exit(
        monkeypatch, capsys):
    """Text still in the buffer when the command ends: its flush fails on the full disk,
    and the exit code is 2, not the command's 0."""
    import sys

    from tcpmm.cli import _flushed

    monkeypatch.setattr(sys, "stdout", _FillingDisk(0))
    sys.stdout.write("a table\n")
    assert _flushed(0) == 2
    assert capsys.readouterr().err.strip() == (
        "error: No space left on device (standard output)")


def test_an_output_the_user_may_not_write_is_refused_before_the_work(tmp_path, monkeypatch,
                                                                    capsys):
    """A file made read-only (chmod 444, a measured run kept safe) is not replaced through
    the rename the folder allows: exit 2, one line naming it and the fix, the file as it
    was. (``os.access`` answers as for its owner without root's override.)"""
    import os

    from tcpmm.path import circle_command, write_command_csv

    command = tmp_path / "cmd.csv"
    write_command_csv(circle_command(0.005, 1.0 / 60, turns=0.25), command)
    kept = tmp_path / "measured.csv"
    kept.write_text("time_s,x_cmd_mm\n")
    kept.chmod(0o444)
    access = os.access
    monkeypatch.setattr(os, "access", lambda p, mode, **kw: (
        not (mode & os.W_OK and os.path.realpath(p) == str(kept))
        and access(p, mode, **kw)))
    assert main(["simulate", "builtin:vmc", "--command", str(command), "-o", str(kept)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and str(kept) in err[0] and "chmod u+w" in err[0]
    assert kept.read_text() == "time_s,x_cmd_mm\n"


def test_a_result_for_a_closed_standard_output_is_refused_at_the_start(tmp_path,
                                                                       monkeypatch, capsys):
    """``>&-``: Python's standard output is None, and the circle's figures, its only
    output, went nowhere with exit 0. It is refused before the work, in one line; a
    command that writes its result to a file runs."""
    import sys

    run = _circle_run(tmp_path / "run.csv")
    prog = tmp_path / "p.nc"
    prog.write_text("G21 G90\nG1 X1 F1000\nM30\n")
    monkeypatch.setattr(sys, "stdout", None)
    for args in (["circle", str(run), "--radius", "35", "--json"],
                 ["circle", str(run), "--radius", "35"], ["--version"]):
        assert main(args) == 2, args
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and err[0].startswith("error: standard output is closed")
    assert main(["path", str(prog), "-o", str(tmp_path / "cmd.csv")]) == 0
    assert (tmp_path / "cmd.csv").is_file()
