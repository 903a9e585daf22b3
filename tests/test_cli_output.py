"""Output fit for pipes and logs: every result table in the one plain style, titles and
captions on lines of their own that are never wrapped and end without spaces, a stream
that cannot encode µ written with ASCII stand-ins, and units said alike in a command's
titles and columns.

Everything is captured from streams that are no terminal, so nothing here depends on the
terminal's width or on the temporary folder's length."""

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from conftest import bench_path, run_cli
from tcpmm.cli import main
from tcpmm.demo import paper_circle_command
from tcpmm.ident.frf import FRF
from tcpmm.io.frffile import write_frf_csv
from tcpmm.path import write_command_csv

SRC = Path(__file__).resolve().parents[1] / "src"

#: Characters of rich's boxes with vertical rules (its default heavy head): none of them
#: in a result table [-].
BOXED = set("┏━┳┃┡╇┩│└┴┘┓┐┌┼├┤")

SQUARE = "G21 G17 G90\nG0 X0 Y0\nG1 X20 Y0 F3000\nX20 Y20\nX0 Y20\nM30\n"


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """A square and the paper's circle on the built-in machine, and a measured FRF."""
    d = tmp_path_factory.mktemp("pipe")
    (d / "sq.nc").write_text(SQUARE)
    write_command_csv(paper_circle_command(), d / "circle_cmd.csv")
    for args in (["path", d / "sq.nc", "-o", d / "sq_cmd.csv"],
                 ["simulate", "builtin:vmc", "--command", d / "sq_cmd.csv", "-o", d / "sq.csv"],
                 ["simulate", "builtin:vmc", "--command", d / "circle_cmd.csv", "-o",
                  d / "circle.csv"]):
        assert main([str(a) for a in args]) == 0
    f = np.geomspace(10.0, 1000.0, 50)
    H = 1.0 / (1.0 + 2j * np.pi * f / (2 * np.pi * 100.0))
    write_frf_csv(FRF(f, H, np.ones(f.size), 10, np.zeros(f.size), name="lowpass"),
                  d / "m.csv")
    return d


def commands(d: Path) -> dict:
    """Each command that prints result tables, with its arguments [-]."""
    return {"contour": ["contour", d / "sq.csv"],
            "circle": ["circle", d / "circle.csv", "--radius", 35],
            "frf show": ["frf", "show", d / "m.csv"],
            "compare": ["compare", d / "circle.csv", d / "circle.csv", "--radius", 35],
            "tune": ["tune", "builtin:vmc"]}


#: What each command of :func:`commands` printed, by name: run once per module, as the
#: tests only read its text [-].
_PRINTED: dict = {}


def printed(capsys, d: Path, name: str) -> tuple:
    """``(exit code, stdout, stderr)`` of command ``name`` of :func:`commands` on ``d`` [-]."""
    if name not in _PRINTED:
        _PRINTED[name] = run_cli(capsys, *commands(d)[name])
    return _PRINTED[name]


def test_no_command_builds_a_table_of_its_own():
    """contour, circle, frf and tune built rich tables of the default heavy box, the others
    the plain one of ``print_table``: every table is made in ``cli/_tables.py``."""
    cli = SRC / "tcpmm" / "cli"
    own = [p.name for p in sorted(cli.glob("*.py"))
           if p.name != "_tables.py" and "Table(" in p.read_text(encoding="utf-8")]
    assert own == []


@pytest.mark.parametrize("name", ["contour", "circle", "frf show", "compare", "tune"])
def test_every_result_table_is_plain(capsys, runs, name):
    """No vertical rules and no heavy head: columns apart by spaces, the head ruled."""
    code, out, err = printed(capsys, runs, name)
    assert code == 0, err
    assert not BOXED & set(out), out
    rules = [line for line in out.splitlines() if line and set(line) <= {"─", " "}]
    assert rules, out  # each table's head is ruled


@pytest.mark.parametrize("name", ["contour", "circle", "frf show", "compare", "tune"])
def test_no_line_in_a_pipe_ends_in_spaces(capsys, runs, name):
    """Titles and captions were centred and padded to the table's width, and each row to
    the last column's: a log held spaces at the end of most lines."""
    code, out, err = printed(capsys, runs, name)
    assert code == 0, err
    assert [line for line in out.splitlines() if line != line.rstrip()] == []


def test_titles_and_captions_are_lines_of_their_own(capsys, runs):
    """A caption was word-wrapped to its table's width and centred: 'overshoot: outside
    the path ... settled within 1 µm' came in three pieces, and a grep for a figure in it
    failed. Titles and captions are now lines of their own, never wrapped in a pipe. The
    caption says when settling reads n/a, which it did with no word where a tool still
    rang at the next corner."""
    code, out, _ = printed(capsys, runs, "contour")
    lines = out.splitlines()
    assert code == 0 and "corners, tcp" in lines and "signed, +: left of travel" in lines
    assert any(line.startswith("turn: of the command over 0.5 mm before and after")
               and "overshoot: outside the path past the corner, rounding: " in line
               and line.endswith("settled within 1 µm, n/a where it has not by halfway "
                                 "to the next corner or by the run's end")
               for line in lines), out
    # the settling's path length is named with its unit, and the caption says what it is
    head = next(line for line in lines if line.startswith("#"))
    assert head.split()[-4:] == ["settle", "ms", "settle", "mm"], head
    assert "settle ms, settle mm: the time and the commanded path length" in out
    code, out, _ = printed(capsys, runs, "circle")
    lines = out.splitlines()
    assert code == 0 and f"{runs / 'circle.csv'} [µm]" in lines
    assert "circle diagnostics (tcp) [µm]" in lines
    assert any(line.startswith("terms ranked by their share of G(b)") for line in lines)
    assert any(line.startswith("A-D: reversal spike after the pair's terms")
               and line.endswith("G circular deviation") for line in lines), out
    # the paper's circle ranks nothing (its spikes lie in what its transient leaves); an
    # independent machine's pair, with a TCP and a scale, ranks its terms, and the caption
    # ends with what the scale's column says
    assert any(line.startswith("not ranked: reversal spikes: none of the 8 spikes")
               and line.endswith("from the noise") for line in lines), out
    bench = bench_path("c")
    code, out, _ = run_cli(capsys, "circle", bench / "circle_ccw_meas.csv",
                           bench / "circle_cw_meas.csv", "--radius", 35)
    lines = out.splitlines()
    assert code == 0 and "terms ranked by their share of G(b)" in lines
    assert any(line.startswith("G(b) alone: the G(b) the term's radial error alone makes")
               and line.endswith("not in the drive") for line in lines), out
    code, out, _ = printed(capsys, runs, "tune")
    lines = out.splitlines()
    assert code == 0
    assert "axis X: tuning for 6 dB / 45 deg, stable with the modes 5 % off: met" in lines
    code, out, _ = printed(capsys, runs, "compare")
    assert code == 0
    assert ("measured - predicted (raw spikes e - b, as in the paper's Table 2)"
            in out.splitlines())


def in_process(tmp_path: Path, env: dict, *args) -> tuple:
    """``tcpmm args`` in a process of its own, its outputs into files under ``env``
    (added to the environment without the settings of the encoding): exit code,
    stdout's and stderr's bytes [-]."""
    script = "import sys; from tcpmm.cli import main; sys.exit(main())"
    base = {k: v for k, v in os.environ.items()
            if k not in ("PYTHONIOENCODING", "PYTHONUTF8", "PYTHONCOERCECLOCALE", "LC_ALL",
                         "LC_CTYPE", "LANG")}
    full = {**base, "PYTHONPATH": str(SRC), **env}
    with open(tmp_path / "out", "wb") as o, open(tmp_path / "err", "wb") as e:
        code = subprocess.run([sys.executable, "-c", script, *map(str, args)], stdout=o,
                              stderr=e, env=full, timeout=300).returncode
    return code, (tmp_path / "out").read_bytes(), (tmp_path / "err").read_bytes()


@pytest.mark.parametrize("env", [{"PYTHONIOENCODING": "ascii"},
                                 {"LC_ALL": "C", "PYTHONUTF8": "0",
                                  "PYTHONCOERCECLOCALE": "0"}])
def test_a_stream_that_cannot_encode_micro_gets_ascii_stand_ins(tmp_path, runs, env):
    """``PYTHONIOENCODING=ascii tcpmm contour RUN.csv > f`` ended as 'internal error, a
    defect of tcpmm (UnicodeEncodeError ... '\\xb5')'. µ, ° and the rules are written as
    u, deg and -, and the table keeps its plain style."""
    code, out, err = in_process(tmp_path, env, "contour", runs / "sq.csv")
    assert code == 0, err
    assert out.isascii() and err.isascii()
    text = out.decode("ascii")
    assert f"{runs / 'sq.csv'}: contour error in XY [um]" in text.splitlines()
    assert " over um " in text and " 90deg " in text
    assert not any(line.startswith(("|", "+")) for line in text.splitlines())  # rich's ASCII box
    assert any(line and set(line) <= {"-", " "} for line in text.splitlines())


def test_json_on_an_ascii_stream_escapes_what_it_cannot_write(tmp_path, runs):
    """--json is the machine interface: what ASCII cannot hold is escaped (\\u00b5),
    which a reader reads back as it was, not written with a stand-in."""
    named = tmp_path / "µ_frf.csv"
    named.write_bytes((runs / "m.csv").read_bytes())
    code, out, err = in_process(tmp_path, {"PYTHONIOENCODING": "ascii"}, "frf", "show",
                                named, "--json")
    assert code == 0, err
    assert out.isascii() and json.loads(out)["file"] == str(named)


def test_lc_all_c_keeps_working(tmp_path, runs):
    """Python reads the C locale as UTF-8: µ as it is."""
    code, out, err = in_process(tmp_path, {"LC_ALL": "C"}, "contour", runs / "sq.csv")
    assert code == 0, err
    assert f"{runs / 'sq.csv'}: contour error in XY [µm]" in out.decode("utf-8").splitlines()


def test_a_command_says_its_units_alike_in_titles_and_columns(capsys, runs):
    """tune's path table was titled '[um]' over figures the other tables head '[µm]', and
    compare's verdicts likewise."""
    code, out, err = printed(capsys, runs, "tune")
    assert code == 0, err
    assert "predicted path (TCP) [µm]" in out.splitlines() and "[um]" not in out
    code, out, err = run_cli(capsys, *commands(runs)["compare"], "--model", "builtin:vmc")
    assert code == 0, err
    assert "tcp: measured - predicted against the predicted 90 % interval [µm]" in (
        out.splitlines())
    assert "[um]" not in out


def test_the_corner_table_names_the_axes_of_its_coordinates(capsys, tmp_path):
    """The corner table of a G18 run listed its corners as "at, mm" 0.000, 25.400: in the
    plane's order Z, X, which the head did not say, so the corner read as X 0, Z 25.4."""
    prog = tmp_path / "p.nc"
    prog.write_text("G21 G90 G18\nG1 X25.4 Z0 F2500\nG2 X0 Z25.4 I-25.4 K0\nM30\n")
    run = str(tmp_path / "r.csv")
    assert run_cli(capsys, "simulate", "builtin:vmc", "--gcode", str(prog), "-o", run)[0] == 0
    code, out, err = run_cli(capsys, "contour", run)
    assert code == 0, err
    head = next(ln for ln in out.splitlines() if ln.startswith("#"))
    assert "at Z, X mm" in head, out
    assert any(ln.split()[1:3] == ["0.000,", "25.400"] for ln in out.splitlines()
               if ln.startswith("1 ")), out


#: A table as the circle's: two columns of names, seven of numbers [-]
TABLE_HEADS = ("dir", "sensor", "A", "B", "C", "D", "±95%", "contour", "G")
TABLE_ROWS = [("CCW", s, *[f"{v:.2f}" for v in (8.63 + k, 12.24 + k, -23.97, 12.26, 0.12,
                                                 73.51, 12.31)]) for k, s in
              enumerate(("motor", "scale", "tcp"))]


def _shown(terminal: bool, cols: int, *titles) -> list:
    """The lines :data:`TABLE_ROWS` is printed in by ``print_plain`` with ``titles`` (title,
    caption) on a console of ``cols`` columns, a terminal or not [-]."""
    import io
    import re

    from rich.console import Console

    from tcpmm.cli._tables import plain_table, print_plain

    buf = io.StringIO()
    screen = Console(file=buf, width=cols, force_terminal=terminal, no_color=True,
                     highlight=False)
    t = plain_table(TABLE_HEADS, left=("dir", "sensor"))
    for r in TABLE_ROWS:
        t.add_row(*r)
    print_plain(t, screen, *titles)
    return re.sub(r"\x1b\[[0-9;]*m", "", buf.getvalue()).splitlines()


@pytest.mark.parametrize("width", [40, 60, 80])
def test_a_wide_table_on_a_narrow_terminal_keeps_every_number_whole(width):
    """A table made with ``plain_table`` (the circle's, the contour's, Table 2) on a
    terminal of 60 columns had rich fold its cells: ``12.24`` read ``12.2`` with a ``4``
    on the line below. It is printed as tables one under the other, each with the
    leading name columns, every cell whole on its line; in a pipe it is one table, never
    wrapped."""
    lines = _shown(True, width, "title", "caption")
    assert all(len(line) <= width for line in lines)
    for r in TABLE_ROWS:  # each cell whole, on a line that names its row
        for cell in r[2:]:
            assert any(cell in line.split() and r[1] in line.split() for line in lines), cell
    piped = _shown(False, width, "title", "caption")
    assert sum(1 for line in piped if line.startswith("CCW")) == len(TABLE_ROWS)


@pytest.mark.parametrize("width", [12, 20])
def test_a_table_on_a_terminal_too_narrow_for_its_names_and_a_column_keeps_its_numbers(
        width):
    """On 20 columns the circle's table had no header and no number left: rich squeezed
    the nine columns into the width and blanked the cells. Each column is now a table of
    its own after the names, wider than the terminal, every number whole on the line of
    its row."""
    lines = [ln.split() for ln in _shown(True, width, "title")]
    for h in TABLE_HEADS[2:]:
        assert ["dir", "sensor", h] in lines, h
    for r in TABLE_ROWS:
        for cell in r[2:]:
            assert [r[0], r[1], cell] in lines, cell


def test_help_in_a_pipe_is_not_wrapped_nor_cut_short():
    """Piped to a file, the help was wrapped at 80 columns and the list of commands cut
    their summaries short with '...': a sentence of ``tune --help`` came in pieces and the
    summary of ``path`` lost its end. Read from a pipe, each stays on one line, whole."""
    env = dict(os.environ, PYTHONPATH=str(SRC), COLUMNS="60")

    def helped(*args):
        script = "import sys; from tcpmm.cli import main; sys.exit(main())"
        done = subprocess.run([sys.executable, "-c", script, *args, "--help"], env=env,
                              capture_output=True, text=True,
                              timeout=120)
        assert done.returncode == 0, done.stderr
        return done.stdout.splitlines()

    top = helped()
    path = next(line for line in top if line.lstrip().startswith("path "))
    assert path.rstrip().endswith("which limit holds it back where it does not."), path
    assert not any(line.rstrip().endswith("...") for line in top[1:]), top
    tune = helped("tune")
    assert any("predict the path before and after." in line
               and line.lstrip().startswith("Propose velocity-loop gains") for line in tune)


@pytest.mark.parametrize(("share", "decimals", "text"), [
    (0.998, 0, "99.8%"), (0.002, 0, "0.2%"), (1.0, 0, "100%"), (0.0, 0, "0%"),
    (0.49, 0, "49%"), (0.99996, 1, "99.996%"), (0.5, 1, "50.0%")])
def test_a_share_short_of_whole_never_reads_whole(share, decimals, text):
    """compensate said "no sample's error rises, on 100% of the samples (trusted)" above
    "on 0.2% of the samples the draws cannot rule out a rise", and "headroom 0.999: 0% of
    the axes' acceleration"; path "at the programmed feed on 100.0 %" beside a stretch
    below it. A share strictly between 0 and 1 keeps the decimals that say so."""
    from tcpmm.cli._tables import percent

    assert percent(share, decimals) == text
