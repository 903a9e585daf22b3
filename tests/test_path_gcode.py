"""G-code interpreter: words, modal state, arcs, warnings, and errors with line and column."""

from __future__ import annotations

import math
import re
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tcpmm.errors import InputError, InputWarning
from tcpmm.path import Arc, Dwell, Line, Rapid, parse_gcode, program_to_command
from tcpmm.path.gcode_stream import run_program


def _parse(text, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("error", InputWarning)
        return parse_gcode(text, **kw)


def test_lines_units_distance_modes_and_modal_state():
    segs = _parse(
        "%\n"
        "N10 G21 G90 (mm, absolute)\n"
        "N20 G1 X10 Y-5 F600 ; first feed move\n"
        "N30 Z2.5\n"  # G1 and F are modal
        "G91 X1 Y1\n"
        "G20 X1\n"  # incremental, inch
        "G0 G90 X0 Y0 Z0\n"
        "%\n"
    )
    assert [type(s) for s in segs] == [Line, Line, Line, Line, Rapid]
    assert segs[0].end_m == pytest.approx((0.01, -0.005, 0.0))
    assert segs[0].feed_m_per_s == pytest.approx(0.01)
    assert segs[1].end_m == pytest.approx((0.01, -0.005, 0.0025))
    assert segs[2].end_m == pytest.approx((0.011, -0.004, 0.0025))
    assert segs[3].end_m == pytest.approx((0.011 + 0.0254, -0.004, 0.0025))
    assert segs[3].feed_m_per_s == pytest.approx(0.01)  # F is kept in SI when units change
    assert segs[4].end_m == (0.0, 0.0, 0.0)
    assert [s.line for s in segs] == [3, 4, 5, 6, 7]


def test_feed_in_inch_per_minute_and_start_position():
    segs = _parse("G20 G1 X1 F10\n", start_position_m=(0.0, 0.0, 0.1))
    assert segs[0].start_m == (0.0, 0.0, 0.1)
    assert segs[0].feed_m_per_s == pytest.approx(0.254 / 60)


@pytest.mark.parametrize(
    ("plane", "g", "words", "centre", "axes"),
    [
        (17, 3, "X0 Y10 I-10 J0", (0.0, 0.0, 0.0), ("X", "Y")),
        (17, 2, "X0 Y10 I-10 J0", (0.0, 0.0, 0.0), ("X", "Y")),
        (18, 3, "Z0 X10 K-10 I0", (0.0, 0.0, 0.0), ("Z", "X")),
        (18, 2, "Z0 X10 K-10 I0", (0.0, 0.0, 0.0), ("Z", "X")),
        (19, 3, "Y0 Z10 J-10 K0", (0.0, 0.0, 0.0), ("Y", "Z")),
        (19, 2, "Y0 Z10 J-10 K0", (0.0, 0.0, 0.0), ("Y", "Z")),
    ],
)
def test_every_plane_and_direction_of_g2_g3(plane, g, words, centre, axes):
    # start on the first plane axis at +10 mm, end on the second at +10 mm
    first = axes[0]
    start = {"X": 0.0, "Y": 0.0, "Z": 0.0, first: 0.01}
    program = f"G0 {first}10\nG{plane} G{g} {words} F1000\n"
    segs = _parse(program)
    arc = segs[-1]
    assert isinstance(arc, Arc)
    assert arc.plane_axes == axes
    assert arc.centre_m == pytest.approx(centre)
    assert arc.start_m == pytest.approx(tuple(start.values()))
    # G3 turns the first plane axis into the second (quarter turn), G2 the long way round
    assert arc.sweep_rad == pytest.approx(math.pi / 2 if g == 3 else -1.5 * math.pi)
    cmd = program_to_command(program)
    p = {a: cmd.positions.get(a, np.zeros(cmd.time_s.size)) for a in "XYZ"}
    on_arc = cmd.meta["path_s_m"] >= 0.01
    a, b = p[axes[0]][on_arc], p[axes[1]][on_arc]
    assert np.abs(np.hypot(a, b) - 0.01).max() < 1e-12
    turn = np.unwrap(np.arctan2(b, a))
    assert (turn[-1] - turn[0]) == pytest.approx(arc.sweep_rad, abs=1e-3)
    assert np.all(np.diff(turn) * np.sign(arc.sweep_rad) >= 0)


def test_radius_form_short_and_long_way_and_full_circle_and_helix():
    short, long_ = _parse("G1 X10 F100\nG3 X0 Y10 R10\nG0 X10 Y0\nG3 X0 Y10 R-10\n")[1::2]
    assert short.centre_m == pytest.approx((0.0, 0.0, 0.0), abs=1e-15)
    assert short.sweep_rad == pytest.approx(math.pi / 2)
    assert long_.centre_m == pytest.approx((0.01, 0.01, 0.0))
    assert long_.sweep_rad == pytest.approx(1.5 * math.pi)
    full, helix = _parse("G1 X10 F100\nG2 I-10\nG2 I-10 Z-3\n")[1:]
    assert full.sweep_rad == pytest.approx(-2 * math.pi)
    assert full.length_m == pytest.approx(2 * math.pi * 0.01)
    assert helix.helix_m == pytest.approx(-0.003)
    assert helix.length_m == pytest.approx(math.hypot(2 * math.pi * 0.01, 0.003))


def test_absolute_arc_centres_dwell_and_exact_stop():
    segs = _parse("G1 X10 F100\nG90.1 G3 X0 Y10 I0 J0\nG4 P0.5\nG4 X0.25\nG61 G1 X5\nG64 X0\n")
    assert segs[1].centre_m == pytest.approx((0.0, 0.0, 0.0))
    assert isinstance(segs[2], Dwell) and segs[2].duration_s == 0.5
    assert segs[3].duration_s == 0.25 and segs[3].position_m == pytest.approx((0, 0.01, 0))
    assert segs[4].exact_stop and not segs[5].exact_stop


def test_harmless_words_warn_once_per_kind_with_their_first_line():
    text = "O100\nG17 G40 G49 G54 G80 G94\nS1000 M3\nT1 M6\nG1 X1 F100 M8\nX2 S2000\nM5\nM30\nX9\n"
    with pytest.warns(InputWarning) as record:
        segs = parse_gcode(text, "prog.nc")
    assert len(segs) == 2  # X9 after M30 is not executed
    msgs = [str(w.message) for w in record]
    assert any("prog.nc, line 3, column 1: S ignored (and 1 more time)" in m for m in msgs)
    assert any("line 2, column 13: G54 ignored" in m for m in msgs)
    assert any("M8 ignored" in m and "coolant" in m for m in msgs)
    assert any("line 9: blocks after M2/M30 ignored: the program ends on line 8" in m for m in msgs)
    keys = [m.split(": ")[1].split(" ignored")[0] for m in msgs]
    assert len(keys) == len(set(keys))  # one warning per kind


def test_ignored_words_are_said_in_the_order_of_the_program():
    """'G1 X10 F1000 S1000 M3 T1' said S (column 14), T (23), then M3 (20): the words are
    read by kind, and the warnings came in that order."""
    with pytest.warns(InputWarning) as record:
        parse_gcode("G21 G90\nG1 X10 F1000 S1000 M3 T1\nG43 H1\nG1 Y10\nM30\n", "p.nc")
    at = [tuple(int(x.split()[-1]) for x in str(w.message).split(": ")[0].split(", ")[1:3])
          for w in record if "ignored" in str(w.message)]
    assert at == sorted(at) and len(at) == 5, at


ERRORS = [
    # (program, line, column, part of the message)
    ("G1 X10\n", 1, 1, "no feed rate"),
    ("G0 X5\nX10 Y3 G1\n", 2, 8, "no feed rate"),
    ("G1 X5 F100\nG2 X10 Y0 I3 J0\n", 2, 11, "radius to the start is 3 mm but to the end 2 mm"),
    ("G1 X1 F100 Q5\n", 1, 12, "Q is only read with G64 (and ignored there); remove it"),
    ("G1 X1O F100\n", 1, 6, "a zero typed as the letter O? write X10 for X1O"),
    ("G1 X1 F100 O\n", 1, 12, "letter O has no number after it; write e.g. O0"),
    ("G1 X1.2.3 F100\n", 1, 4, "malformed number '1.2.3'"),
    ("G1 X1 F100\nG2 X1 Y0 R5\n", 2, 10, "full circle"),
    ("G2 X0 Y0 I0 J0 F100\n", 1, 10, "zero radius"),
    # a full circle of 0.1 nm was drawn; within the radii's tolerance no arc is defined
    ("G1 X10 F100\nG2 X10 Y0 I0.0000001 J0\n", 2, 11, "arc of zero radius: the centre is "
     "1e-07 mm from the start or end point, within the arcs' tolerance of 0.005 mm"),
    ("G20 G1 X1 F10\nG2 X1 Y0 I0.0001 J0\n", 2, 10, "0.0001 in from the start"),
    ("G1 X5 F100\nG3 X10 R0\n", 2, 8, "zero"),
    ("G1 X1 X2 F100\n", 1, 7, "X is given twice"),
    ("X10\n", 1, 1, "without a motion mode"),
    ("G1 X1 F0\n", 1, 7, "feed F0 must be positive"),
    ("G1 X1 F100 (unclosed\n", 1, 12, "not closed"),
    ("G1 X1 F100 (a (b) c)\n", 1, 15, "nested"),
    ("G1 X1 F100 )\n", 1, 12, "without a '('"),
    ("G41 G1 X1 F100\n", 1, 1, "G41 cannot be used"),
    ("G2 G3 X1 I1 F100\n", 1, 4, "both motion codes"),
    ("G4\n", 1, 1, "G4 needs the dwell time"),
    ("G4 P1 X1\n", 1, 7, "not both"),
    # with G1 modal, X20 is most often the move's end written before the dwell
    ("G1 X10 F100\nX20 G4 P1\n", 2, 1, "X20 is read as a second dwell time; if it is a "
     "move's end point, put the dwell (P1) in a block of its own"),
    # Y is never a dwell's time
    ("G1 X10 F100\nG4 P1 G1 Y5\n", 2, 7, "Y5 is the move's end point, which a dwell does "
     "not take"),
    # a dwell of 20 s, the move dropped; with P, "not both" named the move's X20
    ("G1 X20 G4\n", 1, 1, "G4 (dwell) and G1 in one block: X20 would be the move's end"),
    ("G1 X20 G4 P1\n", 1, 1, "put the dwell in a block of its own"),
    ("G4 P-1\n", 1, 4, "must not be negative"),
    ("G4 P1 Y2\n", 1, 7, "cannot be used in a G4"),
    ("G1 X1 F100 A5\n", 1, 12, "axis A is not modelled"),
    ("G17 G2 X10 K5 F100\n", 1, 12, "K is not a centre word of the G17 plane"),
    ("G1 X0 F100\nG2 X10 Y0 R2\n", 2, 11, "smaller than half the distance"),
    ("G1 I5 F100\n", 1, 4, "I is only used with G2/G3"),
    ("M98 P100\n", 1, 1, "subprograms"),
    ("G1 X1 F100 P2\n", 1, 12, "P is only used with G4"),
    ("N1.5 G1 X1 F100\n", 1, 1, "whole number"),
    ("G1 X1 5 F100\n", 1, 7, "unexpected character '5'"),
    ("G1 X F100\n", 1, 4, "letter X has no number"),
    ("G2 X10 I5 R5 F100\n", 1, 11, "not both"),
    ("G2 X10 F100\n", 1, 1, "needs the centre"),
    ("G65 X1\n", 1, 1, "G65 cannot be used"),
    ("G1.5 X1\n", 1, 1, "G1.5 cannot be used"),
    ("G90.1 G2 X10 I5 F100\n", 1, 14, "both I and J"),
    ("M3.5\n", 1, 1, "not an M-code"),
    ("G1 X1 F100 #1=5\n", 1, 12, "'#1=5' is a variable or an expression"),
    ("G1 X1 F100\n/G1 X2\n", 2, 1, "block delete is not read: remove the '/'"),
    ("G1 X1e3 F100\n", 1, 4, "exponent notation 'X1e3' is not G-code; write the number "
     "out, e.g. X1000"),
    ("G1 X1 F1.5E-2\n", 1, 7, "e.g. F0.015"),
    ("G1 X1 E3 F100\n", 1, 7, "unknown word letter E"),
    # a letter O for a zero: X1O.5 went to X1, with a warning about the program number
    ("G1 X0 Y0 F100\nG1 X1O.5 Y5\n", 2, 6, "a letter O for a zero?"),
    ("G1 X1 F100 O12\n", 1, 12, "O (a program number) after other words"),
]


@pytest.mark.parametrize(("text", "line", "column", "msg"), ERRORS)
def test_errors_name_file_line_and_column(text, line, column, msg):
    with pytest.raises(InputError) as info:
        parse_gcode(text, "bad.nc")
    err = info.value
    assert (err.file, err.line, err.column) == ("bad.nc", line, column)
    assert msg in err.message
    assert str(err).startswith(f"bad.nc, line {line}, column {column}: ")


MALFORMED = [
    "",
    "%\n%\n",
    "G1 X1\n",
    "G2 X1 Y1 F100\n",
    "G3 X1 Y1 I0.0001 J0 F100\n",
    "G1 X1 F-100\n",
    "G1 X1 F100\nG1 X1\n",  # zero-length move only
    "G1 X1 F0.000001\n",  # would last far too long
    "G0 X1e\n",
    "G1 X--1 F1\n",
    "G1 X+ F1\n",
    "G1 X. F1\n",
    "G18 G2 X1 J1 F100\n",
    "G1 X1 F100 G1\n",
    "G1 X1 F100 G0\n",
    "G1 X1 F100 F200\n",
    "(\n",
    ";only a comment\n",
    "G4 P0\n",  # a dwell of nothing is fine; a program of nothing is not
    "\x00G1 X1 F100\n",
    "G1 X1 F100\nG2 X1 Y1 R0.0001\n",
    "G1 X99999999999 F100\n",
]


@pytest.mark.parametrize("text", MALFORMED)
def test_malformed_programs_fail_only_with_input_error(text):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", InputWarning)
        try:
            cmd = program_to_command(text)
        except InputError as err:
            assert err.message  # says what is wrong
        else:
            assert np.all(np.isfinite(cmd.positions["X"]))


_tokens = st.sampled_from([*"GXYZIJKRFPNMST0123456789.-+ ()%;\n", "G1 ", "G2 ", "F99 "])


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(text=st.lists(_tokens, max_size=40).map("".join))
def test_random_text_parses_or_raises_input_error(text):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", InputWarning)
        try:
            segs = parse_gcode(text)
        except InputError as err:
            assert err.line is not None
            return
    for s in segs:
        assert all(math.isfinite(c) for c in s.start_m + s.end_m)


def test_program_file_errors_name_the_file(tmp_path):
    path = tmp_path / "p.nc"
    path.write_text("G1 X1 F100\nG1 Y1 Q1\n")
    with pytest.raises(InputError) as info:
        program_to_command(path)
    assert info.value.file == str(path) and info.value.line == 2
    with pytest.raises(InputError, match="not found"):
        program_to_command(tmp_path / "missing.nc")
    path.write_text("G1 X1 F100\n", encoding="utf-16")
    with pytest.raises(InputError, match="not plain text") as info:
        program_to_command(path)
    assert info.value.file == str(path)
    with pytest.raises(InputError, match="not found"):
        program_to_command(str(tmp_path / "missing.nc"))
    # a command file given as a program read "letter T has no number after it"
    path.write_text("time_s,x_mm,y_mm\n0,0,0\n0.001,0.001,0\n")
    with pytest.raises(InputError, match=r"is a table .* a command file goes to --command"):
        program_to_command(path)


def test_a_closing_percent_ends_the_program_as_controllers_do():
    text = "%\nG90 G21 F1000\nG1 X10\n%\nG1 X99\n"
    with pytest.warns(InputWarning, match=r"line 5.*blocks after the closing % ignored"):
        segs = parse_gcode(text)
    assert [s.end_m[0] for s in segs] == [pytest.approx(0.01)]
    # without an opening %, the first % after blocks ends the program too
    with pytest.warns(InputWarning, match="closing %"):
        assert len(parse_gcode("G1 X10 F1000\n%\nG1 X50\n")) == 1
    # an opening % alone, and a closing % with nothing after it, say nothing
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert len(parse_gcode("%\nG1 X10 F1000\n%\n")) == 1


def test_blocks_on_a_percent_line_are_an_error_not_dropped():
    with pytest.raises(InputError, match=r"line 2, column 2.*'%' line"):
        parse_gcode("%\n%G1 X50 F1000\n")
    assert len(parse_gcode("% (program 12)\nG1 X10 F1000\n")) == 1


@pytest.mark.parametrize("sep", ["\n", "\r\n", "\r"])
def test_line_numbers_count_only_line_breaks(sep):
    """A form feed, or \\x85 (cp1252's ellipsis read as latin-1) in a comment, ended a
    line for str.splitlines, and every error after it named a line too far."""
    text = sep.join(["G21 G90", "(page\x0c two)", "(wait\x85)", "G1 X1.2.3", ""])
    with pytest.raises(InputError) as e:
        parse_gcode(text, "p.nc")
    assert (e.value.line, e.value.column) == (4, 4)


def test_a_form_feed_in_a_block_is_named():
    with pytest.raises(InputError, match=r"unexpected character '\\x0c' \(a control") as e:
        parse_gcode("G21 G90\nG1 X10 F1000\x0cG1 X20\nG1 X1.2.3\n", "p.nc")
    assert (e.value.line, e.value.column) == (2, 13)


@pytest.mark.parametrize(("ch", "words"), [
    ("\xa0", "(a no-break space, not a plain one; replace it with a space)"),
    ("\u2009", "(a thin space, not a plain one; replace it with a space)"),
    ("\u200b", "(an invisible zero width space; remove it)"),
    ("\ufeff", "(an invisible zero width no-break space; remove it)"),
])
def test_a_blank_of_another_kind_is_named_as_what_it_is(ch, words):
    """A no-break space (text pasted from a word processor or a PDF), a zero-width space
    or a byte-order mark within the file shows as a blank or as nothing, and was called
    "a control character": the user looked for one and found none. Read whole or
    streamed, the message says what it is and the fix."""
    from tcpmm.path.stream import stream_program

    text = f"G21 G90\nG1 X10 F1000\nG1{ch}X20\n"
    for read in (lambda: parse_gcode(text, "p.nc"),
                 lambda: list(stream_program(text, chunk_blocks=1))):
        with pytest.raises(InputError) as e:
            read()
        assert words in e.value.message
        assert (e.value.line, e.value.column) == (3, 3)


@pytest.mark.parametrize(("text", "column", "needle"), [
    ("G" + "9" * 400, 1, "the number after G has 400 characters"),
    ("G1 X" + "9" * 400 + " F100", 4, "the number after X has 400 characters"),
    ("G" + "9" * 30, 1, "is not a G-code"),
    ("M" + "9" * 30, 1, "is not an M-code"),
    ("M" + "9" * 400, 1, "the number after M has 400 characters"),
])
def test_numbers_of_hundreds_of_digits(text, column, needle):
    """A number of 309 digits or more is infinite as a float, and a G or M code took its
    round() or int(): an OverflowError traceback. Long words are cut short in the
    message."""
    with pytest.raises(InputError, match=needle) as e:
        parse_gcode(f"G21 G90\n{text}\nM30\n", "p.nc")
    assert (e.value.line, e.value.column) == (2, column)
    assert len(str(e.value)) < 200


@pytest.mark.parametrize(("block", "line", "column", "needle"), [
    ("G1 X10 Y1000000000000000000 F1000", 2, 8, "Y would be at 1e+18 mm, beyond 1e+06 mm"),
    ("G91 G1 X900000 F1000\nX200000", 3, 1, "X would be at 1.1e+06 mm"),
    ("G20 G1 X40000 F10", 2, 8, "X would be at 40000 in, beyond 39370.1 in"),
    ("G2 X10 Y0 R10000000 F1000", 2, 11, "R10000000 is beyond 1e+06 mm"),
    ("G2 X0 Y0 I-10000000 F1000", 2, 10, "I-10000000 is beyond 1e+06 mm"),
    ("G1 X10 F10000000", 2, 8, "feed F10000000 is above F1000000"),
])
def test_numbers_beyond_any_machine(block, line, column, needle):
    """A coordinate of 1e18 mm interpolated to a command of two samples, exit 0: the
    travel's duration overflowed the sample counter. A coordinate, centre offset or
    radius beyond a thousand metres, or a feed beyond 1000 m/min, is a typo."""
    with pytest.raises(InputError, match=re.escape(needle)) as e:
        parse_gcode(f"G21 G90\n{block}\nM30\n", "p.nc")
    assert (e.value.line, e.value.column) == (line, column)


def test_a_long_dwell_written_as_fanuc_writes_milliseconds_is_said():
    """P is read in seconds (LinuxCNC's dialect); a Fanuc program's G04 P500 (500 ms) ran
    a dwell of 500 s with no word. A whole P of 10 s or more is warned of, once, with the
    P that would mean the milliseconds; a P with a decimal point, or shorter, is not."""
    with pytest.warns(InputWarning) as said:
        segs = parse_gcode("G21\nG1 X5 F1000\nG04 P500\nG4 P20\nM30\n", "f.nc")
    (w,) = [str(m.message) for m in said]
    assert w.startswith("f.nc, line 3, column 5: G4 P500 rests 500 s (and 1 more time): ")
    assert "a Fanuc control reads P500 in ms (write P0.5 for that)" in w
    assert [s.duration_s for s in segs if isinstance(s, Dwell)] == [500.0, 20.0]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        parse_gcode("G21\nG1 X5 F1000\nG4 P12.0\nG4 P2\nG4 X30\nM30\n", "f.nc")


@pytest.mark.filterwarnings("ignore::tcpmm.errors.InputWarning")  # the dwell's P, said
@pytest.mark.parametrize("block", ["G1 X10 F0.000000000000000000001", "G4 P" + "9" * 30])
def test_a_command_too_long_to_count_is_refused(block):
    """Ten millimetres at 1e-21 mm/min last 6e23 s: their periods overflowed the 64-bit
    counter of the compiled timeline into a command of two samples, exit 0."""
    with pytest.raises(InputError, match="the command would last") as e:
        program_to_command(f"G21 G90\n{block}\nM30\n")
    assert e.value.line == 2


def test_the_interpolators_errors_name_the_program_file(tmp_path):
    """What the interpolator refuses named the line but not the file, as `tcpmm path`
    printed it; the interpreter's errors named both."""
    prog = tmp_path / "s.nc"
    prog.write_text("G21 G90\nG1 X10 F0.0000001\nM30\n")
    with pytest.raises(InputError, match="the command would last") as e:
        program_to_command(prog)
    assert (e.value.file, e.value.line) == (str(prog), 2)
    assert str(e.value).startswith(f"{prog}, line 2: ")


def test_repeated_points_are_skipped_and_counted():
    """CAM output repeats points; a controller skips such blocks. The path is the one
    without them, and one warning counts them all, G0 as G1, with the first line."""
    clean = "G21 G90\nG1 X10 Y0 F3000\nG1 X10 Y10\nG1 X0 Y10\nM30\n"
    repeated = "G21 G90\nG1 X10 Y0 F3000\nG1 X10 Y0\nG1 X10 Y10\nG1 X10.000 Y10\nG0 X10 Y10\n" \
               "G1 X0 Y10\nM30\n"
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        got = parse_gcode(repeated, "cam.nc")
    want = parse_gcode(clean)
    assert [(s.start_m, s.end_m) for s in got] == [(s.start_m, s.end_m) for s in want]
    said = [str(w.message) for w in caught if "zero-length" in str(w.message)]
    assert said == ["cam.nc, line 3, column 4: zero-length move ignored (and 2 more times): "
                    "a G0 or G1 to where the tool already is, skipped"]


def said_by(it) -> list[str]:
    """The warnings an interpreter gives at the end of its program, as texts."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        it.emit_warnings()
    return [str(w.message) for w in caught]


#: a G1 to X2, then two G0 and one G1 to where the tool stands (lines 4, 5 and 7)
G0_REPEATS = "G21 G90 G17\nG1 X1 Y0 F3000\nX2\nG0 X2\nG0 X2\nG1 X3\nX3\nM30\n"


@pytest.mark.parametrize("fast", [True, False])
def test_a_rapid_to_where_the_tool_stands_is_counted_as_a_feed_move_is(fast):
    """Two G0 to where the tool stood were skipped without a word and not counted: the
    summary said one repeated point of three, and the fast parser and the reference
    alike."""
    it = run_program(G0_REPEATS, "z.nc", (0.0, 0.0, 0.0), fast=fast)
    assert said_by(it) == [
        "z.nc, line 4, column 4: zero-length move ignored (and 2 more times): a G0 or G1 to "
        "where the tool already is, skipped"]
    assert [type(s) for s in it.segments] == [Line, Line, Line]


def test_zero_length_skipped_reads_the_count_of_the_warning_alone():
    from tcpmm.path.gcode import zero_length_skipped

    said = ["p.nc, line 4, column 4: zero-length move ignored (and 2 more times): a G0 or G1 "
            "to where the tool already is, skipped",
            "p.nc, line 9, column 1: M3 ignored (and 5 more times): spindle",
            "zero-length move.nc, line 2, column 1: M8 ignored: coolant",
            "q.nc, line 3, column 4: zero-length move ignored: a G0 or G1 to where ..."]
    assert zero_length_skipped(said) == 4
    assert zero_length_skipped([]) == 0


@pytest.mark.parametrize("prog", [
    "G21 G90 F3000\nG1 X0 Y0.001\nG91\nG1 X0.3 Y0.1\nX0.3 Y0.1\nX0.3 Y0.1\nG90\n"
    "G1 X0.9 Y0.301\nG1 X1.8 Y0.601\nM30\n",
    "G21 G90 F3000\nG91\n" + "G1 X0.1\n" * 10 + "G90 G1 X1.0\nG1 X2.0\nM30\n"])
def test_a_move_rounding_left_is_skipped_as_a_repeated_point(prog):
    """0.3 + 0.3 + 0.3 mm in G91 is 0.8999999999999999 mm: the G90 move to X0.9 then went
    1e-16 mm, in a direction of its own, and the feed fell to 96 mm/min at a corner of no
    size on a straight line (ten G91 X0.1, then G90 X1.0: to a stop). Such a move is
    skipped as a repeated point is, with its warning."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        cmd = program_to_command(prog)
    assert any("zero-length move" in str(w.message) for w in caught)
    p = np.array([cmd.positions["X"], cmd.positions["Y"]])
    speed = np.linalg.norm(np.diff(p, axis=1), axis=0)
    top = int(np.argmax(speed))  # the feed rises to its top and falls once: no dip
    assert np.all(np.diff(speed[:top]) >= -1e-12) and np.all(np.diff(speed[top:]) <= 1e-12)


@pytest.mark.parametrize("fast", [True, False])
def test_a_header_rapid_to_the_start_repeats_no_point_but_a_later_one_does(fast):
    """A program's first G0 to where the tool starts (``G0 X0 Y0`` of a header, as the
    shipped example has) repeats no point the program has programmed, and is not counted;
    the same G0 after the tool has moved away and back is a repeated point."""
    program = "G90 G21\nG0 X0 Y0\nG1 X5 F1000\nG1 X3 Y2\nG0 X0 Y0\nG0 X0 Y0\n"
    assert said_by(run_program(program, "h.nc", (0.0, 0.0, 0.0), fast=fast)) == [
        "h.nc, line 6, column 4: zero-length move ignored: a G0 or G1 to where the tool "
        "already is, skipped"]


@pytest.mark.parametrize("fast", [True, False])
def test_a_dwell_before_the_header_rapid_programs_no_point(fast):
    """A dwell programs no point: a G0 to the start after it is still the header's, not a
    repeated point. The reference parser counted it (the dwell was a segment, so the tool
    had "moved"), the fast one did not; the hypothesis test comparing them found
    ``G4 P0.1`` then ``G0 X0``."""
    assert said_by(run_program("G4 P0.1\nG0X0.0000\n", "d.nc", (0.0, 0.0, 0.0),
                               fast=fast)) == []
