"""The controller-side parameters file ``tcpmm compensate --controller-out`` writes, read
back: what a commissioning engineer typed into the controller, for ``tcpmm simulate
--controller`` to apply as the drives do (:mod:`.drive`)."""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field, create_model

from ..errors import InputError
from ..io.text import read_text
from ..io.yamlutil import key_lines, load_yaml, validate_yaml
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


def _check_axes(text: str, path, axes) -> None:
    """Refuse a top-level key that is none of ``axes``, naming the model's axes: the schema
    alone would call it an unknown key, as if the file, not the model, were wrong."""
    data, node = load_yaml(text, path)
    if not isinstance(data, dict):
        return  # the schema says what the file should be
    lines = key_lines(node)
    for name in data:
        if name not in axes:
            raise InputError(f"{name} is not an axis of the model (it has "
                             f"{', '.join(axes)}); give the parameters of its axes only",
                             file=path, line=lines.get((str(name),)), column=str(name))


def read_controller_parameters(path, axes=("X", "Y", "Z")) -> dict[str, AxisController]:
    """The parameters of a controller-side compensation file, per axis.

    The drive applies the pulse as a current (``friction_pulse_A``, decaying with
    ``friction_pulse_decay_ms``); ``FRICT_COMP_TIME_s`` is the same decay as a quadrant
    error compensation takes it, and must agree with it.

    Parameters
    ----------
    path : str or Path
        The file ``tcpmm compensate --controller-out`` writes [-].
    axes : sequence of str
        The axes of the model the parameters are for; the file may name these only [-].

    Returns
    -------
    dict of str to AxisController
        Per axis the file names [SI].
    """
    text = read_text(path, "controller parameters")
    axes = list(axes)
    _check_axes(text, path, axes)
    schema = create_model("ControllerParameters", __config__=ConfigDict(extra="forbid"),
                          **{a: (_Axis | None, None) for a in axes})
    f = validate_yaml(text, schema, path, "controller parameters", _HINT)
    out = {}
    for name in axes:
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
