"""A length written without a decimal point: X50000 is 50 m here and 50 mm on a Fanuc
control without calculator-type input, which reads it in 0.001 mm. It is warned of once a
program, at its first line and word, whole or streamed, by the fast path as by the
reference."""

from __future__ import annotations

import warnings

import pytest

from conftest import run_cli
from tcpmm.errors import InputWarning
from tcpmm.io.text import file_lines
from tcpmm.path import gcode_stream, parse_gcode
from tcpmm.path.gcode_fast import scan_chunk
from tcpmm.path.gcode_words import NO_POINT

FANUC = ("O0001\nN10 G21 G90 G17\nN20 G0 X0 Y0\nN30 G1 X50000 Y0 F3000\nN40 Y50000\n"
         "N50 X0\nN60 Y0\nN70 M30\n")
SAID = ("p.nc, line 4, column 8: X50000 has no decimal point: tcpmm reads it as 50000 mm; "
        "a Fanuc control without calculator-type input reads it in 0.001 mm (50 mm): "
        "write X50. if that is meant")


def _said(text: str) -> list[str]:
    """The warnings of the program, as texts [-]."""
    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("always")
        parse_gcode(text, "p.nc")
    return [str(w.message) for w in record if issubclass(w.category, InputWarning)]


def test_a_fanuc_program_without_points_is_warned_of_once():
    said = [s for s in _said(FANUC) if "decimal point" in s]
    assert said == [SAID]


@pytest.mark.parametrize("word", ["X50.", "X500", "X999", "X-999", "X50.000", "X1000.0"])
def test_a_point_or_a_length_below_a_metre_is_not_warned_of(word):
    text = f"G21 G90 G17\nG0 X0 Y0\nG1 {word} Y0 F3000\nG1 X0 Y1000.\n"
    assert not [s for s in _said(text) if "decimal point" in s]


def test_the_feed_is_no_length():
    assert not [s for s in _said("G21 G90\nG1 X10. Y0 F12000\n") if "decimal point" in s]


def test_centre_words_radii_and_inches_are_lengths():
    said = _said("G21 G90 G17\nG1 X0 Y0 F3000\nG2 X0. Y20. R-10000\n")
    assert any("line 3, column 13: R-10000 has no decimal point: tcpmm reads it as -10000 mm"
               in s for s in said)
    said = _said("G20 G90 G17\nG1 X0 Y0 F30\nG1 X1.5 Y12345\n")
    assert any("line 3, column 9: Y12345 has no decimal point: tcpmm reads it as 12345 in; "
               "a Fanuc control without calculator-type input reads it in 0.0001 in "
               "(1.2345 in): write Y1.2345 if that is meant" in s for s in said)


def test_a_dwell_time_in_x_is_no_length():
    """G4 X is a time (seconds) [-]."""
    assert not [s for s in _said("G4 X2000\nG1 X1. F100\n") if "decimal point" in s]


def _program(first_marked: int, blocks: int = 60) -> str:
    """Plain G1 blocks (runs long enough for the compiled run), with lengths without a
    point from block ``first_marked`` on, every third block [-]."""
    lines = ["G21 G90 G1 X0 Y0 F3000"]
    for k in range(1, blocks):
        x = f"{k * 1000}" if k >= first_marked and k % 3 == first_marked % 3 else f"{k}.5"
        lines.append(f"G1 X{x} Y{k % 5}.25")
    return "\n".join([*lines, "M30"]) + "\n"


@pytest.mark.parametrize("first_marked", [1, 2, 17, 40])
@pytest.mark.parametrize("chunk", [1, 4, 9, 25, 1000])
def test_whole_streamed_fast_and_reference_warn_alike(first_marked, chunk):
    text = _program(first_marked)
    ref = gcode_stream.run_program(text, "p.nc", (0.0, 0.0, 0.0), fast=False)
    assert ref.warned[NO_POINT][0][:2] == (first_marked + 1, 4)
    lines = file_lines(text)
    chunks = [lines[i:i + chunk] for i in range(0, len(lines), chunk)]
    segments = []
    for it in gcode_stream.interpret_chunks(chunks, "p.nc", (0.0, 0.0, 0.0)):
        segments += it.segments
        it.segments = []
    assert repr(it.warned) == repr(ref.warned)
    assert repr(segments) == repr(ref.segments)


def test_the_compiled_lexer_marks_a_length_without_a_point():
    lines = ["G1 X50000", "G1 X50.", "G1 X500", "X1 F3000", "G2 X1 Y1 R-1000", "Y-01000",
             "G1 X1 F100000", "N1 X50000", "G1 Z" + "9" * 20]
    codes, _, _ = scan_chunk(lines)
    assert codes[:, 3].tolist() == [1, 0, 0, 0, 1, 1, 0, 0, 1]


def test_the_command_line_warns_whole_and_streamed_alike(tmp_path, capsys):
    prog = tmp_path / "p.nc"
    # a square of 1 m at the fastest feed: the warning's line, in a run of seconds
    prog.write_text(FANUC.replace("50000", "1000").replace("F3000", "F30000"))
    want = (SAID.replace("p.nc", str(prog), 1).replace("50000", "1000")
            .replace("(50 mm)", "(1 mm)").replace("X50.", "X1."))
    said = []
    for extra in ([], ["--chunk-blocks", "2"]):
        code, _, err = run_cli(capsys, "path", prog, "-o", tmp_path / "cmd.csv", *extra)
        assert code == 0
        said.append([x for x in err.splitlines() if "decimal point" in x])
    assert said[0] == said[1] == [f"warning: {want}"]


def test_the_expression_stops_before_a_length_without_a_point():
    """Without the compiled lexer's scan, the expression's run leaves the line to the
    interpreter until the program has had the warning [-]."""
    from tcpmm.path.gcode import Interpreter
    from tcpmm.path.gcode_fast import plain_run

    lines = ["G1 X1. Y0 F3000", "X2.", "X3000 Y1.", "X4."]
    it = Interpreter("p.nc", (0.0, 0.0, 0.0))
    it.motion, it.feed = 1, 0.05
    assert plain_run(it, lines, 0) == 2
    it.warned[NO_POINT] = [(3, 1, "", ""), 1]
    assert plain_run(it, lines, 2) == 4


def test_the_compiled_scanner_takes_the_interpreters_threshold_and_column():
    """The scanner, compiled on its own, holds the threshold as a literal, and the fast
    path the scanner's column: were they to differ, the fast path would run a line the
    interpreter warns of."""
    from tcpmm.path import gcode_fast, gcode_scan, gcode_words

    assert gcode_scan._WHOLE_LENGTH == gcode_words.WHOLE_LENGTH
    assert gcode_fast._WHOLE_LONG == gcode_scan.WHOLE_LONG
