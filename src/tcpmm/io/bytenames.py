"""Names the system hands over as bytes (a file name, an argument), written as text.

Python gives a file name or an argument whose bytes its locale does not decode with each
such byte as a lone surrogate, U+DC80 to U+DCFF (PEP 383): the name still opens its file,
but no UTF-8 text holds it. Written into an output, a run of such bytes is read as the
UTF-8 it is where it is one (an "ü" typed in a C locale), and each byte that is none (a
Latin-1 "ü" of an old share) stands as U+FFFD: an output is written, never refused, for
a name.
"""

from __future__ import annotations

import codecs

#: Name of the codecs error handler that writes a name's undecoded bytes as text [-].
HANDLER = "tcpmm-names"


def _as_text(exc: UnicodeError) -> tuple[bytes, int]:
    """The codecs error handler of UTF-8 files: the surrogates ``exc`` could not encode,
    as the UTF-8 of the text they decode to (as bytes: a handler's text must be ASCII) [-]."""
    if not isinstance(exc, UnicodeEncodeError):
        raise exc
    raw = bytearray()
    for char in exc.object[exc.start:exc.end]:
        code = ord(char)
        # a surrogate of a byte is that byte; any other lone one is no character at all
        raw += bytes([code - 0xDC00]) if 0xDC80 <= code <= 0xDCFF else b"\xff"
    return raw.decode("utf-8", "replace").encode("utf-8"), exc.end


codecs.register_error(HANDLER, _as_text)


def readable(text: str) -> str:
    """``text`` with the undecoded bytes of a name (lone surrogates) decoded as
    :data:`HANDLER` writes them; any other text is returned as it is [-]."""
    if text.isascii():
        return text
    return text.encode("utf-8", HANDLER).decode("utf-8")
