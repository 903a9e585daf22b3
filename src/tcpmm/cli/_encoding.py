"""ASCII stand-ins for the characters tcpmm prints, on a standard output or error whose
encoding cannot hold them (``PYTHONIOENCODING=ascii``, a C locale without UTF-8): a figure
in µm is written in um there rather than ending the command on the first µ."""

from __future__ import annotations

import codecs
import sys

#: What a stream that cannot encode a character of tcpmm's output gets instead; any other
#: character gets its letter without accents, else "?" [-].
STAND_INS = {
    "µ": "u", "μ": "u", "°": "deg", "²": "^2", "³": "^3", "−": "-", "–": "-", "—": "-",
    "±": "+-", "×": "x", "·": ".", "…": "...", "≤": "<=", "≥": ">=", "─": "-", "━": "-",
    "│": "|", "┃": "|",
}

#: Name of the codecs error handler that writes :data:`STAND_INS` [-].
HANDLER = "tcpmm-ascii"


def _stand_in(exc: UnicodeError) -> tuple[str, int]:
    """The codecs error handler: the characters ``exc`` could not encode, as ASCII."""
    if not isinstance(exc, UnicodeEncodeError):
        raise exc
    return "".join(map(_ascii_of, exc.object[exc.start:exc.end])), exc.end


def _ascii_of(char: str) -> str:
    if char in STAND_INS:
        return STAND_INS[char]
    import unicodedata

    return unicodedata.normalize("NFKD", char).encode("ascii", "ignore").decode() or "?"


codecs.register_error(HANDLER, _stand_in)


def as_written(text: str, stream) -> str:
    """``text`` as ``stream`` writes it: :data:`STAND_INS` for what its encoding cannot
    hold. A table's cells are measured as written, or a column of "90°" written "90deg"
    would stand two characters out of line [-]."""
    encoding = getattr(stream, "encoding", None) or "utf-8"
    try:
        return text.encode(encoding, HANDLER).decode(encoding)
    except LookupError:  # an encoding Python does not know: nothing to be done about it
        return text


def holds(stream, text: str = "".join(STAND_INS)) -> bool:
    """Whether ``stream``'s encoding holds every character of ``text`` (by default, every
    character tcpmm prints beyond ASCII); a stream that says no encoding is taken to [-]."""
    encoding = getattr(stream, "encoding", None)
    if not encoding:
        return True
    try:
        text.encode(encoding)
    except UnicodeEncodeError:
        return False
    except LookupError:  # an encoding Python does not know: nothing to be done about it
        return True
    return True


def unicode_stream(stream) -> bool:
    """Whether ``stream`` is written in one of Unicode's encodings (UTF-8 ...), which hold
    any text: elsewhere ``--json`` escapes what is not ASCII (``\\u00b5``), which a reader
    reads back as it was, rather than writing a stand-in [-]."""
    encoding = (getattr(stream, "encoding", None) or "utf-8").lower()
    return encoding.startswith("utf")


def _utf8(stream) -> bool:
    """Whether ``stream`` writes UTF-8 [-]."""
    try:
        return codecs.lookup(getattr(stream, "encoding", None) or "").name == "utf-8"
    except LookupError:
        return False


def fit_standard_streams() -> None:
    """Make the standard output and error write :data:`STAND_INS` for what their encoding
    cannot hold, where it cannot hold tcpmm's characters, and a name's undecoded bytes as
    text (:mod:`tcpmm.io.bytenames`) where a UTF-8 stream would refuse them; a stream that
    cannot be reconfigured is left as it is."""
    from ..io.bytenames import HANDLER as NAMES

    for stream in (sys.stdout, sys.stderr):
        if stream is None or not hasattr(stream, "reconfigure"):
            continue
        if not holds(stream):
            errors = HANDLER
        elif _utf8(stream) and getattr(stream, "errors", "") == "strict":
            errors = NAMES
        else:
            continue
        try:
            stream.reconfigure(errors=errors)
        except (ValueError, OSError):  # closed, or a stream of another kind
            continue
