"""What a tuning proposal says of its gains (:mod:`tcpmm.servo.tune`): a note per changed
gain with what limits it, and why an axis has the common position gain."""

from __future__ import annotations

import math

from .tunevelocity import SAME_GAIN


def gain_notes(before, after, limits) -> list[str]:
    """A note per changed gain saying why it changed and what limits it [-]."""
    notes = []
    if not math.isclose(after.K_vp, before.K_vp, rel_tol=SAME_GAIN):
        notes.append(f"K_vp {before.K_vp:.4g} -> {after.K_vp:.4g} A s/rad: the largest "
                     f"velocity gain meeting the margins, limited by {limits['K_vp']}")
    if not math.isclose(after.K_vi, before.K_vi, rel_tol=SAME_GAIN):
        notes.append(f"K_vi {before.K_vi:.4g} -> {after.K_vi:.4g} A/rad: the integral action "
                     "follows K_vp (PI corner at a quarter of the rigid-body crossover "
                     "K_vp K_tc / J)")
    if not math.isclose(after.K_pp, before.K_pp, rel_tol=SAME_GAIN):
        notes.append(f"K_pp {before.K_pp:.4g} -> {after.K_pp:.4g} 1/s: {limits['K_pp']}")
    return notes


def kpp_reason(name, lead, found, names) -> str:
    """Why an axis has the common position gain of the axes ``names`` set by axis ``lead``;
    None for none: no gain proposed meets the margins and stability on every axis [-]."""
    if lead is None:
        return ("kept: no position gain proposed meets the margins and the stability with the "
                "modes off by the tolerance on every axis (--mode-tolerance)")
    if len(names) == 1:
        return f"the largest position gain of this axis, limited by {found[lead][1]}"
    why = (f"the common position gain of axes {', '.join(names)} (equal gains keep a "
           "contour's shape: a circle round)")
    if name == lead:
        return f"{why}, set by this axis: {found[lead][1]}"
    return f"{why}, set by axis {lead}: {found[lead][1]}; this axis alone would take " \
           f"{found[name][0]:.4g} 1/s"
