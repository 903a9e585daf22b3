"""The controller-side parameters file ``tcpmm compensate --controller-out`` writes, read
back: what a commissioning engineer typed into the controller, for ``tcpmm simulate
--controller`` to apply as the drives do (:mod:`.drive`)."""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field

from ..errors import InputError
from ..io.text import read_text
from ..io.yamlutil import validate_yaml
from .controller import AxisController

_HINT = "the keys tcpmm compensate --controller-out writes"


class _Axis(BaseModel):
    """One axis's parameters, in the file's units (A, ms, mm/min, s, um/(m/s^2))."""

    model_config = ConfigDict(extra="forbid")

    friction_pulse_A: float = Field(0.0, allow_inf_nan=False)
    friction_pulse_decay_ms: float = Field(0.0, ge=0.0, allow_inf_nan=False)
    FRICT_COMP_CONST_MAX_mm_per_min: float = Field(0.0, allow_inf_nan=False)
    FRICT_COMP_TIME_s: float | None = Field(None, ge=0.0, allow_inf_nan=False)
    cross_talk_um_per_m_per_s2: float = Field(0.0, allow_inf_nan=False)


class _File(BaseModel):
    model_config = ConfigDict(extra="forbid")

    X: _Axis | None = None
    Y: _Axis | None = None
    Z: _Axis | None = None


def read_controller_parameters(path) -> dict[str, AxisController]:
    """The parameters of a controller-side compensation file, per axis.

    The drive applies the pulse as a current (``friction_pulse_A``, decaying with
    ``friction_pulse_decay_ms``); ``FRICT_COMP_TIME_s`` is the same decay as a quadrant
    error compensation takes it, and must agree with it.

    Parameters
    ----------
    path : str or Path
        The file ``tcpmm compensate --controller-out`` writes [-].

    Returns
    -------
    dict of str to AxisController
        Per axis the file names [SI].
    """
    f = validate_yaml(read_text(path, "controller parameters"), _File, path,
                      "controller parameters", _HINT)
    out = {}
    for name in ("X", "Y", "Z"):
        p = getattr(f, name)
        if p is None:
            continue
        decay = p.friction_pulse_decay_ms * 1e-3
        if p.friction_pulse_A != 0.0 and decay <= 0.0:
            raise InputError(f"axis {name}: a friction pulse needs its decay time "
                             "(friction_pulse_decay_ms > 0)", file=path)
        if p.FRICT_COMP_TIME_s is not None and abs(p.FRICT_COMP_TIME_s - decay) > 1e-6 * max(
                decay, 1e-3):
            raise InputError(f"axis {name}: FRICT_COMP_TIME_s {p.FRICT_COMP_TIME_s:g} s and "
                             f"friction_pulse_decay_ms {p.friction_pulse_decay_ms:g} ms are "
                             "one decay time and disagree; give them alike", file=path)
        out[name] = AxisController(p.friction_pulse_A, decay,
                                   p.FRICT_COMP_CONST_MAX_mm_per_min / 6e4,
                                   p.cross_talk_um_per_m_per_s2 * 1e-6)
    return out
