"""Schema of ``machine.yaml``, the user-known part of a measurement bundle.

The file uses the units a machine-tool engineer reads (mm, um, N m/A); the models keep
those values as written and expose SI accessors (``lead_m``, ``scale_resolution_m``, ...).
Unknown keys are errors: a typo must never change a result silently.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated, Literal

import yaml
from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    ValidationInfo,
    field_validator,
    model_validator,
)

from tcpmm._validate import axis_names, plausible
from tcpmm.errors import InputError
from tcpmm.io.atomic import write_text_atomic
from tcpmm.io.text import read_text
from tcpmm.io.yamlutil import validate_yaml
from tcpmm.mechanics.lumped import RANGES as MECHANICS_RANGES
from tcpmm.servo.currentfilters import MAX_FILTERS, ServoFilter
from tcpmm.servo.params import RANGES as SERVO_RANGES
from tcpmm.units import MM, UM

FORMAT_VERSION = "tcpmm-bundle/1"

PosFloat = Annotated[float, Field(gt=0, allow_inf_nan=False)]
NonNegFloat = Annotated[float, Field(ge=0, allow_inf_nan=False)]



def _in(ranges: dict, key: str, scale: float = 1.0, unit: str | None = None) -> tuple:
    """A model parameter's plausible range in the unit of machine.yaml: lowest, highest
    [that unit] and the unit [-]."""
    low, high, si_unit = ranges[key]
    return low * scale, high * scale, unit or si_unit


#: Plausible position loop period of machine.yaml: controllers close it every 0.1 to 20 ms;
#: the range leaves a factor 10 below and 2.5 above, and refuses a period written in ms
#: (0.5 for 0.5 ms), which the model's own range (to 10 s) let through to an unstable
#: sampled loop found only after the fit [s].
POSITION_PERIOD_RANGE = (1e-5, 0.05, "s")
#: Plausible velocity loop period: drives close it every 31.25 us to 2 ms; a factor 6 below
#: and 10 above, refusing one written in ms (0.0625 for 62.5 us) or in us [s].
VELOCITY_PERIOD_RANGE = (5e-6, 0.02, "s")
#: Plausible range of the numbers of machine.yaml, those of the model's parameters
#: (:data:`tcpmm.servo.params.RANGES`, :data:`tcpmm.mechanics.lumped.RANGES`) in its
#: units: a gain of 1e300 made identification divide by zero [-].
RANGES = {"position_gain_1_per_s": _in(SERVO_RANGES, "K_pp"),
          "velocity_gain_A_s_per_rad": _in(SERVO_RANGES, "K_vp"),
          "velocity_integral_gain_A_per_rad": _in(SERVO_RANGES, "K_vi"),
          "position_loop_period_s": POSITION_PERIOD_RANGE,
          "velocity_loop_period_s": VELOCITY_PERIOD_RANGE,
          "current_limit_A": _in(SERVO_RANGES, "current_limit"),
          "lead_mm": _in(MECHANICS_RANGES, "lead", 1e3, "mm"),
          "torque_constant_Nm_per_A": _in(MECHANICS_RANGES, "K_tc"),
          "scale_resolution_um": (0.0, 1e4, "um"), "tcp_resolution_um": (0.0, 1e4, "um"),
          "encoder_counts_per_rev": (0, 1e12, "counts/rev")}


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=True, frozen=True)

    @field_validator("*")
    @classmethod
    def _plausible(cls, v, info: ValidationInfo):
        return plausible(v, info.field_name, RANGES)


class ServoConfig(_Strict):
    """Cascade servo settings of one axis (paper Fig. 2; docs/model.md section 3).

    Parameters
    ----------
    position_feedback : {"scale", "encoder"}
        Fully closed (linear scale) or semi-closed (motor encoder) position loop [-].
    position_gain_1_per_s : float
        Position-loop gain K_pp [1/s].
    velocity_gain_A_s_per_rad : float
        Velocity-loop proportional gain K_vp [A s/rad].
    velocity_integral_gain_A_per_rad : float
        Velocity-loop integral gain K_vi [A/rad].
    velocity_feedforward : float
        Fraction of the command velocity fed forward, 0..1 [-].
    position_loop_period_s : float
        Position-loop sample period T_p [s].
    velocity_loop_period_s : float
        Velocity-loop sample period T_v [s].
    current_limit_A : float
        Drive current limit [A].
    current_setpoint_filters : list
        The drive's current-setpoint filters as the model file gives them
        (:mod:`tcpmm.servo.currentfilters`); carried into the identified model [-].
    """

    position_feedback: Literal["scale", "encoder"]
    position_gain_1_per_s: PosFloat
    velocity_gain_A_s_per_rad: PosFloat
    velocity_integral_gain_A_per_rad: NonNegFloat
    velocity_feedforward: Annotated[float, Field(ge=0, le=1, allow_inf_nan=False)] = 0.0
    position_loop_period_s: PosFloat
    velocity_loop_period_s: PosFloat
    current_limit_A: PosFloat
    current_setpoint_filters: list[ServoFilter] = Field(default_factory=list,
                                                        max_length=MAX_FILTERS)

    @model_validator(mode="after")
    def _inner_loop_faster(self):
        if self.velocity_loop_period_s > self.position_loop_period_s * (1 + 1e-9):
            raise ValueError(
                f"velocity_loop_period_s ({self.velocity_loop_period_s:g} s) is longer than "
                f"position_loop_period_s ({self.position_loop_period_s:g} s); the inner "
                "velocity loop must run at least as fast as the position loop"
            )
        return self


class SensorConfig(_Strict):
    """Position sensors of one axis.

    Parameters
    ----------
    encoder_counts_per_rev : int
        Motor encoder counts per motor revolution [-].
    scale_resolution_um : float
        Linear-scale resolution [um].
    tcp_resolution_um : float, optional
        Resolution of the TCP measuring device; omit when none is fitted [um].
    """

    encoder_counts_per_rev: Annotated[int, Field(gt=0)]
    scale_resolution_um: PosFloat
    tcp_resolution_um: PosFloat | None = None

    @property
    def encoder_resolution_rad(self) -> float:
        """Motor angle per encoder count [rad]."""
        return 2.0 * math.pi / self.encoder_counts_per_rev

    @property
    def scale_resolution_m(self) -> float:
        """Linear-scale resolution [m]."""
        return self.scale_resolution_um * UM

    @property
    def tcp_resolution_m(self) -> float | None:
        """TCP-device resolution, None when no device is declared [m]."""
        return None if self.tcp_resolution_um is None else self.tcp_resolution_um * UM


class AxisConfig(_Strict):
    """What the user knows about one feed axis.

    Parameters
    ----------
    lead_mm : float
        Ball-screw lead per motor revolution [mm].
    torque_constant_Nm_per_A : float
        Motor torque constant K_tc [N m/A].
    servo : ServoConfig
        Servo-loop settings [-].
    sensors : SensorConfig
        Sensor resolutions [-].
    """

    lead_mm: PosFloat
    torque_constant_Nm_per_A: PosFloat
    servo: ServoConfig
    sensors: SensorConfig

    @property
    def lead_m(self) -> float:
        """Ball-screw lead [m]."""
        return self.lead_mm * MM

    @property
    def screw_ratio_m_per_rad(self) -> float:
        """R_L = lead / (2 pi), carriage travel per screw angle [m/rad]."""
        return self.lead_m / (2.0 * math.pi)

    @property
    def torque_constant(self) -> float:
        """Motor torque constant K_tc [N m/A]."""
        return self.torque_constant_Nm_per_A


class MachineConfig(_Strict):
    """Contents of ``machine.yaml``.

    Parameters
    ----------
    format : str
        Format tag, must be ``tcpmm-bundle/1`` [-].
    name : str
        Free-text machine name [-].
    axes : dict of str to AxisConfig
        One entry per feed axis; the key is the axis folder name [-].
    """

    format: str
    name: Annotated[str, Field(min_length=1)]
    axes: Annotated[dict[str, AxisConfig], Field(min_length=1)]

    @field_validator("format")
    @classmethod
    def _version(cls, v: str) -> str:
        if v != FORMAT_VERSION:
            raise ValueError(
                f"format is '{v}' but this tcpmm reads '{FORMAT_VERSION}'; write "
                f"'format: {FORMAT_VERSION}' and use the keys of that version"
            )
        return v

    @field_validator("axes")
    @classmethod
    def _axis_names(cls, v: dict[str, AxisConfig]) -> dict[str, AxisConfig]:
        try:
            axis_names(v)
        except ValueError as err:
            raise ValueError(f"{err} (a key here is its axis's folder name: rename "
                             "both)") from None
        return v


def parse_machine_yaml(text: str, file: str | Path = "<machine.yaml>") -> MachineConfig:
    """Parse and validate the text of a ``machine.yaml``.

    Parameters
    ----------
    text : str
        YAML text [-].
    file : str or Path
        Name used in error messages [-].

    Returns
    -------
    MachineConfig
        The validated configuration.

    Raises
    ------
    InputError
        On a YAML syntax error, a duplicate or unknown key, a missing key, a wrong type or
        an out-of-range value; names the key path and its line.
    """
    return validate_yaml(text, MachineConfig, file,
                         "machine description with keys format, name, axes",
                         "check the spelling against docs/formats.md section 1", FORMAT_VERSION,
                         "as docs/formats.md section 1 shows")


def read_machine_yaml(path: str | Path) -> MachineConfig:
    """Read and validate a ``machine.yaml`` file.

    Parameters
    ----------
    path : str or Path
        File to read [-].

    Returns
    -------
    MachineConfig
        The validated configuration.
    """
    path = Path(path)
    if not path.is_file():
        raise InputError(
            "machine.yaml not found; every bundle needs one (see docs/formats.md section 1)",
            file=path,
        )
    return parse_machine_yaml(read_text(path, "machine description"), file=path)


def machine_to_dict(machine: MachineConfig) -> dict:
    """Plain-dict form of a configuration, ``format`` first, unset optionals left out."""
    data = machine.model_dump(exclude_none=True)
    for a in data.get("axes", {}).values():
        if not a.get("servo", {}).get("current_setpoint_filters", True):
            a["servo"].pop("current_setpoint_filters")  # bundles without stay as they were
    return {"format": data.pop("format"), **data}


def _plain(obj):
    """Nested mappings/sequences with numpy scalars turned into plain Python values."""
    if isinstance(obj, dict):
        return {str(k): _plain(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [_plain(v) for v in obj]
    return obj.item() if hasattr(obj, "item") and callable(obj.item) else obj


def as_machine_config(machine, file=None) -> MachineConfig:
    """Validate a dict in the machine.yaml layout (numpy scalars allowed) [-].

    Parameters
    ----------
    machine : MachineConfig or dict
        Configuration [-].
    file : str or Path, optional
        File named in error messages [-].

    Returns
    -------
    MachineConfig
        The validated configuration.
    """
    if isinstance(machine, MachineConfig):
        return machine
    text = yaml.safe_dump(_plain(dict(machine)), sort_keys=False)
    return parse_machine_yaml(text, file=file or "<machine description>")


def write_machine_yaml(machine: MachineConfig | dict, path: str | Path) -> Path:
    """Write ``machine.yaml`` atomically (temp file in the same folder, then rename).

    Parameters
    ----------
    machine : MachineConfig or dict
        Configuration; a dict is validated first [-].
    path : str or Path
        Target file [-].

    Returns
    -------
    Path
        The file written.
    """
    machine = as_machine_config(machine, file=path)
    text = yaml.safe_dump(machine_to_dict(machine), sort_keys=False, default_flow_style=False)
    write_text_atomic(path, text)
    return Path(path)
