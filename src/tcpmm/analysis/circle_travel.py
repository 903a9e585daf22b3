"""How far each axis has travelled since it reversed, and how it takes up its lost motion
over that travel (:func:`tcpmm.analysis.circle_model.term_columns`).

The travel is that of the axis' own command, ``R (1 - cos phi)`` from its reversal, and
the circle is read at the tool's angle. The two differ where the other axis stands off
its command across the radius: at A, where X reverses, Y's lost motion ``b_Y / 2`` turns
the tool's angle from X's own by ``b_Y / 2R`` (0.86 mrad for 60 um on R 35 mm), and X's
travel, read at the tool's angle, runs ``R phi`` times that ahead or behind, 0.5 um within
the take-up of a 100 um dead band: the take-up read short and left a bump the spikes
took for a transient. Each axis' travel is read at the command's angle, the tool's less
the turn the axes' lost motion makes (:func:`axis_phase`), where a take-up has a width;
a step, which has none, is placed by the signs alone, as before.
"""

from __future__ import annotations

import numpy as np


def axis_signs(angle, s, mu=0.0):
    """``(sx, sy)``: signs of the X and Y velocities, each axis reversing where it does with
    a servo mismatch angle ``mu`` (:mod:`tcpmm.analysis.circle_model`) [-].

    Parameters
    ----------
    angle : ndarray
        Angle CCW from the first axis [rad].
    s : float
        +1 CCW, -1 CW [-].
    mu : float
        Servo mismatch as an angle, ``w (ty - tx)`` [rad].
    """
    return -s * np.sign(np.sin(angle + s * mu)), s * np.sign(np.cos(angle - s * mu))


def axis_positions(angle, s, mu) -> tuple:
    """``(cos, sin)`` of each axis' own angle where the tool is at ``angle``: with a servo
    mismatch ``mu`` each axis runs on its own sine, X ahead of the tool's angle by
    ``s mu cos^2`` and Y behind it by ``s mu sin^2`` (each at its reversal by the whole
    ``mu``, :func:`axis_signs`), and an error of one axis' position is
    taken where that axis is: a squareness read where the tool is, beside a 2 ms mismatch
    at F10000 on R 20 mm, made 0.15 um of lateral play (X position over R, Y over R) [-].
    ``angle`` [rad], ``s`` [-] and ``mu`` [rad] as for :func:`axis_signs`.
    """
    c, n = np.cos(angle), np.sin(angle)
    if not mu:
        return c, n
    return np.cos(angle + s * mu * c * c), np.sin(angle - s * mu * n * n)


class Widths(tuple):
    """Each axis' take-up width, as a tuple ``(x, y)`` [m], with ``lost``: each axis' lost
    motion (its backlash as last fitted), which turns the tool's angle from the axes'
    own (:func:`axis_phase`) [m]."""

    lost: tuple = (0.0, 0.0)

    def __new__(cls, widths, lost=(0.0, 0.0)):
        out = super().__new__(cls, tuple(float(w) for w in widths))
        out.lost = tuple(float(b) for b in np.nan_to_num(np.asarray(lost, float)))
        return out


def axis_phase(angle, s, radius, mu, lost):
    """The command's angle where the tool is at ``angle``: less the turn
    ``(dy cos - dx sin) / R`` the axes' lost motion ``lost`` makes, each axis off by half
    of it against its velocity [rad].

    Parameters
    ----------
    angle, s, radius, mu
        As for :func:`travel_since_reversal`, ``angle`` the tool's [rad, -, m, rad].
    lost : tuple of float
        Each axis' lost motion (:attr:`Widths.lost`) [m].
    """
    a = np.asarray(angle)
    if not any(lost):
        return a
    sx, sy = axis_signs(a, s, mu)
    dx, dy = -0.5 * sx * lost[0], -0.5 * sy * lost[1]  # each -b/2 along its velocity
    return a - (dy * np.cos(a) - dx * np.sin(a)) / radius


def travel_since_reversal(angle, s, radius, mu, axis):
    """How far the axis ``axis`` (0 the first, 1 the second) has been commanded since its
    last reversal, each axis reversing where it does with a servo mismatch angle ``mu``
    (:func:`axis_signs`): ``R (1 - cos phi)``, ``phi`` the
    angle travelled since [m].

    Parameters
    ----------
    angle : ndarray
        Angle CCW from the first axis about the circle's centre [rad].
    s : float
        +1 CCW, -1 CW [-].
    radius : float
        Nominal radius [m].
    mu : float
        Servo mismatch angle of this circle [rad].
    axis : int
        0 for the first axis, 1 for the second [-].
    """
    own = np.asarray(angle) + (s * mu if axis == 0 else -s * mu)
    return radius * (1.0 - np.cos(np.mod(s * own - axis * np.pi / 2, np.pi)))


def take_up(travel, width):
    """The share of an axis' lost motion taken up after its reversal, from -1 (the side
    before it) to +1 (the side after), linear in the commanded travel since the reversal
    over ``width``: a dead band (the table stands while the motor crosses the play) has the
    backlash's own width, an instant step none [-].

    Parameters
    ----------
    travel : ndarray
        Commanded travel since the reversal (:func:`travel_since_reversal`) [m].
    width : float
        Travel over which the lost motion is taken up [m].
    """
    return take_up_twice(2.0 * travel, width)


def take_up_twice(twice_travel, width):
    """:func:`take_up` from twice the travel [m], which a search over widths works out
    once [-]."""
    if not width > 0:
        return np.ones_like(twice_travel)
    return np.clip(twice_travel / width - 1.0, -1.0, 1.0)
