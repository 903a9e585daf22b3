"""The compiled lexer and executor of plain G0/G1 blocks, a chunk of lines at a time.

:func:`scan_lines` reads the bytes of a chunk of lines (each ended by ``\\n``) and finds
for every line whether it is a plain move as :data:`tcpmm.path.gcode_fast.PLAIN_MOVE`
matches it, its motion code and its X, Y, Z and F values; or a plain arc (``G2``/``G3``
or none, then X, Y, Z, I, J, K, R and F, each at most once and in that order, every
number exact), executed by :func:`tcpmm.path.gcode_arcs.arc_run`; and whether a length
word of such a line is written without a decimal point and reaches 1000 (X50000), of
which the interpreter warns (:meth:`tcpmm.path.gcode_geometry.GeometryMixin.no_point`).
A number is converted only where the conversion is exact: a mantissa of at most 2^53 and
at most 22 digits after the point, divided by a power of ten that is a double exactly, is
one correctly rounded division, the value Python's ``float`` gives for the same text
(Clinger's fast path); a line with any other number is marked for the regular expression
and ``float``.
:func:`run_plain` executes a run of the lines as :func:`tcpmm.path.gcode_fast.plain_run`
does, with the same arithmetic in the same order, and stops where it would.

Both are called through :mod:`tcpmm._compiled`, so that a command parses without numba.
"""

from __future__ import annotations

import numpy as np
from numba import njit

#: :data:`tcpmm.path.gcode_words.ZERO_MOVE_M`, here a literal: this module is compiled on
#: its own [m]
_ZERO_MOVE_M = 1e-9 * (1.0 + 1e-6)

#: a line's status in :func:`scan_lines`' codes: not a plain move, a plain move with
#: its numbers converted, a plain move with a number converted only by ``float``, a
#: plain arc with its numbers converted [-]
NOT_PLAIN, PLAIN, PLAIN_SLOW, ARC = 0, 1, 2, 3
#: columns of the codes: status, motion code (-1 for none), present words (bit j for
#: the value in column j of the values: X, Y, Z, F, I, J, K, R), and 1 where a length word
#: (not F) is written without a decimal point and reaches :data:`_WHOLE_LENGTH` [-]
STATUS, MOTION, WORDS, WHOLE_LONG = 0, 1, 2, 3
#: :data:`tcpmm.path.gcode_words.WHOLE_LENGTH`, here a literal: this module is compiled on
#: its own [-]
_WHOLE_LENGTH = 1000
#: the letters of a line in the order they may come, each with its column of the values
_LETTERS = ((88, 0), (89, 1), (90, 2), (73, 4), (74, 5), (75, 6), (82, 7), (70, 3))
#: the words of a move (X, Y, Z) and of an arc's centre or radius (I, J, K, R) [-]
MOVE_WORDS, ARC_WORDS = 7, 240
#: the largest mantissa a double holds exactly [-]
_MANTISSA_MAX = 1 << 53
#: the state :func:`run_plain` starts from and its layout: position, motion code (-1
#: none), feed (NaN none), unit, absolute (1 or 0), the largest feed and coordinate [SI]
STATE_FIELDS = ("x", "y", "z", "motion", "feed", "unit", "absolute", "max_feed",
                "max_coordinate")


@njit(cache=True)
def _blank(buf, i, end):
    while i < end and (buf[i] == 32 or buf[i] == 9):
        i += 1
    return i


@njit(cache=True)
def _number(buf, i, end, pow10):
    """The number at ``buf[i]`` as the regular expression takes it: the index after it
    (``-1`` where there is none), its value, whether the value is exact, and whether it
    has no decimal point and a size of :data:`_WHOLE_LENGTH` or more [-]."""
    neg = False
    if i < end and (buf[i] == 45 or buf[i] == 43):
        neg = buf[i] == 45
        i += 1
    m, exact, before, after = 0, True, 0, 0
    while i < end and 48 <= buf[i] <= 57:
        m = m * 10 + (buf[i] - 48) if exact else m
        exact = exact and m <= _MANTISSA_MAX
        before += 1
        i += 1
    point = i < end and buf[i] == 46
    if point:
        i += 1
        while i < end and 48 <= buf[i] <= 57:
            m = m * 10 + (buf[i] - 48) if exact else m
            exact = exact and m <= _MANTISSA_MAX
            after += 1
            i += 1
    if before == 0 and after == 0:
        return -1, 0.0, False, False
    # a mantissa no longer exact is past 2^53, and long
    whole_long = not point and (m >= _WHOLE_LENGTH or not exact)
    exact = exact and after < pow10.size
    value = float(m) / pow10[after] if exact else 0.0
    return i, -value if neg else value, exact, whole_long


@njit(cache=True)
def _scan_line(buf, i, end, vals, pow10):
    """Status, motion code, present words and the mark of a length without a point
    (:data:`WHOLE_LONG`) of the line ``buf[i:end]``; its values go into ``vals`` [-]."""
    i = _blank(buf, i, end)
    motion = -1
    if i < end and (buf[i] == 71 or buf[i] == 103):  # G or g
        i = _blank(buf, i + 1, end)
        j = i
        while j < end and 48 <= buf[j] <= 57:
            j += 1
        # 0*[0-3]: zeros, and a last digit 0 to 3
        if j == i or buf[j - 1] > 51:
            return NOT_PLAIN, -1, 0, 0
        for q in range(i, j - 1):
            if buf[q] != 48:
                return NOT_PLAIN, -1, 0, 0
        motion = buf[j - 1] - 48
        i = _blank(buf, j, end)
    status, words, no_point = PLAIN, 0, 0
    for letter, slot in _LETTERS:
        if i < end and (buf[i] == letter or buf[i] == letter + 32):
            i, value, exact, whole_long = _number(buf, _blank(buf, i + 1, end), end, pow10)
            if i < 0:
                return NOT_PLAIN, -1, 0, 0
            vals[slot] = value
            words |= 1 << slot
            status = status if exact else PLAIN_SLOW
            no_point = 1 if whole_long and slot != 3 else no_point  # F is no length
            i = _blank(buf, i, end)
    if i != end:
        return NOT_PLAIN, -1, 0, 0
    if motion < 2 and not words & ARC_WORDS:
        return status, motion, words, no_point
    # an arc (or a centre word where G0/G1 is given: the interpreter's message)
    if status != PLAIN or 0 <= motion < 2 or not words & (MOVE_WORDS | ARC_WORDS):
        return NOT_PLAIN, -1, 0, 0
    return ARC, motion, words, no_point


@njit(cache=True)
def scan_lines(buf):
    """Lex a chunk of lines.

    Parameters
    ----------
    buf : ndarray of uint8
        The chunk's bytes, every line ended by ``\\n`` (10) [-].

    Returns
    -------
    codes : ndarray of int64, shape (lines, 4)
        Per line its status, motion code, present words and length mark (:data:`STATUS`,
        :data:`MOTION`, :data:`WORDS`, :data:`WHOLE_LONG`; the words and the mark 0 where
        the line is not plain) [-].
    vals : ndarray, shape (lines, 8)
        Per line the values of X, Y, Z, F, I, J, K and R as written (0 where absent) [-].
    """
    n = 0
    for b in buf:
        n += b == 10
    codes = np.zeros((n, 4), dtype=np.int64)
    vals = np.zeros((n, 8))
    pow10 = np.empty(23)
    pow10[0] = 1.0
    for e in range(1, 23):
        pow10[e] = pow10[e - 1] * 10.0  # exact: every 10^e to 10^22 is a double
    _lines(buf, codes, vals, pow10)
    return codes, vals


# Compiled without reference counting (``_nrt=False``): the loop allocates nothing, and the
# counts numba kept on the row of values handed to each line's scan, up and down for
# every line, took two thirds of the lexing.
@njit(cache=True, _nrt=False)
def _lines(buf, codes, vals, pow10):
    """The loop of :func:`scan_lines` over the lines of ``buf``, into ``codes`` and
    ``vals`` [-]."""
    start, k = 0, 0
    for end in range(buf.size):
        if buf[end] == 10:
            s, mo, w, p = _scan_line(buf, start, end, vals[k], pow10)
            codes[k, 0], codes[k, 1], codes[k, 2], codes[k, 3] = s, mo, w, p
            start, k = end + 1, k + 1


@njit(cache=True)
def block_feed(w, v, feed, unit, max_feed):
    """The feed after a block of words ``w`` and values ``v`` (:func:`scan_lines`): its F
    word's, else ``feed``; -1 where its F word is not within 0 and ``max_feed`` [m/s]."""
    if w & 8:
        if not 0.0 < v[3] <= max_feed:
            return -1.0
        return v[3] * unit / 60.0
    return feed


@njit(cache=True)
def block_end(w, v, px, py, pz, unit, absolute, max_c):
    """Whether a block of words ``w`` and values ``v`` from ``(px, py, pz)`` keeps every
    coordinate it gives within ``max_c``, and its end point [-], [m] (numbers, not an
    array: a run of blocks carries its position in registers)."""
    x = px if not w & 1 else v[0] * unit if absolute else px + v[0] * unit
    y = py if not w & 2 else v[1] * unit if absolute else py + v[1] * unit
    z = pz if not w & 4 else v[2] * unit if absolute else pz + v[2] * unit
    ok = not ((w & 1 and not abs(x) <= max_c) or (w & 2 and not abs(y) <= max_c)
              or (w & 4 and not abs(z) <= max_c))
    return ok, x, y, z


@njit(cache=True)
def run_plain(codes, vals, k, state):
    """Execute lines from ``k`` on as the interpreter would, up to the first that is not
    a plain move or that would warn or fail.

    Parameters
    ----------
    codes, vals : ndarray
        As :func:`scan_lines` gives them [-].
    k : int
        0-based index of the first line [-].
    state : ndarray
        The modal state before it, laid out as :data:`STATE_FIELDS`; updated [SI].

    Returns
    -------
    stop : int
        Index of the first line not executed [-].
    ends : ndarray, shape (stop - k, 3)
        End point of each block executed [m].
    feeds : ndarray
        Feed after each block, NaN where there is none yet [m/s].
    motions : ndarray of int64
        Motion code of each block [-].
    """
    n = codes.shape[0]
    ends = np.empty((n - k, 3))
    feeds = np.empty(n - k)
    motions = np.empty(n - k, dtype=np.int64)
    px, py, pz, motion, feed = state[0], state[1], state[2], int(state[3]), state[4]
    unit, absolute, max_feed, max_c = state[5], state[6] != 0.0, state[7], state[8]
    i = k
    while i < n and codes[i, 0] == PLAIN:
        w, v = codes[i, 2], vals[i]
        mo = motion if codes[i, 1] < 0 else codes[i, 1]
        fe = block_feed(w, v, feed, unit, max_feed)
        if fe < 0.0 or (w & 7) == 0 or mo < 0 or mo > 1 or (mo == 1 and np.isnan(fe)):
            break
        ok, x, y, z = block_end(w, v, px, py, pz, unit, absolute, max_c)
        if not ok:
            break
        if (abs(x - px) <= _ZERO_MOVE_M and abs(y - py) <= _ZERO_MOVE_M
                and abs(z - pz) <= _ZERO_MOVE_M):  # a zero-length move warns
            break
        ends[i - k, 0], ends[i - k, 1], ends[i - k, 2] = x, y, z
        feeds[i - k], motions[i - k] = fe, mo
        px, py, pz, motion, feed = x, y, z, mo, fe
        i += 1
    state[0], state[1], state[2], state[3], state[4] = px, py, pz, motion, feed
    return i, ends[: i - k], feeds[: i - k], motions[: i - k]
