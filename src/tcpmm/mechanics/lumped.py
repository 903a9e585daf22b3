"""Physical parameters of one feed axis: the five inertial systems of the TCP-MM."""

from __future__ import annotations

import math

from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    ValidationError,
    ValidationInfo,
    field_validator,
    model_validator,
)

from .._validate import plausible, validation_message
from ..errors import InputError

_POS = {"gt": 0.0, "allow_inf_nan": False}
_NONNEG = {"ge": 0.0, "allow_inf_nan": False}
_J, _B, _M, _C, _K = ("kg m^2", "N m s/rad", "kg", "N s/m", "N/m")
#: Plausible range of each parameter: decades beyond the feed axes of real machines,
#: from a desktop mill's to a gantry's, so that a model the gates of identification find
#: suspect (a time column in ms scales stiffnesses by 1e-6) can still be written, marked;
#: but not 1e300, which overflows the plant's matrices: lowest, highest [SI], unit [-].
RANGES = {"J_m": (1e-12, 1e4, _J), "J_L": (1e-12, 1e4, _J), "B_m": (0.0, 1e6, _B),
          "B_L": (0.0, 1e6, _B), "K_L": (1e-6, 1e12, "N m/rad"), "lead": (1e-5, 10.0, "m"),
          **{f"M_{s}": (1e-6, 1e8, _M) for s in "tbh"},
          **{f"C_{s}": (0.0, 1e12, _C) for s in "tbh"},
          **{f"K_{s}": (1e-6, 1e16, _K) for s in "tbh"},
          "K_tc": (1e-4, 1e4, "N m/A"), "load_force": (-1e8, 1e8, "N")}


class AxisMechanics(BaseModel):
    """Lumped parameters of one axis (docs/model.md section 1), all SI.

    Parameters
    ----------
    J_m, B_m : float
        Motor shaft inertia [kg m^2] and viscous damping [N m s/rad].
    J_L, B_L, K_L : float
        Rotating transmission inertia [kg m^2], damping [N m s/rad] and torsional
        stiffness [N m/rad].
    lead : float
        Ball-screw lead per revolution [m].
    M_t, C_t, K_t : float
        Axial transmission (nut, carriage, table) mass [kg], damping [N s/m] and axial
        stiffness [N/m].
    M_b, C_b, K_b : float
        Bed mass [kg], damping [N s/m] and stiffness to ground [N/m].
    M_h, C_h, K_h : float
        TCP structure (column, headstock, spindle) mass [kg], damping [N s/m] and
        stiffness [N/m].
    K_tc : float
        Motor torque constant [N m/A].
    load_force : float
        Constant external force on the carriage, e.g. gravity on a vertical axis without
        counterweight (positive along the axis) [N].
    """

    model_config = ConfigDict(extra="forbid", frozen=True)

    J_m: float = Field(**_POS)
    B_m: float = Field(**_NONNEG)
    J_L: float = Field(**_POS)
    B_L: float = Field(**_NONNEG)
    K_L: float = Field(**_POS)
    lead: float = Field(**_POS)
    M_t: float = Field(**_POS)
    C_t: float = Field(**_NONNEG)
    K_t: float = Field(**_POS)
    M_b: float = Field(**_POS)
    C_b: float = Field(**_NONNEG)
    K_b: float = Field(**_POS)
    M_h: float = Field(**_POS)
    C_h: float = Field(**_NONNEG)
    K_h: float = Field(**_POS)
    K_tc: float = Field(**_POS)
    load_force: float = Field(0.0, allow_inf_nan=False)

    @model_validator(mode="before")
    @classmethod
    def _no_bool(cls, data):
        if isinstance(data, dict):
            for k, v in data.items():
                if isinstance(v, bool):
                    raise ValueError(f"{k} must be a number, not a boolean")
        return data

    @field_validator("*")
    @classmethod
    def _plausible(cls, v, info: ValidationInfo):
        return plausible(v, info.field_name, RANGES)

    @classmethod
    def create(cls, **values) -> AxisMechanics:
        """Build and validate; raise :class:`InputError` naming every bad field."""
        try:
            return cls(**values)
        except ValidationError as err:
            raise InputError("invalid axis mechanics: " + validation_message(err)) from None

    @property
    def R_L(self) -> float:
        """Screw transmission ratio lead/2pi [m/rad]."""
        return self.lead / (2.0 * math.pi)

    @property
    def J_total(self) -> float:
        """Rigid-body inertia seen by the motor, J_m + J_L + M_t R_L^2 [kg m^2]."""
        return self.J_m + self.J_L + self.M_t * self.R_L**2

    def replace(self, **changes) -> AxisMechanics:
        """A validated copy with some parameters changed (what-if studies)."""
        return self.create(**{**self.model_dump(), **changes})

    def scaled(self, **factors) -> AxisMechanics:
        """A validated copy with parameters multiplied by factors, e.g. ``K_h=2.0``."""
        d = self.model_dump()
        for k, f in factors.items():
            if k not in d:
                raise InputError(f"unknown mechanics parameter '{k}'; known: {', '.join(d)}")
            d[k] = d[k] * f
        return self.create(**d)
