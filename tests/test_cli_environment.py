"""What the system around a command gives it: names in bytes no locale decodes, colour
asked for by the environment, standard streams closed or full, files the user may not
write, narrow terminals. A command writes what it can or refuses in one line, never ends
in a traceback, and never says it wrote what it did not."""

import json

import numpy as np

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


def test_json_stays_json_where_the_environment_forces_colour(monkeypatch, capsys):
    """FORCE_COLOR=1 (as CI systems set it) on a standard output that is no terminal: the
    JSON is written without colour codes and parses."""
    monkeypatch.setenv("FORCE_COLOR", "1")
    assert main(["machine", "show", "builtin:vmc", "--json"]) == 0
    text = capsys.readouterr().out
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
