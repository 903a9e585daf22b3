"""The paper's Section 3.3 circular test: the command that the demo, the what-if sweeps
and the servo tuning all run on the machine."""

from __future__ import annotations

import math

from ..path import circle_command
from ..path.command import concatenate
from ..units import feed_mm_per_min_to_m_per_s, mm_to_m

RADIUS_MM = 35.0
FEED_MM_PER_MIN = 5000.0
#: The circle starts between quadrant points, so that none of A-D lies on the transient
#: that follows the feed-in arc.
START_ANGLE_DEG = 45.0
#: Turns of a circular test whose figures are judged (identify's verdict, the what-if
#: sweeps, the tuning's prediction): the analysis takes the middle turn, a quarter turn
#: after the feed-in joins the circle and a quarter turn before the feed-out. Where the
#: feed-in's semicircle of half the radius joins, the servo's lag steps with the
#: curvature, and that transient would set the contour error and G of a single turn (on
#: the six benches' models up to 2.8 times the settled contour error and 4.9 times G, and
#: one direction apart from the other on a symmetric machine). The middle turn's figures
#: are within 0.5 % of those of a turn taken after half a turn, where the machine settles
#: on the circle at all [-].
SETTLED_TURNS = 1.5


def paper_circle_command(machine=None, turns: float = 1.0):
    """CCW then CW circle, R35 mm at 5000 mm/min in XY, with feed-in and feed-out, each
    starting at 45 deg (the paper's Section 3.3 test).

    Parameters
    ----------
    machine : Machine, optional
        Not used: the command is the same for every machine [-].
    turns : float
        Turns of each circle: one, the paper's; :data:`SETTLED_TURNS` where its figures
        are judged settled on the circle [-].

    Returns
    -------
    Command
        The position command [m].
    """
    return circle_test_command(mm_to_m(RADIUS_MM), feed_mm_per_min_to_m_per_s(FEED_MM_PER_MIN),
                               turns=turns)


def circle_test_command(radius_m: float, feed_m_per_s: float, plane_axes=("X", "Y"),
                        turns: float = 1.0):
    """The paper's circular test at any radius and feed: a CCW then a CW circle about the
    origin, each fed in from the centre and out to it, starting at :data:`START_ANGLE_DEG`.

    Parameters
    ----------
    radius_m : float
        Radius [m].
    feed_m_per_s : float
        Feed [m/s].
    plane_axes : tuple of str
        The circle's plane [-].
    turns : float
        Turns of each circle (:data:`SETTLED_TURNS` where its figures are judged) [-].

    Returns
    -------
    Command
        The position command [m].
    """
    kw = dict(radius_m=radius_m, feed_m_per_s=feed_m_per_s,
              start_angle_rad=math.radians(START_ANGLE_DEG), plane_axes=plane_axes,
              turns=turns)
    return concatenate([circle_command(direction=d, **kw) for d in ("ccw", "cw")])
