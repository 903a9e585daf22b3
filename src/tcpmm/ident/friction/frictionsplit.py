"""How the identified friction of an axis was split between guideway and screw.

:class:`FrictionSplit` records the share, the lost motion, where they came from and the
estimates behind them; :func:`tcpmm.ident.friction.split.identify_friction` makes it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...model import BACKLASH_MAX_M

__all__ = ["UNFOUND_Z", "FrictionSplit"]

#: Standard deviations of a lost motion the runs do not find that could hide in them [-].
UNFOUND_Z = 3.0


def _or_none(x: float):
    """``x`` as a float, ``None`` when it is not finite (JSON has no NaN) [-]."""
    return float(x) if math.isfinite(x) else None


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
