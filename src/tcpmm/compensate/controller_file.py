"""The controller-side parameters file ``tcpmm compensate --controller-out`` writes, read
back: what a commissioning engineer typed into the controller, for ``tcpmm simulate
--controller`` to apply as the drives do (:mod:`.drive`)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, create_model

from ..errors import InputError
from ..io.text import read_text
from ..io.yamlutil import key_lines, load_yaml, validate_yaml
from .adaptation import Characteristic
from .controller import AxisController, velocity_per_ampere

_HINT = "the keys tcpmm compensate --controller-out writes"
#: Longest decay of a friction pulse taken [s]: the pulse breaks the friction's hold at a
#: reversal, over milliseconds to a few tenths of a second (the decays tuned run 3-300 ms);
#: one of seconds is a standing current offset, or milliseconds typed as seconds.
LONGEST_DECAY_S = 10.0
#: Largest cross-talk gain taken [m/(m/s^2)]: a TCP deflection of 1 mm per m/s^2 is that
#: of a structural mode at 1/(2 pi sqrt(1e-3 s^2)) = 5 Hz, below any machine tool's (20 Hz
#: gives 63 um per m/s^2); a larger gain is a unit slip (nm typed as um).
LARGEST_CROSS_TALK = 1e-3


class _Axis(BaseModel):
    """One axis's parameters, in the file's units (A, ms, mm/min, s, um/(m/s^2))."""

    model_config = ConfigDict(extra="forbid")

    friction_pulse_A: float = Field(0.0, allow_inf_nan=False)
    friction_pulse_decay_ms: float = Field(0.0, ge=0.0, allow_inf_nan=False)
    FRICT_COMP_CONST_MAX_mm_per_min: float = Field(0.0, allow_inf_nan=False)
    FRICT_COMP_TIME_s: float | None = Field(None, ge=0.0, allow_inf_nan=False)
    FRICT_COMP_ADAPT_ENABLE: Literal[0, 1] | None = None
    friction_pulse_min_A: float | None = Field(None, allow_inf_nan=False)
    FRICT_COMP_CONST_MIN_mm_per_min: float | None = Field(None, allow_inf_nan=False)
    FRICT_COMP_ACCEL1_m_per_s2: float | None = Field(None, gt=0.0, allow_inf_nan=False)
    FRICT_COMP_ACCEL2_m_per_s2: float | None = Field(None, gt=0.0, allow_inf_nan=False)
    FRICT_COMP_ACCEL3_m_per_s2: float | None = Field(None, gt=0.0, allow_inf_nan=False)
    cross_talk_um_per_m_per_s2: float = Field(0.0, allow_inf_nan=False)


class _Model(BaseModel):
    """The model the parameters were computed on: its name and its file's digest
    (:func:`tcpmm.io.modelfile.model_identity`)."""

    model_config = ConfigDict(extra="forbid")

    name: str
    digest: str


def _check_axes(text: str, path, axes) -> None:
    """Refuse a top-level key that is none of ``axes`` (nor ``model``), naming the
    model's axes: the schema alone would call it an unknown key, as if the file, not the
    model, were wrong."""
    data, node = load_yaml(text, path)
    if not isinstance(data, dict):
        return  # the schema says what the file should be
    lines = key_lines(node)
    for name in data:
        if name not in axes and name != "model":
            raise InputError(f"{name} is not an axis of the model (it has "
                             f"{', '.join(axes)}); give the parameters of its axes only",
                             file=path, line=lines.get((str(name),)), column=str(name))


def read_controller_parameters(path, axes=("X", "Y", "Z"),
                               model: dict | None = None) -> dict[str, AxisController]:
    """The parameters of a controller-side compensation file, per axis.

    The drive applies the pulse as a current (``friction_pulse_A``, decaying with
    ``friction_pulse_decay_ms``); ``FRICT_COMP_CONST_MAX_mm_per_min`` and
    ``FRICT_COMP_TIME_s`` are the same pulse as a velocity setpoint pulse, as a quadrant
    error compensation takes it (:func:`~.controller.velocity_per_ampere`). Either form alone is
    applied; both given must agree. Values no drive could mean are refused: a pulse beyond
    the axis's current limit, a decay shorter than one velocity-loop period or longer than
    :data:`LONGEST_DECAY_S`, a cross-talk gain above :data:`LARGEST_CROSS_TALK`.

    Parameters
    ----------
    path : str or Path
        The file ``tcpmm compensate --controller-out`` writes [-].
    axes : dict of str to Axis, or sequence of str
        The axes of the model the parameters are for; the file may name these only. Names
        alone cannot convert the velocity form nor check the current limit and the
        velocity-loop period: a file with the velocity form only is then refused [-].
    model : dict, optional
        The name and digest of the model the parameters are applied on
        (:func:`tcpmm.io.modelfile.model_identity`): a file computed on another says so,
        as an :class:`~tcpmm.errors.InputWarning` [-].

    Returns
    -------
    dict of str to AxisController
        Per axis the file names [SI].
    """
    text = read_text(path, "controller parameters")
    models = axes if isinstance(axes, Mapping) else {}
    axes = list(axes)
    _check_axes(text, path, axes)
    schema = create_model("ControllerParameters", __config__=ConfigDict(extra="forbid"),
                          model=(_Model | None, None),
                          **{a: (_Axis | None, None) for a in axes})
    f = validate_yaml(text, schema, path, "controller parameters", _HINT)
    _say_other_model(f.model, model, path)
    out = {}
    for name in axes:
        p = getattr(f, name)
        if p is not None:
            out[name] = _axis_parameters(name, p, models.get(name), path)
    return out


def _say_other_model(written: _Model | None, model: dict | None, path) -> None:
    """Warn where the file was computed on another model than the one it is applied on:
    its pulses answer that model's friction, its feed-forward that model's structure."""
    if written is None or model is None or written.digest == model["digest"]:
        return
    import warnings

    from ..errors import InputWarning

    warnings.warn(f"{path} was computed on the model {written.name!r} (digest "
                  f"{written.digest}), not on this one ({model['name']!r}, digest "
                  f"{model['digest']}): its pulses and feed-forward answer that model's "
                  "friction and structure; compute them on this one (tcpmm compensate "
                  "--controller-out) unless that is what you are trying", InputWarning,
                  stacklevel=3)


def _axis_parameters(name: str, p: _Axis, axis, path) -> AxisController:
    """One axis's parameters in SI, its two forms of the pulse made one and checked
    against ``axis`` (None: the model's axis unknown) [SI]."""
    given = p.model_fields_set
    decay, key = _decay(name, p, given, path)
    _check_decay(name, decay, 0.0 if axis is None else axis.servo.T_v, key, path)
    pulse = _pulse(name, p, given, axis, path)
    if pulse != 0.0 and decay <= 0.0:
        raise InputError(f"axis {name}: a friction pulse needs its decay time "
                         "(friction_pulse_decay_ms or FRICT_COMP_TIME_s > 0)", file=path)
    gain = p.cross_talk_um_per_m_per_s2 * 1e-6
    if abs(gain) > LARGEST_CROSS_TALK:
        raise InputError(
            f"axis {name}: cross_talk_um_per_m_per_s2 {p.cross_talk_um_per_m_per_s2:g} is a "
            f"TCP deflection of {abs(gain) * 1e3:.4g} mm per m/s^2, that of a structural mode "
            "below 5 Hz, which no machine tool has; the gain is in um per m/s^2 (nm typed "
            "as um?)", file=path)
    velocity = pulse * velocity_per_ampere(axis) if axis is not None else (
        p.FRICT_COMP_CONST_MAX_mm_per_min / 6e4)
    return AxisController(pulse, decay, velocity, gain,
                          _characteristic(name, p, pulse, axis, path))


#: Largest acceleration at a reversal an adaptation characteristic may name [m/s^2]: 5 g,
#: beyond the linear axes of machine tools (2 g at most); a larger one is mm/s^2 typed as
#: m/s^2, which would leave every reversal on the characteristic's ramp from zero.
LARGEST_ACCEL = 50.0
#: The keys of the adaptation characteristic, which FRICT_COMP_ADAPT_ENABLE switches on [-].
ADAPTATION_KEYS = ("friction_pulse_min_A", "FRICT_COMP_CONST_MIN_mm_per_min",
                   "FRICT_COMP_ACCEL1_m_per_s2", "FRICT_COMP_ACCEL2_m_per_s2",
                   "FRICT_COMP_ACCEL3_m_per_s2")


def _characteristic(name: str, p: _Axis, pulse_A: float, axis,
                    path) -> Characteristic | None:
    """The pulse's adaptation characteristic where ``FRICT_COMP_ADAPT_ENABLE`` is 1, as
    the controller applies it, its amplitudes within ``axis``'s current limit (``None``:
    not known); its keys given without the switch are refused, as the controller would
    leave them unused [-]."""
    given = [k for k in ADAPTATION_KEYS if getattr(p, k) is not None]
    if p.FRICT_COMP_ADAPT_ENABLE != 1:
        if given and p.FRICT_COMP_ADAPT_ENABLE is None:
            raise InputError(f"axis {name}: {', '.join(given)} given without "
                             "FRICT_COMP_ADAPT_ENABLE; set it to 1 to apply the adaptation "
                             "characteristic, or to 0 to leave it off", file=path)
        return None
    acc = (p.FRICT_COMP_ACCEL1_m_per_s2, p.FRICT_COMP_ACCEL2_m_per_s2,
           p.FRICT_COMP_ACCEL3_m_per_s2)
    if None in acc or not acc[0] < acc[1] < acc[2]:
        raise InputError(f"axis {name}: FRICT_COMP_ADAPT_ENABLE 1 needs "
                         "FRICT_COMP_ACCEL1_m_per_s2 < FRICT_COMP_ACCEL2_m_per_s2 < "
                         "FRICT_COMP_ACCEL3_m_per_s2, each given", file=path)
    ratios = [mn / mx for mn, mx in ((p.friction_pulse_min_A, pulse_A),
                                     (p.FRICT_COMP_CONST_MIN_mm_per_min,
                                      p.FRICT_COMP_CONST_MAX_mm_per_min))
              if mn is not None and mx != 0.0]
    if not ratios:
        if pulse_A == 0.0:
            return None  # no pulse to adapt
        raise InputError(f"axis {name}: FRICT_COMP_ADAPT_ENABLE 1 needs the amplitude "
                         "beyond FRICT_COMP_ACCEL3: friction_pulse_min_A or "
                         "FRICT_COMP_CONST_MIN_mm_per_min", file=path)
    if max(ratios) - min(ratios) > 2e-3 * max(abs(r) for r in ratios):  # 4 digits each
        raise InputError(f"axis {name}: friction_pulse_min_A and "
                         "FRICT_COMP_CONST_MIN_mm_per_min are one amplitude and disagree "
                         f"({ratios[0]:.4g} and {ratios[1]:.4g} of the largest); give one, "
                         "or both alike", file=path)
    if acc[2] > LARGEST_ACCEL:
        raise InputError(f"axis {name}: FRICT_COMP_ACCEL3_m_per_s2 {acc[2]:g} is an "
                         f"acceleration of {acc[2] / 9.81:.3g} g at a reversal, beyond any "
                         f"feed axis's ({LARGEST_ACCEL:g} m/s^2 at most); the "
                         "accelerations are in m/s^2 (mm/s^2 typed as m/s^2?)", file=path)
    if ratios[0] < 0.0:
        raise InputError(f"axis {name}: the amplitude beyond FRICT_COMP_ACCEL3 has the "
                         "opposite sign to the largest; give both with the same sign",
                         file=path)
    if axis is not None and abs(pulse_A * ratios[0]) > axis.servo.current_limit:
        raise InputError(f"axis {name}: the amplitude beyond FRICT_COMP_ACCEL3, "
                         f"{pulse_A * ratios[0]:.4g} A, is beyond the axis's current limit of "
                         f"{axis.servo.current_limit:g} A (friction_pulse_min_A in A, "
                         "FRICT_COMP_CONST_MIN_mm_per_min in mm/min: a unit slip?)", file=path)
    return Characteristic(tuple(acc), ratios[0])


def _decay(name: str, p: _Axis, given, path) -> tuple[float, str]:
    """The pulse's decay time from whichever of its two keys is given (both must agree),
    and that key [s, -]."""
    ms = p.friction_pulse_decay_ms * 1e-3
    s = p.FRICT_COMP_TIME_s
    if "friction_pulse_decay_ms" in given and s is not None and abs(s - ms) > 1e-6 * max(
            ms, 1e-3):
        raise InputError(f"axis {name}: FRICT_COMP_TIME_s {s:g} s and "
                         f"friction_pulse_decay_ms {p.friction_pulse_decay_ms:g} ms are "
                         "one decay time and disagree; give them alike", file=path)
    if "friction_pulse_decay_ms" in given or s is None:
        return ms, "friction_pulse_decay_ms"
    return s, "FRICT_COMP_TIME_s"


def _check_decay(name: str, decay: float, T_v: float, key: str, path) -> None:
    """Refuse a decay no drive applies: under one velocity-loop period ``T_v`` (0: not
    known) it is over before the loop sees it, above :data:`LONGEST_DECAY_S` it is no
    pulse; each most likely a unit slip in ``key``, the key it was given by [s]."""
    in_ms = key == "friction_pulse_decay_ms"
    said = f"axis {name}: {key} {decay * 1e3 if in_ms else decay:g} {'ms' if in_ms else 's'}"
    if 0.0 < decay < T_v:
        slip = (f"seconds typed as ms? ({decay * 1e3:g} s is {decay * 1e6:g} ms)" if in_ms
                else "give the decay in s")
        raise InputError(f"{said} is a friction pulse decay shorter than one velocity-loop "
                         f"period (T_v {T_v * 1e3:g} ms): it does nothing; {slip}", file=path)
    if decay > LONGEST_DECAY_S:
        slip = (f"us typed as ms? ({decay * 1e3:g} us is {decay:g} ms)" if in_ms
                else f"ms typed as s? ({decay:g} ms is {decay * 1e-3:g} s)")
        raise InputError(f"{said} is a friction pulse decay longer than "
                         f"{LONGEST_DECAY_S:g} s, a standing current offset rather than a "
                         f"pulse; {slip}", file=path)


def _pulse(name: str, p: _Axis, given, axis, path) -> float:
    """The pulse's current from whichever of its two forms is given, through the axis's
    ``K_vp`` and ``R_L``; both must agree, and it must be within the current limit [A]."""
    amp, vmax = p.friction_pulse_A, p.FRICT_COMP_CONST_MAX_mm_per_min
    has_amp, has_v = "friction_pulse_A" in given, "FRICT_COMP_CONST_MAX_mm_per_min" in given
    if has_v and axis is None:
        if not has_amp and vmax != 0.0:
            raise InputError(f"axis {name}: FRICT_COMP_CONST_MAX_mm_per_min {vmax:g} is "
                             "converted to the drive's current through the model's K_vp "
                             "and R_L; read it with the model's axes", file=path)
        has_v = False  # the current form is applied, unchecked against the velocity form
    if has_v:
        conv = f"{vmax:g} mm/min / 60000 / R_L {axis.mechanics.R_L:.4g} m/rad * K_vp " \
               f"{axis.servo.K_vp:.4g} A s/rad"
        from_v = vmax / 6e4 / velocity_per_ampere(axis)
        # the file writes 4 significant digits of each
        if has_amp and abs(amp - from_v) > 2e-3 * max(abs(amp), abs(from_v)):
            raise InputError(f"axis {name}: friction_pulse_A {amp:g} A and "
                             f"FRICT_COMP_CONST_MAX_mm_per_min {vmax:g} are one pulse and "
                             f"disagree: the latter is {conv} = {from_v:.4g} A; give one, "
                             "or both alike (written for another model?)", file=path)
        amp = amp if has_amp else from_v
    if axis is not None and abs(amp) > axis.servo.current_limit:
        raise InputError(f"axis {name}: a friction pulse of {amp:.4g} A is beyond the "
                         f"axis's current limit of {axis.servo.current_limit:g} A; the pulse "
                         "is in A (mA typed as A?)", file=path)
    return amp
