"""Friction and lost motion of feed-axis transmissions: models and parameter vectors.

Sign convention
---------------
Every friction force ``F`` of these models is the force the friction exerts *against* the
body's motion, expressed along the axis coordinate, so that the body obeys

    m v' = f_applied - F

``F`` has the sign of the velocity while sliding. ``f_applied`` is the sum of every other
force on the body along the same coordinate (actuator, springs, dampers, gravity, process
force) [N].

Models
------
``StribeckFriction``
    Coulomb + viscous + Stribeck with direction-dependent levels. While sliding
    (``v != 0``), with ``d = +`` for ``v > 0`` and ``d = -`` for ``v < 0``::

        F(v) = sign(v) * (Fc_d + (Fs_d - Fc_d) * exp(-|v / vs|**delta)) + Fv_d * v

    At rest the friction balances the applied force up to the static level:
    ``-Fs_- <= F <= Fs_+``.
``LuGreFriction``
    LuGre dynamic friction with pre-sliding (bristle deflection ``z`` [m])::

        g(v)  = Fc_d + (Fs_d - Fc_d) * exp(-|v / vs|**delta)
        z'    = v - sigma0 * |v| / g(v) * z
        F     = sigma0 * z + s1(v) * z' + Fv_d * v

    with ``s1(v) = sigma1``, or ``sigma1 exp(-|v / vs|**delta)`` when the micro-damping
    fades with speed (``sigma1_fades``).

    At constant velocity it gives the Stribeck curve above; at small displacements it is a
    spring of stiffness ``sigma0`` [N/m] with a hysteretic force-displacement loop.
``Backlash``
    Lost motion of a screw-nut: dead-zone spring of contact stiffness ``k`` [N/m] and total
    free play ``play`` [m] (the dead zone spans ``+/- play/2``), with optional contact
    damping ``c`` [N s/m]. The play is the total free play, the lost motion at a reversal,
    as everywhere in the package (the model file's ``friction.backlash``, the identified
    lost motion, the circle diagnostics).

Parameter vectors
-----------------
``friction_params_array(model)`` and ``backlash_params_array(model)`` pack a model into
the float vector that the compiled functions of :mod:`tcpmm.sim.contact` read. The
friction vector layout is given by the ``P_*`` index constants of this module; the model
code ``params[P_MODEL]`` is ``MODEL_NONE`` (no friction), ``MODEL_STATIC`` or
``MODEL_LUGRE``, and the static-model friction state is ``STUCK`` or ``SLIDING``. The
backlash vector is ``[k, play/2, c]`` (the half gap is what the compiled function reads),
indexed by ``B_K``, ``B_GAP`` and ``B_C``.
"""

from __future__ import annotations

import warnings

import numpy as np
from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    ValidationError,
    ValidationInfo,
    field_validator,
    model_validator,
)

from tcpmm._validate import plausible
from tcpmm.errors import InputError

__all__ = [
    "MODEL_LUGRE",
    "MODEL_NONE",
    "MODEL_STATIC",
    "N_FRICTION_PARAMS",
    "SLIDING",
    "STUCK",
    "Backlash",
    "LuGreFriction",
    "StribeckFriction",
    "backlash_params_array",
    "friction_params_array",
]

MODEL_NONE = 0
MODEL_STATIC = 1
MODEL_LUGRE = 2

P_MODEL = 0
P_FC_POS = 1
P_FC_NEG = 2
P_FS_POS = 3
P_FS_NEG = 4
P_VS = 5
P_DELTA = 6
P_FV_POS = 7
P_FV_NEG = 8
P_SIGMA0 = 9
P_SIGMA1 = 10
P_V_STICK = 11
P_SIGMA1_FADES = 12
N_FRICTION_PARAMS = 13

#: Plausible range of a contact's parameters, decades beyond a feed axis's (and a suspect
#: identified model's): lowest, highest [SI] and the unit [-].
RANGES = {**{f"{k}_{d}": (0.0, 1e8, "N") for k in ("fc", "fs") for d in ("pos", "neg")},
          **{f"fv_{d}": (0.0, 1e10, "N s/m") for d in ("pos", "neg")},
          "vs": (1e-12, 100.0, "m/s"), "delta": (0.0, 100.0, "-"), "v_stick": (0.0, 10.0, "m/s"),
          "sigma0": (0.0, 1e16, "N/m"), "sigma1": (0.0, 1e12, "N s/m")}

SLIDING = 0.0
STUCK = 1.0

B_K = 0
B_GAP = 1
B_C = 2
N_BACKLASH_PARAMS = 3


def _explain(exc: ValidationError, name: str) -> str:
    parts = []
    for err in exc.errors():
        loc = ".".join(str(x) for x in err.get("loc", ())) or name
        parts.append(f"{name}.{loc}: {err.get('msg', 'invalid value')}")
    return "; ".join(parts) + " (fix the value and try again)"


class _Holder(BaseModel):
    """Validated, immutable parameter holder that raises ``InputError`` on bad input."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    def __init__(self, **data):
        try:
            super().__init__(**data)
        except ValidationError as exc:
            raise InputError(_explain(exc, type(self).__name__)) from None


class StribeckFriction(_Holder):
    """Coulomb + viscous + Stribeck friction with direction-dependent levels.

    Parameters
    ----------
    fc_pos : float
        Coulomb level for positive velocity [N].
    fc_neg : float
        Coulomb level for negative velocity, as a positive number [N].
    fs_pos : float, optional
        Static (break-away) level in the positive direction; defaults to ``fc_pos`` [N].
    fs_neg : float, optional
        Static level in the negative direction, positive; defaults to ``fc_neg`` [N].
    vs : float
        Stribeck velocity [m/s].
    delta : float
        Stribeck shape exponent [-].
    fv_pos : float
        Viscous coefficient for positive velocity [N s/m].
    fv_neg : float
        Viscous coefficient for negative velocity [N s/m].
    v_stick : float
        Half-width of the Karnopp stick band, used only when the caller does not give
        the body's mass to ``friction_force`` [m/s].
    """

    fc_pos: float = Field(ge=0.0)
    fc_neg: float = Field(ge=0.0)
    fs_pos: float | None = Field(default=None, ge=0.0)
    fs_neg: float | None = Field(default=None, ge=0.0)
    vs: float = Field(default=1e-3, gt=0.0)
    delta: float = Field(default=2.0, gt=0.0)
    fv_pos: float = Field(default=0.0, ge=0.0)
    fv_neg: float = Field(default=0.0, ge=0.0)
    v_stick: float = Field(default=1e-6, ge=0.0)

    @field_validator("*")
    @classmethod
    def _plausible(cls, v, info: ValidationInfo):
        return plausible(v, info.field_name, RANGES)

    @model_validator(mode="before")
    @classmethod
    def _fill_static(cls, data):
        if isinstance(data, dict):
            data = dict(data)
            for fs, fc in (("fs_pos", "fc_pos"), ("fs_neg", "fc_neg")):
                if data.get(fs) is None and fc in data:
                    data[fs] = data[fc]
        return data

    @property
    def slides_both_ways(self) -> bool:
        """A Coulomb level above 0 in both directions: what LuGre bristles relax towards
        while sliding [-]."""
        return min(self.fc_pos, self.fc_neg) > 0.0

    @classmethod
    def symmetric(cls, fc, fv=0.0, fs=None, vs=1e-3, delta=2.0, v_stick=1e-6):
        """Direction-independent friction.

        Parameters
        ----------
        fc : float
            Coulomb level [N].
        fv : float
            Viscous coefficient [N s/m].
        fs : float, optional
            Static level; defaults to ``fc`` [N].
        vs : float
            Stribeck velocity [m/s].
        delta : float
            Stribeck shape exponent [-].
        v_stick : float
            Karnopp band half-width [m/s].

        Returns
        -------
        StribeckFriction
            The parameter holder [-].
        """
        return cls(
            fc_pos=fc, fc_neg=fc, fs_pos=fs, fs_neg=fs, vs=vs, delta=delta,
            fv_pos=fv, fv_neg=fv, v_stick=v_stick,
        )


class LuGreFriction(StribeckFriction):
    """LuGre dynamic friction (pre-sliding bristle model) with asymmetric levels.

    Parameters
    ----------
    fc_pos, fc_neg, fs_pos, fs_neg, vs, delta, fv_pos, fv_neg, v_stick
        As in ``StribeckFriction`` ([N], [N], [N], [N], [m/s], [-], [N s/m], [N s/m],
        [m/s]); ``v_stick`` is not used by this model.
    sigma0 : float
        Bristle (pre-sliding) stiffness [N/m].
    sigma1 : float
        Bristle micro-damping [N s/m].
    sigma1_fades : bool
        The micro-damping fades with speed as the Stribeck hump does,
        ``sigma1 exp(-|v / vs|**delta)``: it damps pre-sliding without adding to the
        viscous friction of steady sliding [-].
    """

    sigma0: float = Field(gt=0.0)
    sigma1: float = Field(default=0.0, ge=0.0)
    sigma1_fades: bool = False

    @model_validator(mode="after")
    def _slides(self):
        if not self.slides_both_ways:
            raise ValueError(
                f"a LuGre contact needs a Coulomb level above 0 in both directions (got "
                f"fc_pos {self.fc_pos}, fc_neg {self.fc_neg} N): its bristles relax towards "
                "it while sliding; give the contact its sliding friction, or make it a "
                "static Stribeck contact by leaving out sigma0 and sigma1")
        return self


class Backlash(_Holder):
    """Lost motion of a screw-nut pair: dead-zone spring.

    Parameters
    ----------
    k : float
        Contact stiffness once the gap is closed [N/m].
    play : float
        Total free play across the nut, the lost motion at a reversal; the dead zone spans
        ``+/- play/2`` [m]. ``b=``, half the gap, is still accepted, with a
        ``DeprecationWarning``, as ``play = 2 b`` [m].
    c : float
        Contact damping, active only in contact [N s/m].
    """

    k: float = Field(gt=0.0)
    play: float = Field(ge=0.0)
    c: float = Field(default=0.0, ge=0.0)

    @model_validator(mode="before")
    @classmethod
    def _half_gap(cls, data):
        """Accept the former ``b`` (half the gap) as ``play = 2 b``."""
        if isinstance(data, dict) and "b" in data:
            warnings.warn("Backlash(b=...) is half the gap and deprecated: give play=2*b, the "
                          "total free play [m]", DeprecationWarning, stacklevel=2)
            data = dict(data)
            b = data.pop("b")
            data.setdefault("play", 2.0 * b if isinstance(b, (int, float)) else b)
        return data


def friction_params_array(model) -> np.ndarray:
    """Pack a friction model into the float vector the compiled functions read.

    Parameters
    ----------
    model : StribeckFriction, LuGreFriction or None
        The friction model; ``None`` means no friction [-].

    Returns
    -------
    numpy.ndarray
        Parameter vector of length ``N_FRICTION_PARAMS``, layout given by the ``P_*``
        constants [-].
    """
    p = np.zeros(N_FRICTION_PARAMS)
    if model is None:
        p[P_MODEL] = MODEL_NONE
        p[P_VS] = 1.0
        p[P_DELTA] = 2.0
        return p
    if not isinstance(model, StribeckFriction):
        raise InputError(
            f"friction model must be StribeckFriction, LuGreFriction or None, got "
            f"{type(model).__name__}; build one of those holders first",
            column="model",
        )
    p[P_MODEL] = MODEL_LUGRE if isinstance(model, LuGreFriction) else MODEL_STATIC
    p[P_FC_POS] = model.fc_pos
    p[P_FC_NEG] = model.fc_neg
    p[P_FS_POS] = model.fs_pos
    p[P_FS_NEG] = model.fs_neg
    p[P_VS] = model.vs
    p[P_DELTA] = model.delta
    p[P_FV_POS] = model.fv_pos
    p[P_FV_NEG] = model.fv_neg
    p[P_V_STICK] = model.v_stick
    if isinstance(model, LuGreFriction):
        p[P_SIGMA0] = model.sigma0
        p[P_SIGMA1] = model.sigma1
        p[P_SIGMA1_FADES] = 1.0 if model.sigma1_fades else 0.0
    return p


def backlash_params_array(model: Backlash | None) -> np.ndarray:
    """Pack a backlash element into the float vector ``backlash_force`` reads.

    Parameters
    ----------
    model : Backlash or None
        The element; ``None`` gives a rigid contact without play (``k = inf``) that
        callers must not use; it is returned as zeros [-].

    Returns
    -------
    numpy.ndarray
        ``[k, play/2, c]``: stiffness, half the gap, damping [N/m, m, N s/m].
    """
    p = np.zeros(N_BACKLASH_PARAMS)
    if model is None:
        return p
    if not isinstance(model, Backlash):
        raise InputError(
            f"backlash must be a Backlash holder, got {type(model).__name__}",
            column="backlash",
        )
    p[B_K] = model.k
    p[B_GAP] = 0.5 * model.play
    p[B_C] = model.c
    return p
