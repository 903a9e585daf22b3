"""Where whole turns are taken out of a longer circle: symmetrically, unless that puts
their ends in a quadrant point's reversal window.

A circle of 1.25 turns from 45 deg (between quadrant points, as the analysis advises)
trimmed symmetrically to one turn started at 90 deg, on quadrant point B: its spike there
was not reported, and the warning advised starting between quadrant points, as the run
did. The turns are moved, within the run, to the place nearest the symmetric one whose
ends lie clear of every reversal window.
"""

from __future__ import annotations

import numpy as np

from .circle_spikes import AFTER_DEG, BEFORE_DEG

#: Margin kept from a reversal window's edges [deg]
MARGIN_DEG = 2.0


def turns_offset(ang, excess: float) -> float:
    """The angle the whole turns start after the start of the unwrapped angles ``ang``:
    ``excess`` (the symmetric place, half the angle beyond the turns), or the nearest
    within ``0 .. 2 excess`` whose start, and so whose end, is clear of the reversal
    windows (:data:`.circle_spikes.BEFORE_DEG` before each quadrant point to
    :data:`.circle_spikes.AFTER_DEG` after it, along the travel) [rad]."""
    if excess <= 0.0:
        return 0.0
    s = 1.0 if ang[-1] >= ang[0] else -1.0
    start = s * np.degrees(ang[0])  # the angle along the travel
    offs = np.linspace(0.0, 2.0 * excess, 721)
    phase = (start + np.degrees(offs)) % 90.0
    clear = (phase > AFTER_DEG[1] + MARGIN_DEG) & (phase < 90.0 + BEFORE_DEG[0] - MARGIN_DEG)
    on = np.flatnonzero(clear)
    if on.size == 0 or clear[360]:
        return excess
    return float(offs[on[np.argmin(np.abs(on - 360))]])
