"""What the compensated command may ask of an axis: velocity, acceleration and jerk from the
model's interpolation settings, and the servo's current limit.

A limit applies where the programmed command itself stays within it; where the program
already asks for more, the compensation may not ask for more than the program does.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..path.limits import OVER_SHARE, derivative, peak
from ..path.settings import AXES, InterpolatorSettings

#: Share of the current limit the nominal compensated run may use [-].
CURRENT_SHARE = 0.95

#: Length of the window over which a correction is scaled back around an excess [s].
SHRINK_WINDOW_S = 0.03

#: Length of the zero-phase Hann window whose weighted mean is a correction's slow part
#: (:func:`fit_within`): the servo's lag and the structure's deflection change as the
#: program's own acceleration does, over a tenth of a second and more; a friction
#: transient and a mode's ringing over a few hundredths [s].
SLOW_WINDOW_S = 0.12


@dataclass(frozen=True)
class AxisBounds:
    """Limits of one axis.

    Parameters
    ----------
    velocity : float
        Velocity limit [m/s].
    accel : float
        Acceleration limit [m/s^2].
    jerk : float
        Jerk limit, ``inf`` where the interpolator sets none [m/s^3].
    current : float
        Current limit of the servo [A].
    """

    velocity: float
    accel: float
    jerk: float
    current: float

    def to_dict(self) -> dict:
        """The limits in SI, ``None`` for no limit [-]."""
        return {k: (None if not math.isfinite(v) else float(v)) for k, v in
                (("velocity_m_per_s", self.velocity), ("accel_m_per_s2", self.accel),
                 ("jerk_m_per_s3", self.jerk), ("current_A", self.current))}


def machine_bounds(machine, accel_m_per_s2=None, jerk_m_per_s3=None) -> dict[str, AxisBounds]:
    """Limits per axis from the model's interpolation settings and servo.

    Parameters
    ----------
    machine : Machine
        The model; without an ``interpolation`` block the interpolator's defaults
        apply [SI].
    accel_m_per_s2 : float, optional
        Acceleration limit of every axis instead of the settings' [m/s^2].
    jerk_m_per_s3 : float, optional
        Jerk limit of every axis instead of the settings' (none for a trapezoid
        profile) [m/s^3].
    """
    for name, v, opt in (("acceleration", accel_m_per_s2, "--accel-m-per-s2 [m/s^2]"),
                         ("jerk", jerk_m_per_s3, "--jerk-m-per-s3 [m/s^3]")):
        if v is not None and not (math.isfinite(v) and v > 0.0):
            raise InputError(f"the {name} limit ({opt}) must be a positive number (got {v})")
    s = InterpolatorSettings.model_validate(machine.interpolation or {})
    vel = dict(zip(AXES, s.axis_velocity(), strict=True))
    rapid = dict(zip(AXES, s.rapid(), strict=True))
    acc = dict(zip(AXES, s.axis_accel(), strict=True))
    jerk = s.jerk() if jerk_m_per_s3 is None else jerk_m_per_s3
    out = {}
    for name, axis in machine.axes.items():
        v = min(vel.get(name, math.inf), rapid.get(name, max(rapid.values())))
        a = acc.get(name, s.path_accel_m_per_s2) if accel_m_per_s2 is None else accel_m_per_s2
        out[name] = AxisBounds(v, a, jerk, axis.servo.current_limit)
    return out


def excess(reference: np.ndarray, correction: np.ndarray, period_s: float,
           bounds: AxisBounds, kept: np.ndarray | None = None) -> np.ndarray:
    """Largest factor the correction may keep at each sample, 1 where nothing is exceeded.

    Parameters
    ----------
    reference, correction : ndarray
        Programmed command and the correction added to it [m].
    period_s : float
        Command period [s].
    bounds : AxisBounds
        The axis's limits [-].
    kept : ndarray, optional
        A part of the correction added as it is, ``correction`` being the rest: the
        factor is the rest's, in the room the program and ``kept`` leave [m].
    """
    keep = np.ones_like(reference)
    for order, lim in ((1, bounds.velocity), (2, bounds.accel), (3, bounds.jerk)):
        if not math.isfinite(lim):
            continue
        r = derivative(reference, order, period_s, from_rest=True)
        c = derivative(correction, order, period_s, from_rest=True)
        allowed = np.maximum(lim, np.abs(r))
        if kept is not None:
            r = r + derivative(kept, order, period_s, from_rest=True)
        over = np.abs(r + c) > allowed * (1 + 1e-9)
        room = np.clip((allowed - np.abs(r)) / np.maximum(np.abs(c), 1e-300), 0.0, 1.0)
        keep = np.where(over, np.minimum(keep, room), keep)
    return keep


def shrink(correction: np.ndarray, keep: np.ndarray, period_s: float) -> np.ndarray:
    """The correction scaled back smoothly around the samples whose ``keep`` is below 1 [m]."""
    w = max(3, round(SHRINK_WINDOW_S / period_s))
    low = keep.copy()
    for k in np.flatnonzero(keep < 1.0):  # the whole window down to the sample's factor
        lo, hi = max(0, k - w), min(keep.size, k + w + 1)
        low[lo:hi] = np.minimum(low[lo:hi], 0.9 * keep[k])
    kernel = np.hanning(2 * w + 1)
    smooth = np.convolve(low - 1.0, kernel / kernel.sum(), mode="same") + 1.0
    # The box reaches a window beyond each sample, so the smoothed factor at the sample
    # itself is the box's value.
    return correction * smooth


def fit_within(reference: np.ndarray, correction: np.ndarray, period_s: float,
               bounds: AxisBounds, rounds: int = 40) -> np.ndarray:
    """The correction scaled back until the command keeps the velocity, acceleration and
    jerk limits (:func:`excess`): first its fast part alone, what its mean over
    :data:`SLOW_WINDOW_S` leaves, then, where the slow part alone exceeds a limit, the
    whole (:func:`scaled_within`) [m].

    Where an axis reverses, the program's own acceleration leaves the least room, and the
    correction's fast part (against the friction's transient) asks the most. Scaled back
    whole, the correction also lost its slow part there, the servo's lag it takes away:
    on bench C's model at F10000 the circle's radius dipped by up to 80 µm at each
    quadrant, and its largest spike grew from 44 to 85 µm. A fast part scaled back to
    nothing leaves its mean over the window in the slow part: a bump the limit does not
    allow is smoothed, not dropped.
    """
    if np.all(excess(reference, correction, period_s, bounds) >= 1.0):
        return correction
    w = max(1, round(SLOW_WINDOW_S / (2.0 * period_s)))
    window = np.hanning(2 * w + 1)
    slow = np.convolve(correction, window / window.sum(), mode="same")
    fast = correction - slow
    for _ in range(rounds):
        keep = excess(reference, fast, period_s, bounds, kept=slow)
        if np.all(keep >= 1.0):
            return slow + fast
        fast = shrink(fast, keep, period_s)
    return scaled_within(reference, slow + fast, period_s, bounds, rounds)


def scaled_within(reference: np.ndarray, correction: np.ndarray, period_s: float,
                  bounds: AxisBounds, rounds: int = 40) -> np.ndarray:
    """The whole correction scaled back until the command keeps the velocity,
    acceleration and jerk limits (:func:`excess`) [m]."""
    for _ in range(rounds):
        keep = excess(reference, correction, period_s, bounds)
        if np.all(keep >= 1.0):
            return correction
        correction = shrink(correction, keep, period_s)
    # What is left over: the correction dropped wherever a limit is still exceeded.
    keep = excess(reference, correction, period_s, bounds)
    return shrink(correction, np.where(keep < 1.0, 0.0, 1.0), period_s)


#: Per limit an axis's command is held to: the order of its derivative, the attribute of
#: :class:`AxisBounds` that holds it and its unit [-].
LIMITS = {"velocity": (1, "velocity", "m/s"), "acceleration": (2, "accel", "m/s²"),
          "jerk": (3, "jerk", "m/s³")}


def over_limits(command, reference, bounds: dict) -> list[tuple]:
    """Where the compensated command goes beyond an axis's velocity, acceleration or jerk
    limit, and how far the program as planned does so itself: the interpolator passes a
    sharp corner with a velocity step of the axis's acceleration times its period, which
    the samples read as up to half as much again for one period, and a tangent junction
    of a line or arc into an arc of another curvature with a step of the acceleration,
    which they read as a jerk of that step over one period; the correction adds nothing
    there (:func:`excess` keeps it within what the program takes).

    Parameters
    ----------
    command, reference : Command
        The compensated command and the program as planned [m].
    bounds : dict of str to AxisBounds
        The limits [-].

    Returns
    -------
    list of tuple
        ``(axis, "velocity", "acceleration" or "jerk", peak, limit, the program's own
        peak)`` [SI].
    """
    out = []
    T = command.period_s
    for name, x in command.positions.items():
        b = bounds.get(name)
        if b is None or name not in reference.positions:
            continue
        for what, (order, attr, _) in LIMITS.items():
            most, lim = peak(x, order, T, from_rest=True), getattr(b, attr)
            if math.isfinite(lim) and most > lim * (1 + OVER_SHARE):
                out.append((name, what, most, lim,
                            peak(reference.positions[name], order, T, from_rest=True)))
    return out


def over_limit_words(command, reference, bounds: dict, planner: dict | None = None,
                     headroom: float = 0.0) -> list[str]:
    """A sentence per axis and limit the compensated command goes beyond
    (:func:`over_limits`), with the program's own peak and its cause: a command file's is
    its own; a program planned within the limit goes beyond it only at a sharp corner's
    velocity step or, in jerk, at a tangent junction's step of curvature (told apart on
    the path where its peak is, :func:`velocity_steps`), one planned to a higher limit of
    the model's interpolator wherever it ramps.

    Parameters
    ----------
    command, reference : Command
        The compensated command and the program as planned [m].
    bounds : dict of str to AxisBounds
        The limits kept [-].
    planner : dict of str to AxisBounds, optional
        The interpolator's own limits, where the command was planned from an NC program,
        not read from a file [-].
    headroom : float
        The headroom ``reference`` was planned with, 0 where it is the program as
        programmed: named so, as the console names the program at the full limits "as
        programmed" a line before [-].
    """
    unit = {what: u for what, (_, _, u) in LIMITS.items()}
    plan_name = f"planned with headroom {headroom:g}" if headroom else "as programmed"
    out = []
    for name, what, most, lim, own in over_limits(command, reference, bounds):
        if planner is None:
            itself = f"the command file reaches {own:.3g} itself"
        else:
            plan = getattr(planner[name], LIMITS[what][1])
            itself = (f"the program {plan_name} reaches {own:.3g} itself ("
                      f"{_step_cause(reference, name, what)})" if plan <= lim * (1 + 1e-9) else
                      f"the program {plan_name} reaches {own:.3g} itself: the model's "
                      f"interpolator plans it {_planned(plan, what, unit[what])}, not to the "
                      "limit given; set that limit in the model's interpolation settings"
                      + _scurve_remedy(what, plan))
        by = ("the correction adds nothing beyond it" if most <= own * (1 + 1e-6) else
              f"the correction takes it {most - own:.3g} {unit[what]} further")
        out.append(f"{name}: {what} up to {most:.3g} {unit[what]} for a sample, above its "
                   f"limit of {lim:.3g}: {itself}, {by}")
    return out


def _scurve_remedy(what: str, plan: float) -> str:
    """How a program planned with no jerk limit keeps the one given (:func:`tcpmm.
    compensate.headroom.within_bounds`), where that is the cause [-]."""
    if what != "jerk" or math.isfinite(plan):
        return ""
    return (", or compensate the NC program with --headroom above 0: it is then planned "
            "with an S-curve within the jerk given (where the draws keep the correction "
            "learned on that plan)")


def _planned(value: float, what: str, unit: str) -> str:
    return f"with no {what} limit" if value == math.inf else f"to {value:.3g} {unit}"


def _step_cause(reference, name: str, what: str) -> str:
    """Why the program as planned goes beyond a limit it was planned within: a sharp
    corner's velocity step, or in jerk a tangent junction's step of curvature, as the
    path shows where the axis's peak is. A curvature step takes the acceleration no
    further than the curve's own, which the plan keeps within the limit [-]."""
    if what == "velocity":
        return "its feed, beyond the axis's velocity limit"
    x = reference.positions[name]
    order = LIMITS[what][0]
    k = int(np.argmax(np.abs(derivative(x, order, reference.period_s, from_rest=True))))
    if order == 3 and not velocity_steps(reference, k):
        return ("a step of curvature where a line or an arc joins an arc tangentially, or "
                "at the corners of a curve posted as short blocks: the velocity's direction "
                "turns there no faster than along the curve, its acceleration steps, so the "
                "jerk is unbounded within one period; an NC program compensated with "
                "headroom (--headroom above 0) is planned slower there, within the jerk "
                "given, and transition_jerk_m_per_s3 in the model's interpolation settings "
                "holds the program itself to it")
    return "a sharp corner's velocity step, one period"


#: How many times the turn of the velocity's direction on either side a turn about a
#: sample takes to be a corner, and the least turn that is one (a kink of a polyline of
#: 0.5 deg at F5000 steps the velocity by 0.7 mm/s: a jerk of 700 m/s³ at 1 ms) [-, rad].
CORNER_TURN_RATIO, CORNER_TURN_RAD = 3.0, math.radians(0.01)

#: Steps of the path over which its turn is taken: the stencil of a third difference
#: and one on either side [-].
TURN_SPAN = 5


def velocity_steps(command, k: int) -> bool:
    """Whether the path's velocity changes direction abruptly about sample ``k``: its
    direction turns from the step into sample ``k - 4`` to the step into ``k + 1`` (the
    samples a difference of up to third order at ``k`` is taken of, and one more) by more
    than :data:`CORNER_TURN_RAD` and :data:`CORNER_TURN_RATIO` times what it turns over
    as many steps just before and just after, which is the path's curvature there; at a
    tangent junction it turns no faster than the curvature on either side [-].

    Parameters
    ----------
    command : Command
        The path [m].
    k : int
        The sample [-].
    """
    v = np.diff(np.array(list(command.positions.values())), axis=1)  # v[:, i]: into i + 1

    def turn(i: int) -> float:
        """Angle between the steps into samples ``i`` and ``i + TURN_SPAN`` [rad]."""
        if i < 1 or i + TURN_SPAN > v.shape[1]:
            return 0.0
        a, b = v[:, i - 1], v[:, i + TURN_SPAN - 1]
        cross = np.linalg.norm(np.outer(a, b) - np.outer(b, a)) / np.sqrt(2)  # |a||b| sin
        return float(np.arctan2(cross, a @ b))

    start = k - TURN_SPAN + 1
    around = max(turn(start - TURN_SPAN), turn(start + TURN_SPAN))
    return turn(start) > max(CORNER_TURN_RAD, CORNER_TURN_RATIO * around)
