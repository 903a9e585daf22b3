"""Splitting one G-code line into words (letter + number) with their columns.

Comments ``( ... )`` and ``; ...`` are removed, keeping columns; a line that starts
with ``%`` is a tape marker and holds no words. Columns are 1-based.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

from ..errors import InputError

# ``o``: any other character, a form feed or a control character too (\S would miss
# those, and the match would fail)
_TOKEN = re.compile(r"[ \t]*(?:(?P<l>[A-Za-z])[ \t]*(?P<n>[-+]?[0-9.]*)|(?P<o>.))", re.S)
_NUMBER = re.compile(r"[-+]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)\Z")


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
        On a malformed number, a letter without a number, a stray character or an
        unclosed comment, with the column where it is.
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
    hint = (" (a number needs a letter before it, e.g. X10)" if ch in "+-.0123456789"
            else " (block delete is not read: remove the '/' to run the block, or the "
                 "block to skip it)" if ch == "/"
            else "" if ch.isprintable() else " (a control character; remove it)")
    raise InputError(f"unexpected character {ch!r}{hint}", file=file, line=line,
                     column=m.start("o") + 1)


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
    if not num:
        fix = f"write e.g. {letter}0"
        if letter == "O" and words and col > 1 and body[col - 2] in "0123456789.":
            # a zero typed as the letter O in the number before: X1O for X10
            typed = body[words[-1].column - 1: col]
            fix = f"a zero typed as the letter O? write {typed[:-1]}0 for {typed}"
        raise InputError(f"letter {letter} has no number after it; {fix}",
                         file=file, line=line, column=col)
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
