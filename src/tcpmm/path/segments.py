"""Motion segments: the tool path as the G-code interpreter hands it to the interpolator.

Every position is a point ``(X, Y, Z)`` in metres, absolute. A list of segments is a
continuous path: each segment starts where the previous one ends.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

AXES = ("X", "Y", "Z")
AXIS_INDEX = {"X": 0, "Y": 1, "Z": 2}
#: kinds of a segment in the look-ahead's columns (:func:`tcpmm.path.geometry.to_arrays`)
LINE, ARC, DWELL, BLEND = 0, 1, 2, 3
#: planes of G17, G18, G19: positive (counter-clockwise) rotation turns the first axis
#: into the second, seen from the positive third axis.
PLANES = {17: ("X", "Y"), 18: ("Z", "X"), 19: ("Y", "Z")}
#: start and end closer than this in the plane make a full circle [m]
FULL_CIRCLE_TOL_M = 1e-9


@dataclass(frozen=True, slots=True)
class Line:
    """Straight feed motion (G1).

    Parameters
    ----------
    start_m, end_m : tuple of float
        Start and end point (X, Y, Z) [m].
    feed_m_per_s : float
        Programmed feed [m/s].
    exact_stop : bool
        Come to rest at the end of the segment (G61, G9) [-].
    line : int or None
        Source line number, 1-based [-].
    tolerance_m : float or None
        Contour tolerance of the corner at its end (G64 P): how far a blend may round it
        off; ``None`` takes the interpolator's ``blend_tolerance_m``, 0 keeps it sharp [m].
    """

    start_m: tuple[float, float, float]
    end_m: tuple[float, float, float]
    feed_m_per_s: float
    exact_stop: bool = False
    line: int | None = None
    tolerance_m: float | None = None

    @property
    def length_m(self) -> float:
        """Length of the segment [m]."""
        return math.dist(self.start_m, self.end_m)


@dataclass(frozen=True, slots=True)
class Rapid:
    """Rapid positioning (G0): straight, at the axis rapid speeds, from rest to rest.

    Parameters
    ----------
    start_m, end_m : tuple of float
        Start and end point (X, Y, Z) [m].
    line : int or None
        Source line number, 1-based [-].
    """

    start_m: tuple[float, float, float]
    end_m: tuple[float, float, float]
    line: int | None = None

    @property
    def length_m(self) -> float:
        """Length of the segment [m]."""
        return math.dist(self.start_m, self.end_m)


@dataclass(frozen=True, slots=True)
class Arc:
    """Circular (or helical) feed motion (G2/G3).

    Parameters
    ----------
    start_m, end_m : tuple of float
        Start and end point (X, Y, Z) [m].
    centre_m : tuple of float
        Centre (X, Y, Z); only its coordinates in the plane are used [m].
    plane_axes : tuple of str
        The two axes of the plane, e.g. ``("X", "Y")``; counter-clockwise turns the
        first into the second. The third axis moves linearly (helix) [-].
    direction : {"cw", "ccw"}
        Sense of rotation [-].
    feed_m_per_s : float
        Programmed feed along the (helical) path [m/s].
    extra_turns : int
        Full turns added to the sweep from start to end [-].
    exact_stop : bool
        Come to rest at the end of the segment (G61) [-].
    line : int or None
        Source line number, 1-based [-].

    Notes
    -----
    If the end point lies slightly off the circle through the start point, the radius
    changes linearly with the angle so that the path still ends exactly on the end point.
    """

    start_m: tuple[float, float, float]
    end_m: tuple[float, float, float]
    centre_m: tuple[float, float, float]
    plane_axes: tuple[str, str]
    direction: str
    feed_m_per_s: float
    extra_turns: int = 0
    exact_stop: bool = False
    line: int | None = None

    @property
    def _ab(self):
        ia, ib = AXIS_INDEX[self.plane_axes[0]], AXIS_INDEX[self.plane_axes[1]]
        return ia, ib, 3 - ia - ib

    @property
    def radius_m(self) -> float:
        """Radius at the start point [m]."""
        ia, ib, _ = self._ab
        return math.hypot(
            self.start_m[ia] - self.centre_m[ia], self.start_m[ib] - self.centre_m[ib]
        )

    @property
    def end_radius_m(self) -> float:
        """Radius at the end point [m]."""
        ia, ib, _ = self._ab
        return math.hypot(self.end_m[ia] - self.centre_m[ia], self.end_m[ib] - self.centre_m[ib])

    @property
    def start_angle_rad(self) -> float:
        """Angle of the start point about the centre, from the first plane axis [rad]."""
        ia, ib, _ = self._ab
        return math.atan2(
            self.start_m[ib] - self.centre_m[ib], self.start_m[ia] - self.centre_m[ia]
        )

    @property
    def sweep_rad(self) -> float:
        """Signed swept angle, positive counter-clockwise [rad]."""
        ia, ib, _ = self._ab
        return arc_sweep(
            self.start_m[ia] - self.centre_m[ia],
            self.start_m[ib] - self.centre_m[ib],
            self.end_m[ia] - self.centre_m[ia],
            self.end_m[ib] - self.centre_m[ib],
            self.direction == "ccw",
            self.extra_turns,
        )

    @property
    def helix_m(self) -> float:
        """Travel of the axis normal to the plane [m]."""
        _, _, ih = self._ab
        return self.end_m[ih] - self.start_m[ih]

    @property
    def length_m(self) -> float:
        """Length of the (helical) path [m]."""
        r = 0.5 * (self.radius_m + self.end_radius_m)
        return math.hypot(r * self.sweep_rad, self.helix_m)


@dataclass(frozen=True, slots=True)
class Blend:
    """Arc that rounds off a corner between two straight blocks (G64 P), in the plane of
    the two, whatever its orientation; it turns by less than half a turn.

    Parameters
    ----------
    start_m, end_m : tuple of float
        Tangent points on the incoming and the outgoing line (X, Y, Z) [m].
    centre_m : tuple of float
        Centre (X, Y, Z), as far from both [m].
    feed_m_per_s : float
        Programmed feed [m/s].
    line : int or None
        Source line number of the block after the corner, 1-based [-].
    """

    start_m: tuple[float, float, float]
    end_m: tuple[float, float, float]
    centre_m: tuple[float, float, float]
    feed_m_per_s: float
    line: int | None = None

    @property
    def radius_m(self) -> float:
        """Radius [m]."""
        return math.dist(self.start_m, self.centre_m)

    @property
    def sweep_rad(self) -> float:
        """Angle turned, in (0, pi) [rad]."""
        a = [s - c for s, c in zip(self.start_m, self.centre_m, strict=True)]
        b = [e - c for e, c in zip(self.end_m, self.centre_m, strict=True)]
        cross = math.dist((0.0, 0.0, 0.0), (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                                            a[0] * b[1] - a[1] * b[0]))
        return math.atan2(cross, sum(x * y for x, y in zip(a, b, strict=True)))

    @property
    def length_m(self) -> float:
        """Length of the arc [m]."""
        return self.radius_m * self.sweep_rad


@dataclass(frozen=True, slots=True)
class Dwell:
    """Rest at a point (G4).

    Parameters
    ----------
    position_m : tuple of float
        Where the axes rest (X, Y, Z) [m].
    duration_s : float
        How long; rounded up to whole interpolation periods [s].
    line : int or None
        Source line number, 1-based [-].
    """

    position_m: tuple[float, float, float]
    duration_s: float
    line: int | None = None

    @property
    def start_m(self):
        """Same as ``position_m`` [m]."""
        return self.position_m

    @property
    def end_m(self):
        """Same as ``position_m`` [m]."""
        return self.position_m

    @property
    def length_m(self) -> float:
        """Zero [m]."""
        return 0.0


Segment = Line | Rapid | Arc | Blend | Dwell


def arc_sweep(xs, ys, xe, ye, ccw, extra_turns=0):
    """Signed sweep of an arc from the start to the end vector about the centre.

    Parameters
    ----------
    xs, ys : float or ndarray
        Start point relative to the centre, in the plane [m].
    xe, ye : float or ndarray
        End point relative to the centre, in the plane [m].
    ccw : bool or ndarray
        Counter-clockwise [-].
    extra_turns : int or ndarray
        Full turns to add [-].

    Returns
    -------
    float or ndarray
        Swept angle, positive counter-clockwise, in (0, 2 pi] plus the extra turns (or
        its negative) [rad].
    """
    import numpy as np

    two_pi = 2.0 * np.pi
    full = np.hypot(np.asarray(xe) - xs, np.asarray(ye) - ys) < FULL_CIRCLE_TOL_M
    d = np.mod(np.arctan2(ye, xe) - np.arctan2(ys, xs), two_pi)
    ccw = np.asarray(ccw, dtype=bool)
    sweep = np.where(ccw, d, np.mod(-d, two_pi))
    sweep = np.where(full | (sweep <= 0.0), two_pi, sweep)
    sweep = sweep + two_pi * np.asarray(extra_turns)
    out = np.where(ccw, sweep, -sweep)
    return float(out) if out.ndim == 0 else out
