"""Gates: checks that keep a physically absurd identified model from being written silently.

Each check takes the identified axis (or a record and what ``machine.yaml`` declares) and
returns a list of :class:`Finding`; an empty list means the check passed. The checks:

* :func:`~tcpmm.ident.gates.timebase.check_time_base` -- the time column of a record against
  plausible DAQ periods and feed speeds (e.g. a sweep written with milliseconds under
  ``time_s``), in a module of its own;
* :func:`check_static_friction_vs_drive` -- friction at rest above what the drive can push
  at its current limit;
* :func:`check_static_over_coulomb` -- a static level far above Coulomb that the friction
  runs never saw (Stribeck speed below their slowest plateau);
* :func:`check_fit_percent` -- a physical model worse than the mean of its FRF;
* :func:`check_sampled_loop` -- a loop that is unstable as the drive samples it;
* :func:`skew_findings` -- a channel of the sweep recorded out of step with the others;
* :func:`~tcpmm.ident.gates.masses.check_tcp_gain` -- a TCP device that reads a share of
  the motion.

:func:`~tcpmm.ident.gates.timebase.time_base_findings` and :func:`axis_findings` run them on
a bundle's records and on an :class:`~tcpmm.ident.identification.AxisIdentification`, the
latter with the masses against the FRFs' static gains (:mod:`~tcpmm.ident.gates.masses`);
:class:`~tcpmm.ident.gates.finding.SuspectModelError` reports them.
"""

from __future__ import annotations

import math

import numpy as np

from ...model import drive_force_limit
from ...servo.sampled import is_stable_radius, sampled_spectral_radius
from ..friction.steadycurve import slowest_plateau, stribeck_from_record
from ..friction.sweepforce import travel_speed
from ..lti.goodness import fit_percent
from ..options import MIN_COHERENCE
from ..physical.skew import SKEW_MIN_SAMPLES, SKEW_Z, skewed_channels
from .finding import Finding
from .masses import mass_findings

__all__ = ["FIT_TRIM", "STATIC_OVER_COULOMB", "axis_findings",
           "check_fit_percent", "check_sampled_loop", "check_static_friction_vs_drive",
           "check_static_over_coulomb", "drive_force_limit", "skew_findings",
           "slowest_plateau_speed", "trimmed_fit_percent"]

#: Static friction above this many times the Coulomb level counts as far above it. Static
#: over Coulomb friction of feed axes is 1.1 to 1.5 for preloaded rolling guides and ball
#: screws and up to about 2 for sliding (plastic-lined) guides; 3 leaves margin above the
#: largest of these, so a ratio beyond it is not a machine's but a fit's [-].
STATIC_OVER_COULOMB = 3.0
#: Share of an FRF's bins left out of the fit percentage that gates a model. A lightly
#: damped mode of the model a few Hz off puts its whole peak into one or two bins, which
#: then decide the plain figure: on one sane axis G_M gave -390 % with every bin and 82 %
#: without the worst 1 % (of 2729). A model worse than the mean over 99 % of the band is
#: wrong, not unlucky [-].
FIT_TRIM = 0.01
#: Lowest fit to the logarithm of each FRF that passes [%]. ``G_M`` spans decades, and a
#: model worse than its mean has the drive wrong. ``G_T`` and ``G_tcp`` are nearly flat
#: over much of the band, where the mean of the data is already a fair model: a sane fit of
#: an axis whose sweep crossed free play in the nut read -16 % there and predicted its
#: circle within 3.7 um, while a model of the wrong sign or scale reads -200 % or less.
FIT_FLOOR = {"G_M": 0.0, "G_T": -50.0, "G_tcp": -50.0}


def _contacts(axis):
    """``(name, contact)`` of the friction contacts of an axis [-]."""
    fr = axis.friction
    if fr is None:
        return []
    return [(k, c) for k, c in (("screw", fr.screw), ("guideway", fr.guideway)) if c is not None]


def check_static_friction_vs_drive(name: str, axis, data: str = "the friction runs"
                                   ) -> list[Finding]:
    """Friction at rest (static levels of screw and guideway, table units) above the
    force the drive delivers at its current limit: such an axis could never start, yet
    the records show it moving.

    Parameters
    ----------
    name : str
        Axis name [-].
    axis : Axis
        The identified axis [SI].
    data : str
        The data its friction came from, for the message [-].

    Returns
    -------
    list of Finding
        One finding per direction that exceeds the drive's force [-].
    """
    limit = drive_force_limit(axis)
    out = []
    for d in ("pos", "neg"):
        total = sum(getattr(c, f"fs_{d}") for _, c in _contacts(axis))
        if total > limit:
            out.append(Finding(
                name, f"static friction fs_{d} (screw + guideway)", total, "N",
                f"above the drive's force at its current limit, {limit:.4g} N "
                f"({axis.servo.current_limit:g} A x K_tc {axis.mechanics.K_tc:g} N m/A / R_L "
                f"{axis.mechanics.R_L * 1e3:.4g} mm/rad)", data,
                "check lead_mm, torque_constant_Nm_per_A and current_limit_A in machine.yaml "
                "and the unit of current_cmd_A in friction.csv"))
    return out


def slowest_plateau_speed(record, cfg, axis: str | None = None) -> float:
    """Slowest constant-speed plateau of the friction runs, as the Stribeck fit sees them.

    Parameters
    ----------
    record : FrictionRecord
        The friction runs [SI].
    cfg : AxisConfig
        The axis's bundle configuration [-].
    axis : str, optional
        Axis name, for messages [-].

    Returns
    -------
    float
        Smallest absolute plateau velocity [m/s].
    """
    return slowest_plateau(stribeck_from_record(record, cfg, axis)[4])


def check_static_over_coulomb(name: str, axis, slowest_speed: float,
                              data: str = "the friction runs") -> list[Finding]:
    """A static level above :data:`STATIC_OVER_COULOMB` times Coulomb with a Stribeck speed
    below the slowest plateau of the friction runs: the runs never saw the hump, so the
    static level is an extrapolation of the fit.

    Parameters
    ----------
    name : str
        Axis name [-].
    axis : Axis
        The identified axis [SI].
    slowest_speed : float
        Slowest plateau speed of the friction runs [m/s].
    data : str
        The data its friction came from, for the message [-].

    Returns
    -------
    list of Finding
        One finding per contact and direction [-].
    """
    out = []
    for contact, c in _contacts(axis):
        if c.vs >= slowest_speed:
            continue
        for d in ("pos", "neg"):
            fs, fc = getattr(c, f"fs_{d}"), getattr(c, f"fc_{d}")
            if fs > STATIC_OVER_COULOMB * fc:
                out.append(Finding(
                    name, f"friction.{contact}.fs_{d}", fs, "N",
                    f"above {STATIC_OVER_COULOMB:g} x its Coulomb level {fc:.4g} N, with a "
                    f"Stribeck speed of {c.vs * 1e3:.3g} mm/s below the slowest run "
                    f"{slowest_speed * 1e3:.3g} mm/s: the runs never saw that static level",
                    data, "add friction runs slower than the Stribeck speed (e.g. 0.1 and "
                    "0.2 mm/s, each held for at least 0.2 s in both directions)"))
    return out


def trimmed_fit_percent(H, H_model, trim: float = FIT_TRIM) -> float:
    """Fit of the model to the logarithm of the FRF, ``ln|H| + j arg H`` (the quantity the
    physical fit minimises), without the ``trim`` share of bins (at least one) where the
    model is furthest; NaN without bins [%].

    On the logarithm every decade of the response counts alike, so a resonance peak a few
    bins off does not outweigh the rest of the band as it does on the complex FRF, where a
    sane model of a lightly damped axis can read -400 %.

    Parameters
    ----------
    H : array_like
        Measured FRF on its coherent bins [SI].
    H_model : array_like
        Model response on the same bins [SI].
    trim : float
        Share of bins left out [-].
    """
    H, h = np.asarray(H, dtype=complex), np.asarray(H_model, dtype=complex)
    ok = (np.abs(H) > 0) & (np.abs(h) > 0)
    H, h = H[ok], h[ok]
    if H.size < 3:
        return float("nan")
    lH, lh = np.log(H), np.log(h)
    lh = lh.real + 1j * (lH.imag + np.angle(np.exp(1j * (lh.imag - lH.imag))))  # same branch
    n_out = min(max(1, math.ceil(trim * H.size)), H.size - 2)
    keep = np.argsort(np.abs(lH - lh))[: H.size - n_out]
    return fit_percent(lH[keep], lh[keep])


#: Cause and remedy of a failed fit when the sweep does not travel.
STANDING_SWEEP = (
    "the sweep does not travel (torque mode, or loops holding one place), so no part of it "
    "shows the linear mechanics: at its lowest frequencies the axis sticks and slips at "
    "every reversal, and above them the friction pre-slides and answers with the contacts' "
    "stiffness (G_T = X_LS/theta_m is that of the pre-sliding spring, not of the nut). "
    "Record the sweep with the loops closed while the axis travels at constant speed "
    "(10-20 mm/s keeps the friction sliding)")


def check_fit_percent(name: str, tf: str, H, H_model, data: str = "the sweep",
                      remedy: str | None = None) -> list[Finding]:
    """A physical model worse than its measured FRF allows: a fit to its logarithm below
    :data:`FIT_FLOOR` even without the :data:`FIT_TRIM` worst bins
    (:func:`trimmed_fit_percent`), or no coherent bin at all.

    Parameters
    ----------
    name : str
        Axis name [-].
    tf : str
        Transfer function, e.g. ``G_M`` [-].
    H : array_like
        Measured FRF on its coherent bins [SI].
    H_model : array_like
        The identified model's response on the same bins [SI].
    data : str
        The sweep record, for the message [-].
    remedy : str, optional
        What to do, when the cause is known; by default the checks of a record [-].

    Returns
    -------
    list of Finding
        Empty when the fit is not negative [-].
    """
    remedy = remedy or ("check the sweep (time unit, columns, excitation amplitude) and the "
                        "band (--band)")
    if np.asarray(H).size < 2:
        return [Finding(name, f"fit of the physical model to {tf}", float("nan"), "%",
                        "not computable: no bin of the FRF is coherent", data, remedy)]
    trimmed = trimmed_fit_percent(H, H_model)
    floor = FIT_FLOOR.get(tf, 0.0)
    if not trimmed < floor:
        return []
    return [Finding(name, f"fit of the physical model to log {tf}", trimmed, "%",
                    f"below {floor:g} % (0 %: no better than the mean of the data) without "
                    f"the worst {FIT_TRIM:.0%} of its bins (on the complex FRF "
                    f"{fit_percent(H, H_model):.3g} %)", data, remedy)]


def check_sampled_loop(name: str, axis, data: str = "the sweep",
                       cover=None) -> list[Finding]:
    """The identified position loop, as the drive samples it, unstable (spectral radius of
    the lifted sampled loop above 1 by more than rounding:
    :func:`~tcpmm.servo.sampled.is_stable_radius`): a simulation of the model diverges.
    Where the FRFs' band leaves out a mode the fitted mechanics put where the sweep
    excites, the remedy names the band before the servo settings.

    Parameters
    ----------
    name : str
        Axis name [-].
    axis : Axis
        The identified axis [SI].
    data : str
        The sweep record, for the message [-].
    cover : BandCover, optional
        What the band the user set leaves out, and how far the sweep's excitation
        reaches (:func:`~tcpmm.ident.frf.excited.band_cover`) [-].

    Returns
    -------
    list of Finding
        Empty when the sampled loop is stable [-].
    """
    rho = sampled_spectral_radius(axis.mechanics, axis.servo)
    if is_stable_radius(rho):
        return []
    servo = "check the servo settings in machine.yaml (gains, loop periods) and the sweep"
    band = None if cover is None else (cover.words(axis.mechanics)
                                       or cover.reach_words(axis.mechanics, axis.servo))
    return [Finding(name, "spectral radius of the sampled position loop", rho, "",
                    "above 1: the loop as the drive samples it is unstable", data,
                    servo if band is None else f"{band}; failing that, {servo}")]


def axis_findings(ident, records, cfg) -> list[Finding]:
    """Every model check on one identified axis.

    Parameters
    ----------
    ident : AxisIdentification
        The axis as identified [-].
    records : AxisRecords
        Its records from the bundle [-].
    cfg : AxisConfig
        Its bundle configuration [-].

    Returns
    -------
    list of Finding
        Empty when the axis passes [-].
    """
    name, axis = ident.name, ident.axis
    sweep = records.sweep.source or f"{name}/sweep.csv"
    remedy = STANDING_SWEEP if travel_speed(records.sweep) == 0.0 else None
    if remedy is None and ident.band_cover is not None:
        remedy = ident.band_cover.reach_words(axis.mechanics, axis.servo)
    out = skew_findings(name, ident.channel_skews, sweep)
    for tf, frf in ident.frfs.items():
        good = frf.coherence >= MIN_COHERENCE
        out += check_fit_percent(name, tf, frf.H[good],
                                 ident.fitted_response(tf, frf.freq_hz)[good], sweep,
                                 remedy)
    out += check_sampled_loop(name, axis, sweep, ident.band_cover)
    out += mass_findings(name, ident.frfs, axis.mechanics, sweep, MIN_COHERENCE,
                         records.sweep.excitation_A,
                         lambda f: ident.fitted_response("G_tcp", f))
    if records.friction is not None and axis.friction is not None:
        runs = records.friction.source or f"{name}/friction.csv"
        out += check_static_friction_vs_drive(name, axis, runs)
        slowest = slowest_plateau_speed(records.friction, cfg, name)
        out += check_static_over_coulomb(name, axis, slowest, runs)
    return out


def skew_findings(name: str, skews, sweep: str) -> list[Finding]:
    """A channel of the sweep recorded out of step with the others
    (:func:`~tcpmm.ident.physical.skew.skewed_channels`): the fit takes the lag for
    dynamics, and what it then says of the others is suspect too, so it comes first [-].

    Parameters
    ----------
    name : str
        Axis name [-].
    skews : tuple of ChannelSkew
        The delays read [s].
    sweep : str
        The sweep's file [-].
    """
    return [Finding(name, f"delay of the {k.channel}", k.samples, "samples",
                    f"{k.words()}, beyond {SKEW_MIN_SAMPLES:g} samples and {SKEW_Z:g} "
                    f"standard uncertainties: the channels were not recorded in step",
                    f"{sweep}, its FRFs refitted with delays", f"{k.remedy()} (or record "
                    f"the channels in step) and identify again: the fit takes the lag for "
                    f"dynamics, and the model's reversal spikes follow it")
            for k in skewed_channels(skews)]
