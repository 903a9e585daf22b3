"""A fitted value with its standard deviation, and when it is said to be determined:
what :mod:`~tcpmm.ident.lti.tfsd` reports of the poles, delay and gain and
:mod:`~tcpmm.ident.lti.zerosd` of the zeros."""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["DETERMINED", "Estimate"]

#: Largest relative standard deviation of a parameter said to be determined [-].
DETERMINED = 0.5


@dataclass(frozen=True)
class Estimate:
    """A fitted value and its standard deviation.

    Parameters
    ----------
    value : float
        Fitted value [unit of the parameter].
    sd : float
        Standard deviation; ``inf`` where the data do not bound it [unit of the parameter].
    why : str, optional
        Why the value is undetermined whatever its sd (see :mod:`~tcpmm.ident.lti.tfsd`);
        empty if not [-].
    """

    value: float
    sd: float
    why: str = ""

    @property
    def determined(self) -> bool:
        """Whether no reason holds it open and the sd is finite and at most
        :data:`DETERMINED` of the value [-]."""
        return bool(not self.why and math.isfinite(self.sd)
                    and self.sd <= DETERMINED * abs(self.value))

    def opened(self, why: str) -> Estimate:
        """The value, undetermined for the reason ``why``, its sd infinite [-]."""
        return Estimate(self.value, math.inf, why)

    @property
    def bound(self) -> float:
        """The sd where determined, else ``inf``: no sd is given for a value left open,
        lest it be read as one [unit of the parameter]."""
        return self.sd if self.determined else math.inf

    def to_dict(self, key: str) -> dict:
        """``{key: value, key_sd: sd or None, key_determined: bool}``; a ``key`` ending in a
        unit (``freq_hz``) puts ``_sd`` before it (``freq_sd_hz``) [-]."""
        stem, _, unit = key.rpartition("_") if key.endswith(("_hz", "_s")) else (key, "", "")
        sd_key = f"{stem}_sd_{unit}" if unit else f"{key}_sd"
        return {key: float(self.value),
                sd_key: float(self.sd) if self.determined else None,
                f"{stem}_determined": self.determined}

    def text(self, fmt: str = ".4g", scale: float = 1.0, pm: str = "+-") -> str:
        """``value +- sd`` (each times ``scale``, the value in format ``fmt``, the sd to two
        digits, ``pm`` the sign the medium writes), or the value and ``(undetermined)``
        where the data do not determine it [-]."""
        v = f"{self.value * scale:{fmt}}"
        if not self.determined:
            return f"{v} (undetermined)"
        return f"{v} {pm} {self.sd * scale:.2g}"
