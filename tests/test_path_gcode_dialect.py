"""Other dialects' syntax in a program: macro variables, expressions, control statements
and other controllers' words are refused by name, with what to do, at their line and
column, through the reference tokeniser and the fast path alike."""

from __future__ import annotations

import pytest

from conftest import run_cli
from tcpmm.errors import InputError
from tcpmm.path import gcode_stream

HEAD = "G21 G90 G17\nG0 X0 Y0\n"
MACRO = "is a variable or an expression: variables and expressions (#1, [..], =) are not "
WORDS = "is a word of letters, not a letter and its number: control statements and other "

# (block on line 3, column, what the message says); "write e.g. X0" had been the fix for
# most of them, and following it changed the geometry
REFUSED = [
    ("G1 X#1 F100", 4, f"'X#1' {MACRO}"),
    ("G1 X[10+2] F100", 4, f"'X[10+2]' {MACRO}"),
    ("G1 X=R1 F100", 4, f"'X=R1' {MACRO}"),
    ("G1 X-#1 F100", 4, f"'X-#1' {MACRO}"),
    ("#1=5", 1, f"'#1=5' {MACRO}"),
    ("R1=5", 3, f"'R1=5' {MACRO}"),
    ("IF [#1 GT 0] GOTO 10", 1, f"'IF' {WORDS}"),
    ("WHILE [#1 LT 3] DO1", 1, f"'WHILE' {WORDS}"),
    ("ROT Z45", 1, f"'ROT' {WORDS}"),
    ("TRANS X10", 1, f"'TRANS' {WORDS}"),
    ("N20 MSG(\"roughing\")", 5, f"'MSG' {WORDS}"),
    ("CYCLE800()", 1, f"'CYCLE800' {WORDS}"),
    ("SOFT", 1, f"'SOFT' {WORDS}"),
    ("BRISK", 1, f"'BRISK' {WORDS}"),
    ("FFWON", 1, f"'FFWON' {WORDS}"),
    ("GOTO 10", 1, f"'GOTO' {WORDS}"),
    ("L X+10 Y+5 F3000", 1, "'L' with no number after it is no word of this dialect: "
     "control statements and other dialects"),
    # a letter of the dialect with its number left out: writing one is the fix
    ("G1 X F100", 4, "letter X has no number after it; write e.g. X0"),
    ("G1 X Y5 F100", 4, "letter X has no number after it; write e.g. X0"),
]


@pytest.mark.parametrize(("block", "column", "msg"), REFUSED)
@pytest.mark.parametrize("fast", [True, False])
def test_other_dialects_are_refused_by_name(block, column, msg, fast):
    text = f"{HEAD}{block}\nG1 X1 F100\n"
    with pytest.raises(InputError) as info:
        gcode_stream.run_program(text, "p.nc", (0.0, 0.0, 0.0), fast=fast)
    err = info.value
    assert (err.file, err.line, err.column) == ("p.nc", 3, column)
    assert err.message.startswith(msg), err.message
    assert "write e.g." not in err.message or block.startswith("G1 X ")


def test_a_macro_says_what_to_do():
    with pytest.raises(InputError) as info:
        gcode_stream.run_program(f"{HEAD}G1 X#1 F100\n", "p.nc", (0.0, 0.0, 0.0))
    assert "write the values out" in info.value.message
    with pytest.raises(InputError) as info:
        gcode_stream.run_program(f"{HEAD}IF [#1 GT 0] GOTO 10\n", "p.nc", (0.0, 0.0, 0.0))
    assert "post the program as ISO G-code" in info.value.message


def test_the_command_line_refuses_a_macro_in_one_line(tmp_path, capsys):
    prog = tmp_path / "p.nc"
    prog.write_text(f"{HEAD}G1 X#1 F100\nG1 X1 F100\n")
    code, out, err = run_cli(capsys, "path", prog, "-o", tmp_path / "cmd.csv")
    assert code == 2 and not out
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err
    assert lines[0].startswith(f"error: {prog}, line 3, column 4: 'X#1' {MACRO}")
