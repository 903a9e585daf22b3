"""Whether a CCW and a CW circle are a pair of one test: a pair's terms hold at one feed."""

from __future__ import annotations

import numpy as np

#: Largest relative difference of the steady angular speeds of a CCW and a CW circle that
#: still form a pair: a pair's terms (the servo mismatch's angle, the hysteresis, G(b))
#: hold at one feed, and the same program's circles run at the same steady feed to a
#: hundredth of a per cent; circles 2 % apart read a servo mismatch angle 1 % off the
#: slower one's, with a ± of 0.00 [-].
PAIR_SPEED_TOL = 0.005


def other_feeds(ccw, cw, radius_m: float) -> str | None:
    """Why the passes ``ccw`` and ``cw`` (:class:`.circle_passes.CirclePass`) are no pair
    of one test, in words; None where they run at one feed (within
    :data:`PAIR_SPEED_TOL`, or a speed unknown) [-].

    Parameters
    ----------
    ccw, cw : CirclePass
        The two circles [-].
    radius_m : float
        The nominal radius, for the feeds in words [m].
    """
    a, b = abs(ccw.feed_rate_rad_s), abs(cw.feed_rate_rad_s)
    if not (np.isfinite(a) and np.isfinite(b)) or abs(a - b) <= PAIR_SPEED_TOL * max(a, b):
        return None
    feeds = [f"F{w * radius_m * 60e3:.0f}" for w in (a, b)]
    return (f"the CCW circle runs at {feeds[0]} ({a:.4g} rad/s) and the CW circle at "
            f"{feeds[1]} ({b:.4g} rad/s) at their steady feeds: a pair's terms (the servo "
            "mismatch's angle, the hysteresis, G(b)) hold at one feed")


def command_radius(ccw, cw, radius_m: float) -> float:
    """The radius the commands of ``ccw`` and ``cw`` (:class:`.circle_passes.CirclePass`)
    run on: the nominal one moved by their mean radial deviation (a controller's filter
    pulls a circle in, a radius offset moves it); the nominal one where neither has a
    command. The errors of an axis' position that scale with it (a squareness, a scale
    mismatch, a lag's angle) make radial errors in proportion to it [m]."""
    d = [p.command_radial_deviation for p in (ccw, cw)
         if np.isfinite(p.command_radial_deviation)]
    return radius_m + (sum(d) / len(d) if d else 0.0)
