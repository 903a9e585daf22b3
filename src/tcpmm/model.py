"""A machine: named axes, each with its mechanics, servo and sensors."""

from __future__ import annotations

import math
from typing import Annotated, Literal

from pydantic import (
    BaseModel,
    BeforeValidator,
    ConfigDict,
    Field,
    ValidationInfo,
    field_validator,
)

from ._validate import axis_names, plausible
from .errors import InputError
from .mechanics.friction import LuGreFriction, StribeckFriction
from .mechanics.lumped import AxisMechanics
from .path.settings import TOLERANCE_MAX_M, InterpolatorSettings
from .servo.params import ServoParams


def _contact(data):
    """A friction contact from its parameters: LuGre when ``sigma0`` is given, else Stribeck."""
    if isinstance(data, StribeckFriction):
        return data
    if not isinstance(data, dict):
        raise ValueError("give the friction parameters as a mapping (fc_pos, fc_neg, ..., and "
                         "sigma0 for LuGre friction), or null for none")
    kind = LuGreFriction if "sigma0" in data else StribeckFriction
    contact = kind.__new__(kind)  # the constructor would flatten the errors into one text
    kind.__pydantic_validator__.validate_python(data, self_instance=contact)
    return contact


#: Plausible range of the sensors' resolutions: lowest, highest [SI] and the unit [-].
SENSOR_RANGES = {"encoder_counts_per_rev": (0, 1e12, "counts/rev"),
                 "scale_resolution": (0.0, 1e-2, "m"), "tcp_resolution": (0.0, 1e-2, "m")}

#: Largest lost motion of a feed axis's screw-nut a model may have: a worn nut has tens of
#: micrometres; a millimetre is no ball screw's [m].
BACKLASH_MAX_M = 1e-3

#: Largest circular deviation G a machine tool's specification may state: the circular
#: tests of machine tools stay within tens of micrometres, so a millimetre is a number
#: written in another unit than metres [m].
SPECIFIED_G_MAX_M = 1e-3

FrictionModel = Annotated[LuGreFriction | StribeckFriction, BeforeValidator(_contact)]


class Sensors(BaseModel):
    """Resolution of the position sensors of one axis; 0 means ideal.

    Parameters
    ----------
    encoder_counts_per_rev : int
        Motor encoder counts per revolution, 0 for an ideal encoder [-].
    scale_resolution : float
        Linear scale resolution [m].
    tcp_resolution : float
        TCP measuring device resolution [m].
    """

    model_config = ConfigDict(extra="forbid", frozen=True)

    encoder_counts_per_rev: int = Field(0, ge=0)
    scale_resolution: float = Field(0.0, ge=0, allow_inf_nan=False)
    tcp_resolution: float = Field(0.0, ge=0, allow_inf_nan=False)

    @field_validator("*")
    @classmethod
    def _plausible(cls, v, info: ValidationInfo):
        return plausible(v, info.field_name, SENSOR_RANGES)

    @property
    def encoder_quantum(self) -> float:
        """One encoder count [rad] (0 when ideal)."""
        c = self.encoder_counts_per_rev
        return 2 * math.pi / c if c else 0.0


class AxisFriction(BaseModel):
    """Friction of one axis in table units: force [N] against table velocity [m/s].

    Parameters
    ----------
    screw : StribeckFriction or LuGreFriction, optional
        Screw, nut and support-bearing friction, acting as a torque on the screw
        (``R_L`` times the force) at the screw's table-equivalent velocity [N].
    guideway : StribeckFriction or LuGreFriction, optional
        Linear-guide friction acting on the carriage [N].
    backlash : float
        Lost motion of the screw-nut: the total free play across the nut, in which the
        nut transmits no force; outside it the nut stiffness ``K_t`` acts [m].
    substeps : int
        Sub-steps of a velocity-loop step in which a friction velocity reverses or
        sticks, or in which the nut is inside or crosses its free play [-].
    guideway_velocity : {"table", "relative"}
        Velocity the guideway friction acts on: the table's, or the table's relative to
        the bed, with the reaction on the bed as a real guide has it [-].
    """

    model_config = ConfigDict(extra="forbid", frozen=True)

    screw: FrictionModel | None = None
    guideway: FrictionModel | None = None
    backlash: float = Field(0.0, ge=0.0, le=BACKLASH_MAX_M, allow_inf_nan=False)
    guideway_velocity: Literal["table", "relative"] = "table"
    substeps: int = Field(16, ge=1, le=1024)


class OpenRange(BaseModel):
    """A quantity the identification data leave open: the range it may lie in, why, and
    the measurement that would settle it.

    Parameters
    ----------
    quantity : str
        ``guideway_share`` [-], ``backlash`` [m], ``presliding`` [m], ``C_t`` [N s/m],
        ``B_m`` [N m s/rad], ``mechanics`` (a factor on the table mass and the structure
        behind it, ``M_t``, ``M_b``, ``K_b``, ``M_h``, ``K_h``) [-] or ``damping`` (a
        factor on the axial modes' damping ``C_t``, ``C_b``, ``C_h``) [-], ``column``
        (the stiffness ``K_h`` of a TCP structure no TCP device measured, or whose mass or
        stiffness the FRFs do not determine) [N/m], ``bed`` (the stiffness ``K_b`` to ground
        of a bed whose mass or stiffness the FRFs do not determine) [N/m], or
        ``column_damping`` / ``bed_damping`` (the damping ratio of the mode of ``M_h`` on
        ``K_h`` / of ``M_b`` on ``K_b``, where the sweep's excitation starts above that mode
        or the FRFs do not determine ``C_h`` / ``C_b``) [-], or ``static_level`` (the
        static friction level over the Coulomb level, where the friction runs fix no
        Stribeck hump and the model holds it at the Coulomb level) [-], or ``time_base``
        (the sweep record's true time over its stamped one, where its controller output
        is not what the declared gains give: the masses and inertias scale with its
        square, the dampings with it) [-], or one of ``J_m``, ``J_L``, ``B_L``, ``K_L``,
        ``K_t``, ``M_t`` (a drive parameter the FRFs do not determine, whose fitted value
        the model keeps) [SI], or ``position_feedback`` (0 the sensor the bundle declares
        the position loop closed on, 1 the other, which the sweep reads better) [-], or
        ``position_gain`` (the position-loop gain, where the sweep reads another than the
        declared one) [1/s].
    low, high : float
        The range, in the quantity's unit [SI].
    cause : str
        Why the data do not determine it [-].
    settle : str
        The measurement that would determine it [-].
    """

    model_config = ConfigDict(extra="forbid", frozen=True)

    quantity: Literal["guideway_share", "backlash", "presliding", "C_t", "B_m", "mechanics",
                      "damping", "column", "bed", "column_damping", "bed_damping",
                      "static_level", "time_base", "J_m", "J_L", "B_L", "K_L", "K_t",
                      "M_t", "position_feedback", "position_gain"]
    low: float = Field(ge=0.0, allow_inf_nan=False)
    high: float = Field(ge=0.0, allow_inf_nan=False)
    cause: str
    settle: str


class AxisUncertainty(BaseModel):
    """One standard deviation of what identification determined for an axis.

    A prediction's spread (:mod:`tcpmm.whatif.spread`) draws machines from it. Quantities the
    data do not determine are left out and not varied, except the guideway share.

    Parameters
    ----------
    mechanics : dict of str to float
        Standard deviation per :class:`AxisMechanics` parameter, in its unit [SI].
    friction_level : float
        Relative standard deviation of the Coulomb and static levels [-].
    guideway_share : float
        Standard deviation of the share of the friction on the guideway; ``inf`` when the
        data do not determine the share (it is then drawn from 0 to 1) [-].
    backlash : float
        Standard deviation of the lost motion [m].
    presliding : float
        Standard deviation of the logarithm of the contacts' pre-sliding distance (one
        for both), a quarter of the logarithm of the range its fit leaves [-].
    open : tuple of OpenRange
        Quantities the data leave open, with the range each may lie in; a prediction's
        interval takes each over its whole range [-].
    """

    model_config = ConfigDict(extra="forbid", frozen=True)

    mechanics: dict[str, float] = {}
    friction_level: float = Field(0.0, ge=0.0, allow_inf_nan=False)
    guideway_share: float = Field(0.0, ge=0.0)
    backlash: float = Field(0.0, ge=0.0, allow_inf_nan=False)
    presliding: float = Field(0.0, ge=0.0, allow_inf_nan=False)
    open: tuple[OpenRange, ...] = ()

    @field_validator("mechanics")
    @classmethod
    def _known(cls, v):
        names = set(AxisMechanics.model_fields)
        for k, sd in v.items():
            if k not in names:
                raise ValueError(f"{k!r} is not a mechanics parameter; "
                                 f"parameters: {', '.join(sorted(names))}")
            if not (math.isfinite(sd) and sd >= 0.0):
                raise ValueError(f"the standard deviation of {k} must be finite and 0 or "
                                 f"more, got {sd}")
        return v


class Axis(BaseModel):
    """One feed axis of the machine.

    Parameters
    ----------
    mechanics : AxisMechanics
        Five-inertia parameters [SI].
    servo : ServoParams
        Cascade controller [SI].
    sensors : Sensors
        Sensor resolutions [SI].
    friction : AxisFriction or None
        Friction elements, ``None`` for a linear axis [SI].
    uncertainty : AxisUncertainty or None
        What identification says of its own accuracy; ``None`` when unknown [SI].
    """

    model_config = ConfigDict(extra="forbid", frozen=True)

    mechanics: AxisMechanics
    servo: ServoParams
    sensors: Sensors = Sensors()
    friction: AxisFriction | None = None
    uncertainty: AxisUncertainty | None = None

    def replace(self, **changes) -> Axis:
        """A copy with some fields changed."""
        return self.model_copy(update=changes)


def drive_force_limit(axis: Axis) -> float:
    """Force the drive delivers at the table at its current limit,
    ``current_limit K_tc / R_L`` with ``R_L = lead / 2 pi`` [N].

    Parameters
    ----------
    axis : Axis
        The axis [SI].
    """
    m = axis.mechanics
    return float(axis.servo.current_limit * m.K_tc / m.R_L)


class Specification(BaseModel):
    """What the machine's builder states it meets, to judge its tests against where the
    user gives no tolerance.

    Parameters
    ----------
    circular_deviation_m : float
        Largest circular deviation G (ISO 230-4) of a circular test at the tool [m].
    """

    model_config = ConfigDict(extra="forbid", frozen=True)

    circular_deviation_m: float = Field(gt=0.0, allow_inf_nan=False)

    @field_validator("circular_deviation_m")
    @classmethod
    def _in_metres(cls, v):
        if v > SPECIFIED_G_MAX_M:
            raise ValueError(f"{v:g} m is no machine tool's circular deviation: the key is in "
                             f"metres and a specification above {SPECIFIED_G_MAX_M * 1e3:g} mm "
                             f"({SPECIFIED_G_MAX_M:g} m) is a number in another unit; "
                             f"{_metres_meant(v)}")
        return v


def _metres_meant(value: float) -> str:
    """``did you mean ...?`` for a length written in µm (1 and above) or else in mm [-]."""
    um = value if value >= 1.0 else value * 1e3
    return f"did you mean {um:g}e-6 ({um:g} µm)?"


class Machine(BaseModel):
    """A machine tool model: axes by name (``"X"``, ``"Y"``, ...).

    Parameters
    ----------
    name : str
        Human-readable name [-].
    axes : dict of str to Axis
        The feed axes [-].
    interpolation : dict or None
        CNC interpolator settings as given, checked against
        :class:`tcpmm.path.InterpolatorSettings` [SI].
    suspect : tuple of str
        What the gates of identification found physically suspect in this model, when it
        was written anyway (``tcpmm identify --accept-suspect``); empty for a model that
        passed them or was made by hand [-].
    specification : Specification or None
        What the builder states the machine meets; a circle verdict given no tolerance
        judges against it [SI].
    """

    model_config = ConfigDict(extra="forbid", frozen=True)

    name: str = "machine"
    axes: dict[str, Axis]
    interpolation: dict | None = None
    suspect: tuple[str, ...] = ()
    specification: Specification | None = None

    @field_validator("axes")
    @classmethod
    def _names(cls, v):
        if not v:
            raise ValueError("a machine needs at least one axis")
        return {upper: v[k] for upper, k in axis_names(v).items()}

    @field_validator("interpolation")
    @classmethod
    def _interpolation(cls, v):
        if v is not None:
            s = InterpolatorSettings.model_validate(v)
            for key in ("corner_tolerance_m", "blend_tolerance_m"):
                if getattr(s, key) > TOLERANCE_MAX_M:
                    raise ValueError(
                        f"{key} of {getattr(s, key):g} m is no CNC's contour tolerance: the "
                        f"key is in metres and a tolerance above {TOLERANCE_MAX_M * 1e3:g} mm "
                        f"is a number in another unit; {_metres_meant(getattr(s, key))}")
        return v

    def axis(self, name: str) -> Axis:
        """The axis of that name [-]."""
        try:
            return self.axes[name.upper()]
        except KeyError:
            raise InputError(
                f"no axis {name!r} in machine '{self.name}'; axes: {', '.join(self.axes)}"
            ) from None

    def with_axis(self, name: str, axis: Axis) -> Machine:
        """A copy with one axis replaced or added."""
        return self.model_copy(update={"axes": {**self.axes, name.upper(): axis}})
