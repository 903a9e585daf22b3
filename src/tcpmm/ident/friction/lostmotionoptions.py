"""Settings of :func:`~tcpmm.ident.friction.lostmotion.estimate_lost_motion`, apart from
the estimate so that the plateau fits of :mod:`~tcpmm.ident.friction.hysteresis` can
take them too."""

from __future__ import annotations

from dataclasses import dataclass

from ...errors import InputError

__all__ = ["LostMotionOptions"]


@dataclass(frozen=True)
class LostMotionOptions:
    """Settings of :func:`estimate_lost_motion`.

    Parameters
    ----------
    encoder_quantum : float
        Encoder step at the motor; 0 for ideal [rad].
    scale_resolution : float
        Scale step; 0 for ideal [m].
    stiffness_rel_std : float
        Relative standard deviation of ``K_t``; the share scales with it [-].
    viscous : {"known", "fit"}
        ``"known"``: the viscous forces of the mechanics (``B_m``, ``B_L``, ``C_t``) are
        taken as known, ``F_fric`` is the plateau force minus them and ``s`` applies to
        all of it. ``"fit"``: the part of the deflection proportional to the speed is a
        free parameter (it takes up ``C_t``, ``B_m`` and the viscous friction, which FRF
        fits rarely determine), ``F_fric`` is the plateau force minus its viscous part
        (``total_viscous`` times the speed), and ``s`` is the share of the Coulomb and
        Stribeck friction only [-].
    offset : {"common", "per_speed"}
        One encoder-to-scale offset for the whole record, or one per speed (forward and
        back plateaus of a speed cover the same travel, so lead errors of the screw and
        slow thermal drift cancel) [-].
    share : float, optional
        Guideway share given by the user: only offset and lost motion are fitted [-].
    backlash : float, optional
        Lost motion (total free play) known from elsewhere (e.g.
        :func:`tcpmm.ident.friction.estimate_nut`): only offsets, the speed-proportional
        part and the share are fitted [m].
    backlash_std : float
        Standard deviation of that lost motion; it enters the share's [m].
    max_share_std : float
        Largest standard deviation of the share for which the split counts as
        determined [-].
    z_lost_motion : float
        Lost motion and share are both fitted only when the lost motion exceeds this many
        of its standard deviations [-].
    min_plateaus : float
        Fewest plateaus that must carry the fit, counted by weight
        ``(sum w)^2 / sum w^2`` with ``w = 1/std^2``; fewer means that the quantisation
        averages out on too few plateaus to trust the split [-].
    max_chi2 : float
        Largest reduced chi-square of the kept fit; above it the deflections do not
        follow the model (wrong damping or stiffness, position-dependent errors) and the
        split counts as not determined [-].
    rel_tol : float
        Relative speed tolerance that groups plateaus of one speed [-].
    total_viscous : float, optional
        Viscous slope of the plateau forces, all contacts and damping together, from a
        friction curve that models the Stribeck hump; ``viscous="fit"`` only. Default: a
        line through the plateau forces, which the hump at the slow plateaus tilts: its
        slope comes out low, and what the speed-proportional deflection then gives for
        the table's viscous force as well, by the share times that error (measured: 4 %
        low on the built-in axes, 14 % on axis Y of machine 1 of
        ``studies/unseen_machines.py --seed 0 --backlash``) [N s/m].
    """

    encoder_quantum: float = 0.0
    scale_resolution: float = 0.0
    stiffness_rel_std: float = 0.0
    viscous: str = "known"
    offset: str = "common"
    share: float | None = None
    backlash: float | None = None
    backlash_std: float = 0.0
    max_share_std: float = 0.1
    z_lost_motion: float = 4.0
    min_plateaus: float = 4.0
    max_chi2: float = 25.0
    rel_tol: float = 0.05
    total_viscous: float | None = None

    def check(self) -> None:
        """Raise :class:`~tcpmm.errors.InputError` for a setting out of its choices."""
        if self.offset not in ("common", "per_speed"):
            raise InputError(f"offset must be 'common' or 'per_speed', got {self.offset!r}",
                             column="offset")
        if self.viscous not in ("known", "fit"):
            raise InputError(f"viscous must be 'known' or 'fit', got {self.viscous!r}",
                             column="viscous")
