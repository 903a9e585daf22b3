"""Output fit for pipes and logs: every result table in the one plain style, titles and
captions on lines of their own that are never wrapped and end without spaces.

Everything is captured from streams that are no terminal, so nothing here depends on the
terminal's width or on the temporary folder's length."""

from pathlib import Path

import numpy as np
import pytest

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


def run(capsys, *args):
    code = main([str(a) for a in args])
    cap = capsys.readouterr()
    return code, cap.out, cap.err


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
    code, out, err = run(capsys, *commands(runs)[name])
    assert code == 0, err
    assert not BOXED & set(out), out
    rules = [line for line in out.splitlines() if line and set(line) <= {"─", " "}]
    assert rules, out  # each table's head is ruled


@pytest.mark.parametrize("name", ["contour", "circle", "frf show", "compare", "tune"])
def test_no_line_in_a_pipe_ends_in_spaces(capsys, runs, name):
    """Titles and captions were centred and padded to the table's width, and each row to
    the last column's: a log held spaces at the end of most lines."""
    code, out, err = run(capsys, *commands(runs)[name])
    assert code == 0, err
    assert [line for line in out.splitlines() if line != line.rstrip()] == []


def test_titles_and_captions_are_lines_of_their_own(capsys, runs):
    """A caption was word-wrapped to its table's width and centred: 'overshoot: outside
    the path ... settled within 1 µm' came in three pieces, and a grep for a figure in it
    failed. Titles and captions are now lines of their own, never wrapped in a pipe."""
    code, out, _ = run(capsys, *commands(runs)["contour"])
    lines = out.splitlines()
    assert code == 0 and "corners, tcp" in lines and "signed, +: left of travel" in lines
    assert any(line.startswith("overshoot: outside the path past the corner, rounding: ")
               and line.endswith("settled within 1 µm") for line in lines), out
    code, out, _ = run(capsys, *commands(runs)["circle"])
    lines = out.splitlines()
    assert code == 0 and f"{runs / 'circle.csv'} [µm]" in lines
    assert "circle diagnostics (tcp) [µm]" in lines
    assert "terms ranked by their contribution" in lines
    assert any(line.startswith("A-D: reversal spike after the fitted terms")
               and line.endswith("G circular deviation") for line in lines), out
    assert any(line.startswith("contribution: peak to valley")
               and line.endswith("it shows in the contour error)") for line in lines), out
    code, out, _ = run(capsys, *commands(runs)["tune"])
    lines = out.splitlines()
    assert code == 0 and "axis X: tuning for 6 dB / 45 deg: met" in lines
    code, out, _ = run(capsys, *commands(runs)["compare"])
    assert code == 0
    assert ("measured - predicted (raw spikes e - b, as in the paper's Table 2)"
            in out.splitlines())
