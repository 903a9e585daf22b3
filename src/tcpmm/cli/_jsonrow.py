"""A row of scalars as the JSON text :func:`json.dumps` writes with ``indent=2``, made
without its encoder: with an indent, ``json`` encodes in Python, not C, and a corner table
of a long run (a row per corner and sensor, hundreds of thousands) took longer to write
than to measure."""

from __future__ import annotations

import math
from json.encoder import encode_basestring, encode_basestring_ascii

from ..io.bytenames import readable

_LITERAL = {type(None): lambda v: "null", bool: lambda v: "true" if v else "false",
            int: int.__repr__}
_KEYS: dict = {}  # (key, ascii_only) -> the key's JSON text and the separator


def flat_row_json(row: dict, ascii_only: bool) -> str | None:
    """``row`` as ``json.dumps(row, indent=2, ensure_ascii=ascii_only, allow_nan=False)``
    writes it, a float that is not finite as ``null``; ``None`` where a key is not text or
    a value is not a number, text, ``True``, ``False`` or ``None`` (the caller encodes
    it) [-]."""
    text = encode_basestring_ascii if ascii_only else encode_basestring
    items = []
    for k, v in row.items():
        key = _KEYS.get((k, ascii_only)) if type(k) is str else None
        if key is None:
            if type(k) is not str:
                return None
            key = _KEYS.setdefault((k, ascii_only), text(readable(k)) + ": ")
        t = type(v)
        if t is float:  # finite where v - v is 0 (inf - inf and NaN are NaN)
            items.append(key + (float.__repr__(v) if v - v == 0.0 else "null"))
        elif isinstance(v, float):  # numpy's, whose v - v would warn
            items.append(key + (float.__repr__(v) if math.isfinite(v) else "null"))
        elif t is str:
            items.append(key + text(v if v.isascii() else readable(v)))
        elif t in _LITERAL:
            items.append(key + _LITERAL[t](v))
        else:
            return None
    return "{\n  " + ",\n  ".join(items) + "\n}" if items else "{}"
