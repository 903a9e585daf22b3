"""Samples whose closest command point leaps to another stretch of the path.

A sample's contour error is its distance to the closest command point within the window.
Where the path comes back beside itself within the window (a zig-zag's passes, a
pocket's rings), a tool more than half their spacing off the stretch it runs along is
nearer the next one, and its error reads as its distance to that: no more than half the
spacing (a tool 30.6 um off its pass, 50 um from the next, read 19.4 um). The closest
point then leaps along the path between two samples, by far more than the straight line
between the two points: the leap is counted, and the error where it happens said, since
the error from the stretch being run may be larger there. Crossing a corner from one leg
to the next the closest point moves along the path by less than :data:`FOLD` times the
straight line (a right angle: 1.4 times) unless the corner folds back on itself within
the error; a U-turn between passes is such a fold, and the error read at it is the
tool's distance to the path, which the corners' rounding states.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

#: The closest point leaps to another stretch where the path between two samples' closest
#: points is longer than this many times the straight line between them (and than the
#: errors and the samples' own travel allow) [-]
FOLD = 3.0


def leap_between(a: tuple, b: tuple) -> np.ndarray:
    """Per pair of samples, whether the closest command point of the second lies on
    another stretch of the path than the first's [-].

    Parameters
    ----------
    a, b : tuple of ndarray
        Of the first and the second samples of the pairs: ``(q, e, foot, s, way)``, their
        positions (n, d), errors (n,), closest command points (n, d), the path length there
        (n,) and the unit direction of the segment each lies on (n, d; 0 for a segment of
        no length) (:func:`closest_points`) [m], [-].
    """
    (qa, ea, fa, sa, ua), (qb, eb, fb, sb, ub) = a, b
    along = np.abs(sb - sa)
    step = fb - fa
    straight = np.sqrt(np.sum(step**2, axis=1))
    travel = np.sqrt(np.sum((qb - qa) ** 2, axis=1))
    both = np.abs(ea) + np.abs(eb)
    # a path run back over itself (CCW then CW): the new closest point lies on the line of
    # the old one's segment, running the other way, not beside it as the next pass does
    across = np.sqrt(np.maximum(straight**2 - np.sum(step * ua, axis=1) ** 2, 0.0))
    back = (np.sum(ua * ub, axis=1) < -0.9) & (across <= 0.5 * both)
    return (along > FOLD * straight + 2.0 * (both + travel)) & ~back


def leaps(q, e, seg, p, s_p, prev=None) -> tuple[np.ndarray, tuple | None]:
    """Per sample, whether its closest command point lies on another stretch of the path
    than the previous sample's (the first sample's against ``prev``, or not at all), and
    the last sample's ``prev`` for the next run of samples [-].

    Only samples whose closest segment moves on by more than two segments are measured:
    a leap crosses many, and the rest of millions of samples cost nothing.

    Parameters
    ----------
    q : ndarray, shape (n, d)
        The samples [m].
    e : ndarray, shape (n,)
        Their errors [m].
    seg, p, s_p
        Each one's closest segment of the polyline ``p`` of path lengths ``s_p``, as for
        :func:`closest_points` [-], [m], [m].
    prev : tuple, optional
        ``(q, e, foot, s, way)`` of the sample before the first, as :func:`leap_between`
        takes them (``s`` on the scale of ``s_p``) [m], [-].
    """
    n = seg.size
    flags = np.zeros(n, dtype=bool)
    if n == 0:
        return flags, prev
    first = np.flatnonzero(np.abs(np.diff(seg)) > 2)
    rows = np.unique(np.concatenate([first, first + 1, [0, n - 1]]))
    near = (q[rows], e[rows], *closest_points(q[rows], p, s_p, seg[rows]))
    at = np.searchsorted(rows, first)
    flags[first + 1] = leap_between(tuple(v[at] for v in near), tuple(v[at + 1] for v in near))
    if prev is not None:
        flags[0] = leap_between(tuple(np.asarray(v)[None] for v in prev),
                                tuple(v[:1] for v in near))[0]
    return flags, tuple(v[-1] for v in near)


def closest_points(q, p, s_p, seg) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each sample's closest point on its closest segment ``seg`` of the polyline ``p``
    (path lengths ``s_p`` at its vertices), that point's path length, and the segment's
    unit direction [m], [m], [-].

    Parameters
    ----------
    q : ndarray, shape (n, d)
        The samples [m].
    p : ndarray, shape (m, d)
        The polyline [m].
    s_p : ndarray, shape (m,)
        Path length at each vertex [m].
    seg : ndarray of int, shape (n,)
        Each sample's closest segment, from ``p[seg]`` to ``p[seg + 1]`` [-].
    """
    a, b = p[seg], p[np.minimum(seg + 1, p.shape[0] - 1)]
    d = b - a
    ln2 = np.sum(d * d, axis=1)
    f = np.clip(np.divide(np.sum((q - a) * d, axis=1), ln2, out=np.zeros(ln2.shape),
                          where=ln2 > 0), 0.0, 1.0)
    way = np.divide(d, np.sqrt(ln2)[:, None], out=np.zeros(d.shape), where=ln2[:, None] > 0)
    s = s_p[seg] + f * (s_p[np.minimum(seg + 1, s_p.size - 1)] - s_p[seg])
    return a + f[:, None] * d, s, way


@dataclass
class Leaps:
    """Per sensor, the leaps of the closest point counted so far and the largest error
    read at one [-, m]."""

    count: dict = field(default_factory=dict)
    top: dict = field(default_factory=dict)

    def add(self, sensor: str, flags, e) -> None:
        """Count the samples ``flags`` marks, of errors ``e`` [-, m]."""
        n = int(np.count_nonzero(flags))
        self.count[sensor] = self.count.get(sensor, 0) + n
        if n:
            self.top[sensor] = max(self.top.get(sensor, 0.0), float(np.max(np.abs(e[flags]))))

    def result(self) -> dict:
        """Per sensor with a leap: their number and the largest error read at one [-, m]."""
        return {k: {"leaps": n, "max_abs_m": self.top[k]} for k, n in self.count.items() if n}


def whole_leaps(actual: dict, errors: dict, feet: dict, cmd, s_cmd, counted=None) -> dict:
    """:meth:`Leaps.result` of a whole run: per sensor its samples ``actual``, errors and
    closest segments ``feet`` along the command ``cmd`` of path lengths ``s_cmd``, of the
    samples ``counted`` (all where None) [m, -].

    Parameters
    ----------
    actual, errors, feet : dict
        Per sensor: positions (n, d), errors (n,) and closest segments (n,) [m], [m], [-].
    cmd : ndarray, shape (m, d)
        The command's vertices [m].
    s_cmd : ndarray, shape (m,)
        The path length at each [m].
    counted : ndarray of bool, optional
        The samples counted (those out of rapids) [-].
    """
    got = Leaps()
    for k, e in errors.items():
        flags = leaps(actual[k], e, np.asarray(feet[k]), cmd, s_cmd)[0]
        got.add(k, flags if counted is None else flags & counted, e)
    return got.result()


def leap_notes(found: dict) -> list[str]:
    """A note per sensor whose closest point leaps to another stretch of the path [-].

    Parameters
    ----------
    found : dict
        :meth:`Leaps.result` [-, m].
    """
    return [f"{k}: the closest command point leaps {v['leaps']} time"
            f"{'' if v['leaps'] == 1 else 's'} to another stretch of the path, which comes "
            f"back beside itself within the window (passes side by side); there the error "
            f"reads the distance to the stretch nearest, up to {v['max_abs_m'] * 1e6:.2f} "
            "µm, and the error from the stretch being run may be larger"
            for k, v in found.items()]
