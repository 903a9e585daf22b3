"""Parameters of the discrete cascade servo of one axis (docs/model.md section 3)."""

from __future__ import annotations

import math
from typing import Literal

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
from .currentfilters import MAX_FILTERS, ServoFilter, check_filters

#: Most FIR taps of the velocity estimate.
MAX_VELOCITY_TAPS = 8
#: Plausible range of the gains, periods and current loop, decades beyond those of real
#: drives (and of a suspect identified model): lowest, highest [SI] and the unit [-].
RANGES = {"K_pp": (0.0, 1e6, "1/s"), "K_vp": (0.0, 1e8, "A s/rad"),
          "K_vi": (0.0, 1e12, "A/rad"), "T_p": (1e-7, 10.0, "s"), "T_v": (1e-7, 10.0, "s"),
          "current_limit": (1e-4, 1e6, "A"), "current_bandwidth_hz": (1e-3, 1e7, "Hz")}


class ServoParams(BaseModel):
    """Cascade controller: P position loop, PI velocity loop, current loop.

    Parameters
    ----------
    position_feedback : {"scale", "encoder"}
        Fully closed (linear scale) or semi-closed (motor encoder) position loop [-].
    K_pp : float
        Position loop gain [1/s].
    K_vp : float
        Velocity loop proportional gain, ``i_c = K_vp e_w + K_vi int(e_w)`` [A s/rad].
    K_vi : float
        Velocity loop integral gain [A/rad]; 0 makes the velocity loop a P controller.
    k_ff : float
        Velocity feedforward fraction, 0..1 [-].
    T_p : float
        Position loop period, an integer multiple of ``T_v`` [s].
    T_v : float
        Velocity loop period [s].
    current_limit : float
        Saturation of the current command [A].
    current_bandwidth_hz : float or None
        First-order current loop bandwidth; ``None`` for the ideal loop of the paper [Hz].
    delay_samples : int
        Computation delay between velocity-loop output and applied current [samples of T_v].
    velocity_feedback : {"state", "difference"}
        Encoder velocity as the true shaft speed, or as the backward difference of the
        (quantised) encoder angle, as drives compute it [-].
    feedforward : {"segment", "centred"}
        Command velocity of the feedforward: the slope of the current command segment,
        as a CNC fed interpolated commands computes it (causal), or the centred
        difference of the command samples, half a command period ahead [-].
    velocity_filter : list of float
        FIR taps on the encoder angle before the difference, newest first and summing to
        1 (``[0.5, 0.5]`` averages two samples); ``[1.0]`` is the plain difference. Used
        with ``velocity_feedback="difference"`` [-].
    filters : list of LowPass or Notch
        Up to four current-setpoint filters on the velocity controller's output, run at
        ``T_v`` (:mod:`tcpmm.servo.currentfilters`) [-].
    """

    model_config = ConfigDict(extra="forbid", frozen=True)

    position_feedback: Literal["scale", "encoder"] = "scale"
    K_pp: float = Field(gt=0, allow_inf_nan=False)
    K_vp: float = Field(gt=0, allow_inf_nan=False)
    K_vi: float = Field(ge=0, allow_inf_nan=False)
    k_ff: float = Field(0.0, ge=0, le=1, allow_inf_nan=False)
    T_p: float = Field(5e-4, gt=0, allow_inf_nan=False)
    T_v: float = Field(1.25e-4, gt=0, allow_inf_nan=False)
    current_limit: float = Field(20.0, gt=0, allow_inf_nan=False)
    current_bandwidth_hz: float | None = Field(None, gt=0, allow_inf_nan=False)
    delay_samples: int = Field(0, ge=0, le=64)
    velocity_feedback: Literal["state", "difference"] = "state"
    feedforward: Literal["segment", "centred"] = "segment"
    velocity_filter: list[float] = Field(default_factory=lambda: [1.0], min_length=1,
                                         max_length=MAX_VELOCITY_TAPS)
    filters: list[ServoFilter] = Field(default_factory=list, max_length=MAX_FILTERS)

    @field_validator(*RANGES)
    @classmethod
    def _plausible(cls, v, info: ValidationInfo):
        return plausible(v, info.field_name, RANGES)

    @field_validator("filters")
    @classmethod
    def _below_nyquist(cls, v, info: ValidationInfo):
        # judged at the filters, so that a file's error names their lines, not the servo's
        if "T_v" in info.data:
            check_filters(v, info.data["T_v"])
        return v

    @field_validator("velocity_filter")
    @classmethod
    def _taps(cls, v):
        if not all(math.isfinite(x) for x in v) or abs(sum(v) - 1.0) > 1e-9:
            raise ValueError(f"taps must be finite and sum to 1, got {v}")
        return v

    @model_validator(mode="after")
    def _periods(self):
        ratio = self.T_p / self.T_v
        if abs(ratio - round(ratio)) > 1e-6 or round(ratio) < 1:
            raise ValueError(
                f"position loop period T_p={self.T_p} s must be an integer multiple of the "
                f"velocity loop period T_v={self.T_v} s"
            )
        return self

    @classmethod
    def create(cls, **values) -> ServoParams:
        """Build and validate; raise :class:`InputError` naming every bad field."""
        try:
            return cls(**values)
        except ValidationError as err:
            raise InputError("invalid servo parameters: " + validation_message(err)) from None

    @property
    def n_pos(self) -> int:
        """Velocity-loop steps per position-loop step [-]."""
        return round(self.T_p / self.T_v)

    @classmethod
    def tuned(cls, J_total: float, K_tc: float, bandwidth_hz: float = 80.0,
              integral_corner_hz: float = 20.0, K_pp: float = 40.0, **kw) -> ServoParams:
        """Velocity loop tuned for a bandwidth on a rigid inertia (docs/model.md section 5).

        Parameters
        ----------
        J_total : float
            Inertia seen by the motor [kg m^2].
        K_tc : float
            Torque constant [N m/A].
        bandwidth_hz : float
            Velocity loop crossover [Hz].
        integral_corner_hz : float
            PI corner ``K_vi/K_vp / 2pi`` [Hz].
        K_pp : float
            Position loop gain [1/s].
        """
        K_vp = 2 * math.pi * bandwidth_hz * J_total / K_tc
        return cls.create(K_pp=K_pp, K_vp=K_vp, K_vi=K_vp * 2 * math.pi * integral_corner_hz, **kw)
