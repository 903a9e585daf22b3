"""What a gate reports: a :class:`Finding` per physically suspect result, and the error that
refuses a model with findings (:class:`SuspectModelError`); and the records the gates
read (:func:`bundle_records`)."""

from __future__ import annotations

import re
from dataclasses import dataclass

from ...errors import InputError

__all__ = ["Finding", "SuspectModelError", "bundle_records"]


@dataclass(frozen=True)
class Finding:
    """A physically suspect result of identification.

    Parameters
    ----------
    axis : str
        Axis name [-].
    parameter : str
        What is suspect, e.g. ``friction.guideway.fs_pos`` [-].
    value : float
        Its value, in ``unit`` [unit].
    unit : str
        Unit of ``value`` as shown, e.g. ``N`` [-].
    bound : str
        The bound it violates, with its value and unit [-].
    data : str
        Which data led there (file and what in it) [-].
    remedy : str
        What to do about it [-].
    """

    axis: str
    parameter: str
    value: float
    unit: str
    bound: str
    data: str
    remedy: str

    def __str__(self) -> str:
        unit = f" {self.unit}" if self.unit else ""
        return (f"axis {self.axis}: {self.parameter} = {_beside(self.value, self.bound)}"
                f"{unit}, {self.bound} (from {self.data}); {self.remedy}")


def _beside(value: float, bound: str) -> str:
    """``value`` to four significant digits, more where those would read as a number of
    ``bound`` ("1.25, outside 0.8 to 1.25" for 1.2501) [-]."""
    said = set(re.findall(r"\d+(?:\.\d+)?(?:e[-+]?\d+)?", bound))
    for digits in range(4, 11):
        text = f"{value:.{digits}g}"
        if text.lstrip("-") not in said:
            break
    return text


class SuspectModelError(InputError):
    """Identification gave a physically suspect model, which is therefore not written.

    Parameters
    ----------
    findings : list of Finding
        What the gates found [-].
    file : str or Path, optional
        The bundle [-].
    """

    def __init__(self, findings, file=None):
        self.findings = list(findings)
        text = " | ".join(str(f) for f in self.findings)
        super().__init__(
            f"the identified model is physically suspect and was not written: {text}. "
            "Fix the data as said, or write the model anyway, marked as suspect, with "
            "--accept-suspect (Python: identify_bundle(..., accept_suspect=True))",
            file=file)


def bundle_records(bundle):
    """Every sweep and friction record of a bundle, as ``(axis, record, file name)`` [-].

    Parameters
    ----------
    bundle : Bundle
        Read with :func:`tcpmm.io.bundle.read_bundle` [-].
    """
    for name, rec in bundle.axes.items():
        for record, kind in ((rec.sweep, "sweep.csv"), (rec.friction, "friction.csv")):
            if record is not None:
                yield name, record, kind
