"""Checks that warn before an identified model misleads a prediction.

Two failures give no error on the way and a useless model at the end:

* **Friction holds the axis during the sweep.** Recorded at standstill, the sweep's motion
  at the bottom of the band is so small that the friction sticks or dominates it. Below its
  first axial mode a free axis answers the current like a mass, ``omega_m/i_c`` lagging by
  90 deg; a stuck one answers like a stiff damper, with almost no lag. The FRFs are then not
  those of the linear mechanics, and masses, stiffnesses and damping fitted to them can be
  far off. Travelling at constant speed keeps the friction sliding, which is why sweeps are
  usually recorded that way.
* **The identified loop is unstable as the drive samples it.** The continuous loop can be
  stable while the sampled one is not, e.g. with a motor inertia fitted a hundred times too
  small: a simulation of the model then diverges.
"""

from __future__ import annotations

import warnings
from dataclasses import asdict, dataclass

import numpy as np

from ...errors import InputWarning
from ...io.csvutil import warn_input
from ...servo.sampled import is_stable_radius, radius_text, sampled_spectral_radius

__all__ = ["FRICTION_LEAD_DEG", "LOW_BAND_HZ", "FrictionHold", "friction_holds_sweep",
           "warn_friction_holds_sweep", "warn_unstable_sampled_loop"]

#: Phase lead of ``omega_m/i_c`` over a free mass (-90 deg) at the bottom of the band beyond
#: which the friction, not the inertia, sets the motion: the apparent damping then exceeds
#: the inertia's impedance ``J omega``. A sliding axis stays within about 10 deg [deg].
FRICTION_LEAD_DEG = 45.0
#: Top of the band examined: below the first axial mode of a feed drive, where a free axis
#: is a rigid body [Hz].
LOW_BAND_HZ = 15.0


@dataclass(frozen=True)
class FrictionHold:
    """Friction holding the axis during a sweep, as the bottom of the band shows it.

    Parameters
    ----------
    lead_deg : float
        Median phase lead of ``G_M`` over the -90 deg of a free axis there [deg].
    f_lo_hz, f_hi_hz : float
        The band examined: the lowest octave of good bins [Hz].
    """

    lead_deg: float
    f_lo_hz: float
    f_hi_hz: float

    def to_dict(self) -> dict:
        """Plain dictionary for the JSON report [-]."""
        return asdict(self)


def friction_holds_sweep(frf, min_coherence: float) -> FrictionHold | None:
    """Whether the motor's response at the bottom of the band is that of a held axis.

    Parameters
    ----------
    frf : FRF
        ``G_M = omega_m/i_c`` [rad/s/A].
    min_coherence : float
        Bins with a lower coherence are not examined [-].

    Returns
    -------
    FrictionHold or None
        Median phase lead over -90 deg in the lowest octave of good bins (at most up to
        :data:`LOW_BAND_HZ`), when it exceeds :data:`FRICTION_LEAD_DEG`; ``None`` otherwise
        or when no bin is low enough [-].
    """
    good = np.asarray(frf.coherence) >= min_coherence
    f = np.asarray(frf.freq_hz, dtype=float)[good]
    if f.size == 0 or f[0] > LOW_BAND_HZ:
        return None
    low = f <= min(2.0 * f[0], LOW_BAND_HZ)
    phase = np.degrees(np.angle(np.asarray(frf.H)[good][low]))
    lead = float(np.median(phase)) + 90.0
    if lead <= FRICTION_LEAD_DEG:
        return None
    return FrictionHold(lead, float(f[low][0]), float(f[low][-1]))


def warn_friction_holds_sweep(name: str, sweep, frf, min_coherence: float,
                              standing: bool) -> FrictionHold | None:
    """Warn when friction held the axis during the sweep (see :func:`friction_holds_sweep`).

    Parameters
    ----------
    name : str
        Axis name [-].
    sweep : SweepRecord
        The record, for its file name [-].
    frf : FRF
        Its ``G_M`` [rad/s/A].
    min_coherence : float
        Coherence below which bins are not examined [-].
    standing : bool
        The sweep does not travel [-].

    Returns
    -------
    FrictionHold or None
        What :func:`friction_holds_sweep` found [-].
    """
    held = friction_holds_sweep(frf, min_coherence)
    if held is None:
        return None

    remedy = ("The sweep stands still: record it while the axis travels at constant speed "
              "(e.g. 20 mm/s), which keeps the friction sliding, or raise its amplitude."
              if standing else "Raise the sweep's amplitude or its travel speed.")
    warn_input(
        f"axis {name}: at {held.f_lo_hz:.1f}-{held.f_hi_hz:.1f} Hz the phase of "
        f"the motor's velocity over the current is {held.lead_deg - 90.0:+.0f} deg where a "
        "free axis gives -90: friction holds the axis during the sweep, its FRFs are not those of "
        "the linear mechanics, and the masses, stiffnesses and damping fitted to them can be "
        f"far off. {remedy}",
        file=getattr(sweep, "source", None),
    )
    return held


def warn_unstable_sampled_loop(name: str, axis, undetermined, cover=None) -> float:
    """Warn when the identified axis's loop is unstable as the drive samples it; where the
    FRFs' band leaves out a mode the fitted mechanics put where the sweep excites, name
    the band as the likely cause before the servo settings.

    Parameters
    ----------
    name : str
        Axis name [-].
    axis : Axis
        The identified axis [SI].
    undetermined : list of str
        Parameters the FRFs did not determine [-].
    cover : BandCover, optional
        What the band the user set leaves out, and how far the sweep's excitation
        reaches (:func:`~tcpmm.ident.frf.excited.band_cover`) [-].

    Returns
    -------
    float
        Spectral radius of the lifted sampled loop (stable as
        :func:`~tcpmm.servo.sampled.is_stable_radius` says) [-].
    """
    rho = sampled_spectral_radius(axis.mechanics, axis.servo)
    if not is_stable_radius(rho):
        suspects = (f"; the FRFs did not determine {', '.join(undetermined)}"
                    if undetermined else "")
        band = None if cover is None else (cover.words(axis.mechanics)
                                       or cover.reach_words(axis.mechanics, axis.servo))
        check = ("Check the servo settings in machine.yaml and the sweep." if band is None else
                 f"{band[0].upper()}{band[1:]}; failing that, check the servo settings in "
                 "machine.yaml and the sweep.")
        warnings.warn(
            f"axis {name}: the identified position loop is unstable as the drive samples it "
            f"(spectral radius {radius_text(rho)} of the sampled loop), so a simulation of "
            f"this model diverges{suspects}. {check}",
            InputWarning,
            stacklevel=3,
        )
    return rho
