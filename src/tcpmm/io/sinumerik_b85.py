"""The base-85 encoding of numeric arrays in Sinumerik Operate XML files.

Layout (as Sinumerik Operate writes ``<raw name="m_pNumberArray">``):

* the data are 32-bit words; a word is five base-85 digits, most significant first, taken
  from the alphabet :data:`ALPHABET` (not the Adobe/btoa one), or a single ``.`` for a word
  that is zero;
* a double is two words, the most significant word first (IEEE 754, big-endian);
* a complex number is two doubles, real part first;
* white space between the digits carries no meaning.
"""

from __future__ import annotations

import re

import numpy as np

from ..errors import InputError

#: The 85 digits in order of value.
ALPHABET = "0123456789abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ!#$`()*+-/:;=?@[]^_{|}~"
_VALUE = np.full(256, -1, dtype=np.int64)
_VALUE[np.frombuffer(ALPHABET.encode("ascii"), dtype=np.uint8)] = np.arange(85)
_DIGITS = np.frombuffer(ALPHABET.encode("ascii"), dtype=np.uint8)
_SPACE = re.compile(r"\s+")
_TOKEN = re.compile(r"\.|[^.]{1,5}")

__all__ = ["ALPHABET", "decode_doubles", "decode_words", "encode_doubles"]


def decode_words(text: str, element: str = "raw", file=None) -> np.ndarray:
    """The 32-bit words of a base-85 text.

    Parameters
    ----------
    text : str
        Base-85 digits and ``.`` for zero words; white space is ignored [-].
    element : str
        Name of the XML element the text comes from, for errors [-].
    file : str or Path, optional
        Source file, for errors [-].

    Returns
    -------
    ndarray of uint32
        The words [-].
    """
    s = _SPACE.sub("", text or "")
    try:
        raw = s.encode("ascii")
    except UnicodeEncodeError:
        bad = next(i for i, c in enumerate(s) if ord(c) > 127)
        raise _bad(f"character {s[bad]!r} at digit {bad + 1} is not a base-85 digit",
                   element, file) from None
    tokens = _TOKEN.findall(s)
    short = next((i for i, t in enumerate(tokens) if t != "." and len(t) != 5), None)
    if short is not None:
        pos = sum(len(t) for t in tokens[:short])
        raise _bad(f"a word at digit {pos + 1} has {len(tokens[short])} digits instead of "
                   "5: the data are truncated", element, file)
    zero = np.array([t == "." for t in tokens], dtype=bool)
    digits = np.frombuffer(raw.replace(b".", b""), dtype=np.uint8)
    values = _VALUE[digits]
    if np.any(values < 0):
        i = int(np.flatnonzero(values < 0)[0])
        raise _bad(f"character {chr(digits[i])!r} is not a base-85 digit", element, file)
    groups = values.reshape(-1, 5)
    words = np.zeros(groups.shape[0], dtype=np.int64)
    for k in range(5):
        words = words * 85 + groups[:, k]
    if np.any(words > 0xFFFFFFFF):
        i = int(np.flatnonzero(words > 0xFFFFFFFF)[0])
        raise _bad(f"word {i + 1} exceeds 32 bits: the data are damaged", element, file)
    out = np.zeros(zero.size, dtype=np.uint32)
    out[~zero] = words
    return out


def decode_doubles(text: str, element: str = "raw", file=None) -> np.ndarray:
    """The doubles of a base-85 text (two words each, most significant first).

    Parameters
    ----------
    text : str
        Base-85 text [-].
    element : str
        Name of the XML element, for errors [-].
    file : str or Path, optional
        Source file, for errors [-].

    Returns
    -------
    ndarray of float64
        The values [-].
    """
    words = decode_words(text, element, file)
    if words.size % 2:
        raise _bad(f"{words.size} words do not make whole doubles (two words each): the "
                   "data are truncated", element, file)
    return words.astype(">u4").view(">f8").astype(float)


def encode_doubles(values) -> str:
    """Base-85 text of doubles, as Sinumerik Operate writes it (without line breaks).

    Parameters
    ----------
    values : array_like
        Values [-].

    Returns
    -------
    str
        The text [-].
    """
    words = np.ascontiguousarray(np.asarray(values, dtype=">f8").ravel()).view(">u4")
    w = words.astype(np.int64)
    digits = np.empty((w.size, 5), dtype=np.uint8)
    for k in range(4, -1, -1):
        digits[:, k] = _DIGITS[w % 85]
        w //= 85
    return "".join("." if x == 0 else d.tobytes().decode("ascii")
                   for x, d in zip(words, digits, strict=True))


def _bad(message: str, element: str, file) -> InputError:
    return InputError(f"element <{element}>: {message}; export the measurement again from "
                      "Sinumerik Operate", file=file)
