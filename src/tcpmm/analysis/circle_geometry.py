"""What the columns of a circle's error terms are made of
(:func:`tcpmm.analysis.circle_model.term_columns`): the angle's cosine and sine, each axis'
direction along the radius with the servo mismatch's slope, the angle the axes travel at,
their velocities' signs, positions and travel since their reversals. Each is worked out
when a column first asks for it: a fit of some terms, or of the servo mismatch alone,
needs only some of them."""

from __future__ import annotations

from functools import cached_property

import numpy as np

from .circle_travel import (
    axis_phase,
    axis_positions,
    axis_signs,
    take_up,
    travel_since_reversal,
)


def with_slope(c, n, angle, s, mu):
    """``(wx, wy)`` of :func:`tcpmm.analysis.circle_model.radial_weights` from the angle's
    cosine ``c`` and sine ``n``, ``mu`` this circle's mismatch angle (``ratio`` times the
    fit's) [-]."""
    if not mu:
        return c, n
    # the ellipse -s mu R sin cos has the slope -s mu R cos 2theta, and an error (dx, dy)
    # turns the angle by (-dx sin + dy cos) / R
    k = s * mu * np.cos(2.0 * np.asarray(angle))
    return c - k * n, n + k * c


class TermGeometry:
    """The parts of the term columns of a circle at ``angle`` (arguments as for
    :func:`tcpmm.analysis.circle_model.term_columns`) [-]."""

    def __init__(self, angle, s, radius, ratio, mu, rev, widths):
        self.angle, self.s, self.radius, self.rev, self.widths = angle, s, radius, rev, widths
        self.mu = ratio * mu  # this circle's mismatch angle

    @cached_property
    def cn(self):
        """The angle's cosine and sine [-]."""
        return np.cos(self.angle), np.sin(self.angle)

    @cached_property
    def w(self):
        """``(wx, wy)``: the axes' directions along the radius, with the slope [-]."""
        return with_slope(*self.cn, self.angle, self.s, self.mu)

    @cached_property
    def own(self):
        """The angle the axes reverse and travel at: their own, off the tool's by the turn
        the other axis' lost motion makes (a step there too, which fine sampling
        resolves) [rad]."""
        own = self.angle if self.rev is None else self.rev
        return axis_phase(own, self.s, self.radius, self.mu,
                          getattr(self.widths, "lost", (0.0, 0.0)))

    @cached_property
    def signs(self):
        """``(sx, sy)``: the axes' velocities' signs [-]."""
        return axis_signs(self.own, self.s, self.mu)

    @cached_property
    def positions(self):
        """``(px, py)``: each axis' position over the radius [-]."""
        return axis_positions(self.angle if self.rev is None else self.rev, self.s, self.mu)

    def taken_up(self, axis):
        """The share of ``axis``' lost motion taken up over its width of ``widths`` [-]."""
        travel = travel_since_reversal(self.own, self.s, self.radius, self.mu, axis)
        return take_up(travel, self.widths[axis])
