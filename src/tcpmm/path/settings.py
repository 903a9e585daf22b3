"""Interpolator settings: the CNC's feed, acceleration and filter parameters.

A plain pydantic model with defaults, embedded in the machine model file. Every
number is SI; the unit is in the field name.
"""

from __future__ import annotations

import math
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, field_validator

from .._validate import upper_names

AXES = ("X", "Y", "Z")

#: Largest contour tolerance of the interpolator, in a model file or a program's ``G64 P``:
#: a CNC's corner and blend tolerances are micrometres to tenths of a millimetre, so 10 mm
#: is a number written in another unit [m].
TOLERANCE_MAX_M = 1e-2


def _axis_dict(value: dict[str, float]) -> dict[str, float]:
    out = {}
    for key, name in upper_names(value).items():
        v = value[name]
        if key not in AXES:
            raise ValueError(f"unknown axis {name!r}; use one of {', '.join(AXES)}")
        if not (math.isfinite(v) and v > 0):
            raise ValueError(f"axis {name} must be a positive number, got {v}")
        out[key] = float(v)
    return out


class InterpolatorSettings(BaseModel):
    """How the CNC turns a tool path into the sampled position command.

    Parameters
    ----------
    period_s : float
        Interpolation period: the command is sampled at this interval [s].
    profile : {"trapezoid", "scurve"}
        Feed profile along the path: constant acceleration (trapezoid) or
        jerk-limited (S-curve) [-].
    path_accel_m_per_s2 : float
        Tangential (path) acceleration limit [m/s^2].
    path_jerk_m_per_s3 : float
        Tangential (path) jerk limit, used by the S-curve profile [m/s^3].
    axis_velocity_m_per_s : dict of str to float
        Maximum velocity per axis; an axis not listed, and any axis above it, is limited
        by its rapid traverse [m/s].
    axis_accel_m_per_s2 : dict of str to float
        Maximum acceleration per axis; an axis not listed uses ``path_accel_m_per_s2``
        [m/s^2].
    rapid_m_per_s : dict of str to float
        Rapid traverse speed (G0) per axis; an axis not listed uses the largest listed
        value [m/s].
    corner_tolerance_m : float
        Allowed deviation from the programmed path that the post-interpolation filter
        may cause at corners and on arcs; it limits corner and arc speeds [m].
    filter_kind : {"none", "linear", "bell"}
        Post-interpolation acc/dec filter per axis: one moving average (linear) or two
        cascaded moving averages of half the length each (bell-shaped) [-].
    filter_time_s : float
        Total length of the post-interpolation filter [s].
    blend_tolerance_m : float
        Contour tolerance of continuous-path mode (G64) where the program gives no ``P``:
        a corner between two straight blocks is rounded off by an arc that stays within
        this distance of the corner point; 0 keeps corners sharp [m].
    corner_step_share : float
        Share of each axis's acceleration limit that the velocity step of a sharp corner
        may take over the spread of the post-interpolation filter (one period without
        one). The step comes on top of the braking into the corner and the speeding up
        out of it, so the sampled command's acceleration may read up to ``1 + share``
        times an axis's limit there; 0 makes every sharp corner an exact stop [-].
    transition_jerk_m_per_s3 : float or None
        Jerk every axis may take at a block transition where the path's curvature jumps
        (a line into an arc tangentially, an arc into one of another radius or turn, the
        ends of a G64 blend): the axis's acceleration steps there by ``v^2`` times the
        jump of the curvature vector's component within the time the filter spreads it
        over (one period without one), so the speed at the transition is held to
        ``sqrt(j * T / |delta kappa_axis|)`` for every axis, as Sinumerik's
        ``PATH_TRANS_JERK_LIM`` does; ``None`` sets no such limit, as the trapezoid and
        S-curve profiles limit the jerk along the path only [m/s^3].
    """

    model_config = ConfigDict(extra="forbid")

    period_s: float = Field(1e-3, gt=0.0, le=1.0)
    profile: Literal["trapezoid", "scurve"] = "trapezoid"
    path_accel_m_per_s2: float = Field(1.0, gt=0.0)
    path_jerk_m_per_s3: float = Field(50.0, gt=0.0)
    axis_velocity_m_per_s: dict[str, float] = Field(default_factory=dict)
    axis_accel_m_per_s2: dict[str, float] = Field(default_factory=dict)
    rapid_m_per_s: dict[str, float] = Field(default_factory=lambda: {"X": 0.5, "Y": 0.5, "Z": 0.5})
    corner_tolerance_m: float = Field(1e-5, gt=0.0)
    filter_kind: Literal["none", "linear", "bell"] = "none"
    filter_time_s: float = Field(0.0, ge=0.0, le=10.0)
    blend_tolerance_m: float = Field(0.0, ge=0.0, le=0.1)
    corner_step_share: float = Field(1.0, ge=0.0, le=1.0)
    transition_jerk_m_per_s3: float | None = Field(None, gt=0.0, allow_inf_nan=False)

    @field_validator("axis_velocity_m_per_s")
    @classmethod
    def _check_vel(cls, v):
        return _axis_dict(v)

    @field_validator("axis_accel_m_per_s2")
    @classmethod
    def _check_acc(cls, v):
        return _axis_dict(v)

    @field_validator("rapid_m_per_s")
    @classmethod
    def _check_rapid(cls, v):
        v = _axis_dict(v)
        if not v:
            raise ValueError("give the rapid speed of at least one axis")
        return v

    def axis_velocity(self) -> tuple[float, float, float]:
        """Velocity limit of X, Y, Z: the one given, and never above the axis's rapid
        traverse (a control feeds no axis faster than it traverses: G1 F100000 ran at
        42 m/min on axes of 30) [m/s]."""
        return tuple(min(self.axis_velocity_m_per_s.get(a, math.inf), r)
                     for a, r in zip(AXES, self.rapid(), strict=True))

    def axis_accel(self) -> tuple[float, float, float]:
        """Acceleration limit of X, Y, Z [m/s^2]."""
        return tuple(self.axis_accel_m_per_s2.get(a, self.path_accel_m_per_s2) for a in AXES)

    def corner_step_accel(self) -> tuple[float, float, float]:
        """Acceleration of X, Y, Z that a sharp corner's velocity step may take over the
        filter's spread: ``corner_step_share`` of :meth:`axis_accel` [m/s^2]."""
        return tuple(self.corner_step_share * a for a in self.axis_accel())

    def rapid(self) -> tuple[float, float, float]:
        """Rapid traverse speed of X, Y, Z [m/s]."""
        top = max(self.rapid_m_per_s.values())
        return tuple(self.rapid_m_per_s.get(a, top) for a in AXES)

    def jerk(self) -> float:
        """Path jerk limit in effect: ``inf`` for the trapezoidal profile [m/s^3]."""
        return self.path_jerk_m_per_s3 if self.profile == "scurve" else math.inf
