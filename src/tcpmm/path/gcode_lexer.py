"""Splitting one G-code line into words (letter + number) with their columns.

Comments ``( ... )`` and ``; ...`` are removed, keeping columns; a line that starts
with ``%`` is a tape marker and holds no words. Columns are 1-based. What is no word of
this dialect is refused by what it likely is: a macro variable or expression (``X#1``,
``X[10+2]``, ``X=R1``), a word of letters (``IF``, ``GOTO``, ``CYCLE800``) or another
dialect's letter (Heidenhain's ``L``), so that no "write e.g. X0" changes the geometry.
"""

from __future__ import annotations

import math
import re
import unicodedata
from dataclasses import dataclass

from ..errors import InputError
from .gcode_words import KNOWN_LETTERS, OTHER_AXES

# ``o``: any other character, a form feed or a control character too (\S would miss
# those, and the match would fail)
_TOKEN = re.compile(r"[ \t]*(?:(?P<l>[A-Za-z])[ \t]*(?P<n>[-+]?[0-9.]*)|(?P<o>.))", re.S)
_NUMBER = re.compile(r"[-+]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)\Z")
#: a name of a control statement or of another dialect's command: IF, GOTO, CYCLE800
_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
#: characters of a controller's macro language: Fanuc's variables (#1) and expressions
#: ([10+2]), Sinumerik's assignments (X=R1, R1=5)
MACRO_CHARACTERS = "#[]="
#: what to do with a variable or an expression: a value written out is the only kind of
#: number this dialect reads
MACRO_FIX = ("variables and expressions (#1, [..], =) are not supported; write the values "
             "out (a CAM post-processor without macros, or the controller's own listing "
             "of the program)")
#: what to do with a control statement or a block of another dialect
DIALECT_FIX = ("control statements and other dialects (IF, WHILE, GOTO, ROT, TRANS, MSG, "
               "CYCLE800, Heidenhain's L X+10) are not supported; post the program as ISO "
               "G-code (G0 to G3 blocks of X, Y, Z), its loops and cycles written out as moves")


@dataclass(frozen=True, slots=True)
class Word:
    """One word of a block.

    Parameters
    ----------
    letter : str
        Upper-case letter [-].
    value : float
        The number as written, in program units [-].
    text : str
        The word as written, e.g. ``"X-1.5"`` [-].
    column : int
        1-based column of the letter [-].
    """

    letter: str
    value: float
    text: str
    column: int


def _plain(letter: str, mantissa: float, exponent: str) -> str:
    """``mantissa * 10**exponent`` written out, or a hint when it is too large [-]."""
    try:
        value = mantissa * 10.0 ** int(exponent)
    except (ValueError, OverflowError):
        value = float("inf")
    if not abs(value) < 1e12:
        return "as a plain decimal number"
    return f"e.g. {letter}" + f"{value:.6f}".rstrip("0").rstrip(".")


def strip_comments(text: str, file=None, line=None) -> str:
    """The line with comments replaced by blanks (columns are kept) [-]."""
    if "(" not in text and ";" not in text and ")" not in text:
        return text
    out = []
    pos = 0
    n = len(text)
    while pos < n:
        c = text[pos]
        if c == ";":
            break
        if c == "(":
            close = text.find(")", pos + 1)
            inner = text.find("(", pos + 1)
            if close < 0:
                raise InputError(
                    "comment '(' is not closed; add ')' at its end or use ';' for a "
                    "comment to the end of the line",
                    file=file,
                    line=line,
                    column=pos + 1,
                )
            if 0 <= inner < close:
                raise InputError(
                    "comments cannot be nested; remove the inner '('",
                    file=file,
                    line=line,
                    column=inner + 1,
                )
            out.append(" " * (close - pos + 1))
            pos = close + 1
            continue
        if c == ")":
            raise InputError(
                "')' without a '(' before it; remove it or open the comment",
                file=file,
                line=line,
                column=pos + 1,
            )
        out.append(c)
        pos += 1
    return "".join(out)


def tokenize(text: str, file=None, line=None) -> list[Word]:
    """Words of one program line.

    Parameters
    ----------
    text : str
        The line as written [-].
    file : str or Path, optional
        Program file, for error messages [-].
    line : int, optional
        1-based line number, for error messages [-].

    Returns
    -------
    list of Word
        The words in order [-].

    Raises
    ------
    InputError
        On a malformed number, a letter without a number, a stray character, a
        variable, an expression, a word of letters or an unclosed comment, with the
        column where it is.
    """
    body = strip_comments(text, file, line).rstrip()
    if not body or body.lstrip().startswith("%"):
        return []
    words = []
    pos = 0
    n = len(body)
    match = _TOKEN.match
    while pos < n:
        m = match(body, pos)
        if m.group("o") is not None:
            _stray(m, file, line)
        words.append(_word(m, body, words, file, line))
        pos = m.end()
    return words


def _stray(m, file, line):
    """Refuse the character that starts no word [-]."""
    ch = m.group("o")
    at = m.start("o")
    if ch in MACRO_CHARACTERS:
        body = m.string
        start = max(body.rfind(" ", 0, at), body.rfind("\t", 0, at)) + 1
        raise InputError(f"{_construct(body, start, at)} is a variable or an expression: "
                         f"{MACRO_FIX}", file=file, line=line, column=at + 1)
    hint = (" (a number needs a letter before it, e.g. X10)" if ch in "+-.0123456789"
            else " (block delete is not read: remove the '/' to run the block, or the "
                 "block to skip it)" if ch == "/"
            else "" if ch.isprintable() else _unseen(ch))
    raise InputError(f"unexpected character {ch!r}{hint}", file=file, line=line,
                     column=at + 1)


def _unseen(ch: str) -> str:
    """What a character an editor shows as nothing or as a blank is, and the fix: a
    no-break or other space (text pasted from a word processor or a PDF) is no blank
    here, an invisible format character (a zero-width space, a byte-order mark within
    the file) no character at all [-]."""
    kind = unicodedata.category(ch)
    name = unicodedata.name(ch, f"U+{ord(ch):04X}").lower()
    if kind == "Zs":
        return f" (a {name}, not a plain one; replace it with a space)"
    if kind == "Cf":
        return f" (an invisible {name}; remove it)"
    return " (a control character; remove it)"


def _construct(body: str, start: int, at: int) -> str:
    """``body`` from ``start`` to the first blank from ``at`` on, quoted, cut short [-]."""
    end = len(body)
    for blank in " \t":
        j = body.find(blank, at)
        end = j if 0 <= j < end else end
    text = body[start:end]
    return repr(text if len(text) <= 20 else text[:16] + "...")


def _no_number(m, body: str, words: list[Word], file, line):
    """Refuse a letter without a number after it, saying what the text likely is: a word
    of letters (IF, CYCLE800), a variable or expression (X#1, X=R1), another dialect's
    letter (Heidenhain's L), a zero typed as O, or a number left out [-]."""
    col = m.start("l") + 1
    letter = m.group("l").upper()
    after = body[m.end("l"):m.end("l") + 1]
    if letter == "O" and words and col > 1 and body[col - 2] in "0123456789.":
        # a zero typed as the letter O in the number before: X1O for X10
        typed = body[words[-1].column - 1: col]
        fix = f"a zero typed as the letter O? write {typed[:-1]}0 for {typed}"
    elif after.isascii() and (after.isalpha() or after == "_"):
        name = _NAME.match(body, col - 1).group()
        raise InputError(f"{name!r} is a word of letters, not a letter and its number: "
                         f"{DIALECT_FIX}", file=file, line=line, column=col)
    elif letter not in KNOWN_LETTERS and letter not in OTHER_AXES:
        raise InputError(f"{letter!r} with no number after it is no word of this dialect: "
                         f"{DIALECT_FIX}", file=file, line=line, column=col)
    else:
        fix = f"write e.g. {letter}0"
    raise InputError(f"letter {letter} has no number after it; {fix}",
                     file=file, line=line, column=col)


def _word(m, body: str, words: list[Word], file, line) -> Word:
    """The word of a match of a letter and its number, checked [-]."""
    col = m.start("l") + 1
    letter = m.group("l").upper()
    num = m.group("n")
    if letter == "E" and words and col > 1 and body[col - 2] in "0123456789." and num:
        prev = words[-1]
        mantissa = body[prev.column : col - 1].strip()
        raise InputError(
            f"exponent notation '{prev.letter}{mantissa}{m.group('l')}{num}' is not "
            f"G-code; write the number out, {_plain(prev.letter, prev.value, num)}",
            file=file,
            line=line,
            column=prev.column,
        )
    rest = body[m.end():]
    at = m.end() + len(rest) - len(rest.lstrip(" \t"))  # what follows, past blanks
    if num in ("", "-", "+") and at < len(body) and body[at] in MACRO_CHARACTERS:
        raise InputError(f"{_construct(body, col - 1, at)} is a variable or an "
                         f"expression: {MACRO_FIX}", file=file, line=line, column=col)
    if not num:
        _no_number(m, body, words, file, line)
    if _NUMBER.match(num) is None:
        raise InputError(f"malformed number {num!r} after {letter}; write a decimal "
                         "number such as 12.5 or -0.25", file=file, line=line, column=col)
    value = float(num)
    if not math.isfinite(value):  # over 308 digits
        raise InputError(f"the number after {letter} has {len(num)} characters, too large "
                         "for any word; check it", file=file, line=line, column=col)
    return Word(letter, value, letter + num, col)


def tape_marker(raw: str, file, number: int) -> bool:
    """Whether a line is a ``%`` tape marker; text after the ``%`` is an error, since a
    controller would not run it."""
    body = strip_comments(raw, file, number).strip()
    if not body.startswith("%"):
        return False
    if body[1:].strip():
        raise InputError("a '%' line marks the start or end of the program and holds "
                         "nothing else; put the blocks after it on lines of their own",
                         file=file, line=number, column=raw.index("%") + 2)
    return True
