"""A lost motion the friction runs "could miss" is void where their scale and motor angle
disagree through the lead: :func:`lead_voids_bound` says so in place of the spike range
:func:`~tcpmm.ident.friction.sensitivity.warn_lost_motion_sensitivity` would give."""

from __future__ import annotations

import numpy as np

from ...io.checks import LEAD_TOLERANCE, lead_ratio
from ...io.csvutil import warn_input

__all__ = ["lead_voids_bound"]


def lead_voids_bound(name: str, split, machine, friction) -> bool:
    """Where the runs find no lost motion while their scale and motor angle disagree
    through the lead beyond :data:`~tcpmm.io.checks.LEAD_TOLERANCE` (said by the columns'
    gate), say that their bound on one is void, and return ``True``: the nut's fit reads
    the lead's difference as a deflection growing with the travel, so its deviation, and
    the lost motion it "could miss", are that difference's (877 um on bench C's X with lead_mm
    2 % off, where with it right they leave none worth a word), not the nut's.

    Parameters
    ----------
    name : str
        Axis name [-].
    split : FrictionSplit
        The axis's friction split, with the lost motion the runs leave open [-].
    machine : Machine
        The identified machine, whose lead the runs are read through [SI].
    friction : FrictionRecord or None
        The axis's friction runs [SI].

    Returns
    -------
    bool
        Whether the bound is void, and said so [-].
    """
    if friction is None or not (split.lost_motion_unbounded
                                or np.isfinite(split.unfound_backlash)):
        return False
    ratio = lead_ratio(friction, machine.axes[name].mechanics.R_L)
    if not (np.isfinite(ratio) and abs(ratio - 1.0) > LEAD_TOLERANCE):
        return False
    warn_input(
        f"axis {name}: the friction runs find no lost motion in the nut, and cannot bound "
        f"one while their scale travels {ratio:.4f} times what the motor angle does through "
        f"lead_mm: the nut's fit reads that difference as a deflection growing with the "
        f"travel, which sets its bound ({split.unfound_backlash * 1e6:.4g} um), not the "
        "nut. Correct lead_mm in machine.yaml (or the scale's resolution) and identify "
        "again for a bound on the lost motion", file=getattr(friction, "source", None))
    return True
