"""Where Table 2's raw spikes hide a difference that the spikes after the terms show.

The raw spike ``e - b`` (the paper's) is the extreme of the radial error in a window after
the reversal less the level before it. Where another term slopes across the window (a
servo mismatch's ellipse crosses the quadrant points at its steepest), the extreme lies at
the window's end, on that slope, in the measured and the predicted circle alike: a 5 um
spike the prediction misses read 0.01 um of difference, where the spikes after the pair's
terms (:meth:`.circular.SensorCircle.spikes_after_terms`) differ by 5.06 um.
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from ..errors import InputWarning
from .circle_spikes import QUADRANTS

#: Least excess of the difference after the terms over the raw one that is said, beside
#: the spikes' own 95 % uncertainty: the sensors' noise when a circle is compared with
#: itself, some tenths of a micrometre [m].
HIDDEN_MIN_M = 0.5e-6
#: The most one run's sample period may exceed the other's, as a ratio, unsaid [-].
PERIOD_RATIO = 1.5


def warn_sampling(measured, predicted) -> None:
    """Warn (:class:`InputWarning`) where the measured and the predicted run are logged
    at sample periods more than :data:`PERIOD_RATIO` apart: a raw spike is the extreme of
    its window's samples, which a sparser log reads lower on a sharp peak, and the point
    by point difference interpolates between the sparser samples. One simulated circle
    logged every 4 ms against itself every 1 ms read spikes up to 0.76 um and points up
    to 0.70 um apart at the TCP, under no word.

    Parameters
    ----------
    measured, predicted : Run
        The runs compared [SI].
    """
    pm, pp = (float(np.median(np.diff(r.time_s))) for r in (measured, predicted))
    if not max(pm, pp) > PERIOD_RATIO * min(pm, pp):
        return
    warnings.warn(InputWarning(
        f"the measured run is logged every {pm * 1e3:.3g} ms, the predicted every "
        f"{pp * 1e3:.3g} ms: a reversal spike is the extreme of its window's samples, "
        "which the sparser log reads lower on a sharp peak, and the point-by-point "
        "difference interpolates between its samples, so part of each difference is the "
        "logging's; simulate at the measured run's period (tcpmm simulate MODEL --command "
        f"MEASURED.csv --record-period-s {pm:.4g})"), stacklevel=3)


def hidden_spikes(sm, sp, direction: str, sensor: str) -> list[dict]:
    """Per quadrant point where the measured - predicted spike after the terms of one
    sensor's circles exceeds the raw one in size by more than both spikes' 95 %
    uncertainty and :data:`HIDDEN_MIN_M`: ``direction``, ``sensor``, ``point``,
    ``raw_um``, ``after_terms_um`` and ``u95_um`` [um].

    Parameters
    ----------
    sm, sp : SensorCircle
        The measured and the predicted circle of ``sensor`` [-].
    direction, sensor : str
        Their direction and sensor, for the rows [-].
    """
    out = []
    am, ap = sm.spikes_after_terms(), sp.spikes_after_terms()
    um, up = sm.spike_uncertainty(), sp.spike_uncertainty()
    for q in QUADRANTS:
        raw, after = sm.spikes[q] - sp.spikes[q], am[q] - ap[q]
        u = math.hypot(um[q], up[q])
        if not all(map(math.isfinite, (raw, after, u))):
            continue
        if abs(after) - abs(raw) > max(u, HIDDEN_MIN_M):
            out.append({"direction": direction.upper(), "sensor": sensor, "point": q,
                        "raw_um": raw * 1e6, "after_terms_um": after * 1e6,
                        "u95_um": u * 1e6})
    return out


def hidden_notes(hidden: list) -> list[str]:
    """One sentence per sensor on the spike differences the raw figures hide
    (:func:`hidden_spikes`) [-]."""
    out = []
    for sensor in dict.fromkeys(h["sensor"] for h in hidden):
        pts = ", ".join(f"{h['direction']} {h['point']} {h['after_terms_um']:+.2f} ± "
                        f"{h['u95_um']:.2f} (raw {h['raw_um']:+.2f})"
                        for h in hidden if h["sensor"] == sensor)
        out.append(f"{sensor}: measured - predicted after the terms reads {pts} um: another "
                   "term slopes across the reversals' windows (a servo mismatch's ellipse, "
                   "say), the raw extremes lie on it in both runs, and the raw differences "
                   "hide where measurement and prediction part there")
    return out
