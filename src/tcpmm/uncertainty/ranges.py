"""What the identification data of an axis leave open, and the range each open quantity may
lie in.

A fit's standard deviation counts the noise of the data it was fitted to; it says nothing of
a quantity whose signal never rose above the sensor's resolution, or that rests on a motion
the records never made. Such a quantity is *open*: a prediction takes it over its whole
plausible range (:class:`tcpmm.model.OpenRange`), never over a small deviation.
"""

from __future__ import annotations

import math

import numpy as np

from ..ident.frf.excited import EXCITED_SHARE
from ..ident.friction.nutstiffness import RESOLUTION_STEPS
from ..ident.physical.structure import STIFFNESS_FLOOR
from ..ident.physical.uncertainty import FIT_DEVIATION_SCALE
from ..model import OpenRange
from .driveranges import (
    controller_mismatch,
    drive_undetermined,
    feedback_contradicted,
    position_gain_contradicted,
)
from .frictionranges import play_open, static_open

__all__ = [
    "BED_RANGE",
    "COLUMN_RANGE",
    "DAMPING_RANGE",
    "MECHANICS_RANGE",
    "MODE_DAMPING",
    "MODE_STRUCTURE",
    "PLATEAU_SHARE_REL_SD",
    "PRESLIDING_RANGE_M",
    "SCALE_STEPS",
    "SHARE_RANGE",
    "STRUCTURE_ZETA_RANGE",
    "mode_damping_bounds",
    "open_ranges",
    "structure_of",
]

#: A deflection between encoder and scale of fewer scale steps than this rests on the
#: sensor's resolution: its rounding, not the nut, shapes what the runs see [-].
SCALE_STEPS = RESOLUTION_STEPS
#: Range of an open guideway share: preloaded guides and sealed nuts span nearly all of it [-].
SHARE_RANGE = (0.02, 0.98)
#: Range of an open pre-sliding distance: that of rolling guides and ball-screw nuts [m].
PRESLIDING_RANGE_M = (0.2e-6, 10e-6)
#: Factor on the table mass and the structure behind it where the sweep's FRFs are not
#: those of the linear mechanics (friction held the axis) [-].
MECHANICS_RANGE = (0.7, 1.3)
#: Stiffness of a TCP structure no TCP device measured, from a slender column's to the rigid
#: one the fit takes (1 to 1000 N/um) [N/m]; with it a head of :data:`COLUMN_MASS_KG`
#: damped at :data:`COLUMN_ZETA`, as machining centres' columns are: head modes of 9 to
#: 290 Hz. Light heads on slender columns have modes in the tens of Hz at 2-10 N/um (an
#: independent simulator's machines: 2.0 N/um under 45 kg, 33.9 Hz), which a range from
#: 10 N/um, a 29 Hz mode at that mass, left out.
COLUMN_RANGE = (1e6, 1e9)
COLUMN_MASS_KG, COLUMN_ZETA = 300.0, 0.05
#: Stiffness to ground of a bed whose mass or stiffness the FRFs do not determine, from a
#: bed on soft levelling elements to one grouted on its foundation (100 to 10000 N/um)
#: [N/m]; with it a bed of :data:`BED_MASS_KG` damped at :data:`BED_ZETA`: bed modes of
#: 40-400 Hz, around those of the benches (48-190 Hz, damping ratios 0.04-0.05).
BED_RANGE = (STIFFNESS_FLOOR["b"], 1e10)
BED_MASS_KG, BED_ZETA = 1500.0, 0.05
#: Damping ratio of a structural mode whose damping the sweep leaves undetermined (a sweep
#: whose excitation starts above the mode sees only its mass or stiffness line, where the
#: damping barely shows): the range machine tools' bolted and guided structures span [-].
STRUCTURE_ZETA_RANGE = (0.01, 0.1)
#: Per open structural damping, the damping, mass and stiffness of its mode [-].
MODE_DAMPING = {"column_damping": ("C_h", "M_h", "K_h"), "bed_damping": ("C_b", "M_b", "K_b")}
#: Per open structure, the mass and stiffness whose mode it stands for [-].
MODE_STRUCTURE = {q: MODE_DAMPING[f"{q}_damping"][1:] for q in ("column", "bed")}
#: Factor on the axial modes' damping where a sweep crossed the nut's lost motion and the
#: fit took the nut as linear: the play's impacts and the friction inside it dissipate
#: energy a linear damper is fitted to, up to doubling it [-].
DAMPING_RANGE = (0.5, 2.0)
#: Lowest factor the play may put on the nut's stiffness at an axial mode of a sweep fitted
#: as linear before the structure and the axial damping are open: beyond 2 % softening the
#: fitted modes take up the play's describing function (validation/calibration.md) [-].
PLAY_GAIN_OPEN = 0.98
#: Largest deviation of the plateaus' own guideway share, relative to it, at which it bounds
#: the share of a sweep that friction held from below. Beyond it the plateaus barely tell
#: the guideway's force from the screw's (docs/validation/calibration.md) [-].
PLATEAU_SHARE_REL_SD = 0.25
#: Least difference between the travelling sweep's share and the plateaus' own that opens
#: the share (the benches' agree within 0.08) [-].
SHARE_DISAGREE = 0.1

_SETTLE_SHARE = ("a sweep with a TCP device while the axis travels at constant speed, or a "
                 "scale at least ten times finer than the nut's deflection")
_SETTLE_PRESLIDING = ("friction runs with slow reversals (0.5 mm/s or less) recorded at 1 kHz "
                      "or more")
_SETTLE_CROSSED = ("a sweep while the axis travels at constant speed (the guideway friction "
                   "holds the nut on one flank), or a larger sweep amplitude")
_SETTLE_MODES = ("a sweep whose excitation covers the structure's modes, from a few hertz "
                 "up, with a TCP device")
_SETTLE_HOLD = ("a sweep while the axis travels at constant speed, or a larger sweep "
                "amplitude (within the current limit)")


def _friction_total(a) -> float:
    """Coulomb level of the friction runs, mean of both directions [N]; 0 without."""
    if a.friction is None:
        return 0.0
    v = dict(zip(a.friction.names, a.friction.values, strict=True))
    return 0.5 * (abs(v.get("Fc+", 0.0)) + abs(v.get("Fc-", 0.0)))


def _reversal_step(a, share: float, sd: float) -> float:
    """The jump of the nut's deflection at a reversal that a share is read from, with the
    share two deviations higher [m]."""
    sd = sd if math.isfinite(sd) else 1.0
    return 2.0 * min(share + 2.0 * sd, 1.0) * _friction_total(a) / a.axis.mechanics.K_t


def _held_sweep_share(a) -> tuple[str, float, float]:
    """The range of a share read from a sweep that friction held: from the lower of it and
    the plateaus' own share, two deviations below each (the plateaus' scaled to their real
    error, :data:`~tcpmm.ident.physical.uncertainty.FIT_DEVIATION_SCALE`), to the top of
    :data:`SHARE_RANGE`. A held sweep reads the guideway's share low, and the plateaus can
    read it low as well where the guideway carries most of the friction, so neither bounds
    it from above. The plateaus count where they read their share above the scale's rounding
    and within :data:`PLATEAU_SHARE_REL_SD` of it; else the whole range."""
    split = a.friction_split
    why = ("the share read from the travelling sweep rests on steady sliding, and friction "
           "held the axis during the sweep")
    p, p_sd = split.plateau_share, split.plateau_share_std
    res = a.axis.sensors.scale_resolution
    if not (math.isfinite(p) and math.isfinite(p_sd)) or (
            res > 0.0 and _reversal_step(a, p, p_sd) < SCALE_STEPS * res):
        return why, *SHARE_RANGE
    if p_sd > PLATEAU_SHARE_REL_SD * p:
        return (f"{why}; the friction runs' plateaus read {p:.3f} +- {p_sd:.3f}, too loose "
                "to bound it", *SHARE_RANGE)
    p_sd *= FIT_DEVIATION_SCALE.get("plateau_share", 1.0)
    s = split.guideway_share
    s_sd = split.guideway_share_std if math.isfinite(split.guideway_share_std) else 0.0
    lo = max(SHARE_RANGE[0], min(s - 2.0 * s_sd, p - 2.0 * p_sd))
    return (f"{why}; taken from the lower of it ({s:.3f}) and the friction runs' plateaus' "
            f"({p:.3f}) up, both of which read a guideway that carries most of the friction "
            "low", lo, SHARE_RANGE[1])


def _sweep_against_plateaus(split) -> tuple[str, float, float] | None:
    """The range between the travelling sweep's share and the friction runs' plateaus' own,
    two deviations beyond each, where the two disagree by more than
    :data:`SHARE_DISAGREE` and three deviations together (the plateaus' scaled to their
    real error); ``None`` where they agree or the plateaus give none. The sweep reads the
    share from the mean of scale minus TCP, so a TCP device zeroed apart from the scale,
    or drifting, moves it by its offset over the column's compliance (bench C: 0.25 per
    micrometre) and nothing in the sweep tells [-]."""
    p, p_sd = split.plateau_share, split.plateau_share_std
    s, s_sd = split.guideway_share, split.guideway_share_std
    if not all(math.isfinite(v) for v in (p, p_sd, s, s_sd)):
        return None
    p_sd *= FIT_DEVIATION_SCALE.get("plateau_share", 1.0)
    if abs(s - p) <= max(SHARE_DISAGREE, 3.0 * math.hypot(s_sd, p_sd)):
        return None
    lo = max(SHARE_RANGE[0], min(s - 2.0 * s_sd, p - 2.0 * p_sd))
    hi = min(SHARE_RANGE[1], max(s + 2.0 * s_sd, p + 2.0 * p_sd))
    return (f"the travelling sweep's TCP deflection reads a guideway share of {s:.3f} and "
            f"the friction runs' plateaus {p:.3f}: a TCP device zeroed apart from the scale, "
            "or drifting, moves the first", lo, hi)


def _share_open(a) -> tuple[str, float, float] | None:
    """Why the guideway share is open and its range, or ``None`` when the data determine
    it."""
    split = a.friction_split
    if split is None or split.source == "given":
        return None
    if split.source == "prior":
        return ("the friction runs do not determine the guideway share", *SHARE_RANGE)
    if split.source == "sweep" and a.friction_hold is not None:
        return _held_sweep_share(a)
    if split.source == "sweep":
        return _sweep_against_plateaus(split)
    if split.source != "data":
        return None
    res = a.axis.sensors.scale_resolution
    step = _reversal_step(a, split.guideway_share, split.guideway_share_std)
    if res > 0.0 and step < SCALE_STEPS * res:
        return (f"the nut's deflection at a reversal that the share was read from "
                f"({step * 1e6:.2f} um, with the share two deviations higher) is under "
                f"{SCALE_STEPS:g} steps of the {res * 1e6:g} um scale: the share rests on the "
                "scale's rounding", *SHARE_RANGE)
    return None


def _nonlinear_sweep(a) -> list[OpenRange]:
    """The structure (and with play the axial damping) as open ranges where the sweep's
    FRFs are not those of the linear mechanics: friction held the axis, or the sweep
    crossed the nut's lost motion and the fit kept took the nut as linear."""
    gain = getattr(a.physical, "crossed_play_gain", None)
    crossed = gain is not None and gain < PLAY_GAIN_OPEN
    held = a.friction_hold is not None
    standing = not held and getattr(a, "sweep_standing", False)  # sticks, slips, pre-slides
    causes = []
    if held:
        causes.append("friction held the axis during the sweep")
    if standing:
        causes.append("the sweep did not travel (torque mode, or loops holding one place)")
    if crossed:
        causes.append("the sweep crossed the nut's lost motion")
    if not causes:
        return []
    why = " and ".join(causes) + ": its FRFs are not those of the linear mechanics"
    settle = _SETTLE_HOLD if held or standing else _SETTLE_CROSSED
    out = [OpenRange(quantity="mechanics", low=MECHANICS_RANGE[0], high=MECHANICS_RANGE[1],
                     cause=why, settle=settle)]
    if crossed:
        out.append(OpenRange(quantity="damping", low=DAMPING_RANGE[0], high=DAMPING_RANGE[1],
                             cause=why, settle=_SETTLE_CROSSED))
    return out


def _lowest_excited_hz(a) -> float:
    """The lowest frequency at which the sweep's excitation has more than
    :data:`EXCITED_SHARE` of its peak power (Welch's estimate); 0 without the record [Hz]."""
    from scipy import signal

    rec = getattr(a, "record", None)
    r = None if rec is None else getattr(rec, "excitation_A", None)
    if r is None or np.size(r) < 16:
        return 0.0
    r = np.asarray(r, dtype=float)
    fs_hz = 1.0 / float(np.median(np.diff(rec.time_s)))
    f, p = signal.welch(r - r.mean(), fs=fs_hz, nperseg=min(r.size, 1 << 15))
    k = np.flatnonzero((p > EXCITED_SHARE * p.max()) & (f > 0.0))
    return float(f[k[0]]) if k.size else 0.0


def _structure_damping(a) -> list[OpenRange]:
    """The damping of each structural mode the FRFs do not see, as an open range of its
    damping ratio (:data:`STRUCTURE_ZETA_RANGE`): a mode whose half-power band, at the
    highest of those ratios, starts below the lowest frequency the sweep excites shows
    only its mass or stiffness line, and a damping the fit leaves undetermined. Its
    fitted value says nothing (bench C cut to 45-1000 Hz: 0.26 of the truth, or the fit's
    bound near zero, with deviations of a few per cent), and an undamped mode rings
    through every circle."""
    out = []
    low_hz = _lowest_excited_hz(a)
    for q, (c, mass, k) in MODE_DAMPING.items():
        m = a.axis.mechanics
        f_hz = (math.sqrt(getattr(m, k) / getattr(m, mass)) / (2.0 * math.pi)
                if low_hz > 0.0 else math.inf)
        if f_hz * (1.0 - STRUCTURE_ZETA_RANGE[1]) < low_hz:
            why = (f"its mode of {mass} on {k} ({f_hz:.0f} Hz) lies below the lowest "
                   f"frequency the sweep excites ({low_hz:.0f} Hz)")
        elif c in getattr(a.physical, "undetermined", ()):
            why = "the FRFs do not determine it"
        else:
            continue
        out.append(OpenRange(quantity=q, low=STRUCTURE_ZETA_RANGE[0],
                             high=STRUCTURE_ZETA_RANGE[1], cause=f"{c} open: {why}",
                             settle=_SETTLE_MODES))
    return out


def mode_damping_bounds(mechanics, damping: str) -> tuple[float, float]:
    """The dampings of :data:`STRUCTURE_ZETA_RANGE` of the structural mode whose damping is
    ``damping`` (``C_h`` or ``C_b``, :data:`MODE_DAMPING`) [N s/m]."""
    [(mass, k)] = [(m_, k_) for c, m_, k_ in MODE_DAMPING.values() if c == damping]
    critical = 2.0 * math.sqrt(getattr(mechanics, mass) * getattr(mechanics, k))
    return STRUCTURE_ZETA_RANGE[0] * critical, STRUCTURE_ZETA_RANGE[1] * critical


#: Per open structure: its stiffness range [N/m], typical mass [kg] and damping ratio [-].
_TYPICAL = {"column": (COLUMN_RANGE, COLUMN_MASS_KG, COLUMN_ZETA),
            "bed": (BED_RANGE, BED_MASS_KG, BED_ZETA)}


def structure_of(quantity: str, stiffness: float, mass_kg: float | None = None) -> dict:
    """The parameters of an open ``column`` or ``bed`` (:data:`MODE_STRUCTURE`) of that
    stiffness: a head of ``mass_kg``, or of :data:`COLUMN_MASS_KG` where the fit does not
    determine it, damped at :data:`COLUMN_ZETA`; or a bed of ``mass_kg`` or
    :data:`BED_MASS_KG` damped at :data:`BED_ZETA`, on it [SI]."""
    c, mass, k = MODE_DAMPING[f"{quantity}_damping"]
    _, kg, zeta = _TYPICAL[quantity]
    kg = kg if mass_kg is None else mass_kg
    return {mass: kg, k: stiffness, c: 2.0 * zeta * math.sqrt(stiffness * kg)}


def _structure_undetermined(a) -> list[OpenRange]:
    """The head on its column and the bed as open ranges of their stiffness, each with the
    mass the fit determines or else a typical one, and a typical damping
    (:data:`COLUMN_RANGE`, :data:`BED_RANGE`), where the FRFs do
    not determine the mass or the stiffness: the fit of ``G_tcp`` held its ratio to the
    table mass at a bound, or its deviation is above half its value. Such a value has no
    deviation to move it by, and the mode it places may lie anywhere the sweep did not
    resolve; left out, the interval would hold it exact."""
    und = getattr(a.physical, "undetermined", ())
    out = []
    for q, (mass, k) in MODE_STRUCTURE.items():
        which = [p for p in (mass, k) if p in und]
        # without a TCP device the column is open whole already (open_ranges)
        if not which or (q == "column" and "G_tcp" not in a.frfs):
            continue
        (lo, hi), kg, zeta = _TYPICAL[q]
        # a mode below the band shows its mass line: the mass fitted is kept
        kg, how = ((kg, "taken as") if mass in which else
                   (getattr(a.axis.mechanics, mass), "the fitted"))
        out.append(OpenRange(
            quantity=q, low=lo, high=hi,
            cause=(f"{' and '.join(which)} open: the FRFs do not determine "
                   f"{'them' if len(which) > 1 else 'it'} (held at a bound of the fit, or "
                   f"a deviation above 50 %); {how} {kg:.0f} kg on {lo * 1e-6:g} to "
                   f"{hi * 1e-6:g} N/um, damping ratio {zeta:g}"),
            settle=_SETTLE_MODES))
    return out


def open_ranges(a) -> tuple[OpenRange, ...]:
    """The quantities an identified axis leaves open, each with its range, cause and the
    measurement that would settle it.

    Parameters
    ----------
    a : AxisIdentification
        The identified axis, with its friction split and pre-sliding fit [-].

    Returns
    -------
    tuple of OpenRange
        Open quantities; empty where the data determine everything they are asked [-].
    """
    out = []
    share = _share_open(a)
    if share is not None and a.axis.friction is not None:
        why, lo, hi = share
        out.append(OpenRange(quantity="guideway_share", low=lo, high=hi, cause=why,
                             settle=_SETTLE_SHARE))
    out += [r for r in (play_open(a), static_open(a)) if r is not None]
    fit = a.presliding_fit
    if fit is not None and not fit.determined and a.axis.friction is not None:
        out.append(OpenRange(quantity="presliding", low=PRESLIDING_RANGE_M[0],
                             high=PRESLIDING_RANGE_M[1],
                             cause=f"pre-sliding assumed: {fit.reason}",
                             settle=_SETTLE_PRESLIDING))
    out += _nonlinear_sweep(a)
    out += controller_mismatch(a) + feedback_contradicted(a) + position_gain_contradicted(a)
    out += _structure_damping(a)
    out += _structure_undetermined(a)
    out += drive_undetermined(a)
    if "G_tcp" not in a.frfs:
        out.append(OpenRange(quantity="column", low=COLUMN_RANGE[0], high=COLUMN_RANGE[1],
                             cause="no TCP device: the structure between the scale and the "
                                   "tool is not measured; the fit takes it rigid",
                             settle="a sweep with a TCP device (a laser or a ballbar at the "
                                    "tool)"))
    # the runs fix the steady viscous torque on the motor side, B_m + B_L: only its
    # division is open, all of it: the sweep's own B_m, which the model dropped, is no
    # bound (it came out up to 30 times too large, or at 0)
    mech = a.axis.mechanics
    if a.physical.mechanics.B_m > 0.0 and mech.B_m == 0.0 and mech.B_L > 0.0:
        out.append(OpenRange(quantity="B_m", low=0.0, high=mech.B_L,
                             cause="the FRFs do not separate the motor-bearing damping from "
                                   "the rest of the motor side's steady viscous torque, which "
                                   "the friction runs give; taken as 0",
                             settle="a run-down of the motor decoupled from the screw"))
    return tuple(out)
