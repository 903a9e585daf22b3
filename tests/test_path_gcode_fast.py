"""The fast path for plain G0/G1 blocks against the reference tokeniser and interpreter:
the same segments, modal state and warnings, and the same errors, on generated programs."""

from __future__ import annotations

import contextlib
import math
import struct
import warnings

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tcpmm.errors import InputError
from tcpmm.path import gcode_stream, parse_gcode
from tcpmm.path.gcode_fast import PLAIN_MOVE, scan_chunk
from tcpmm.path.gcode_scan import ARC, NOT_PLAIN, PLAIN, PLAIN_SLOW
from tcpmm.path.runs import as_lines

# numbers the tokeniser takes and ones it refuses, in and out of range
NUMBERS = ["0", "-0", "+1", "1.", ".5", "-.25", "12.3456", "007", "-3", "1000000",
           "1000001", "0.0", "999999.9", "2e3", ".", "-", "1.2.3", "", "9" * 320,
           "50000", "-1000", "999", "1000.", "01000"]
SPACES = ["", " ", "  ", "\t"]
# lines the fast path leaves to the reference: modes, arcs, comments, junk
OTHER = ["G91", "G90", "G20", "G21", "G61", "G64 P0.01", "G9 G1 X1", "G2 X1 Y0 I0.5 J0",
         "G3 X0 Y0 R2", "G4 P0.1", "M30", "M3 S1000", "%", "(comment)", "X1 ; note",
         "X1 (a", "X1 X2", "Y1 X2", "G1 G0 X1", "F0", "F-5", "G1 F100", "T1 M6", "",
         "   ", "X1\f", "#1=2", "A5", "G17", "G18", "N10 G1 X2", "G1 X1e3", "G0", "g1x2y3"]


decimals = st.floats(-500.0, 500.0).map(lambda v: f"{v:.4f}")
feeds = st.floats(1.0, 1e4).map(lambda v: f"{v:.1f}")
# numbers of any length: up to 25 digits before and after the point, leading zeros, the
# shortest repr of a double; the compiled lexer converts some, the rest go to float
digits = st.text("0123456789", max_size=25)
long_numbers = st.one_of(
    st.tuples(st.sampled_from(["", "-", "+"]), digits, st.sampled_from([".", ""]), digits)
    .map("".join),
    st.floats(-1e6, 1e6).map(repr),
    st.floats(-1e3, 1e3).map(lambda v: f"{v:.{len(repr(v))}f}"))


@st.composite
def plain_line(draw):
    """A line shaped like a plain move, often one the fast path takes [-]."""
    parts = []
    if draw(st.booleans()):
        parts.append(draw(st.sampled_from(["G0", "G1", "G00", "G01", "g1", "G 1", "G2"])))
    letters = draw(st.lists(st.sampled_from("XYZF"), min_size=1, max_size=4, unique=True))
    if draw(st.integers(0, 3)):  # mostly in the order the fast path takes
        letters.sort(key="XYZF".index)
    else:  # or shuffled, a letter twice, lower case
        letters = draw(st.permutations(letters + draw(st.sampled_from([[], ["X"], ["y"]]))))
        letters = [c.lower() if draw(st.booleans()) else c for c in letters]
    for letter in letters:
        good = feeds if letter in "Ff" else decimals
        number = draw(st.one_of([good] * 5 + [st.sampled_from(NUMBERS), long_numbers]))
        parts.append(letter + draw(st.sampled_from(SPACES)) + number)
    sep = draw(st.sampled_from(SPACES))
    return draw(st.sampled_from(SPACES)) + sep.join(parts) + draw(st.sampled_from(SPACES))


# mostly plain lines, so that runs of them reach the fast path before an error
lines = st.one_of([plain_line()] * 4 + [st.sampled_from(OTHER)])
programs = st.tuples(st.sampled_from(["", "G1 F3000\n", "G0\n"]), st.lists(lines, max_size=25)
                     ).map(lambda p: p[0] + "\n".join(p[1]) + "\n")


def _outcome(text, fast):
    """What the program gives: segments, modal state and warnings, or the error [-]."""
    try:
        it = gcode_stream.run_program(text, "p.nc", (0.0, 0.0, 0.0), fast=fast)
    except InputError as err:
        return ("error", err.message, err.file, err.line, err.column)
    state = (it.pos, it.motion, it.feed, it.unit, it.absolute, it.exact_stop, it.tolerance)
    # repr keeps the sign of a zero, which == does not
    return ("ok", repr(it.segments), repr(state), repr(it.warned))


@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(programs)
def test_fast_path_matches_the_reference(text):
    assert _outcome(text, fast=True) == _outcome(text, fast=False)


@settings(max_examples=200, deadline=None)
@given(st.lists(plain_line(), min_size=1, max_size=10))
def test_fast_path_matches_the_reference_after_a_header(lines):
    text = "G21 G90 G1 X0 Y0 F3000\n" + "\n".join(lines) + "\n"
    assert _outcome(text, fast=True) == _outcome(text, fast=False)


# modal changes, arcs, numbered and commented blocks and malformed lines, to be mixed
# into runs of plain moves at random positions
MODAL = ["G91", "G90", "G20", "G21", "G61", "G64", "G64 P0.01", "G64 P0.02 Q0.1", "G9 G1 X1",
         "G17", "G18", "G19", "G90.1", "G91.1", "F1500", "G0", "G1", "G2", "G3"]
MALFORMED = ["X1 X2", "G1 X", "X1.2.3", "X-", "G1 X1e3", "A5", "G41 X1", "X1 (open",
             "X1 )", "((a))", "#1=2", "X1\f", "N-5 X1", "N1.5 X1", "G4", "G1 I1", "P1 X1",
             "M98", "F0", "G2 X0 Y0 R1", "X1 Y1 F-3", "G9", "g1 x2 e5", "G1 X#1",
             "X[1+2] Y1", "Y=R1", "R1=5", "ROT Z45", "L X+10", "IF [#1 GT 0] GOTO 10"]
signed = st.sampled_from(["-0.0", "0.0", "-0", "+0", "-0.000", "0.5", "-0.5", "-.0"])
coords = st.one_of([decimals] * 3 + [signed])


@st.composite
def arc_line(draw):
    """A G2/G3 block with I/J or R, most of them well formed for the current point [-]."""
    parts = [draw(st.sampled_from(["G2", "G3", "G02", "g3", ""]))]
    parts += [f"{L}{draw(coords)}" for L in draw(st.sampled_from(["XY", "X", "Y", "XYZ"]))]
    if draw(st.booleans()):
        parts.append(f"R{draw(st.one_of(decimals, signed))}")
    else:
        parts += [f"{L}{draw(coords)}" for L in draw(st.sampled_from(["IJ", "I", "J", "IK"]))]
    if draw(st.booleans()):
        parts.append(f"F{draw(feeds)}")
    return " ".join(p for p in parts if p)


@st.composite
def incremental_line(draw):
    """A plain move of small signed steps, -0.0 among them [-]."""
    letters = draw(st.lists(st.sampled_from("XYZ"), min_size=1, max_size=3, unique=True))
    letters.sort()
    head = draw(st.sampled_from(["", "G1 ", "G0 ", "N10 ", "N20 G1 "]))
    tail = draw(st.sampled_from(["", " F2000", " F1000001", " F0", " (c)", " ; c"]))
    return head + " ".join(f"{L}{draw(coords)}" for L in letters) + tail


mixed_lines = st.one_of([plain_line()] * 3 + [incremental_line()] * 3 + [
    arc_line(), st.sampled_from(MODAL), st.sampled_from(MALFORMED), st.sampled_from(OTHER)])
mixed_programs = st.tuples(
    st.sampled_from(["", "G1 F3000\n", "G91 G1 F3000\n", "G21 G90 G64 P0.01 G1 X0 Y0 F3000\n"]),
    st.lists(mixed_lines, max_size=40)).map(lambda p: p[0] + "\n".join(p[1]) + "\n")


@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(mixed_programs)
def test_fast_path_matches_the_reference_on_mixed_programs(text):
    assert _outcome(text, fast=True) == _outcome(text, fast=False)


_PLANE_WORDS = {"G17": ("XYZ", "IJ"), "G18": ("ZXY", "KI"), "G19": ("YZX", "JK")}


@st.composite
def arc_program(draw):
    """Arcs that chain from the current point (centre words or R, in every plane, absolute
    or incremental, centres absolute or incremental, mm or inch, full circles, helices,
    feed changes), now and then a modal code, a malformed line or a broken arc among them
    [-]."""
    plane = draw(st.sampled_from(sorted(_PLANE_WORDS)))
    (a, b, h), (ca, cb) = _PLANE_WORDS[plane]
    absolute, centre_abs = draw(st.booleans()), draw(st.booleans())
    lines = [f"{draw(st.sampled_from(['G20', 'G21']))} {plane} {'G90' if absolute else 'G91'}"
             f" {'G90.1' if centre_abs else 'G91.1'} G1 X0 Y0 Z0 F1000"]
    pos = [0.0, 0.0, 0.0]  # in the plane's axes a, b, h, as the interpreter has it
    for k in range(draw(st.integers(1, 12))):
        straight = draw(st.sampled_from([0, 0, 1, 2, 9]))
        for i in range(straight):  # straight moves between: G1 modal, the arc names G2/G3
            step = [draw(st.floats(-5.0, 5.0)) for _ in range(2)]
            words = [f"{L}{v:.4f}" for L, v in zip((a, b), step if not absolute else
                                                   [p + d for p, d in zip(pos, step,
                                                                          strict=False)],
                                                   strict=True)]
            lines.append(("G1 " if i == 0 or draw(st.booleans()) else "") + " ".join(words))
            vals = [float(w[1:]) for w in words]
            pos[:2] = vals if absolute else [p + v for p, v in zip(pos, vals, strict=False)]
        r = draw(st.floats(0.5, 50.0))
        phi0, turn = draw(st.floats(-math.pi, math.pi)), draw(st.floats(-6.0, 6.0))
        c = (pos[0] - r * math.cos(phi0), pos[1] - r * math.sin(phi0))
        full = draw(st.integers(0, 9)) == 0 or abs(turn) < 0.05
        end = pos[:2] if full else [c[0] + r * math.cos(phi0 + turn),
                                    c[1] + r * math.sin(phi0 + turn)]
        end += [pos[2] + draw(st.sampled_from([0.0, 1.5]))]
        move = [f"{e if absolute else e - p:.4f}" for e, p in zip(end, pos, strict=True)]
        # a word left out (it stays where it is: mostly an arc off its circle)
        words = [f"{L}{v}" for L, v in zip((a, b, h), move, strict=True)
                 if full or draw(st.integers(0, 19))]
        if not full and draw(st.booleans()):
            words.append(f"R{-r if abs(turn) > math.pi else r:.4f}")
        else:
            cw = c if centre_abs else [c[0] - pos[0], c[1] - pos[1]]
            words += [f"{L}{v:.4f}" for L, v in zip((ca, cb), cw, strict=True)]
        pos = [(p if f"{L}{v}" not in words else float(v) if absolute else p + float(v))
               for L, v, p in zip((a, b, h), move, pos, strict=True)]
        if draw(st.integers(0, 3)) == 0:
            words.append(f"F{draw(feeds)}")
        g = "G3" if turn > 0 else "G2"
        modal = k > 0 and not straight and not draw(st.integers(0, 3))
        lines.append(" ".join(["" if modal else g, *words]).strip())
    if draw(st.integers(0, 2)) == 0:
        other = draw(st.sampled_from([*MODAL, *MALFORMED, "G2 X1 Y1 I0.3 J0",
                                      "G2 I0.000002 J0", "G3 I0.004 J0.003"]))
        lines.insert(draw(st.integers(1, len(lines))), other)
    return "\n".join(lines) + "\n"


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(arc_program())
def test_fast_arcs_match_the_reference(text):
    assert _outcome(text, fast=True) == _outcome(text, fast=False)


def _in_chunks(text, size, runs=False):
    """What the program gives read ``size`` lines at a time, as :func:`_outcome`; with
    ``runs``, its runs of lines and arcs taken as their segments [-]."""
    from tcpmm.io.text import file_lines

    lines = file_lines(text)
    chunks = [lines[i:i + size] for i in range(0, len(lines), size)]
    segments = []
    try:
        for it in gcode_stream.interpret_chunks(chunks, "p.nc", (0.0, 0.0, 0.0), runs=runs):
            segments += it.segments
            it.segments = []
    except InputError as err:
        return ("error", err.message, err.file, err.line, err.column)
    state = (it.pos, it.motion, it.feed, it.unit, it.absolute, it.exact_stop, it.tolerance)
    return ("ok", repr(as_lines(segments)), repr(state), repr(it.warned))


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(arc_program(), st.sampled_from([1, 2, 3, 7]))
def test_fast_arcs_in_chunks_match_the_reference(text, size):
    """Runs of arcs and of lines cut anywhere by the chunks: each run ends where its chunk
    does, and a run of arcs between lines is a few lines long."""
    assert _in_chunks(text, size) == _outcome(text, fast=False)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(arc_program(), st.sampled_from([3, 7, 1000]))
def test_runs_of_arcs_are_the_references_arcs(text, size):
    """As a stream takes them, runs of arcs (and of lines) stand for the reference's
    segments: the same arcs, and the look-ahead's columns the same to the bit."""
    from tcpmm.io.text import file_lines
    from tcpmm.path.geometry import _segment_columns
    from tcpmm.path.runs import ArcRun, path_columns

    assert _in_chunks(text, size, runs=True) == _outcome(text, fast=False)
    lines = file_lines(text)
    segments = []
    with contextlib.suppress(InputError):
        for it in gcode_stream.interpret_chunks(
                [lines[i:i + size] for i in range(0, len(lines), size)], "p.nc",
                (0.0, 0.0, 0.0), runs=True):
            segments += it.segments
            it.segments = []
    if any(type(s) is ArcRun for s in segments):
        got = path_columns(segments, _segment_columns)
        want = _segment_columns(as_lines(segments))
        assert [c.tobytes() for c in got] == [c.tobytes() for c in want]


def test_plain_arcs_skip_the_tokeniser(monkeypatch):
    calls = []
    tokenize = gcode_stream.tokenize
    monkeypatch.setattr(gcode_stream, "tokenize", lambda *a: calls.append(a) or tokenize(*a))
    text = ("G21 G90 G17\nG1 X10 Y0 F3000\nG3 X0 Y10 I-10 J0\nG3 X-10 Y0 R10\n"
            "G2 X0 Y10 I10 J0 F1500\nX10 Y0 R-10\nG1 X20\nM30\n")
    segments = parse_gcode(text)
    assert [c[2] for c in calls] == [1, 8]  # the header and the end only
    assert [type(s).__name__ for s in segments] == ["Line", "Arc", "Arc", "Arc", "Arc", "Line"]
    assert [s.direction for s in segments[1:5]] == ["ccw", "ccw", "cw", "cw"]
    assert segments[3].feed_m_per_s == 1500e-3 / 60
    assert _outcome(text, fast=True) == _outcome(text, fast=False)


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(incremental_line(), min_size=1, max_size=20), st.sampled_from(MALFORMED),
       st.integers(0, 20))
def test_an_error_in_a_run_of_incremental_moves_names_the_same_line(lines, bad, at):
    lines = [*lines]
    lines.insert(min(at, len(lines)), bad)
    text = "G21 G91 G1 F3000\n" + "\n".join(lines) + "\n"
    assert _outcome(text, fast=True) == _outcome(text, fast=False)


def _bits(v: float) -> bytes:
    return struct.pack("<d", v)


@settings(max_examples=500, deadline=None)
@given(long_numbers, st.sampled_from("XYZF"))
def test_the_compiled_lexer_converts_a_number_as_float_does(number, letter):
    """To the bit, -0.0 included; and it converts every number of at most 15 significant
    digits and 22 decimals, so that such blocks stay off the regular expression."""
    codes, vals, _ = scan_chunk([f"G1 {letter}{number}"])
    slot = "XYZF".index(letter)
    if PLAIN_MOVE.fullmatch(f"G1 {letter}{number}") is None:
        assert codes[0, 0] == NOT_PLAIN
        return
    assert codes[0, 0] in (PLAIN, PLAIN_SLOW) and codes[0, 1] == 1
    assert codes[0, 2] == 1 << slot
    mantissa = number.lstrip("+-").replace(".", "").lstrip("0") or "0"
    decimals_ = len(number.partition(".")[2])
    if len(mantissa) <= 15 and decimals_ <= 22:
        assert codes[0, 0] == PLAIN
    if codes[0, 0] == PLAIN:
        assert _bits(vals[0, slot]) == _bits(float(number))


def test_the_compiled_lexer_on_a_chunk():
    lines = ["G1 X1.5 Y-2 Z.25 F3000", "  g00x+1y2  ", "X1 X2", "Y1 X1", "G2 X1", "",
             "G1 X" + "1" * 17, "G1 X1e3", "G 01 Z-0", "G10 X1", "X1 (c)", "F100"]
    codes, vals, _ = scan_chunk(lines)
    assert codes[:, 0].tolist() == [PLAIN, PLAIN, 0, 0, ARC, PLAIN, PLAIN_SLOW, 0, PLAIN, 0,
                                    0, PLAIN]
    assert codes[:, 1].tolist() == [1, 0, -1, -1, 2, -1, 1, -1, 1, -1, -1, -1]
    assert codes[:, 2].tolist() == [15, 3, 0, 0, 1, 0, 1, 0, 4, 0, 0, 8]
    assert vals[0, :4].tolist() == [1.5, -2.0, 0.25, 3000.0] and vals[1, :2].tolist() == [1, 2]
    assert math.copysign(1.0, vals[8, 2]) == -1.0
    assert scan_chunk([]) is None and scan_chunk(["X1\nX2"]) is None


def test_the_compiled_lexer_marks_plain_arcs():
    """An arc block of X, Y, Z, I, J, K, R and F in that order, every number exact, is a
    plain arc; a centre word with G0/G1, another order, an inexact number or no word of a
    move is left to the tokeniser."""
    lines = ["G3 X1 Y2 I-0.5 J0 F1200", "g02x1y2r-3", "I1 J2", "G2 Z-1 I2 K0.5",
             "G1 X1 I1", "G2 I1 X1", "G2 F100", "G3 X1 R" + "1" * 17, "G2 X1 Y1 R1 R2",
             "G03 X1 Y1 Z2 I3 J4 K5 R6 F7", "G4 X1"]
    codes, vals, _ = scan_chunk(lines)
    assert codes[:, 0].tolist() == [ARC, ARC, ARC, ARC, 0, 0, 0, 0, 0, ARC, 0]
    assert codes[:, 1].tolist() == [3, 2, -1, 2, -1, -1, -1, -1, -1, 3, -1]
    assert codes[0, 2] == 1 | 2 | 8 | 16 | 32 and codes[1, 2] == 1 | 2 | 128
    assert vals[0].tolist() == [1.0, 2.0, 0.0, 1200.0, -0.5, 0.0, 0.0, 0.0]
    assert vals[9].tolist() == [1.0, 1.0, 2.0, 7.0, 3.0, 4.0, 5.0, 6.0]
    assert vals[1, 7] == -3.0


def test_a_number_float_alone_converts_exactly_goes_through_it():
    """A mantissa beyond 2^53 is converted by float, not the compiled lexer, and the run
    of compiled blocks goes on after it."""
    big = "0.12345678901234567890123"
    third = repr(1 / 3)
    text = f"G1 F3000\nX1\nX{big}\nX2 Y{third}\nX3\n"
    segments = parse_gcode(text)
    assert [s.end_m[0] for s in segments] == [1e-3, float(big) * 1e-3, 2e-3, 3e-3]
    assert segments[2].end_m[1] == float(third) * 1e-3
    assert _outcome(text, fast=True) == _outcome(text, fast=False)


def test_plain_blocks_skip_the_tokeniser(monkeypatch):
    calls = []
    tokenize = gcode_stream.tokenize
    monkeypatch.setattr(gcode_stream, "tokenize", lambda *a: calls.append(a) or tokenize(*a))
    text = "G21 G90\nG1 X1 Y0 F3000\nX2 Y1\ng0 x0 y0 z1\nG01 X 1.5\nM30\n"
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        segments = parse_gcode(text)
    assert [c[2] for c in calls] == [1, 6]  # the header and the end only
    assert [s.line for s in segments] == [2, 3, 4, 5]


@pytest.mark.parametrize("text", ["X1 (c)", "X1;", "X1 X2", "Y1 X1", "X1e3", "X.", "G2 X1",
                                  "X1 S5", "A1", "%", ""])
def test_lines_that_are_not_plain_moves_do_not_match(text):
    m = PLAIN_MOVE.fullmatch(text)
    assert m is None or m.group(1) == m.group(2) == m.group(3) == m.group(4) is None


def test_the_collector_runs_again_after_a_parse_that_fails():
    import gc

    assert gc.isenabled()
    with pytest.raises(InputError):
        parse_gcode("G1 X1 F100\nX1 X2\n")
    assert gc.isenabled()


def test_the_compiled_scanner_takes_the_interpreters_zero_move():
    """The scanner, compiled on its own, holds the interpreter's ZERO_MOVE_M as a literal:
    were they to differ, the two would skip different moves."""
    from tcpmm.path import gcode_scan, gcode_words

    assert gcode_scan._ZERO_MOVE_M == gcode_words.ZERO_MOVE_M


@pytest.mark.parametrize("fast", [True, False])
def test_a_nanometre_jog_is_a_repeated_point_wherever_it_is(fast):
    """A spiral's points each repeated 0.000001 mm off, as a CAM post writing 6 decimals
    does: the difference of the two positions in metres rounds to either side of 1e-9,
    and 1 671 of 2 857 were skipped, the rest run as moves of 1 nm (137.6 s of program for
    78.7 s). Every one is a repeated point."""
    pts = [(round(20.0 + 0.37 * k, 6), round(5.0 + 0.113 * k, 6)) for k in range(300)]
    body = "".join(f"X{x:.6f} Y{y:.6f}\nX{x + 0.000001:.6f} Y{y:.6f}\n" for x, y in pts)
    it = gcode_stream.run_program("G21 G90 G1 F3000\n" + body, "j.nc", (0.0, 0.0, 0.0),
                                  fast=fast)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        it.emit_warnings()
    [said] = [str(w.message) for w in caught if "zero-length" in str(w.message)]
    assert "(and 299 more times)" in said, said
    assert len(it.segments) == 300
