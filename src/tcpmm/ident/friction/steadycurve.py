"""The steady friction curve of an axis from its ``friction.csv`` record.

``stribeck_from_record`` fits the Stribeck curve to the record's constant-speed plateaus
(:mod:`tcpmm.ident.friction.stribeck`); ``steady_curve`` takes it from the whole record,
accelerations included (:mod:`tcpmm.ident.friction.transients`), where the plateaus leave
the hump open. Both fits are kept per record: the refits of the mechanics ask for them
again.
"""

from __future__ import annotations

import math
import weakref

import numpy as np

from ...errors import InputError
from .stribeck import (
    PLATEAU_DURATIONS_S,
    NoPlateauError,
    friction_record_arrays,
    identify_stribeck_run,
)
from .transients import fit_stribeck_transients

__all__ = ["HUMP_REL_STD", "TRANSIENT_CUTOFF_HZ", "slowest_plateau", "slowest_read",
           "steady_curve", "stribeck_from_record"]

#: Highest low-pass cut-off of the fit to the whole friction record; at most a quarter of
#: the drive's first axial mode, below which the axis moves as one body [Hz].
TRANSIENT_CUTOFF_HZ = 30.0
#: Largest relative standard deviation of the Stribeck speed and static levels of a fit to
#: the plateaus that is taken as determining the hump [-].
HUMP_REL_STD = 0.25


def stribeck_from_record(record, cfg, axis: str | None = None):
    """The Stribeck fit of a friction record, or an error naming its file and axis.

    Parameters
    ----------
    record : FrictionRecord
        Back-and-forth runs at constant speeds (formats.md section 1) [SI].
    cfg : AxisConfig
        The axis's bundle configuration (lead, torque constant) [SI].
    axis : str, optional
        Axis name, for messages [-].

    Returns
    -------
    tuple
        ``(t, x, force, ParameterEstimate, list of Plateau)``: time [s], scale position
        [m], motor force at the table [N], the fitted curve and its plateaus [-].

    Raises
    ------
    InputError
        When the record holds no constant-speed passes long enough for the fit.
    """
    t, x, force = friction_record_arrays(record, cfg.lead_m, cfg.torque_constant)
    _check_uniform(t, record.source)
    try:
        est, plateaus = _memo(record, ("plateaus", cfg.lead_m, cfg.torque_constant),
                              lambda: identify_stribeck_run(t, x, force))
    except NoPlateauError:
        name = axis or record.axis
        raise InputError(
            (f"axis {name}: " if name else "")
            + "no constant-speed passes found in the friction runs; record back-and-forth "
            "passes at several constant speeds, each held for at least "
            f"{min(PLATEAU_DURATIONS_S)} s in both directions (docs/formats.md section 1)",
            file=record.source,
            column="scale_mm",
        ) from None
    except InputError as exc:  # the fit knows the column, not the file
        raise exc.in_file(record.source) from None
    return t, x, force, est, plateaus


def _check_uniform(t, source) -> None:
    """Refuse friction runs whose sampling is not uniform within the 1 % the fit needs,
    naming the file and the first step that differs [-]."""
    dt = np.diff(t)
    step = float(np.median(dt))
    off = np.flatnonzero(~(np.abs(dt - step) <= 0.01 * step))
    if off.size:
        i = int(off[0])
        raise InputError(
            f"the friction runs must be sampled uniformly (1 % tolerance): the step after "
            f"t = {t[i]:.6g} s is {dt[i]:.6g} s, {step:.6g} s elsewhere; record without gaps, "
            "or resample", file=source, column="time_s")


def slowest_plateau(plateaus) -> float:
    """Speed of the slowest constant-speed plateau [m/s]."""
    return float(min(abs(p.velocity) for p in plateaus))


def slowest_read(fit, plateaus) -> float:
    """The slowest speed a fit of the steady curve reads: for a fit to the whole record
    (:func:`~tcpmm.ident.friction.transients.fit_stribeck_transients`) the slowest sample it
    takes as moving, for a fit to the plateaus the slowest plateau [m/s]."""
    return float(fit.extra.get("v_min", slowest_plateau(plateaus)))


#: Fits of a record already made, by the record (held weakly) and what they depend on: the
#: refits of the mechanics ask for the same friction fits several times.
_FITS: dict = {}


def _memo(record, key, make):
    """``make()`` once per record and key; an error is raised again each time."""
    ref, fits = _FITS.get(id(record), (None, None))
    if ref is None or ref() is not record:
        fits = {}
        _FITS[id(record)] = (weakref.ref(record, lambda _, i=id(record): _FITS.pop(i, None)),
                             fits)
    if key not in fits:
        try:
            fits[key] = (make(), None)
        except InputError as exc:
            fits[key] = (None, exc)
    value, exc = fits[key]
    if exc is not None:
        raise exc
    return value


def _plateaus_fix_the_hump(fit, slowest: float) -> bool:
    """Whether a fit to the plateaus determines its Stribeck hump: a Stribeck speed no
    lower than the slowest plateau's ``slowest`` [m/s], and it and the static levels known
    within :data:`HUMP_REL_STD`."""
    v = dict(zip(fit.names, fit.values, strict=True))
    sd = dict(zip(fit.names, fit.std, strict=True))
    rel = [sd[k] / v[k] if v[k] > 0 else np.inf for k in ("vs", "Fs+", "Fs-")]
    return bool(v["vs"] >= slowest and np.all(np.isfinite(rel))
                and max(rel) <= HUMP_REL_STD)


def steady_curve(t, record, force, plateau_fit, plateaus, mechanics):
    """The steady friction curve from the whole record (accelerations included), or the
    plateaus' fit when the record has too little slow motion for it.

    The plateaus alone fix static level and Stribeck speed only in combination when the
    slowest pass is near the Stribeck speed (:mod:`tcpmm.ident.friction.transients`);
    where they fix both (:func:`_plateaus_fix_the_hump`) their fit is kept, since the
    accelerations see the drive's compliance and any free play of the nut as well.

    Parameters
    ----------
    t : ndarray
        Time [s].
    record : FrictionRecord
        The runs, SI [-].
    force : ndarray
        Motor force at the table [N].
    plateau_fit : ParameterEstimate
        The fit to the plateaus [-].
    plateaus : list of Plateau
        The plateaus found [-].
    mechanics : AxisMechanics
        Identified mechanics, for ``R_L`` and the drive's first mode [SI].

    Returns
    -------
    ParameterEstimate
        ``Fc+, Fc-, Fs+, Fs-, vs, Fv`` [N, N, N, N, m/s, N s/m].
    """
    slowest = slowest_plateau(plateaus)
    if _plateaus_fix_the_hump(plateau_fit, slowest):
        return plateau_fit
    m = mechanics
    k_axial = 1.0 / (m.R_L**2 / m.K_L + 1.0 / m.K_t)
    f_axial = math.sqrt(k_axial / (m.M_t + (m.J_m + m.J_L) / m.R_L**2)) / (2 * math.pi)
    cutoff = min(TRANSIENT_CUTOFF_HZ, 0.25 * f_axial)
    try:
        key = ("transients", m.R_L, cutoff, slowest, hash(np.asarray(force).tobytes()))
        return _memo(record, key,
                     lambda: fit_stribeck_transients(t, record.motor_angle_rad * m.R_L, force,
                                                     slowest_plateau=slowest,
                                                     cutoff_hz=cutoff))
    except InputError:
        return plateau_fit
