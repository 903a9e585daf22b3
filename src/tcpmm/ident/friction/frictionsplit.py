"""How the identified friction of an axis was split between guideway and screw.

:class:`FrictionSplit` records the share, the lost motion, where they came from and the
estimates behind them; :func:`tcpmm.ident.friction.split.identify_friction` makes it.
What to tell the user of a split the runs leave open or loose: the prior share used
(:meth:`FrictionSplit.prior_warning`), or a share from the data with a wide deviation
(:func:`share_uncertainty_warning`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...model import BACKLASH_MAX_M

__all__ = ["SHARE_WARN_STD", "UNFOUND_Z", "FrictionSplit", "share_uncertainty_warning"]

#: Standard deviations of a lost motion the runs do not find that could hide in them [-].
UNFOUND_Z = 3.0


def _or_none(x: float):
    """``x`` as a float, ``None`` when it is not finite (JSON has no NaN) [-]."""
    return float(x) if math.isfinite(x) else None


#: Standard deviation of a guideway share from the data above which identification warns:
#: the friction that holds the table at a reversal, and with it the predicted reversal
#: spikes, follows the share, and a shift of 0.15 in it moves them by micrometres on an
#: axis with lost motion [-].
SHARE_WARN_STD = 0.1


@dataclass(frozen=True)
class FrictionSplit:
    """How the identified friction was split between guideway and screw.

    Parameters
    ----------
    guideway_share : float
        Share of the friction put on the guideway, the rest on the screw [-].
    backlash : float
        Lost motion of the screw-nut put into the model [m].
    source : str
        ``"data"`` (from the encoder-minus-scale deflection), ``"sweep"`` (from the TCP
        structure's deflection in a travelling sweep), ``"prior"`` (not determined by the
        data: :data:`~tcpmm.ident.friction.split.GUIDEWAY_SHARE`) or ``"given"`` (set by the
        user) [-].
    estimate : LostMotionEstimate or None
        The estimate from the friction runs, with standard deviations and plateaus [-].
    nut : NutEstimate or None
        Nut stiffness, share and lost motion from the whole record (accelerations and
        plateaus); set when they were used, i.e. when the record shows lost motion [-].
    guideway_share_std : float
        Standard deviation of the share used, from the estimate it came from; NaN when
        the share is the prior or given [-].
    unfound_backlash_std : float
        Standard deviation of the lost motion the whole record gives where it does not
        find any, the scale for how much could hide; NaN otherwise [m].
    viscous_on_table : float
        Viscous force per speed on the table side that a share from the sweep was
        worked out with, which the model then takes; NaN otherwise [N s/m].
    viscous_on_table_std : float
        Its standard deviation; NaN otherwise [N s/m].
    backlash_at_resolution : float
        The largest lost motion the whole record cannot tell from the scale's rounding,
        where it shows one within two scale steps (its value plus three standard
        deviations); NaN otherwise [m].
    plateau_share, plateau_share_std : float
        Where the share came from a sweep: the share the plateaus of the friction runs give
        alone and its standard deviation, a second measure a verdict can weigh the sweep's
        against; NaN otherwise, or where the plateaus do not determine it [-].
    sweep_note : str
        Why a travelling sweep gave no share, where it read one outside 0 to 1; told once
        per axis (:func:`tcpmm.ident.steps.fitcontext.friction_on`), not for each refit of
        the mechanics [-].
    """

    guideway_share: float
    backlash: float
    source: str
    estimate: object = None
    nut: object = None
    guideway_share_std: float = float("nan")
    unfound_backlash_std: float = float("nan")
    viscous_on_table: float = float("nan")
    viscous_on_table_std: float = float("nan")
    backlash_at_resolution: float = float("nan")
    plateau_share: float = float("nan")
    plateau_share_std: float = float("nan")
    sweep_note: str = ""

    def prior_warning(self, axis: str = "") -> str | None:
        """What to tell the user where the friction runs did not determine the split and
        the prior share was used; ``None`` otherwise [-]."""
        if self.source != "prior":
            return None
        name = f"axis {axis}" if axis else "axis"
        reason = getattr(self.estimate, "reason", "") or "no estimate"
        return (f"{name}: the friction runs do not determine how the friction divides "
                f"between guideway and screw ({reason}); using the prior guideway share "
                f"{self.guideway_share} and no lost motion")

    @property
    def backlash_std(self) -> float:
        """Standard deviation of the lost motion, from the estimate it came from: the nut
        estimate when there is one, else the plateaus; NaN without either [m]."""
        play_from = self.nut if self.nut is not None else self.estimate
        return float(play_from.backlash_std) if play_from is not None else float("nan")

    @property
    def unfound_backlash(self) -> float:
        """The lost motion the runs could miss where they find none (:data:`UNFOUND_Z`
        standard deviations); NaN where they find one or give no deviation [m]."""
        if self.backlash > 0.0 or self.source == "given":
            return float("nan")
        return UNFOUND_Z * float(self.unfound_backlash_std)

    @property
    def lost_motion_unbounded(self) -> bool:
        """Whether the runs cannot bound the lost motion they do not find: what they could
        miss is beyond any screw-nut's (:data:`~tcpmm.model.BACKLASH_MAX_M`) [-]."""
        return bool(self.unfound_backlash > BACKLASH_MAX_M)

    @property
    def _table_viscous_from(self):
        """The estimate whose table damping the model takes: the plateaus' when they
        determine it, else the nut estimate's (``None`` without either) [-]."""
        lm = self.estimate
        if self.nut is not None and not (lm is not None and lm.determined
                                         and np.isfinite(lm.table_viscous)):
            return self.nut
        return lm

    @property
    def table_viscous(self) -> float:
        """Viscous force per speed that passes through the nut (``C_t`` plus the
        guideway's viscous friction), from :attr:`_table_viscous_from`; NaN without an
        estimate [N s/m]."""
        if np.isfinite(self.viscous_on_table):
            return float(self.viscous_on_table)
        src = self._table_viscous_from
        return float(src.table_viscous) if src is not None else float("nan")

    @property
    def table_viscous_std(self) -> float:
        """Standard deviation of :attr:`table_viscous` [N s/m]."""
        if np.isfinite(self.viscous_on_table):
            return float(self.viscous_on_table_std)
        src = self._table_viscous_from
        return float(src.table_viscous_std) if src is not None else float("nan")

    def to_dict(self) -> dict:
        """Plain dictionary for the JSON report.

        Returns
        -------
        dict
            Share and lost motion used, their standard deviations when they come from the
            data, the source and the full estimate [-].
        """
        e = self.estimate

        def sd(x, sources):
            ok = e is not None and self.source in sources and np.isfinite(x)
            return float(x) if ok else None

        return {
            "guideway_share": {"value": float(self.guideway_share),
                               "std": sd(self.guideway_share_std, ("data", "sweep"))},
            "backlash_m": {"value": float(self.backlash),
                           "std": sd(self.backlash_std, ("data", "given", "sweep"))},
            "table_viscous_N_s_per_m": {
                "value": _or_none(self.table_viscous if self.source != "prior" else math.nan),
                "std": _or_none(self.table_viscous_std if self.source != "prior" else math.nan)},
            "source": self.source,
            "estimate": e.to_dict() if e is not None else None,
            "nut": self.nut.to_dict() if self.nut is not None else None,
        }


def share_uncertainty_warning(axis: str, split: FrictionSplit, curve, mechanics,
                              cfg, max_std: float = SHARE_WARN_STD) -> str | None:
    """What to tell the user when the friction runs determine the guideway share poorly.

    Parameters
    ----------
    axis : str
        Axis name [-].
    split : FrictionSplit
        The split used [-].
    curve : ParameterEstimate or dict
        Fitted steady friction, by name (``Fc+``, ``Fc-``), table units [N].
    mechanics : AxisMechanics
        Identified mechanics; ``K_t`` is the nut in contact, ``R_L`` the screw ratio [SI].
    cfg : AxisConfig
        Sensors of the axis [-].
    max_std : float
        Standard deviation of the share above which there is something to say [-].

    Returns
    -------
    str or None
        The message, or ``None`` when the share is from the data and within ``max_std``,
        or not from the data at all [-].
    """
    sd = float(split.guideway_share_std)
    if split.source != "data" or not sd > max_std:
        return None
    s = split.guideway_share
    fc = 0.5 * (abs(float(curve["Fc+"])) + abs(float(curve["Fc-"])))
    um = 1e6
    nut = split.nut
    play = (f", told from the {nut.backlash * um:.2f} +/- {nut.backlash_std * um:.2f} um of "
            f"lost motion only by the braking between the plateaus" if nut is not None else "")
    step = mechanics.R_L * cfg.sensors.encoder_resolution_rad
    return (f"axis {axis}: the friction runs determine the guideway share only to {s:.2f} "
            f"+/- {sd:.2f}: the guideway's part of the nut deflection is "
            f"{s * fc / mechanics.K_t * um:.2g} um{play}, and the sensors step by "
            f"{step * um:.3g} um (encoder, at the table) and "
            f"{cfg.sensors.scale_resolution_m * um:.3g} um (scale). The predicted reversal "
            f"spikes follow the share. Finer sensors, or runs to a higher top speed with more "
            f"reversals, determine it; if it is known, set it with --guideway-share")
