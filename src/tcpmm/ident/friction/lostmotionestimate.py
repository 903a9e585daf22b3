"""Guideway share and lost motion of the screw-nut as the plateau deflections give them.

:class:`LostMotionEstimate` is the result of
:func:`~tcpmm.ident.friction.lostmotion.estimate_lost_motion`: the share and the lost motion
with their standard deviations, the explanation kept, and the plateau table it rests on.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["LostMotionEstimate"]


@dataclass(frozen=True)
class LostMotionEstimate:
    """Guideway share and lost motion from the encoder-minus-scale deflection.

    Parameters
    ----------
    guideway_share : float
        Share of the friction acting on the guideway, the rest on the screw [-].
    guideway_share_std : float
        Its standard deviation [-].
    backlash : float
        Total lost motion of the screw-nut [m].
    backlash_std : float
        Its standard deviation; ``nan`` when it was not fitted [m].
    offset : float
        Zero offset ``c`` between encoder (at the table) and scale; the mean of the
        offsets of the speeds with ``offset="per_speed"`` [m].
    determined : bool
        The data determine the split; when ``False`` use a prior and see ``reason`` [-].
    reason : str
        Which explanation was kept, or why the split is not determined [-].
    model : str
        ``"share"`` (``g = 0``), ``"share+lost-motion"`` (both from the speed
        dependence), ``"lost-motion"`` (``s = 1``, the rest is ``g``) or
        ``"lost-motion given"`` (``g`` given, ``s`` fitted) [-].
    chi2 : float
        Reduced chi-square of the kept fit with the plateau standard deviations [-].
    velocity : numpy.ndarray
        Mean velocity of each plateau [m/s].
    deflection : numpy.ndarray
        Mean ``R_L th_m - X_LS`` of each plateau [m].
    deflection_std : numpy.ndarray
        Standard deviation of that mean (statistics and quantisation) [m].
    friction_force : numpy.ndarray
        Friction force of each plateau: motor force minus the viscous forces of the
        linear mechanics, plus the load force [N].
    nut_deflection : numpy.ndarray
        Deflection minus offset, screw torsion and the viscous part of the nut force:
        the measured ``s F_fric/K_t + sign(F_nut) g/2`` [m].
    fitted : numpy.ndarray
        The kept model's value of ``nut_deflection`` [m].
    table_viscous : float
        With ``viscous="fit"``: the viscous force per speed that passes through the nut
        (table damping and viscous guideway friction), from the speed-proportional part
        of the deflection; ``nan`` otherwise [N s/m].
    table_viscous_std : float
        Its standard deviation [N s/m].
    """

    guideway_share: float
    guideway_share_std: float
    backlash: float
    backlash_std: float
    offset: float
    determined: bool
    reason: str
    model: str
    chi2: float
    velocity: np.ndarray
    deflection: np.ndarray
    deflection_std: np.ndarray
    friction_force: np.ndarray
    nut_deflection: np.ndarray
    fitted: np.ndarray
    table_viscous: float = float("nan")
    table_viscous_std: float = float("nan")

    def to_dict(self) -> dict:
        """Plain dictionary for a JSON report.

        Returns
        -------
        dict
            Share, lost motion and offset with standard deviations, the decision, and
            the plateau table (SI: m/s, m, N) [-].
        """

        def num(x):
            return float(x) if np.isfinite(x) else None

        return {
            "guideway_share": {"value": num(self.guideway_share),
                               "std": num(self.guideway_share_std)},
            "backlash_m": {"value": num(self.backlash), "std": num(self.backlash_std)},
            "offset_m": num(self.offset),
            "determined": bool(self.determined),
            "model": self.model,
            "reason": self.reason,
            "chi2_reduced": num(self.chi2),
            "table_viscous_N_s_per_m": {"value": num(self.table_viscous),
                                        "std": num(self.table_viscous_std)},
            "plateaus": [
                {"velocity_m_per_s": float(v), "deflection_m": float(d),
                 "deflection_std_m": float(sd), "friction_force_N": float(f),
                 "nut_deflection_m": float(n), "fitted_m": float(y)}
                for v, d, sd, f, n, y in zip(
                    self.velocity, self.deflection, self.deflection_std,
                    self.friction_force, self.nut_deflection, self.fitted, strict=True)
            ],
        }
