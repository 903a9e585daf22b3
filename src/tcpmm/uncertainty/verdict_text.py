"""A verdict as a user reads it: its interval and its cause in words, where the JSON keeps
the cause's key (``axis Y guideway_share, open``)."""

from __future__ import annotations

import re

__all__ = ["QUANTITY_WORDS", "cause_text", "quantity_text", "verdict_words"]


def verdict_words(verdict: str, half_width_um: float, cause: str, pm: str = "+-",
                  um: str = "um") -> str:
    """A figure's verdict as a user reads it: firm with its interval, uncertain with it and
    its cause, undetermined with its cause; ``pm`` and ``um`` as the medium writes them
    (the console's ASCII, a page's ``±`` and ``µm``) [-].

    Parameters
    ----------
    verdict : str
        ``firm``, ``uncertain`` or ``undetermined`` [-].
    half_width_um : float
        Half-width of the 90 % interval [um].
    cause : str
        What drives it [-].
    pm, um : str
        The plus-minus sign and the micrometre's unit [-].
    """
    if verdict == "firm":
        return f"firm ({pm} {half_width_um:.2f} {um})"
    if verdict == "uncertain":
        return f"uncertain {pm} {half_width_um:.2f} {um} ({cause_text(cause)})"
    return f"undetermined ({cause_text(cause)})"


#: The quantities identification may leave open that have a name, as the docs say them; a
#: model symbol (``K_t``) reads as the model file writes it
QUANTITY_WORDS = {"guideway_share": "guideway share of the friction",
                  "friction_level": "friction level", "static_level": "static friction level",
                  "time_base": "time base", "position_feedback": "position feedback",
                  "position_gain": "position gain", "column_damping": "column damping",
                  "bed_damping": "bed damping"}


def quantity_text(quantity: str) -> str:
    """A quantity as a user reads it (:data:`QUANTITY_WORDS`) [-]."""
    return QUANTITY_WORDS.get(quantity, quantity)


def cause_text(cause: str) -> str:
    """A figure's cause as a user reads it: ``axis Y guideway_share, open`` (the key the
    JSON keeps) reads "axis Y guideway share, which the data leave open" [-]."""
    m = re.fullmatch(r"axis (\S+) (\S+)(, open)?", cause)
    if m is None:
        return cause
    return (f"axis {m[1]} {quantity_text(m[2])}"
            + (", which the data leave open" if m[3] else ""))
