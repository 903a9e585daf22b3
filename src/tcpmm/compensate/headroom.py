"""Room for the correction: an NC program planned with a share of the axes' acceleration and
jerk, the rest left to the correction.

A program interpolated at the axes' own limits leaves the correction nothing where the
feed ramps and at the corners, and that is where the TCP's error is largest. Planned with
less, the path is the same and only its timing changes: the ramps and corners take longer,
the feed is unchanged. The figures before are those of the program planned at the full
limits, as the machine would run it without compensation.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..path.program import program_to_command
from ..path.settings import AXES, InterpolatorSettings

#: Share of the acceleration and jerk left to the correction of an NC program [-].
DEFAULT_HEADROOM = 0.25


def headroom_for(is_program: bool, headroom: float | None) -> float:
    """The headroom a command gets: the one asked or :data:`DEFAULT_HEADROOM` for an NC
    program; 0 for a command already timed, which cannot be planned anew.

    Parameters
    ----------
    is_program : bool
        Whether the command is an NC program [-].
    headroom : float or None
        The share asked, ``None`` for the default [-].
    """
    if not is_program:
        if headroom:
            raise InputError("headroom re-plans an NC program (--gcode); a command file is "
                             "already timed")
        return 0.0
    return DEFAULT_HEADROOM if headroom is None else headroom


def planned_settings(settings: InterpolatorSettings, headroom: float) -> InterpolatorSettings:
    """The interpolator settings with the path's and every axis's acceleration, the
    path's jerk and the axes' jerk at a transition times ``1 - headroom``, and a sharp
    corner's velocity step held to the headroom's share of the axes' full acceleration:
    braking into the corner at the planned limit and the step then add up to the full
    limit, not beyond it.

    Parameters
    ----------
    settings : InterpolatorSettings
        The machine's settings [-].
    headroom : float
        Share left to the correction, in [0, 1) [-].
    """
    if not 0.0 <= headroom < 1.0:
        raise InputError(f"headroom {headroom:g} is not in [0, 1): the share of the axes' "
                         "acceleration and jerk left to the correction")
    k = 1.0 - headroom
    trans = settings.transition_jerk_m_per_s3
    return settings.model_copy(update={
        "path_accel_m_per_s2": settings.path_accel_m_per_s2 * k,
        "path_jerk_m_per_s3": settings.path_jerk_m_per_s3 * k,
        "transition_jerk_m_per_s3": None if trans is None else trans * k,
        "corner_step_share": min(settings.corner_step_share, planned_step_share(headroom)),
        "axis_accel_m_per_s2": {a: v * k for a, v in settings.axis_accel_m_per_s2.items()}})


def planned_step_share(headroom: float) -> float:
    """The share of an axis's full acceleration a sharp corner's velocity step may take
    when planned with ``headroom`` (:func:`planned_settings`): with the braking into the
    corner at ``1 - headroom`` of it, the two add up to the full limit [-]."""
    return headroom / (1.0 - headroom)


def within_bounds(settings: InterpolatorSettings, bounds: dict) -> InterpolatorSettings:
    """The settings with the path's and each axis's acceleration, the path's jerk and the
    axes' jerk at a transition (:func:`transition_within`) no higher than the limits the
    compensated command keeps: the headroom is a share of
    those, and a plan at the interpolator's own higher limits would leave the correction
    less than its share, or none (0.8 m/s^2 given on a 1 m/s^2 interpolator left 6 %
    where 25 % was said). A trapezoid given a jerk limit becomes an S-curve at it: its
    ramps step the acceleration within one period, 750 m/s^3 at 0.75 m/s^2 and 1 ms
    where 50 was given.

    Parameters
    ----------
    settings : InterpolatorSettings
        The machine's settings [-].
    bounds : dict of str to AxisBounds
        The limits per axis (:func:`~tcpmm.compensate.bounds.machine_bounds`) [SI].
    """
    own = dict(zip(AXES, settings.axis_accel(), strict=True))
    lower = {a: b.accel for a, b in bounds.items() if b.accel < own.get(a, np.inf)}
    # the path's vector is held by the axes' limits together, not by the slowest one's
    path = min(settings.path_accel_m_per_s2, max(b.accel for b in bounds.values()))
    jerk = min(settings.jerk(), max(b.jerk for b in bounds.values()))
    trans = transition_within(settings.transition_jerk_m_per_s3, bounds)
    if not lower and path == settings.path_accel_m_per_s2 and jerk == settings.jerk() \
            and trans == settings.transition_jerk_m_per_s3:
        return settings
    # a trapezoid steps the acceleration within one period at every ramp: a jerk given
    # is kept only by an S-curve at it
    return settings.model_copy(update={
        "path_accel_m_per_s2": path, "transition_jerk_m_per_s3": trans,
        **({"profile": "scurve", "path_jerk_m_per_s3": jerk} if np.isfinite(jerk) else {}),
        "axis_accel_m_per_s2": {**settings.axis_accel_m_per_s2, **lower}})


def scurve_plan(settings: InterpolatorSettings, bounds: dict, headroom: float) -> dict | None:
    """The S-curve a trapezoid interpolator's program was planned with to keep the jerk
    given (:func:`within_bounds`, :func:`planned_settings`): its jerk along the path and at
    a block transition and the jerk given; ``None`` where the program kept its own
    profile; ``settings`` and ``bounds`` as :func:`within_bounds` takes them, ``headroom``
    the share left to the correction, 0 where the program is written as programmed
    [m/s^3].
    """
    if not headroom or settings.profile != "trapezoid":
        return None
    planned = planned_settings(within_bounds(settings, bounds), headroom)
    if planned.profile != "scurve":
        return None
    return {"path_jerk_m_per_s3": planned.path_jerk_m_per_s3,
            "transition_jerk_m_per_s3": planned.transition_jerk_m_per_s3,
            "given_jerk_m_per_s3": min(b.jerk for b in bounds.values())}


def scurve_words(plan: dict) -> str:
    """What :func:`scurve_plan` planned the program with, and why, in a line [-]."""
    return (f"planned with an S-curve, {plan['path_jerk_m_per_s3']:.3g} m/s³ along the path "
            f"and {plan['transition_jerk_m_per_s3']:.3g} at block transitions (the jerk "
            f"given, {plan['given_jerk_m_per_s3']:.3g}, less the headroom): the model's "
            "interpolator is a trapezoid, whose ramps step the acceleration within one "
            "period, far beyond the jerk given")


def transition_within(own: float | None, bounds: dict) -> float | None:
    """The axes' jerk at a transition where the curvature jumps
    (:mod:`tcpmm.path.transitions`) that a plan within ``bounds`` keeps: the interpolator's
    own, ``None`` for none, no higher than the lowest jerk an axis is given. The path's
    profile limits the jerk along the path only; at a line's tangent join into an arc an
    axis's acceleration steps by ``v^2 / r`` within one period, and the correction could
    add nothing there to a command already beyond the limit (149 m/s^3 on a line into a
    circle of 35 mm at F5000 and 1 ms, against 50) [m/s^3].

    Parameters
    ----------
    own : float or None
        The interpolator's ``transition_jerk_m_per_s3`` [m/s^3].
    bounds : dict of str to AxisBounds
        The limits per axis (:func:`~tcpmm.compensate.bounds.machine_bounds`) [SI].
    """
    given = min(b.jerk for b in bounds.values())
    if not np.isfinite(given):
        return own
    return given if own is None else min(own, given)


def program_with_headroom(program, settings: InterpolatorSettings, headroom: float,
                          bounds: dict | None = None, full=None):
    """The program interpolated at the full limits and with the headroom.

    Parameters
    ----------
    program : str or Path
        NC program text or file [-].
    settings : InterpolatorSettings
        The machine's settings [-].
    headroom : float
        Share of the acceleration and jerk left to the correction [-].
    bounds : dict of str to AxisBounds, optional
        The limits the compensated command keeps: the plan with the headroom is made
        within them (:func:`within_bounds`) [SI].
    full : Command, optional
        The program at the full limits, where the caller has interpolated it [m].

    Returns
    -------
    tuple of Command
        ``(at the full limits, planned with the headroom)`` [m].
    """
    full = program_to_command(program, settings) if full is None else full
    if headroom == 0.0:
        return full, full
    own = settings if bounds is None else within_bounds(settings, bounds)
    return full, program_to_command(program, planned_settings(own, headroom))


def corner_steps_s(program, settings: InterpolatorSettings, headroom: float,
                   planned_s: float, bounds: dict | None = None) -> float:
    """How much of the program's time planned with ``headroom`` its sharp corners take for
    their smaller velocity step alone: ``planned_s`` less the duration planned, within the
    same limits, with the corners' step at the machine's own share. A curve posted as
    short G1 lines without a blending tolerance turns at every block, a sharp corner each
    [s].

    Parameters
    ----------
    program : str or Path
        NC program text or file [-].
    settings : InterpolatorSettings
        The machine's settings [-].
    headroom : float
        Share of the acceleration and jerk left to the correction [-].
    planned_s : float
        The duration planned with the headroom [s].
    bounds : dict of str to AxisBounds, optional
        The limits ``planned_s`` was planned within (:func:`program_with_headroom`): the
        time a lower limit adds to every ramp is not the corners' [SI].
    """
    own = settings if bounds is None else within_bounds(settings, bounds)
    steps = planned_settings(own, headroom).model_copy(
        update={"corner_step_share": own.corner_step_share})
    return max(0.0, planned_s - float(program_to_command(program, steps).time_s[-1]))


def worse_than_programmed(scores: dict) -> list[str]:
    """The figures a compensation makes worse than the program as programmed by more than
    the sensors' resolution (:data:`tcpmm.compensate.robust.EQUAL_M`), each as ``label
    before -> after um``: the draws judge the correction against the plan it was learned
    on, and a slower plan can itself make a figure worse. The corners' overshoot counts
    too: the corners' guard holds each corner against the slower plan's, which need not
    be the program's. Every corner counts, not only the one furthest passed: a corner
    the program hardly passes can be run past where another's overshoot stays the
    largest [-].

    Parameters
    ----------
    scores : dict
        ``Compensation.scores`` (:func:`tcpmm.compensate.predicted_scores`) [-].
    """
    from .cornerguard import corner_place
    from .robust import EQUAL_M
    from .scores import SCORE_FIGURES, before_after, corner_rises

    equal_um = EQUAL_M * 1e6
    return [f"{label} {b:.2f} -> {a:.2f} µm"
            for label, b, a in before_after(scores, figures=SCORE_FIGURES)
            if a > b + equal_um] + [
        f"corner overshoot{corner_place(at)} {b:.2f} -> {a:.2f} µm"
        for at, b, a in corner_rises(scores, equal_um)]


def on_the_program(machine, full, comp, bounds, relearn, circle=None):
    """The compensation ``comp`` of a program planned with headroom, or one of the program
    as programmed (``full``): written as programmed where the draws keep no share of
    ``comp`` (:func:`as_programmed`), learned again on it (``relearn()``, its figures made
    worse named in ``robustness["relearned"]``) where a figure ends worse than the
    program's (:func:`worse_than_programmed`).

    Parameters
    ----------
    machine : Machine
        The model [SI].
    full : Command
        The program at the axes' full limits [m].
    comp : Compensation
        The compensation of the plan with headroom, judged by draws [-].
    bounds : dict of str to AxisBounds
        The axes' limits [-].
    relearn : callable
        ``relearn()``: the compensation of ``full``, judged by the same draws [-].
    circle : tuple, optional
        ``(radius, centre, plane)`` of the circle the program holds [m, m, -].

    Returns
    -------
    Compensation, bool
        The compensation, and whether it is of the plan with headroom [-].
    """
    worse = worse_than_programmed(comp.scores) if comp.applied else []
    if worse:
        again = relearn()
        again.robustness["relearned"] = worse
        return again, False
    if not comp.applied:
        return as_programmed(machine, full, bounds, comp, circle), False
    return comp, True


#: What the draws say of a command after its correction: its regions' errors, the
#: samples' rises and the circle's figures on the worst draw [-].
DRAWN_AFTER = ("regions", "local_rise", "circle")


def as_programmed(machine, full, bounds, comp, circle=None):
    """The program at the axes' full limits, uncorrected, where the draws keep no share of
    the correction learned on its slower plan: the headroom serves only the correction,
    and the slower plan alone, which no draw has judged, can make a figure worse. The
    draws' shares of ``comp`` are kept; what they say of its command after
    (:data:`DRAWN_AFTER`) is left out: that is the slower plan, not the program written
    (its worst draw read 733 µm on bench H's circle, which the true machine ran at 920).
    The arguments as :func:`on_the_program` takes them, ``comp`` with no share of it
    applied [-].

    Returns
    -------
    Compensation
        Of ``full``, uncorrected, scored [-].
    """
    from ..analysis.circle_find import circle_where
    from .learning import compensate
    from .scores import predicted_scores

    plain = compensate(machine, full, iterations=1, bounds=bounds)
    for a in plain.factors:
        plain.factors[a] = np.zeros_like(plain.factors[a])
    plain.robustness = {**{k: v for k, v in comp.robustness.items() if k not in DRAWN_AFTER},
                        "as_programmed": True}
    plain.trusted = np.zeros(plain.reference.time_s.size, dtype=bool)
    plain.scores = predicted_scores(machine, plain, **circle_where(circle))
    plain.settings = {**comp.settings, "hold_samples": plain.settings["hold_samples"],
                      "programmed_duration_s": float(full.time_s[-1]),
                      "planned_duration_s": float(full.time_s[-1])}
    return plain
