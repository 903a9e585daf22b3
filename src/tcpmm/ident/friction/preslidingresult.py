"""Pre-sliding of an axis's contacts as the friction runs' reversals give it.

:class:`PreslidingFit` is the result of
:func:`~tcpmm.ident.friction.preslidingfit.fit_presliding`: the distance and the bristle
damping with their standard deviations, whether they count, and the range of the distance
over the widths of the play that the fit tried.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["PreslidingFit"]


@dataclass(frozen=True)
class PreslidingFit:
    """Pre-sliding of an axis's contacts fitted to its friction-run reversals.

    Parameters
    ----------
    presliding : float
        Pre-sliding distance of both contacts at the static level [m].
    presliding_std : float
        Its standard deviation [m].
    damping_ratio : float
        Bristle damping ratio against the table mass [-].
    damping_ratio_std : float
        Its standard deviation [-].
    reversals : int
        Reversals the fit used [-].
    rms_force : float
        Root mean square of the force residual [N].
    noise_force : float
        Sample-to-sample noise of the measured motor force in the windows [N].
    determined : bool
        The reversals determine the distance; when ``False`` see ``reason`` [-].
    reason : str
        Why the fit does not count, or ``""`` [-].
    presliding_range : tuple of float
        Smallest and largest distance of the chosen fit and of the fits at the
        neighbouring widths of the play (half and twice), each widened by two of its
        standard deviations [m].
    """

    presliding: float
    presliding_std: float
    damping_ratio: float
    damping_ratio_std: float
    reversals: int
    rms_force: float
    noise_force: float
    determined: bool
    reason: str = ""
    presliding_range: tuple = (float("nan"), float("nan"))

    def to_dict(self) -> dict:
        """The fit as plain numbers (SI) for JSON reports [-]."""
        return {"presliding_m": self.presliding, "presliding_std_m": self.presliding_std,
                "damping_ratio": self.damping_ratio,
                "damping_ratio_std": self.damping_ratio_std, "reversals": self.reversals,
                "rms_force_N": self.rms_force, "noise_force_N": self.noise_force,
                "determined": self.determined,
                "reason": self.reason, "presliding_range_m": list(self.presliding_range)}
