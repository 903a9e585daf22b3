"""The part of each reversal's transient that lasts past the window the fit leaves out.

The fit leaves out the 20 deg after each quadrant point, where the reversal's transient
lies. A transient that decays more slowly (a slow position loop pulling the axis back after
the friction has flipped: a time constant of 60 ms is 8 deg at F5000 on R 35 mm, 16 deg at
F10000) lies in part in the fitted samples, and there it shares the shape of the terms
that step at a reversal or bend the circle between two: on circles with a tail of 3 um
decaying over 20 deg a backlash of 2 um read 3.3 um, and a scale mismatch of 20 ppm read
29 ppm, both with 0.1 um of noise.

So the fit has a column per reversal for what of it lies past the window, decaying
exponentially from the window's end with one time constant for all reversals, ``a exp(-(d
- w) / tau)`` beyond the window ``w``, zero inside it (the spike after the terms is still
the whole transient there). Its shape is one of two (:data:`SHAPES`), whichever fits
better: the reversing axis' position error, seen along the radius as the angle turns away
from the axis (what a servo leaves), or a radial error (what a ballbar's software and
simulators of its errors add). Each arc has four, one per axis and direction it reverses
into, so that a reversal that differs from the others (gravity on an axis, friction unlike
at the travel's ends) is fitted as it is. The time constant is searched on a grid
(:data:`DECAY_DEG`) and refined; the columns are kept where they lower the sum of squares
by :data:`SIGNIFICANT` noise variances (:func:`noise_level`) more than the same columns
turned away from the reversals (:data:`TURN_DEG`), else the fit has none. A tail as long
as the half turn to the next reversal is nearly a step, the backlash itself: where another
tail fits as well, the terms are uncertain by how far they move between the two
(:func:`spread`), and the time constant by its 95 % interval (:func:`decay_interval`).

Only pairs of full turns are fitted with these columns: over part of a turn they are the
arc's centre and bows as much as a transient, and in one direction they take its lateral
play, a step at the reversals too, which it cannot fit.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq, minimize_scalar

from .circle_model import reversal_angle
from .circle_noise import correlation_length
from .circle_travel import axis_signs

#: Time constants searched, as the angle the tool travels in one at the circles' mean
#: speed [deg]
DECAY_DEG = (2.0, 3.0, 4.5, 7.0, 10.0, 15.0, 22.0, 33.0, 50.0)
#: The tails are fitted where they lower the sum of squares by this many noise variances
#: more than the same tails turned away from the reversals do (:data:`TURN_DEG`): eight
#: columns and a time constant fitted to noise lower it by about ten, and what the terms
#: do not model (a servo mismatch's reversals placed between samples, a cyclic error)
#: by up to 85 more on the suite's circles with every error at once [-]
SIGNIFICANT = 100.0
#: The test's tails are turned by this angle from the reversals, halfway between two [deg]
TURN_DEG = 45.0
#: Nor where the largest tail is smaller than this: below any sensor's resolution, and a
#: noise-free circle's rounding [m]
MIN_TAIL_M = 0.01e-6
#: The tails' shapes: the axis' position error, or a radial error
SHAPES = ("axis", "radial")
#: The columns of one arc, by axis and the sign of its velocity after the reversal
TAIL_KEYS = ("X+", "X-", "Y+", "Y-")


def tail_names(n_arcs: int) -> list:
    """The tail columns' names: ``tail_X+_0`` ... per arc [-]."""
    return [f"tail_{k}_{i}" for i in range(n_arcs) for k in TAIL_KEYS]


def tail_columns(angle, s, ratio, mu, rev, after_deg, tail, reversals=None) -> list:
    """The four tail columns of one arc (module docstring) over ``angle`` [m/m].

    Parameters
    ----------
    angle : ndarray
        Angle CCW from the first axis [rad].
    s : float
        +1 CCW, -1 CW [-].
    ratio : float
        The arc's angular speed over the mean of the arcs fitted together [-].
    mu : float
        Servo mismatch angle placing the axes' reversals [rad].
    rev : ndarray or None
        The angle about the circle's own centre, where its axes reverse [rad].
    after_deg : float
        The window after each quadrant point the fit leaves out [deg].
    tail : tuple
        ``(decay, shape)``: the time constant, as the angle travelled in it at the mean
        speed, and one of :data:`SHAPES`; a third entry turns the columns by that angle
        along the travel, away from the reversals (:func:`search_tail`'s test) [rad, -,
        deg].
    """
    decay, shape, *turn = tail
    if reversals is None:
        reversals = axis_reversals(angle, s, ratio, mu, rev, *turn)
    # a tail steps the radius out where its coefficient is positive, as a backlash does:
    # the axis' error against its new direction, seen along the radius as the angle turns
    # from the axis on (past 90 deg the other way), or the radial error itself; one column
    # per sign of the axis' velocity after the reversal
    out = []
    for axis in reversals:
        within, lag, along, rising, falling = axis.parts(after_deg)
        course = np.where(within, np.exp(lag / (ratio * decay)), 0.0)  # from the window's end
        col = along * course if shape == "axis" else course
        out += [np.where(rising, col, 0.0), np.where(falling, col, 0.0)]
    return out


class AxisReversal(tuple):
    """``(since, sign, proj)`` of one axis (:func:`axis_reversals`), with what every tail's
    columns make of it worked out once (:meth:`parts`): a search tries many tails over the
    same reversals."""

    def parts(self, after_deg) -> tuple:
        """``(past the window, -angle past it, -sign proj, sign > 0, sign < 0)`` for the
        window ``after_deg`` after each reversal [-, rad, -, -, -]."""
        cache = self.__dict__.setdefault("_parts", {})
        if after_deg not in cache:
            since, sign, proj = self
            past = since - after_deg
            cache[after_deg] = (past >= 0.0, -np.radians(np.maximum(past, 0.0)),
                                -sign * proj, sign > 0, sign < 0)
        return cache[after_deg]


def axis_reversals(angle, s, ratio, mu, rev, turn_deg=0.0) -> tuple:
    """Per axis of an arc over ``angle`` (arguments of :func:`tail_columns`), ``(since,
    sign, proj)``: the angle travelled since the axis last reversed, the sign of its
    velocity since, and the cosine of the radius with the axis; the reversals turned by
    ``turn_deg`` along the travel [deg, -, -]."""
    if turn_deg:
        angle = angle - s * np.radians(turn_deg)
        rev = None if rev is None else rev - s * np.radians(turn_deg)
    c, n = np.cos(angle), np.sin(angle)
    sx, sy = axis_signs(angle if rev is None else rev, s, ratio * mu)
    u = s * np.degrees(angle)
    return (AxisReversal(((u % 180.0), sx, c)),
            AxisReversal((((u - s * 90.0) % 180.0), sy, n)))


def tail_block(arc, i, n_arcs, mu, tail, angle, rev, reversals=None):
    """The tail columns of arc ``i`` (an ``Arc``) of ``n_arcs`` over ``angle``, zero in the
    other arcs' (:func:`tail_columns`; ``reversals`` its :func:`axis_reversals`, where
    worked out already) [m/m]."""
    out = np.zeros((angle.size, 4 * n_arcs))
    out[:, 4 * i:4 * i + 4] = np.column_stack(tail_columns(
        angle, arc.s, arc.ratio, mu, rev, arc.after_deg, tail, reversals))
    return out


def tail_matrix(pb, mu, tail, reversals=None):
    """The tail columns ``tail`` over the fitted samples of every arc of ``pb`` (a
    ``FitProblem``), each reversing about its centre (:func:`tail_block`); ``reversals``
    per arc, where worked out already (:func:`arc_reversals`) [m/m]."""
    n = len(pb.arcs)
    if reversals is None:
        reversals = arc_reversals(pb, mu, tail[2:])
    return np.vstack([tail_block(a, i, n, mu, tail, a.angle[m], None, r)
                      for i, (a, m, r) in enumerate(zip(pb.arcs, pb.masks, reversals,
                                                        strict=True))])


def arc_reversals(pb, mu, turn=()) -> list:
    """Per arc of ``pb``, :func:`axis_reversals` over its fitted samples, each reversing
    about its centre, turned by ``turn`` (none, or one angle [deg]): what every tail of a
    search shares [deg, -, -]."""
    return [axis_reversals(a.angle[m], a.s, a.ratio, mu, reversal_angle(p, c), *turn)
            for a, m, p, c in zip(pb.arcs, pb.masks, pb.pos, pb.centres, strict=True)]


def noise_level(res) -> float:
    """The variance of what a fit leaves times its correlation length: what one column
    fitted to it takes of its sum of squares, on average, were it noise [m^2]."""
    return float(np.mean(res**2)) * correlation_length(res)


def _tail_costs(pb, mu, res, basis, tried: dict):
    """``ssr(log_decay, shape, *turn)``: the sum of squares the fit leaves with the tails
    of that time constant [rad], shape and turn [deg] added, each kept in ``tried`` by its
    tail [m^2]."""
    base = float(res @ res)
    reversals = {}  # per turn: every tail of the search shares them

    def ssr(log_decay, shape, *turn):
        # the fit with the tails added leaves what of the residual their columns, less
        # their part in the fit's own, do not take: no refit
        tail = (float(np.exp(log_decay)), shape, *turn)
        if tail in tried:  # the search and its intervals come back to a tail
            return tried[tail]
        if turn not in reversals:
            reversals[turn] = arc_reversals(pb, mu, turn)
        t = tail_matrix(pb, mu, tail, reversals[turn])
        q, r = np.linalg.qr(t - basis @ (basis.T @ t))
        q = q[:, np.abs(np.diag(r)) > 1e-9 * max(np.abs(r).max(), 1e-300)]
        tried[tail] = cost = base - float(np.sum((q.T @ res) ** 2))
        return cost
    return ssr


def search_tail(pb, mu, waves):
    """``(decay, shape)`` of the reversals' tails that ``pb`` fits best with the servo
    mismatch ``mu`` [rad] and the cyclic errors ``waves`` [1/m], None where the tails do
    not stand out of the noise (module docstring) [rad, -]. Sets ``pb.tail_spread``: how
    far each column of the fit without the tails moves over the tails that fit as well
    (:func:`spread`) [SI], and ``pb.tail_interval``: the time constants within the 95 %
    interval of either shape that fits as well (:func:`decay_interval`) [rad]; both None
    where no tail is fitted. A transient lasting past the window, or tails whose time
    constant's ± exceeds it, fit no tail, and set ``pb.tail_family`` and
    ``pb.tail_spread`` (:func:`lingering`)."""
    pb.tail, pb.tail_spread, pb.tail_interval, pb.tail_family = None, None, None, ()
    _, res, basis = pb.solve(mu, waves)
    base = float(res @ res)
    tried = {}
    ssr = _tail_costs(pb, mu, res, basis, tried)
    grid = np.log(np.radians(DECAY_DEG))
    for shape in SHAPES:  # each shape's best on the grid refined
        j = int(np.argmin([ssr(g, shape) for g in grid]))
        minimize_scalar(ssr, bounds=(grid[max(j - 1, 0)], grid[min(j + 1, grid.size - 1)]),
                        args=(shape,), method="bounded", options={"xatol": 0.02})
    # the same tails turned away from the reversals: what they take of the residual is
    # what any such columns would, and a reversal's tail starts at the reversal
    elsewhere = base - min(ssr(g, shape, TURN_DEG) for shape in SHAPES for g in grid)
    step = min(ssr(np.log(np.radians(LONG_DEG)), shape) for shape in SHAPES)
    longest = 1.5 * np.radians(DECAY_DEG[-1])  # the step is no tail the search found
    tried = {t: c for t, c in tried.items() if len(t) == 2 and t[0] < longest}
    tail = min(tried, key=tried.get)
    pb.tail = tail
    coef, left, _ = pb.solve(mu, waves, basis=False)  # ``res`` stays the one ``ssr`` projects
    pb.tail = None
    sized = float(np.nanmax(np.abs(coef[-4 * len(pb.arcs):]))) >= MIN_TAIL_M
    # a transient lingers where its tails stand out of the noise from sample to sample
    # more than the same tails turned away do, and a step fits as well as they do
    if (sized and step <= tried[tail] + AS_WELL * noise_level(left)
            and base - tried[tail] - elsewhere > SIGNIFICANT * sample_noise(left)):
        return lingering(pb, mu, waves)
    if not (base - tried[tail] - elsewhere > SIGNIFICANT * noise_level(left) and sized):
        return None
    pb.tail_spread = spread(pb, mu, waves, coef, left, tried)
    target = tried[tail] + AS_WELL * noise_level(left)
    ends = []  # over either shape whose best fits as well, the other's too
    for shape in SHAPES:
        best = min((c, t) for t, c in tried.items() if t[1] == shape)
        if best[0] <= target:
            ends += decay_interval(lambda x, sh=shape: ssr(x, sh), np.log(best[1][0]), target)
    pb.tail_interval = (min(ends), max(ends))
    # its ± exceeds it, or the best is the longest searched: no firmer than a step
    if pb.tail_interval[1] - tail[0] > tail[0] or tail[0] > 0.99 * longest / 1.5:
        return lingering(pb, mu, waves)
    return tail


def sample_noise(res) -> float:
    """The variance of the noise from sample to sample of what a fit leaves, from the
    median of its differences' sizes (the fitted samples jump across each window left
    out): a transient the tails' shape does not describe stays out of it, where
    :func:`noise_level` takes that transient for noise alike over many samples [m^2]."""
    if res.size < 3:
        return 0.0
    return float((1.4826 * np.median(np.abs(np.diff(res)))) ** 2 / 2.0)


#: A tail as long as this is a step to the next reversal of the axis, a backlash [deg]
LONG_DEG = 180.0
#: The tails a transient lasting past the window may be, as the angle travelled in their
#: time constant: the search's, and on to :data:`LONG_DEG` [deg]
FAMILY_DEG = (*DECAY_DEG, 80.0, 120.0, LONG_DEG)


def lingering(pb, mu, waves) -> None:
    """No tail, for a transient lasting past the window (module docstring): the tails
    stand out of the noise from sample to sample (:func:`sample_noise`), and one as long
    as :data:`LONG_DEG` fits the samples as well as the best, so the data past the window
    bound neither the tails' level nor their decay, and the terms of a step at the
    reversals take what the tails do not. Sets ``pb.tail_family``: the fit without tails
    and with every tail of :data:`FAMILY_DEG` of either shape, ``(tail, coefficients,
    waves)``: none of these shapes need be the transient's (one that rises to its peak
    past the window's end fits none of them well), so each is what the samples allow, not
    only those that fit them best; and ``pb.tail_spread``: each column's largest move over
    it from the fit without tails, signed [SI]."""
    pb.tail = None
    ref = pb.solve(mu, waves, basis=False)[0]
    family = [(None, ref, waves)]
    for shape in SHAPES:
        for deg in FAMILY_DEG:
            pb.tail = (float(np.radians(deg)), shape)
            family.append((pb.tail, pb.solve(mu, waves, basis=False)[0], waves))
    pb.tail = None
    n = ref.size
    moves = np.zeros(n)
    for _, c, _ in family:
        d = np.nan_to_num(c[:n] - ref)
        moves = np.where(np.abs(d) > np.abs(moves), d, moves)
    pb.tail_family, pb.tail_spread, pb.tail_interval = tuple(family), moves, None


#: How far either side of the time constant found its interval is sought, as a factor [-]
REACH = 20.0


def decay_interval(cost, x0, target) -> tuple:
    """The time constants either side of ``exp(x0)`` at which the fit's sum of squares
    ``cost(log decay)`` rises to ``target`` (:data:`AS_WELL` noise variances above the
    best): a 95 % interval, of the shape found; a side it does not rise on within
    :data:`REACH` ends there [rad]."""
    ends = []
    for side in (-1.0, 1.0):
        x1 = x0 + side * np.log(REACH)
        if cost(x1) <= target:
            ends.append(x1)
            continue
        ends.append(brentq(lambda x: cost(x) - target, min(x0, x1), max(x0, x1), xtol=0.005))
    return float(np.exp(ends[0])), float(np.exp(ends[1]))


#: The tails within this many noise variances of the best fit as well as it: a 95 %
#: confidence region of one parameter [-]
AS_WELL = 3.84
#: At most this many of them are refitted, the best first [-]
MOST_ALIKE = 8


def spread(pb, mu, waves, coef, res, tried) -> np.ndarray:
    """How far each column of the fit without the tails moves (the largest change, signed)
    over the tails ``tried`` (``(decay, shape) -> sum of squares``) whose sum of squares
    lies within :data:`AS_WELL` noise variances of the best's: a long tail is nearly a
    step to the next reversal, a backlash, and the samples may not tell the two apart (a
    radial tail of 10 um over 40 deg fitted 0.003 % worse as an axis' tail over 31 deg,
    with a backlash 2.6 um apart). The noise variance is :func:`noise_level` of the best
    fit's residual ``res``. One value per column, in the fit's order [SI]."""
    best = min(tried.values())
    level = AS_WELL * noise_level(res)
    alike = sorted((c, t) for t, c in tried.items() if c <= best + level)[1:MOST_ALIKE + 1]
    n = coef.size - 4 * len(pb.arcs)
    moves = np.zeros(n)
    for _, t in alike:
        pb.tail = t
        d = pb.solve(mu, waves, basis=False)[0][:n] - coef[:n]
        moves = np.where(np.abs(d) > np.abs(moves), d, moves)
    pb.tail = None
    return np.nan_to_num(moves)
