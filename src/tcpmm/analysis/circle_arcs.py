"""The arrays of a CCW and a CW circle the diagnostics take, checked: full turns, or two
arcs over the same angles."""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .circle_model import is_full
from .circle_passes import MIN_ARC_DEG


def check_arc(angle, e, what, arc_ok=False):
    """The arrays of one circle, checked: one full turn or more, or with ``arc_ok`` an arc
    of :data:`tcpmm.analysis.circle_passes.MIN_ARC_DEG` or more [rad, m]."""
    angle, e = np.asarray(angle, float), np.asarray(e, float)
    if angle.shape != e.shape or angle.ndim != 1:
        raise InputError(f"the {what} circle needs angle and radial error of the same length "
                         f"(got {angle.shape} and {e.shape})")
    if angle.size < 100:
        raise InputError(f"the diagnostics need at least 100 samples of a circle; the {what} "
                         f"one has {angle.size}: sample faster or run the circle slower")
    if not (np.all(np.isfinite(angle)) and np.all(np.isfinite(e))):
        raise InputError(f"the {what} circle has non-finite angles or radial errors")
    span = np.degrees(abs(angle[-1] - angle[0]))
    if not (is_full(angle) or (arc_ok and span >= MIN_ARC_DEG)):
        raise InputError(f"the {what} circle covers {span:.0f} deg; the diagnostics need a "
                         "full turn, or two arcs over the same angles")
    if (angle[-1] > angle[0]) != (what in ("CCW", "ccw")):
        runs = "counter-clockwise" if angle[-1] > angle[0] else "clockwise"
        raise InputError(f"the {what} circle runs {runs}; give the CCW circle first")
    return angle, e


def same_angles(paths) -> None:
    """Refuse two arcs that do not cover the same angles (to within 10 % of either)."""
    lo = [np.mod(min(a[0], a[-1]), 2 * np.pi) for a, _ in paths]
    span = [abs(a[-1] - a[0]) for a, _ in paths]
    ends = [(lo[i], lo[i] + span[i]) for i in range(2)]
    shift = np.round((ends[0][0] - ends[1][0]) / (2 * np.pi)) * 2 * np.pi
    common = min(ends[0][1], ends[1][1] + shift) - max(ends[0][0], ends[1][0] + shift)
    if common < 0.9 * max(span):
        raise InputError(
            f"the CCW circle covers {np.degrees(span[0]):.0f} deg and the CW circle "
            f"{np.degrees(span[1]):.0f} deg of other angles; the diagnostics need a full "
            "turn, or two arcs over the same angles")
