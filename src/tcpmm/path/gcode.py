"""G-code interpreter: NC program text to motion segments in SI.

Supported: G0, G1, G2, G3 (centre I/J/K or radius R, full circles, helices), G4 dwell
(P or X in seconds), G17/G18/G19, G20/G21, G90/G91, G90.1/G91.1 (arc centre absolute
or incremental), G61 (exact stop, modal), G9 (exact stop, this block only), G64
(continuous path; ``P`` the contour tolerance of its corners, ``Q`` warned and
ignored), F, N, ``( )`` and ``;``
comments, ``%`` lines, M2/M30 (end of program). A length written without a decimal point
and of 1000 or more (``X50000``, 50 mm on a Fanuc control without calculator-type input)
is warned of, once a program. Words that do not change the tool path
(spindle, coolant, tool, work and tool-length offsets, ...) are reported as
:class:`~tcpmm.errors.InputWarning` and skipped; everything else is an
:class:`~tcpmm.errors.InputError` with file, line and column.

The parser is our own regex tokeniser plus a modal interpreter rather than a library.
Of the Python G-code parsers, ``pygcode`` was last released in 2017, and ``gcodeparser``
and ``gcode-lib`` target 3D-printer dialects: they split lines into words but report no
column, keep no modal state, and check neither arcs nor repeated words. The dialect
needed here is small, so owning a few hundred lines (``gcode_lexer``, ``gcode_words``,
``gcode_geometry``, ``gcode_fast`` and this module) keeps every error message exact and
adds no dependency.
"""

from __future__ import annotations

import re
import warnings

from ..errors import InputError, InputWarning
from .gcode_geometry import INCH_M, MM_M, GeometryMixin, short_text
from .gcode_lexer import Word
from .gcode_words import (
    G_GROUP,
    G_IGNORED,
    G_REFUSED,
    KNOWN_LETTERS,
    LETTER_IGNORED,
    M_IGNORED,
    MAX_CODE,
    MAX_FEED,
    MOTION,
    NO_POINT,
    OTHER_AXES,
    ZERO_MOVE_M,
)
from .segments import AXIS_INDEX, Dwell, Line, Rapid
from .settings import TOLERANCE_MAX_M

#: the key of the warning that counts the moves to where the tool already is [-]
ZERO_LENGTH = "zero-length move"
#: a dwell whose P, written without a decimal point, is this long or longer is warned of:
#: a Fanuc control reads P in ms, this dialect (LinuxCNC's) in seconds [s]
LONG_DWELL_S = 10.0
_ZERO_LENGTH_SAID = re.compile(rf": {ZERO_LENGTH} ignored(?: \(and (\d+) more times?\))?: ")


def zero_length_skipped(said) -> int:
    """Zero-length moves skipped, counted from the warnings ``said`` (their texts, as
    :meth:`Interpreter.emit_warnings` words them: the first, and "(and N more times)") [-]."""
    n = 0
    for text in said:
        m = _ZERO_LENGTH_SAID.search(text)
        if m is not None:
            n += 1 + int(m.group(1) or 0)
    return n


def _where(file, line, column):
    parts = [] if file is None else [str(file)]
    parts.append(f"line {line}")
    if column is not None:
        parts.append(f"column {column}")
    return ", ".join(parts)


class Interpreter(GeometryMixin):
    def __init__(self, file, start):
        self.file = file
        # a move before any other goes from the start position taken, not programmed
        self.moved = False
        self._pos = tuple(float(c) for c in start)
        self.motion = None
        self.plane = 17
        self.unit = MM_M
        self.absolute = True
        self.arc_absolute = False
        self.feed = None
        self.exact_stop = False
        self.tolerance = None
        self.segments = []
        self.warned = {}
        #: a run of plain G1 blocks may go into ``segments`` as one LineRun [-]
        self.takes_runs = False

    @property
    def pos(self) -> tuple:
        """Where the tool is, at the end of the last move [m]."""
        return self._pos

    @pos.setter
    def pos(self, value) -> None:
        # the parsers' runs of blocks move the tool here too, not through move(); a run
        # may end where it began, but it left segments. A dwell is none: it programs no
        # point (and until the first move the segments are dwells, few to look through)
        self.moved = (self.moved or tuple(value) != self._pos
                      or any(not isinstance(s, Dwell) for s in self.segments))
        self._pos = tuple(value)

    # ---- reporting -------------------------------------------------------------------
    def error(self, msg, line, column=None):
        raise InputError(msg, file=self.file, line=line, column=column)

    def warn(self, key, msg, line, column, head=None):
        """Warn once per ``key`` of ``msg`` at its first place, counting the rest; said as
        ``head`` (default "<key> ignored") [-]."""
        if key in self.warned:
            self.warned[key][1] += 1
        else:
            self.warned[key] = [(line, column, msg, head or f"{key} ignored"), 1]

    def emit_warnings(self):
        # in the order of the words they name, whatever order a block's words are read in
        firsts = sorted(self.warned.items(), key=lambda kv: (kv[1][0][0], kv[1][0][1] or 0))
        for (line, column, msg, head), count in (v for _, v in firsts):
            more = f" (and {count - 1} more time{'s' * (count > 2)})" if count > 1 else ""
            text = f"{_where(self.file, line, column)}: {head}{more}: {msg}"
            warnings.warn(text, InputWarning, stacklevel=3)

    # ---- one block -------------------------------------------------------------------
    def block(self, words: list[Word], line: int):
        gs, ms, w = self._sort_words(words, line)
        new = self._g_groups(gs, line)
        end = self._feed_and_m_codes(w, ms, line)
        # modal settings, in the order of execution
        if "plane" in new:
            self.plane = round(new["plane"].value)
        if "units" in new:
            self.unit = INCH_M if round(new["units"].value) == 20 else MM_M
        if "distance" in new:
            self.absolute = round(new["distance"].value) == 90
        if "arc distance" in new:
            self.arc_absolute = round(new["arc distance"].value * 10) == 901
        if "path mode" in new:
            self.path_mode(new["path mode"], w, line)
        if "F" in w:
            self.feed = w["F"].value * self.unit / 60.0
        if "motion" in new:
            self.motion = MOTION[round(new["motion"].value * 10)]

        if "dwell" in new:
            self.dwell(w, new["dwell"], line, new.get("motion"))
            return end
        g64 = "path mode" in new and round(new["path mode"].value) == 64
        if "P" in w and not g64:
            self.error("P is only used with G4 (dwell time in seconds) or G64 (contour "
                       "tolerance)", line, w["P"].column)
        if "Q" in w and not g64:
            self.error("Q is only read with G64 (and ignored there); remove it", line,
                       w["Q"].column)
        if any(k in w for k in "XYZIJKR"):
            if NO_POINT not in self.warned:  # once a program: the fast path relies on it
                self.no_point(w, line)
            once = "exact stop once" in new
            self.exact_stop, saved = self.exact_stop or once, self.exact_stop
            self.move(w, new.get("motion"), line)
            self.exact_stop = saved
        elif "exact stop once" in new:
            self.error("G9 (exact stop) needs a move in its block, e.g. G9 G1 X10",
                       line, new["exact stop once"].column)
        return end

    def _sort_words(self, words: list[Word], line: int):
        """The block's G words, M words and other words by letter, checked."""
        gs, ms, w = [], [], {}
        for word in words:
            L = word.letter
            if L == "G":
                gs.append(word)
            elif L == "M":
                ms.append(word)
            elif L in w:
                self.error(
                    f"{L} is given twice in one block (columns {w[L].column} and "
                    f"{word.column}); keep one",
                    line,
                    word.column,
                )
            elif L in OTHER_AXES:
                self.error(
                    f"axis {L} is not modelled; this model has X, Y and Z only", line, word.column
                )
            elif L not in KNOWN_LETTERS:
                self.error(
                    f"unknown word letter {L} in {word.text!r}; supported letters "
                    "are G M N F X Y Z I J K R P Q (and S T H D O, ignored)",
                    line,
                    word.column,
                )
            else:
                w[L] = word
        if "O" in w and any(x.letter != "N" for x in words[:words.index(w["O"])]):
            self.error(f"O (a program number) after other words, in {w['O'].text!r}: it "
                       "starts a block of its own; a letter O for a zero?", line,
                       w["O"].column)
        for L in ("S", "T", "H", "D", "O"):
            if L in w:
                self.warn(L, LETTER_IGNORED[L], line, w[L].column)
        if "N" in w:
            n = w["N"]
            if n.value < 0 or n.value != int(n.value) or "." in n.text:
                self.error(
                    f"line number {n.text!r} must be a whole number, e.g. N10", line, n.column
                )
        return gs, ms, w

    def _g_groups(self, gs, line: int) -> dict:
        """The block's G-codes by modal group, one per group."""
        new = {}
        for g in gs:
            if not abs(g.value) < MAX_CODE:
                self.error(f"{short_text(g.text)} is not a G-code", line, g.column)
            code = round(g.value * 10)
            if abs(g.value * 10 - code) > 1e-9:
                self.error(f"{g.text} is not a G-code", line, g.column)
            group = G_GROUP.get(code)
            if group is None:
                name = f"G{code // 10}" + (f".{code % 10}" if code % 10 else "")
                if code in G_IGNORED:
                    self.warn(name, G_IGNORED[code], line, g.column)
                    continue
                hint = G_REFUSED.get(code, "it is not supported; remove it")
                self.error(f"{name} cannot be used: {hint}", line, g.column)
            if group in new:
                self.error(
                    f"{new[group].text} and {g.text} in one block are both {group} codes; keep one",
                    line,
                    g.column,
                )
            new[group] = g
        return new

    def _feed_and_m_codes(self, w, ms, line: int) -> bool:
        """Check the feed and the M-codes; whether the block ends the program."""
        if "F" in w:
            f = w["F"]
            if not f.value > 0.0:
                self.error(
                    f"feed {f.text} must be positive (mm/min, or in/min with G20)", line, f.column
                )
            if not f.value <= MAX_FEED:
                self.error(f"feed {short_text(f.text)} is above F{MAX_FEED:.0f} (mm/min, or in/min "
                           "with G20), faster than any feed axis; check the number", line,
                           f.column)
        end = False
        for m in ms:
            code = m.value
            if not abs(code) < MAX_CODE or code != int(code):
                self.error(f"{short_text(m.text)} is not an M-code", line, m.column)
            code = int(code)
            if code in (2, 30):
                end = True
            elif code in (98, 99):
                self.error(
                    f"subprograms ({m.text}) are not supported; write the "
                    "subprogram out in the main program",
                    line,
                    m.column,
                )
            else:
                msg = M_IGNORED.get(code, "this M-code is not modelled")
                self.warn(f"M{code}", msg, line, m.column)
        return end

    def path_mode(self, g, w, line):
        """G61: exact stop; G64: continuous path, ``P`` its contour tolerance."""
        self.exact_stop = round(g.value) == 61
        self.tolerance = None
        if "P" in w and not self.exact_stop:
            p = w["P"]
            if not p.value >= 0.0:
                self.error(f"contour tolerance {p.text} must not be negative (mm, or in with "
                           "G20; P0 keeps corners sharp)", line, p.column)
            self.tolerance = p.value * self.unit
            if self.tolerance > TOLERANCE_MAX_M:
                unit, fix = (("mm", "P0.01") if self.unit == MM_M else
                             ("inches under G20", "P0.0004"))
                self.error(f"contour tolerance {p.text} is {self.tolerance * 1e3:g} mm, above "
                           f"{TOLERANCE_MAX_M * 1e3:g} mm: a CNC's are micrometres to tenths "
                           f"of a millimetre, and P is read in {unit}; write {fix} for "
                           "10 µm", line, p.column)
        if "Q" in w and not self.exact_stop:
            self.warn("Q", "the naive-CAM merging of collinear blocks is not modelled; "
                      "corners are blended one by one within the P tolerance", line,
                      w["Q"].column)

    def dwell(self, w, g4, line, motion=None):
        """G4: a rest of ``P`` or ``X`` seconds; ``motion`` a motion word in its block."""
        axes = [k for k in "XYZIJKR" if k in w]
        if motion is not None and axes:  # X20 is a move's end, or (Fanuc) the time
            what = ("would be the move's end point or the dwell's time" if axes[0] == "X"
                    else "is the move's end point, which a dwell does not take")
            self.error(f"G4 (dwell) and {motion.text} in one block: {w[axes[0]].text} {what}; "
                       "put the dwell in a block of its own", line, motion.column)
        if "P" in w and "X" in w:  # a modal move's end written before a dwell, most often
            self.error(f"G4 takes the time in P or in X, not both: {w['X'].text} is read as a "
                       f"second dwell time; if it is a move's end point, put the dwell "
                       f"({w['P'].text}) in a block of its own", line, w["X"].column)
        t = w.get("P") or w.get("X")
        if t is None:
            self.error("G4 needs the dwell time, e.g. G4 P0.5 (seconds)", line, g4.column)
        if t.letter == "P" and "." not in t.text and t.value >= LONG_DWELL_S:
            self.warn("long dwell", f"P is read in seconds, as LinuxCNC reads it; a Fanuc "
                      f"control reads {t.text} in ms (write P{t.value / 1000:g} for that)",
                      line, t.column, head=f"G4 {t.text} rests {t.value:g} s")
        for L in "YZIJKR":
            if L in w:
                self.error(
                    f"{L} cannot be used in a G4 (dwell) block; move it to its own block",
                    line,
                    w[L].column,
                )
        if t.value < 0:
            self.error(f"dwell time {t.text} must not be negative", line, t.column)
        self.segments.append(Dwell(self.pos, t.value, line))

    def move(self, w, gword, line):
        first = next(w[k] for k in "XYZIJKR" if k in w)
        if self.motion is None:
            self.error(
                f"{first.text} without a motion mode: put G0, G1, G2 or G3 before it",
                line,
                first.column,
            )
        target = list(self.pos)
        for axis in "XYZ":
            if axis in w:
                v = w[axis].value * self.unit
                i = AXIS_INDEX[axis]
                target[i] = v if self.absolute else target[i] + v
        target = tuple(target)
        self._check_sizes(w, target, line)
        if self.motion in (0, 1):
            for L in "IJKR":
                if L in w:
                    self.error(
                        f"{L} is only used with G2/G3 (arcs); the active motion is G{self.motion}",
                        line,
                        w[L].column,
                    )
        if self.motion != 0 and self.feed is None:
            col = gword.column if gword is not None else first.column
            self.error(
                f"no feed rate for G{self.motion}: program F (mm/min) in this or an "
                "earlier block, e.g. F1000",
                line,
                col,
            )
        if self.motion in (0, 1) and all(abs(a - b) <= ZERO_MOVE_M
                                         for a, b in zip(target, self.pos, strict=True)):
            target = self.pos
            # a controller skips such a block; it is counted, G0 as G1, so that the summary
            # gives every repeated point the program holds. A program's first G0 to the
            # start position (G0 X0 Y0 of a header) repeats no point it has programmed
            if self.moved or self.motion == 1:
                self.warn(ZERO_LENGTH, "a G0 or G1 to where the tool already is, skipped",
                          line, first.column)
        elif self.motion == 0:
            self.segments.append(Rapid(self.pos, target, line))
        elif self.motion == 1:
            self.segments.append(Line(self.pos, target, self.feed, self.exact_stop, line,
                                      self.tolerance))
        else:
            self.segments.append(self.arc(w, target, gword, line))
        self.pos = target
