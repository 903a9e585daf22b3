"""The error terms of a circle as columns of a least-squares fit of its radial error.

Each column is the first-order radial effect ``e = dx cos(theta) + dy sin(theta)`` of a
position error ``(dx, dy)`` of the tool per unit of the term (the table in
:mod:`tcpmm.analysis.diagnostics`). Two things are not first order and are handled here:

* where each axis reverses: an axis reverses where its own velocity changes sign, and
  with a servo mismatch ``mu = w (ty - tx)`` that is not at the quadrant point of the tool's
  angle but ``-s mu`` (X) and ``+s mu`` (Y) from it; a backlash step placed a sample off
  reads as part of the ellipses and of a cyclic error;
* the ellipse of a servo mismatch: each lagging axis stays on its own sine, and over the
  tool's angle the radius has, besides the ellipse at 45 deg, ``-3/16 R mu^2`` at four
  times the angle and ``-5/16 R mu^2`` in the mean (0.15 and 0.25 um at F10000 on R 35
  with 1 ms), which a cyclic error scan would take for a cyclic error. The fit takes it
  off the data (:func:`servo_remainder`) with the mismatch of the previous fit. Over the
  command's angle (:func:`.circle_ranking.tool_angle`), as the samples come, the mean
  is ``-R mu^2 / 16``;
* the ellipse's slope: a position error across the radius turns the tool's angle by its
  size over R, and the ellipse, some ``R mu / 2`` deep, is read that much further along.
  Each position error ``(dx, dy)`` is seen along the radius with that slope added
  (:func:`radial_weights`); without it a backlash read ``2 mu`` of itself short (3 % at
  F10000 on R 20 mm with a 2 ms mismatch).

Which terms an arc determines is read from the columns themselves (:func:`determined`).
"""

from __future__ import annotations

import functools

import numpy as np

from .circle_geometry import TermGeometry, with_slope
from .circle_travel import Widths, take_up_twice, travel_since_reversal

#: A term is determined where at least this share of its column (unit norm) is independent
#: of the other columns: noise then enters it at most tenfold [-].
MIN_SHARE = 0.1


def angle_step(angle) -> float:
    """Median angle between neighbouring samples, 0 for fewer than two [rad].

    Parameters
    ----------
    angle : ndarray
        Unwrapped angle of the samples [rad].
    """
    return float(np.median(np.abs(np.diff(angle)))) if np.size(angle) > 1 else 0.0


def reversal_lead_deg(angle, mu) -> float:
    """How far before its quadrant point the leading axis reverses under a servo mismatch
    angle ``mu``, and a sample more: where a reversal's transient starts [deg].

    Parameters
    ----------
    angle : ndarray
        Unwrapped angle of the samples [rad].
    mu : float
        Servo mismatch as an angle (module docstring) [rad].
    """
    return float(np.degrees(abs(mu) + angle_step(angle)))


def reversal_angle(pos, centre):
    """The angle about the circle's own ``centre`` of the tool at ``pos``, where its axes
    reverse; None for a circle about the nominal centre, whose own angle it is [rad]."""
    return None if not any(centre) else np.arctan2(pos[1] - centre[1], pos[0] - centre[0])


def radial_weights(angle, s, ratio=1.0, mu=0.0) -> tuple:
    """``(wx, wy)``: the radial error of a unit position error of the first and of the
    second axis, ``cos`` and ``sin`` of the angle, each with the servo mismatch's ellipse
    read along the angle the error turns the tool by (module docstring) [-].

    Parameters
    ----------
    angle : ndarray
        Angle CCW from the first axis [rad].
    s : float
        +1 CCW, -1 CW [-].
    ratio : float
        This circle's angular speed over the mean of the circles fitted together [-].
    mu : float
        Servo mismatch angle of the circles fitted together [rad].
    """
    return with_slope(np.cos(angle), np.sin(angle), angle, s, ratio * mu)


def term_columns(names, angle, s, radius, ratio=1.0, mu=0.0, rev=None,
                 widths=(0.0, 0.0)) -> list:
    """Radial error per unit of each term of ``names``, each part of the columns (the
    angle's sine and cosine, the axes' signs...) worked out once, where a term of ``names``
    needs it (:class:`.circle_geometry.TermGeometry`) [m/unit].

    Parameters
    ----------
    names : sequence of str
        Of ``backlash_X``, ``backlash_Y``, ``lateral_play_X``, ``lateral_play_Y``,
        ``squareness``, ``servo_angle``, ``scale_mismatch``, ``straightness_X``,
        ``straightness_Y`` [-].
    angle : ndarray
        Angle CCW from the first axis [rad].
    s : float
        +1 CCW, -1 CW [-].
    radius : float
        Nominal radius [m].
    ratio : float
        This circle's angular speed over the mean of the circles fitted together [-].
    mu : float
        Servo mismatch angle placing the axes' reversals [rad].
    rev : ndarray, optional
        The angle about the circle's own centre, where its axes reverse and are in their
        travel (a circle off the nominal centre by ``c`` reverses some ``c / R`` from the
        nominal quadrant points); ``angle`` where omitted [rad].
    widths : tuple of float
        Travel of each axis after its reversal over which its backlash is taken up
        (:func:`.circle_travel.take_up`); 0 for an instant step [m].
    """
    g = TermGeometry(angle, s, radius, ratio, mu, rev, widths)
    # each term's position error (the table in :mod:`tcpmm.analysis.diagnostics`) seen
    # along the radius; the servo mismatch is the lag itself
    cols = {"backlash_X": lambda: -0.5 * g.signs[0] * g.taken_up(0) * g.w[0],
            "backlash_Y": lambda: -0.5 * g.signs[1] * g.taken_up(1) * g.w[1],
            "lateral_play_X": lambda: 0.5 * g.signs[0] * g.w[1],
            "lateral_play_Y": lambda: 0.5 * g.signs[1] * g.w[0],
            "squareness": lambda: -radius * g.positions[1] * g.w[0],
            "servo_angle": lambda: -s * ratio * radius * g.cn[1] * g.cn[0],
            "scale_mismatch": lambda: 0.5 * radius * (g.positions[0] * g.w[0]
                                                      - g.positions[1] * g.w[1]),
            # a bow of the axis by 1 at the middle of its travel +-R, 0 at its ends
            "straightness_X": lambda: (1.0 - g.positions[0] * g.positions[0]) * g.w[1],
            "straightness_Y": lambda: (1.0 - g.positions[1] * g.positions[1]) * g.w[0]}
    return [cols[name]() for name in names]


def term_column(name, angle, s, radius, ratio=1.0, mu=0.0, rev=None, widths=(0.0, 0.0)):
    """Radial error per unit of the term ``name`` (:func:`term_columns`) [m/unit]."""
    return term_columns((name,), angle, s, radius, ratio, mu, rev, widths)[0]


def backlash_take_up(axis, angle, s, radius, ratio=1.0, mu=0.0, rev=None,
                     widths=(0.0, 0.0)):
    """``column(width)``: the column of ``axis``' backlash (0 the first, 1 the second;
    :func:`term_columns`) with its take-up over ``width`` and the other axis' over its
    width of ``widths``, the geometry that no width changes worked out once, for a search
    over widths; the same numbers as :func:`term_column` [m/unit]."""
    lost = getattr(widths, "lost", (0.0, 0.0))
    other = widths[1 - axis]
    g = TermGeometry(angle, s, radius, ratio, mu, rev, Widths((1.0, 1.0), lost))
    sign, w = g.signs[axis], g.w[axis]
    travel = travel_since_reversal(g.own, s, radius, ratio * mu, axis)
    # the first steps of the column and of :func:`.circle_travel.take_up`, which no width
    # changes
    half, twice = -0.5 * sign, 2.0 * travel

    def column(width):
        if width > 0 or other > 0:
            return half * take_up_twice(twice, width) * w
        both = Widths((0.0, 0.0), lost)  # no take-up: the axes reverse at the tool's angle
        return term_column(f"backlash_{'XY'[axis]}", angle, s, radius, ratio, mu, rev, both)
    return column


def cyclic_columns(pos, w, wavenumber):
    """Sine and cosine columns of an axis' cyclic error: ``dx = c sin(2 pi k x + phi)``
    seen along the radius by ``w`` (cos for X, sin for Y) [m/m].

    Parameters
    ----------
    pos : ndarray
        Position of the axis [m].
    w : ndarray
        ``cos(theta)`` for the first axis, ``sin(theta)`` for the second [-].
    wavenumber : float
        One over the period [1/m].
    """
    phase = 2 * np.pi * wavenumber * pos
    return [w * np.sin(phase), w * np.cos(phase)]


def servo_remainder(angle, s, radius, mu):
    """The radial error of a servo mismatch angle ``mu`` beyond its ellipse at 45 deg
    (module docstring) [m].

    Parameters
    ----------
    angle : ndarray
        Angle CCW from the first axis [rad].
    s : float
        +1 CCW, -1 CW [-].
    radius : float
        Nominal radius [m].
    mu : float
        Servo mismatch angle of this circle, ``w (ty - tx)`` [rad].
    """
    angle = np.asarray(angle, float)
    if mu == 0.0 or not np.isfinite(mu):
        return np.zeros_like(angle)
    th, r = _servo_ellipse(float(s), float(mu))
    exact = np.interp(np.mod(angle, 2 * np.pi), th, radius * r, period=2 * np.pi)
    return exact - mu * term_column("servo_angle", angle, s, radius)


@functools.lru_cache(maxsize=256)
def _servo_ellipse(s: float, mu: float):
    """The path of a unit circle whose second axis lags by the angle ``mu``, sampled
    finely: its angle, ascending, and its radius less 1 there; a fit asks for the same
    ``mu`` many times (read-only arrays) [rad, -]."""
    u = np.linspace(0.0, 2 * np.pi, 8193)
    # X at its place, Y lagging it by the angle mu along the travel
    x, y = np.cos(u), np.sin(u - s * mu)
    th = np.mod(np.arctan2(y, x), 2 * np.pi)
    order = np.argsort(th)
    out = th[order], np.hypot(x, y)[order] - 1.0
    for a in out:
        a.flags.writeable = False
    return out


def _unit_columns(A):
    """``A`` with each column scaled to unit norm (a zero column left as it is), and the
    norms [-]."""
    norm = np.linalg.norm(A, axis=0)
    return A / np.where(norm > 0, norm, 1.0), norm


def column_shares(A):
    """Per column the share of it (scaled to unit norm) independent of the others [-].

    Parameters
    ----------
    A : ndarray
        Design matrix, one column per term [m/unit].
    """
    An, norm = _unit_columns(A)
    G = An.T @ An
    share = np.zeros(A.shape[1])
    for j in np.flatnonzero(norm > 0):
        # what of the column the others leave: 1 - its best fit by them, squared. (The
        # diagonal of the Gram matrix's pseudo-inverse gives the same where the columns
        # are independent, but a finite share to two columns that are the same.)
        o = np.flatnonzero(np.arange(A.shape[1]) != j)
        c = np.linalg.lstsq(G[np.ix_(o, o)], G[o, j], rcond=None)[0] if o.size else o
        share[j] = np.sqrt(max(1.0 - float(G[j, o] @ c), 0.0))
    return share


def determined(A, protect=()):
    """Which columns the data determine: the least independent column is dropped until
    each left has :data:`MIN_SHARE` of itself independent of the others [-].

    Parameters
    ----------
    A : ndarray
        Design matrix over the fitted samples [m/unit].
    protect : sequence of int
        Columns always kept (the radius of each circle) [-].

    Returns
    -------
    ndarray of bool
        Kept columns [-].
    """
    keep = np.ones(A.shape[1], bool)
    while True:
        idx = np.flatnonzero(keep)
        share = column_shares(A[:, idx])
        share[np.isin(idx, protect)] = np.inf
        worst = int(np.argmin(share))
        if share[worst] >= MIN_SHARE:
            return keep
        keep[idx[worst]] = False


def alias_slopes(A, keep, names, extra=None) -> dict:
    """What a fit leaves out moves what it keeps: per column left out (``~keep``, less the
    radii) and per column of ``extra``, how much each kept column's coefficient moves per
    unit of it, were it in the data: its least-squares fit by the kept columns [SI/SI].

    Parameters
    ----------
    A : ndarray
        Design matrix over the fitted samples, every column [m/unit].
    keep : ndarray of bool
        The columns fitted [-].
    names : sequence of str
        Column names [-].
    extra : dict, optional
        ``name -> column`` of terms not in ``A`` [m/unit].

    Returns
    -------
    dict
        ``left-out name -> {kept name: slope}`` [SI/SI].
    """
    left = {n: A[:, j] for j, n in enumerate(names)
            if not keep[j] and not n.startswith("radius")}
    left.update(extra or {})
    if not left or not keep.any():
        return {}
    slopes = np.linalg.lstsq(A[:, keep], np.column_stack(list(left.values())), rcond=None)[0]
    kept = [n for n, k in zip(names, keep, strict=True) if k]
    return {n: dict(zip(kept, map(float, slopes[:, j]), strict=True))
            for j, n in enumerate(left)}


#: Columns this alike (the cosine of their angle) are twins: the data cannot say which of
#: the two terms they hold [-].
TWIN = 0.99


def drop_twins(A, keep, protect=()):
    """``keep`` less every column that is the twin of one left out: a term kept for a
    twin the arc does not tell from it would carry both under its one name (over an arc
    inside a quadrant, backlash X and lateral play Y) [-]."""
    An = _unit_columns(A)[0]
    out = keep.copy()
    for j in np.flatnonzero(~keep):
        twins = np.abs(An[:, keep].T @ An[:, j]) >= TWIN
        out[np.flatnonzero(keep)[twins]] = False
    out[list(protect)] = keep[list(protect)]
    return out


def fit_mask(angle, s, after_deg=(0.0, 20.0), points=(0.0, 90.0, 180.0, 270.0)):
    """Samples outside the ``after_deg`` window after every quadrant point in the travel
    direction, where the reversal's transient lies [-].

    Parameters
    ----------
    angle : ndarray
        Angle CCW from the first axis [rad].
    s : float
        +1 CCW, -1 CW [-].
    after_deg : tuple of float
        The window after a point, along the travel [deg].
    points : tuple of float
        The quadrant points [deg].
    """
    u = s * np.degrees(angle)
    keep = np.ones(np.size(angle), bool)
    for deg in points:
        # from the window's start, so that a window that starts before the point works
        d = (u - s * deg - after_deg[0]) % 360.0
        keep &= ~(d <= after_deg[1] - after_deg[0])
    return keep


#: The largest sample spacing a full turn's ends may lack four of: a ballbar's 125 Hz at
#: F10000 on R 35 mm is 2.2 deg a sample [deg].
MAX_STEP_DEG = 2.5


def is_full(angle) -> bool:
    """Whether an unwrapped angle covers a full turn (:func:`covers`) [-].

    Parameters
    ----------
    angle : ndarray
        Angle, unwrapped [rad].
    """
    return covers(angle, 360.0)


def covers(angle, deg: float) -> bool:
    """Whether an unwrapped angle covers ``deg`` degrees as a command run over them is
    sampled: cut to whole samples it may lack up to a sample spacing at either end, and a
    sensor's samples within the command's angles up to one more at either end
    (:func:`.circle_passes.within_span`); the spacing is the median step (a gap in the
    samples is no spacing), at most :data:`MAX_STEP_DEG`. The tool's angle is turned from
    the command's by the errors across the radius, so a thousandth of ``deg`` more: a pair
    of 210 deg arcs read 209.96 deg at the tool [-].

    Parameters
    ----------
    angle : ndarray
        Angle, unwrapped [rad].
    deg : float
        The span [deg].
    """
    step = float(np.median(np.abs(np.diff(angle)))) if angle.size > 1 else 0.0
    slack = 4 * min(step, np.radians(MAX_STEP_DEG))
    return abs(angle[-1] - angle[0]) >= np.radians(deg) * (1 - 1e-3) - slack
