"""Gates on the masses against the FRFs' static gains, for sweeps that do not travel.

Below its first axial mode a free feed axis is one rigid body: the motor answers the
current as its whole inertia does, ``G_M = omega_m/i_c ~ K_tc / (j omega J)`` with ``J =
J_m + J_L + M_t R^2`` at the motor, the scale follows the motor angle through the lead
(``G_T ~ R``) and the TCP follows the scale (``G_tcp ~ 1``). A column swapped or in the
wrong unit breaks one of these, and the fit then buries it in absurd masses (the excitation
swapped with the TCP gave a head mass of 0.24 kg for 403 kg). The column gates
(:mod:`~tcpmm.ident.gates.columns`) see it on a record that travels; these see it in the
frequency domain, also on a sweep that stands still:

* :func:`check_static_gains` -- ``G_T`` against the lead and ``G_tcp`` against one;
* :func:`check_mass_line` -- the identified rigid inertia against the mass line of
  ``G_M``, where friction does not hold the axis (:func:`friction_holds_sweep`): a fit that
  gave up the low band for its modes;
* :func:`check_tcp_gain` -- ``G_tcp`` against the fitted model's, where the model's is 1
  whatever its parameters: a TCP device that reads a share of the motion (its scaling, or
  a cosine error of its alignment with the axis) puts the whole record off by that share,
  which the fit cannot follow there and takes for the structure's dynamics above (bench
  R17 with its TCP scaled by 0.9: the predicted F10000 contour error 38 um off the
  measured). :func:`check_static_gains` allows a mode's 12 % against one; against the
  model, the reference machines' axes read within 0.2 % of one (:data:`TCP_GAIN_RANGE`),
  a TCP scaled by 0.9 reads 0.899-0.900.

All judge the good bins up to a third of the model's first mode (and 15 Hz), where a
mode moves a static gain by at most 12 %, and of them only those the sweep's excitation
reaches: elsewhere leakage can make noise look coherent, and a sweep that starts above the
band would be judged on it. :func:`unjudged_static_gains` says why no bin was left. The
TCP's gain against the model is read up to :data:`TCP_MODE_MARGIN` below the first mode,
since the model holds the mode; ``G_tcp`` is read from :data:`SWEEP_START_MARGIN` times the
sweep's lowest excited bin on (:func:`tcp_band`), above the bins its start lifts.
"""

from __future__ import annotations

import math
import warnings
from typing import NamedTuple

import numpy as np

from ...errors import InputWarning
from ..frf.excited import band_cover, excited_bins, mode_frequencies_hz
from .columns import RATIO_RANGE
from .finding import Finding
from .sanity import LOW_BAND_HZ, friction_holds_sweep

__all__ = ["MASS_RANGE", "MIN_BINS", "MODE_MARGIN", "SWEEP_START_MARGIN", "TCP_GAIN_RANGE",
           "TCP_GAIN_SIGMAS", "TCP_MODE_MARGIN", "TcpGain", "check_mass_line",
           "check_static_gains", "check_tcp_gain", "first_mode_hz", "low_band",
           "mass_findings", "tcp_band", "tcp_gain", "unjudged_static_gains"]

#: Ratio of the inertia the mass line of ``G_M`` shows to the identified one taken as
#: agreeing. On free axes of six machines of an independent simulator the two agree within
#: 8 %; the axis' modes and the friction's slope move the bottom octave by a few per cent,
#: a factor of two is a different machine [-].
MASS_RANGE = (0.5, 2.0)
#: The band judged ends this many times below the model's first mode: there a mode moves a
#: static gain by at most 1/(MODE_MARGIN^2 - 1), 12 %, inside the ranges above. A heavy
#: column whose first mode lies at 6 Hz would otherwise read as a swapped TCP column [-].
MODE_MARGIN = 3.0
#: Range of the measured over the modelled ``G_tcp`` below the first mode taken as a TCP
#: device reading the motion in full: the six reference machines depart from one by up
#: to 0.07 % (bench H's X), 16 bench machines with edited masses, head stiffness, damping
#: and friction by up to 0.6 %; on those a TCP scaled by 0.96 read 0.960-0.973 (the fitted
#: mode takes up part of it where the band is short) and by 1.04 read 1.037-1.044. 2 % is
#: a cosine error of 11 deg [-].
TCP_GAIN_RANGE = (0.98, 1.02)
#: A TCP gain is blamed only where it lies outside :data:`TCP_GAIN_RANGE` by more than this
#: many of its standard errors (:class:`TcpGain`): a band of few or scattered bins
#: extrapolated to zero frequency reads a gain it cannot vouch for [-].
TCP_GAIN_SIGMAS = 2.0
#: The TCP's gain is read against the fitted model, which holds the first mode, so its band
#: ends this many times below that mode, nearer than :data:`MODE_MARGIN`: on 16 bench
#: machines with edited masses, head stiffness, damping and friction, a TCP scaled by 1.04
#: read 1.037-1.044 with it, and the same machines' true TCP 1.000-1.006; at 1.3 the fitted
#: mode takes up part of the scaling (1.04 read 1.017) [-].
TCP_MODE_MARGIN = 1.5
#: ``G_tcp`` is read from this many times the lowest bin the sweep excites on: the sweep's
#: start lifts the lowest bins' ``|G_tcp|`` above the model's, by up to 18 % on machines
#: whose first mode lies at 9-17 Hz and by 1 % at most from this factor on; the same
#: machine swept from 2 Hz instead of 5 Hz read 0.999 at 4.4 Hz, where it had read 1.11 [-].
SWEEP_START_MARGIN = 1.5
#: Fewest bins a band must hold to be judged: the lowest bins of a sweep sit at the edge of
#: its excitation, where one bin alone can be off by a factor of two; the median of three
#: or more is not [-].
MIN_BINS = 3


def first_mode_hz(mechanics) -> float:
    """Natural frequency of the mechanics' lowest oscillating mode [Hz]; ``inf`` without
    one.

    Parameters
    ----------
    mechanics : AxisMechanics
        The axis' mechanics [SI].
    """
    modes = mode_frequencies_hz(mechanics)
    return float(modes[0]) if modes.size else math.inf


def low_band(frf, min_coherence: float, top_hz: float = LOW_BAND_HZ,
             excitation=None) -> np.ndarray:
    """Good bins up to ``top_hz`` (at most :data:`LOW_BAND_HZ`) that the excitation
    reaches (:func:`~tcpmm.ident.frf.excited.excited_bins`).

    Parameters
    ----------
    frf : FRF
        Any FRF of a sweep [-].
    min_coherence : float
        Bins with a lower coherence are not used [-].
    top_hz : float
        Highest frequency used [Hz].
    excitation : array_like, optional
        The sweep's excitation; ``None``: every bin counts as excited [A].

    Returns
    -------
    ndarray of bool
        Mask over the FRF's bins; all false when fewer than :data:`MIN_BINS` good bins are
        low enough [-].
    """
    f = np.asarray(frf.freq_hz, dtype=float)
    band = (np.asarray(frf.coherence) >= min_coherence) & (f <= min(top_hz, LOW_BAND_HZ))
    if excitation is not None:
        band &= excited_bins(frf, excitation)
    return band if np.count_nonzero(band) >= MIN_BINS else np.zeros(f.shape, dtype=bool)


def check_static_gains(axis: str, frfs: dict, R_L: float, source: str,
                       min_coherence: float, top_hz: float = LOW_BAND_HZ,
                       excitation=None) -> list[Finding]:
    """``G_T`` against the lead and ``G_tcp`` against one in the low band.

    Parameters
    ----------
    axis : str
        Axis name [-].
    frfs : dict
        The sweep's FRFs by name (``G_T`` [m/rad], ``G_tcp`` [-]) [-].
    R_L : float
        Lead over 2 pi [m/rad].
    source : str
        The sweep's file, for the message [-].
    min_coherence : float
        Bins with a lower coherence are not used [-].
    top_hz : float
        Highest frequency judged (:func:`low_band`; :func:`tcp_band` for ``G_tcp``) [Hz].
    excitation : array_like, optional
        The sweep's excitation: only the bins it reaches are judged [A].

    Returns
    -------
    list of Finding
        One per FRF whose static gain is outside :data:`RATIO_RANGE` of its expected value [-].
    """
    out = []
    for name, expected, cols, fix in (
            ("G_T", R_L, "scale_mm / motor_angle_rad",
             "check lead_mm in machine.yaml and that scale_mm and motor_angle_rad hold the "
             "scale and the motor angle"),
            ("G_tcp", 1.0, "tcp_mm / scale_mm",
             "check that tcp_mm and scale_mm hold the TCP and the scale, in mm; a column "
             "swapped with another reads as a gain far from one")):
        frf = frfs.get(name)
        if frf is None:
            continue
        pick = tcp_band if name == "G_tcp" else low_band
        low = pick(frf, min_coherence, top_hz, excitation)
        if not np.any(low):
            continue
        gain = float(np.median(np.abs(np.asarray(frf.H)[low]))) / expected
        if RATIO_RANGE[0] <= gain <= RATIO_RANGE[1]:
            continue
        out.append(Finding(axis, f"static gain of {name} over its rigid-body value", gain, "",
                           f"outside {RATIO_RANGE[0]:g} to {RATIO_RANGE[1]:g}: below the "
                           "first mode the axis moves as one body",
                           f"{source}, columns {cols}, "
                           f"{frf.freq_hz[low][0]:.3g}-{frf.freq_hz[low][-1]:.3g} Hz", fix))
    return out


def check_mass_line(axis: str, frf, mechanics, source: str, min_coherence: float,
                    top_hz: float = LOW_BAND_HZ, excitation=None) -> list[Finding]:
    """The identified rigid inertia against the mass line of ``G_M``.

    Parameters
    ----------
    axis : str
        Axis name [-].
    frf : FRF
        ``G_M = omega_m/i_c`` [rad/s/A].
    mechanics : AxisMechanics
        The identified mechanics [SI].
    source : str
        The sweep's file, for the message [-].
    min_coherence : float
        Bins with a lower coherence are not used [-].
    top_hz : float
        Highest frequency judged (:func:`low_band`) [Hz].
    excitation : array_like, optional
        The sweep's excitation: only the bins it reaches are judged [A].

    Returns
    -------
    list of Finding
        One when the ratio is outside :data:`MASS_RANGE`; none where friction holds the
        bottom of the band (:func:`~tcpmm.ident.gates.sanity.friction_holds_sweep`) [-].
    """
    low = low_band(frf, min_coherence, top_hz, excitation)
    if not np.any(low) or friction_holds_sweep(frf, min_coherence) is not None:
        return []
    H = np.asarray(frf.H)[low]
    m = mechanics
    j_fit = m.J_m + m.J_L + m.M_t * m.R_L**2
    w = 2.0 * math.pi * np.asarray(frf.freq_hz, dtype=float)[low]
    j_line = float(np.median(m.K_tc / (w * np.abs(H))))
    ratio = j_line / j_fit
    if MASS_RANGE[0] <= ratio <= MASS_RANGE[1]:
        return []
    m_line = (j_line - m.J_m - m.J_L) / m.R_L**2
    return [Finding(axis, "rigid inertia of the FRFs' mass line over the identified one",
                    ratio, "", f"outside {MASS_RANGE[0]:g} to {MASS_RANGE[1]:g}",
                    f"{source}, columns current_cmd_A and motor_angle_rad: the mass line "
                    f"gives a table mass of {m_line:.4g} kg, the fit {m.M_t:.4g} kg",
                    "check torque_constant_Nm_per_A in machine.yaml and the unit of "
                    "current_cmd_A (amperes)")]


class TcpGain(NamedTuple):
    """The TCP device's gain read against the model (:func:`tcp_gain`)."""

    #: Measured over modelled ``G_tcp`` at zero frequency [-].
    gain: float
    #: Its standard error, from the ratio's scatter about its fit [-].
    std: float
    #: The bins it was read on [Hz].
    freq_hz: np.ndarray


def tcp_band(frf, min_coherence: float, top_hz: float = LOW_BAND_HZ,
             excitation=None) -> np.ndarray:
    """The bins of :func:`low_band` (its arguments as it takes them) from
    :data:`SWEEP_START_MARGIN` times the lowest bin the excitation reaches on, the lowest
    coherent bin without an excitation; all false when fewer than :data:`MIN_BINS` are
    left [-]."""
    f = np.asarray(frf.freq_hz, dtype=float)
    band = low_band(frf, min_coherence, top_hz, excitation)
    if not np.any(band):
        return band
    band &= f >= _read_from_hz(frf, excitation, band)
    return band if np.count_nonzero(band) >= MIN_BINS else np.zeros(f.shape, dtype=bool)


def _read_from_hz(frf, excitation, band) -> float:
    """Where :func:`tcp_band` reads ``G_tcp`` from: :data:`SWEEP_START_MARGIN` times the
    lowest bin the excitation reaches, the lowest of ``band`` without one [Hz]."""
    f = np.asarray(frf.freq_hz, dtype=float)
    reached = excited_bins(frf, excitation) if excitation is not None else band
    return SWEEP_START_MARGIN * float(f[np.argmax(reached)])


def tcp_gain(frf, model, min_coherence: float, top_hz: float = LOW_BAND_HZ,
             excitation=None) -> TcpGain | None:
    """The measured ``G_tcp`` over the model's (``model(f)``) at zero frequency, read in
    the band :func:`tcp_band` judges; ``None`` where the band holds too few bins [-].

    The ratio is fitted as ``a + b f^2`` and ``a`` is the gain: a device's scale error is
    the same at every frequency, while a mode the model does not hold (a sweep cut short of
    the column's modes) raises the ratio towards it as ``f^2``. Bench C's Y swept to 10 Hz
    alone read 1.016 at 3.75 Hz to 1.109 at 10.5 Hz, 1.064 by the median: its device was
    blamed, and its readings were to be scaled by 0.94; at zero frequency they read 1.002.
    The other arguments as :func:`tcp_band` takes them."""
    band = tcp_band(frf, min_coherence, top_hz, excitation)
    if not np.any(band):
        return None
    f = np.asarray(frf.freq_hz, dtype=float)[band]
    ratio = np.abs(np.asarray(frf.H)[band] / model(f))
    design = np.column_stack([np.ones_like(f), f * f])
    coef, *_ = np.linalg.lstsq(design, ratio, rcond=None)
    resid = ratio - design @ coef
    var = float(resid @ resid) / (f.size - 2) * np.linalg.inv(design.T @ design)[0, 0]
    return TcpGain(float(coef[0]), math.sqrt(max(var, 0.0)), f)


def check_tcp_gain(axis: str, frf, model, source: str, min_coherence: float,
                   top_hz: float = LOW_BAND_HZ, excitation=None) -> list[Finding]:
    """``G_tcp`` against the fitted model's ``model(f)`` (:func:`tcp_gain`): one finding
    where their ratio lies outside :data:`TCP_GAIN_RANGE` by more than
    :data:`TCP_GAIN_SIGMAS` standard errors; the other arguments as
    :func:`check_static_gains` takes them [-]."""
    read = tcp_gain(frf, model, min_coherence, top_hz, excitation)
    if read is None:  # a device reading a share of the motion would pass unnoticed: say so
        warnings.warn(InputWarning(_unjudged_tcp(axis, frf, source, min_coherence, top_hz,
                                                 excitation)), stacklevel=2)
        return []
    gain, f, slack = read.gain, read.freq_hz, TCP_GAIN_SIGMAS * read.std
    lo, hi = TCP_GAIN_RANGE
    if lo - slack <= gain <= hi + slack:
        return []
    return [Finding(axis, "gain of the TCP device against the scale", gain, "",
                    f"outside {lo:g} to {hi:g} by more than {TCP_GAIN_SIGMAS:g} times its "
                    f"standard error {read.std:.2g}: below the first mode the tool follows "
                    "the table as one body, where the model's G_tcp is 1 whatever its "
                    "parameters",
                    f"{source}, columns tcp_mm / scale_mm, {f[0]:.3g}-{f[-1]:.3g} Hz",
                    f"check the TCP device's scaling and its alignment with the axis (a "
                    f"cosine error), or scale tcp_mm by {1.0 / gain:.4g}, and identify "
                    f"again: the fit takes the gain for the structure's dynamics")]


def _unjudged_tcp(axis: str, frf, source: str, min_coherence: float, top_hz: float,
                  excitation) -> str:
    """Why :func:`check_tcp_gain` read no gain, and the sweep that lets it [-]."""
    start = _read_from_hz(frf, excitation, low_band(frf, min_coherence, top_hz, excitation))
    return (f"{source}: axis {axis}: the TCP device's gain against the scale is not judged: "
            f"the FRF holds fewer than {MIN_BINS} coherent bins from {start:.3g} Hz "
            f"({SWEEP_START_MARGIN:g} times where the sweep starts) up to {top_hz:.3g} Hz (the "
            f"first mode over {TCP_MODE_MARGIN:g}), so a device that reads a share of the "
            "motion (its scaling, a cosine error) would be taken for the structure's "
            f"dynamics unsaid; a sweep from {top_hz / 3:.2g} Hz or lower lets it be judged")


def mass_findings(axis: str, frfs: dict, mechanics, source: str,
                  min_coherence: float, excitation=None, tcp_model=None) -> list[Finding]:
    """The gates of this module on one identified axis, in the band
    :data:`MODE_MARGIN` times below the model's first mode (the TCP's gain against the
    model :data:`TCP_MODE_MARGIN` times below it) [-].

    Parameters
    ----------
    axis : str
        Axis name [-].
    frfs : dict
        The sweep's FRFs by name [-].
    mechanics : AxisMechanics
        The identified mechanics [SI].
    source : str
        The sweep's file, for the message [-].
    min_coherence : float
        Bins with a lower coherence are not used [-].
    excitation : array_like, optional
        The sweep's excitation: only the bins it reaches are judged [A].
    tcp_model : callable, optional
        The fitted model's ``G_tcp`` at the frequencies given; without, the TCP's gain is
        not judged (:func:`check_tcp_gain`) [-].
    """
    mode_hz = first_mode_hz(mechanics)
    top = mode_hz / MODE_MARGIN
    out = check_static_gains(axis, frfs, mechanics.R_L, source, min_coherence, top, excitation)
    if "G_M" in frfs:
        out += check_mass_line(axis, frfs["G_M"], mechanics, source, min_coherence, top,
                               excitation)
    if "G_tcp" in frfs and tcp_model is not None:
        out += check_tcp_gain(axis, frfs["G_tcp"], tcp_model, source, min_coherence,
                              mode_hz / TCP_MODE_MARGIN, excitation)
    return out


def unjudged_static_gains(frfs: dict, excitation, min_coherence: float,
                          top_hz: float = LOW_BAND_HZ) -> str | None:
    """Why :func:`check_static_gains` could judge neither ``G_T`` nor ``G_tcp``: the sweep
    excites nothing low enough, or the FRFs' band starts above it; ``None`` where it judged
    one, has neither to judge, or lacks coherent bins only.

    Parameters
    ----------
    frfs : dict
        The sweep's FRFs by name [-].
    excitation : array_like
        The sweep's excitation [A].
    min_coherence : float
        Bins with a lower coherence are not used [-].
    top_hz : float
        Highest frequency judged (:func:`low_band`) [Hz].
    """
    named = [frfs[n] for n in ("G_T", "G_tcp") if n in frfs]
    if not named or any(np.any(low_band(f, min_coherence, top_hz, excitation)) for f in named):
        return None
    top, cover = min(top_hz, LOW_BAND_HZ), band_cover(named[0], excitation)
    what = "the FRFs' static gains, which need no fitted model, could not be checked"
    if cover is not None and cover.excited_hz[0] > top:
        start = cover.excited_hz[0]
        return (f"the sweep excites nothing up to {top:.3g} Hz (its excitation starts at "
                f"{start:.4g} Hz), so {what}: their bins there hold noise. Nor do the FRFs "
                f"show what lies below {start:.4g} Hz, such as the structure's modes, which "
                "is the likely cause; give a sweep covering those frequencies, from a few "
                "hertz up")
    if named[0].freq_hz[0] > top:
        return (f"the FRFs' band starts at {named[0].freq_hz[0]:.4g} Hz (--band), above the "
                f"{top:.3g} Hz up to which they are read, so {what}. Nor do the FRFs show "
                "what lies below it, such as the structure's modes, which is the likely "
                "cause; widen --band to start at a few hertz")
    return None  # excited bins in reach, too few of them coherent: the step says why
