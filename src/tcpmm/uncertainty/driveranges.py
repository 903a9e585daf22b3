"""Open ranges of an identified axis's drive where its data contradict what the bundle
declares, or leave a drive parameter a guess (:func:`tcpmm.uncertainty.ranges.open_ranges`).
"""

from __future__ import annotations

import math

from ..ident.physical.loop_timing import GAIN_RANGE, GAIN_WARN
from ..mechanics.lumped import RANGES
from ..model import OpenRange


def controller_mismatch(a) -> list[OpenRange]:
    """The record's time base as an open range where the sweep's controller output is
    ``g`` times what the declared gains give (:mod:`tcpmm.ident.physical.loop_timing`):
    a time base off by ``g`` gives every mass and inertia ``g^2`` times its own, gains or
    a lead off leave them, and the sweep does not tell which; its true time is 1 to
    ``1/g`` times the stamped one. A time stamped at 8 kHz for 10 kHz gave the masses
    56 % too large, read as firm."""
    t = getattr(a, "loop_timing", None)
    if t is None or (t.determined and abs(t.gain - 1.0) <= GAIN_WARN):
        return []
    g = t.gain if t.determined and math.isfinite(t.gain) and t.gain > 0 else (
        GAIN_RANGE[0] if math.isfinite(t.gain) and t.gain < 1.0 else GAIN_RANGE[1])
    return [OpenRange(quantity="time_base", low=min(1.0, 1.0 / g), high=max(1.0, 1.0 / g),
                      cause=(f"the controller output in the sweep is {t.gain:.3g} times what "
                             "the declared velocity-loop gains give: the record's time base, "
                             "or the gains or the lead in machine.yaml, are not the drive's; "
                             "a time base off scales the masses and inertias with its "
                             "square"),
                      settle="the record's true sample rate, and the drive's gains and lead "
                             "in machine.yaml")]


#: The drive parameters an open range may hold by name, at its values
#: (:class:`tcpmm.model.OpenRange`) [-].
DRIVE = ("J_m", "J_L", "B_L", "K_L", "K_t", "M_t")
#: Range of a drive parameter the FRFs do not determine, as factors on the fit's value: the
#: fit is started from the bundle's and typical values, and its guess lies within a few of
#: them [-].
GUESS_RANGE = (0.5, 2.0)


def drive_undetermined(a) -> list[OpenRange]:
    """Each drive parameter the FRFs do not determine (relative deviation above 50 %)
    whose fitted value the model keeps, as an open range of :data:`GUESS_RANGE` about it.
    Such a value has no deviation to move it by: a sweep cut to half its length left
    J_m, J_L, K_L and K_t 54-690 % off, and the verdict firm."""
    und = set(getattr(a.physical, "undetermined", ()))
    model, fit = a.axis.mechanics, getattr(a.physical, "mechanics", None)
    out = []
    for p in DRIVE:
        v = getattr(model, p, None)
        if p not in und or v is None or v != getattr(fit, p, None) or not v > 0.0:
            continue
        lo, hi = RANGES.get(p, (0.0, math.inf))[:2]  # within what the model takes
        out.append(OpenRange(
            quantity=p, low=max(GUESS_RANGE[0] * v, lo), high=min(GUESS_RANGE[1] * v, hi),
            cause=f"the FRFs do not determine {p} (relative standard deviation above 50 %): "
                  "the model's value is the fit's guess",
            settle="a sweep over the whole band of the drive's modes (long enough, with the "
                   "excitation reaching above the axial mode)"))
    return out


def feedback_contradicted(a) -> list[OpenRange]:
    """The sensor the position loop closes on as an open range where the sweep's
    controller output reads as a loop closed on the other one
    (:meth:`~tcpmm.ident.physical.loop_timing.LoopTiming.other_sensor_reads_better`): the
    model closes it where the bundle says, which moves a circle's TCP spikes by up to
    20 um, and the warning alone left the verdict firm."""
    t = getattr(a, "loop_timing", None)
    if t is None or not t.other_sensor_reads_better():
        return []
    said = a.axis.servo.position_feedback
    return [OpenRange(quantity="position_feedback", low=0.0, high=1.0,
                      cause=f"the sweep reads as a position loop closed on the other sensor, "
                            f"not on the {said} the bundle declares (relative residual "
                            f"{t.other_feedback_residual:.3f} against {t.residual:.3f})",
                      settle="the drive's parameters: which sensor its position loop closes "
                             "on (Sinumerik: whether a direct measuring system is active)")]


#: Widest range of an open position gain, as factors on the declared one: a sweep taken
#: with the position loop open reads a gain near zero, which says nothing of the drive's
#: own [-].
POSITION_GAIN_RANGE = (0.5, 2.0)


def position_gain_contradicted(a) -> list[OpenRange]:
    """The position-loop gain as an open range from the declared one to the one the sweep
    reads (:meth:`~tcpmm.ident.physical.loop_timing.LoopTiming.position_contradicted`),
    within :data:`POSITION_GAIN_RANGE` of the declared: machine C declared at 45 1/s for its
    drive's 30 had its circle's spikes predicted 240 um off, read as firm."""
    t = getattr(a, "loop_timing", None)
    if t is None or not t.position_contradicted(a.axis.servo.K_pp):
        return []
    declared = a.axis.servo.K_pp
    read = min(max(t.position_gain, POSITION_GAIN_RANGE[0] * declared),
               POSITION_GAIN_RANGE[1] * declared)
    return [OpenRange(quantity="position_gain", low=min(read, declared),
                      high=max(read, declared),
                      cause=("the sweep's controller output "
                             + t.position_words(declared, "the bundle")),
                      settle="the drive's position-loop gain (Sinumerik: MD32200 "
                             "POSCTRL_GAIN, in (m/min)/mm: 1 is 16.7 1/s), and a sweep "
                             "taken with the position loop closed")]
