"""The unit a key's name spells (``lead_mm``, ``position_gain_1_per_s``): what a YAML
file's number is written in, for the messages that say what to write."""

from __future__ import annotations

#: the words a key's name may end with that spell its unit, as they are written [-]
_UNIT_WORDS = {"mm": "mm", "um": "um", "m": "m", "s": "s", "ms": "ms", "min": "min",
               "s2": "s^2", "s3": "s^3", "A": "A", "N": "N", "Nm": "N m", "rad": "rad",
               "hz": "Hz", "Hz": "Hz", "db": "dB", "1": "1", "per": "per"}


def name_unit(key: str) -> str | None:
    """The unit a key's name ends with (``lead_mm``: mm, ``position_gain_1_per_s``: 1/s,
    ``cross_talk_um_per_m_per_s2``: um/(m/s^2)); ``None`` where it names none.

    A lone letter after a symbol of one letter is no unit: ``J_m`` is the motor's
    inertia, not a length in metres.
    """
    words = key.split("_")
    k = len(words)
    while k > 1 and words[k - 1] in _UNIT_WORDS:
        k -= 1
    unit = words[k:]
    if not unit or "per" in (unit[0], unit[-1]) or (
            len(unit) == 1 and len(unit[0]) == 1 and len("_".join(words[:k])) == 1):
        return None
    parts = " ".join(_UNIT_WORDS[w] for w in unit).split(" per ")
    under = "/".join(parts[1:])
    return parts[0] + (f"/({under})" if len(parts) > 2 else f"/{under}" if under else "")
