"""Named parameters of a sweep: dotted names into the model and the program.

A name has the form ``AXIS.GROUP.FIELD`` for a parameter of one axis, e.g.
``X.servo.K_pp`` or ``Y.mechanics.M_t``; ``interpolation.FIELD`` for the interpolator of
an NC program; ``program.FIELD`` for the circle or the program itself. Values are in the
unit of the model file (SI), except where the name carries its unit
(``program.radius_mm``).

======================================  ==================================================
name                                    what
======================================  ==================================================
``AXIS.mechanics.F``                    :class:`~tcpmm.mechanics.lumped.AxisMechanics`
                                        field ``F`` (``J_m``, ``M_t``, ``K_t``, ...) [SI]
``AXIS.servo.F``                        numeric :class:`~tcpmm.servo.params.ServoParams`
                                        field (``K_pp``, ``K_vp``, ``K_vi``, ``k_ff``, ...);
                                        ``position_gain``, ``velocity_gain``,
                                        ``velocity_integral_gain`` and
                                        ``velocity_feedforward`` name ``K_pp``, ``K_vp``,
                                        ``K_vi`` and ``k_ff`` [SI]
``AXIS.sensors.F``                      :class:`~tcpmm.model.Sensors` field [SI]
``AXIS.friction.backlash``              lost motion of the screw-nut [m]
``AXIS.friction.level``                 factor on every friction force of the axis [-]
``AXIS.friction.guideway.F``            field of the guideway contact (``fc_pos``, ...)
``AXIS.friction.screw.F``               field of the screw contact [SI]
``interpolation.F``                     numeric interpolator setting of an NC program
                                        (``path_accel_m_per_s2``, ``filter_time_s``, ...)
``program.radius_mm``                   radius of the circular test [mm]
``program.feed_mm_per_min``             feed of the circular test [mm/min]
``program.feed_override``               factor on every programmed feed of an NC
                                        program [-]
======================================  ==================================================
"""

from __future__ import annotations

import math

from ..._validate import did_you_mean, validation_message
from ...errors import InputError
from ...mechanics.lumped import AxisMechanics
from ...model import Machine, Sensors
from ...servo.params import ServoParams
from ..spread import scaled_contact

#: Other names of servo fields [-].
SERVO_ALIASES = {"position_gain": "K_pp", "velocity_gain": "K_vp",
                 "velocity_integral_gain": "K_vi", "velocity_feedforward": "k_ff"}
#: Parameters of a circular test and of an NC program [-].
CIRCLE_PARAMETERS = ("radius_mm", "feed_mm_per_min")
GCODE_PARAMETERS = ("feed_override",)
INTERPOLATION_PARAMETERS = ("period_s", "path_accel_m_per_s2", "path_jerk_m_per_s3",
                            "corner_tolerance_m", "filter_time_s", "blend_tolerance_m",
                            "corner_step_share")
_SERVO = ("K_pp", "K_vp", "K_vi", "k_ff", "T_p", "T_v", "current_limit",
          "current_bandwidth_hz", "delay_samples")
#: interpolation parameters that act only under a setting of the model, which a sweep
#: cannot vary (it is no number): the setting and its values under which they act [-]
ACTS_UNDER = {"filter_time_s": ("filter_kind", ("linear", "bell")),
              "path_jerk_m_per_s3": ("profile", ("scurve",))}
#: fields that take whole numbers: an lhs draws whole numbers of them [-]
INTEGER_FIELDS = {"delay_samples", "encoder_counts_per_rev"}


def axis_fields(axis) -> dict[str, tuple[str, ...]]:
    """Fields per group of one axis that a sweep can vary [-]."""
    groups = {"mechanics": tuple(AxisMechanics.model_fields), "servo": _SERVO,
              "sensors": tuple(Sensors.model_fields)}
    fr = axis.friction
    if fr is not None:
        contacts = [f"{c}.{f}" for c in ("guideway", "screw") if getattr(fr, c) is not None
                    for f, info in type(getattr(fr, c)).model_fields.items()
                    if info.annotation is not bool]
        groups["friction"] = ("backlash", "level", *contacts)
    return groups


def parameter_names(machine: Machine, program: str = "circle") -> list[str]:
    """Every name a sweep of ``machine`` accepts, canonical (aliases left out).

    Parameters
    ----------
    machine : Machine
        The model [-].
    program : {"circle", "gcode"}
        Kind of program swept [-].

    Returns
    -------
    list of str
        Dotted names [-].
    """
    names = [f"{ax}.{g}.{f}" for ax, a in machine.axes.items()
             for g, fields in axis_fields(a).items() for f in fields]
    if program == "gcode":
        names += [f"interpolation.{f}" for f in INTERPOLATION_PARAMETERS]
        names += [f"program.{f}" for f in GCODE_PARAMETERS]
    else:
        names += [f"program.{f}" for f in CIRCLE_PARAMETERS]
    return names


def _unknown(what: str, name: str, valid, part: str = "") -> InputError:
    hint = did_you_mean(part, valid) if part else ""
    return InputError(f"unknown parameter {name!r}: no {what}{hint}; valid: "
                      f"{', '.join(valid)} (`tcpmm sweep MODEL --list-params` lists every "
                      "name)")


def canonical_name(machine: Machine, name: str, program: str = "circle") -> str:
    """The canonical form of a parameter name, checked against the model and program.

    Parameters
    ----------
    machine : Machine
        The model [-].
    name : str
        Dotted name, e.g. ``x.servo.position_gain`` [-].
    program : {"circle", "gcode"}
        Kind of program swept [-].

    Returns
    -------
    str
        The name with the axis upper case and aliases resolved, e.g. ``X.servo.K_pp`` [-].
    """
    parts = name.strip().split(".")
    head = parts[0]
    if head in ("program", "interpolation"):
        valid = [n for n in parameter_names(machine, program) if n.startswith(head + ".")]
        if not valid:
            raise InputError(f"unknown parameter {name!r}: interpolation settings apply to "
                             "an NC program (--gcode) only")
        if name.strip() not in valid:
            kind = "a circular test" if program == "circle" else "an NC program"
            raise _unknown(f"such {head} parameter of {kind}", name, valid, name.strip())
        return name.strip()
    ax = head.upper()
    if ax not in machine.axes:
        raise _unknown("such axis", name, [f"{a}.GROUP.FIELD" for a in machine.axes]
                       + ["program.FIELD", "interpolation.FIELD"])
    groups = axis_fields(machine.axes[ax])
    if len(parts) < 3 or parts[1] not in groups:
        raise _unknown(f"such group of axis {ax}", name, list(groups),
                       parts[1] if len(parts) > 1 else "")
    group, field = parts[1], ".".join(parts[2:])
    if group == "servo":
        field = SERVO_ALIASES.get(field, field)
    if field not in groups[group]:
        raise _unknown(f"such field of {ax}.{group}", name, groups[group], field)
    return f"{ax}.{group}.{field}"


def _integral(name: str, value: float) -> int:
    if abs(value - round(value)) > 1e-9:
        raise InputError(f"{name} takes whole numbers, got {value:g}; give integer values")
    return round(value)


def _axis_with(axis, group: str, field: str, value: float, name: str):
    """One axis with one parameter set."""
    if field in INTEGER_FIELDS:
        value = _integral(name, value)
    if group == "mechanics":
        return axis.replace(mechanics=axis.mechanics.replace(**{field: value}))
    if group == "servo":
        return axis.replace(servo=ServoParams.create(**{**axis.servo.model_dump(),
                                                        field: value}))
    if group == "sensors":
        return axis.replace(sensors=Sensors(**{**axis.sensors.model_dump(), field: value}))
    fr = axis.friction
    if field == "level":
        if not value >= 0.0:
            raise InputError(f"{name} is a factor, 0 or more; got {value:g}")
        upd = {c: scaled_contact(getattr(fr, c), value) for c in ("guideway", "screw")}
        return axis.replace(friction=fr.model_copy(update=upd))
    if field == "backlash":
        return axis.replace(friction=type(fr)(**{**fr.model_dump(), "backlash": value}))
    contact, f = field.split(".")
    c = getattr(fr, contact)
    return axis.replace(friction=fr.model_copy(
        update={contact: type(c)(**{**c.model_dump(), f: value})}))


def apply_parameters(machine: Machine, values: dict) -> Machine:
    """The model with the axis and interpolation parameters of ``values`` set.

    Names ``program.*`` are left to the program (:mod:`tcpmm.whatif.sweep.task`).

    Parameters
    ----------
    machine : Machine
        The model [-].
    values : dict of str to float
        Canonical names (:func:`canonical_name`) and their values [SI].

    Returns
    -------
    Machine
        The changed model, validated [-].
    """
    from pydantic import ValidationError

    axes, interp = dict(machine.axes), dict(machine.interpolation or {})
    for name, value in values.items():
        if not math.isfinite(value):
            raise InputError(f"{name} must be finite, got {value}")
        head, *rest = name.split(".")
        try:
            if head == "interpolation":
                interp[rest[0]] = float(value)
            elif head != "program":
                axes[head] = _axis_with(axes[head], rest[0], ".".join(rest[1:]), value, name)
        except ValidationError as err:
            raise InputError(f"{name} = {value:g} is not a valid value: "
                             f"{validation_message(err)}") from None
        except InputError as err:
            raise InputError(f"{name} = {value:g}: {err.message}") from None
    update = {"axes": axes}
    if interp:
        try:
            update["interpolation"] = Machine.model_validate(
                {"axes": axes, "interpolation": interp}).interpolation
        except ValidationError as err:
            raise InputError(f"invalid interpolation setting: {validation_message(err)}") from None
    return machine.model_copy(update=update)


def idle_parameters(machine: Machine, names) -> list[str]:
    """A sentence per parameter of ``names`` that has no effect on this model: an
    interpolation parameter whose setting (:data:`ACTS_UNDER`) the model leaves off, so
    that every variant runs the same command [-].

    Parameters
    ----------
    machine : Machine
        The model swept [SI].
    names : iterable of str
        Canonical parameter names [-].
    """
    from ...path.settings import InterpolatorSettings

    settings = InterpolatorSettings.model_validate(machine.interpolation or {})
    said = []
    for name in names:
        head, _, field = name.partition(".")
        if head != "interpolation" or field not in ACTS_UNDER:
            continue
        setting, acting = ACTS_UNDER[field]
        have = getattr(settings, setting)
        if have not in acting:
            said.append(f"{name} has no effect on this model: its interpolation.{setting} is "
                        f"{have}, so every variant runs the same command; set "
                        f"interpolation.{setting} to {' or '.join(acting)} in the model file "
                        "to sweep it")
    return said
