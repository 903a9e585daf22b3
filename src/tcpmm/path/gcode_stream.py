"""The interpreter over a program that comes in chunks of lines.

A long program is read and interpreted a chunk of lines at a time
(:func:`interpret_chunks`), its modal state carried from one chunk to the next, so that
the segments come out in pieces and no chunk's text stays in memory. A whole program is
the same with one chunk (:func:`run_program`): the segments, warnings and errors (line
and column counted over the whole program) are the same however it is cut.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass

from ..errors import InputError
from ..io.text import file_lines
from .gcode import Interpreter
from .gcode_fast import collector_paused, plain_run, scan_chunk
from .gcode_lexer import tape_marker, tokenize


@dataclass
class _Progress:
    """Where the interpretation stands between chunks: a ``%`` opened the program, a block
    ran, and where the program ended (its line and why) if it did [-]."""

    opened: bool = False
    started: bool = False
    end_line: int | None = None
    end_what: str = ""
    rest_warned: bool = False


def run_program(text: str, file, start_position_m, fast: bool = True) -> Interpreter:
    """The interpreter after the program, its warnings not yet issued.

    Parameters
    ----------
    text : str
        The program [-].
    file : str or Path or None
        Where the program came from, for messages [-].
    start_position_m : sequence of float
        Position of X, Y, Z before the program starts [m].
    fast : bool
        Execute plain G0/G1 blocks through :func:`~tcpmm.path.gcode_fast.plain_run`;
        ``False`` sends every line through the tokeniser, the reference the fast path
        is tested against [-].

    Returns
    -------
    Interpreter
        With the segments and the warnings collected [-].
    """
    (it,) = interpret_chunks([file_lines(text)], file, start_position_m, fast)
    return it


def interpret_chunks(chunks: Iterable[list[str]], file, start_position_m,
                     fast: bool = True, runs: bool = False) -> Iterator[Interpreter]:
    """Interpret a program given as consecutive chunks of its lines.

    Parameters
    ----------
    chunks : iterable of list of str
        The program's lines without their line breaks, in chunks [-].
    file : str or Path or None
        Where the program came from, for messages [-].
    start_position_m : sequence of float
        Position of X, Y, Z before the program starts [m].
    fast : bool
        As for :func:`run_program` [-].
    runs : bool
        A run of plain G1 blocks goes into ``segments`` as one
        :class:`~tcpmm.path.runs.LineRun` rather than a Line each [-].

    Yields
    ------
    Interpreter
        The interpreter after each chunk; its ``segments`` are those made so far, which
        the caller may take and clear (``it.segments = []``) [-].
    """
    it = Interpreter(file, start_position_m)
    it.takes_runs = runs
    st = _Progress()
    offset = 0
    for lines in chunks:
        if st.end_line is None:
            # the collector paused while a chunk's segments are made, not while the
            # caller works on them (collector_paused)
            with collector_paused():
                _run_lines(it, lines, offset, st, fast)
        elif not st.rest_warned:
            st.rest_warned = _warn_rest(it, lines, 0, offset, st)
        yield it
        offset += len(lines)


def _run_lines(it: Interpreter, lines: list[str], offset: int, st: _Progress,
               fast: bool) -> None:
    """Interpret one chunk of lines, the first of them line ``offset + 1``."""
    k = 0
    scan = scan_chunk(lines) if fast else None
    while k < len(lines):
        if fast:
            j = plain_run(it, lines, k, offset, scan)
            st.started = st.started or j > k
            if j == len(lines):
                return
            k = j
        number, raw = offset + k + 1, lines[k]
        k += 1
        if tape_marker(raw, it.file, number):
            if st.opened or st.started:  # the closing %: the program ends here
                st.end_line, st.end_what = number, "blocks after the closing %"
                st.rest_warned = _warn_rest(it, lines, k, offset, st)
                return
            st.opened = True
            continue
        words = tokenize(raw, it.file, number)
        if not words:
            continue
        st.started = True
        if it.block(words, number):
            st.end_line, st.end_what = number, "blocks after M2/M30"
            st.rest_warned = _warn_rest(it, lines, k, offset, st)
            return


def _warn_rest(it: Interpreter, lines: list[str], k: int, offset: int,
               st: _Progress) -> bool:
    """Warn of the first line with words from ``lines[k]`` on, after the program's end;
    whether there was one [-]."""
    rest = next((i for i in range(k, len(lines)) if _has_words(lines[i])), None)
    if rest is None:
        return False
    it.warn(st.end_what, f"the program ends on line {st.end_line}", offset + rest + 1, None)
    return True


def _has_words(raw: str) -> bool:
    try:
        return bool(tokenize(raw))
    except InputError:
        return True


def parse_gcode(text: str, file=None, *, start_position_m=(0.0, 0.0, 0.0)):
    """Interpret an NC program.

    Parameters
    ----------
    text : str
        The program [-].
    file : str or Path, optional
        Where the program came from, for messages [-].
    start_position_m : sequence of float
        Position of X, Y, Z before the program starts [m].

    Returns
    -------
    list of Line, Rapid, Arc, Dwell
        The continuous tool path in SI, each segment with its source line [-].

    Raises
    ------
    InputError
        For anything the program says that cannot be executed as written, with file,
        line and column.

    Warns
    -----
    InputWarning
        Once per kind of ignored word (spindle, coolant, tool, offsets, ...), naming the
        first line where it occurs; once for a length written without a decimal point
        and of 1000 or more, which a Fanuc control may read in 0.001 mm.
    """
    if len(tuple(start_position_m)) != 3:
        raise InputError("start_position_m must have three coordinates (X, Y, Z) in m")
    with collector_paused():
        it = run_program(text, file, start_position_m)
    it.emit_warnings()
    return it.segments
