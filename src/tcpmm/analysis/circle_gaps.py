"""Gaps in a circle pass's log: a time step far longer than the others, or, where the
log's time runs on evenly over missing samples, a leap of the reference path."""

from __future__ import annotations

import warnings

import numpy as np

from ..errors import InputWarning

#: A step between samples this many times their median one is a gap in the log [-].
GAP_STEPS = 5.0


def warn_gaps(t, ang, direction: str) -> bool:
    """Warn (:class:`InputWarning`) where a pass's samples break off (a step of
    :data:`GAP_STEPS` median ones or more: a gap in the log), with the time and the angles
    it spans; whether there is one [-].

    Parameters
    ----------
    t : ndarray
        Time of the pass's samples [s].
    ang : ndarray
        Their angle, unwrapped [rad].
    direction : {"ccw", "cw"}
        Direction of travel [-].
    """
    if t.size < 3:
        return False
    dt = np.diff(t)
    gaps = np.flatnonzero(dt > GAP_STEPS * np.median(dt))
    jumps = np.setdiff1d(angle_jumps(ang), gaps)
    if gaps.size == 0 and jumps.size == 0:
        return False
    if gaps.size:
        where = "; ".join(f"{dt[i]:.3g} s from {np.degrees(ang[i]) % 360:.1f} to "
                          f"{np.degrees(ang[i + 1]) % 360:.1f} deg" for i in gaps[:3])
        warnings.warn(InputWarning(
            f"the {direction.upper()} pass's samples break off ({where}"
            f"{'; ...' if gaps.size > 3 else ''}): a gap in the log; nothing is measured "
            "there, and the figures are those of the samples on either side"), stacklevel=3)
    if jumps.size:
        where = "; ".join(f"from {np.degrees(ang[i]) % 360:.1f} to "
                          f"{np.degrees(ang[i + 1]) % 360:.1f} deg at {t[i]:.4g} s"
                          for i in jumps[:3])
        warnings.warn(InputWarning(
            f"the {direction.upper()} pass's reference leaps between two samples one time "
            f"step apart ({where}{'; ...' if jumps.size > 3 else ''}), {GAP_STEPS:g} or "
            "more times its usual step: samples are missing while the time column runs on "
            "evenly (a log that stamps its samples n / rate); nothing is measured there, "
            "the figures are those of the samples on either side, and every time after "
            "it is early; log the recorder's own time stamps"), stacklevel=3)
    return True


def angle_jumps(ang) -> np.ndarray:
    """The samples after which the reference's angle moves :data:`GAP_STEPS` or more times
    its median step that moves at all (a command the log holds for some samples and then
    moves, as an interpolator's at its own period, moves in steps all alike) [-].

    Parameters
    ----------
    ang : ndarray
        The reference path's angle, unwrapped [rad].
    """
    da = np.abs(np.diff(ang))
    moving = da[da > 0]
    if moving.size < 3:
        return np.zeros(0, dtype=int)
    return np.flatnonzero(da > GAP_STEPS * np.median(moving))


def in_gaps(travel, at, period=None) -> np.ndarray:
    """Which of the angles ``at`` lie in a gap of the samples at ``travel``: between two
    successive ones more than :data:`GAP_STEPS` times their median step apart that moves
    (:func:`angle_jumps`), where nothing is measured and an interpolation would make up
    the error [-].

    Parameters
    ----------
    travel : ndarray
        The samples' angles, in any order [rad].
    at : ndarray
        The angles asked about [rad].
    period : float, optional
        Where the angles run round (a full turn), their period: the step from the last
        sample to the first one a period on counts too [rad].
    """
    a = np.sort(np.asarray(travel, dtype=float))
    at = np.asarray(at, dtype=float)
    if period is not None and a.size:
        a = np.r_[a, a[0] + period]
        at = np.mod(at - a[0], period) + a[0]
    gap = np.zeros(max(a.size - 1, 0), dtype=bool)
    gap[angle_jumps(a)] = True  # the rule the gap warning follows
    if not gap.any():
        return np.zeros(at.shape, dtype=bool)
    i = np.clip(np.searchsorted(a, at, side="right") - 1, 0, gap.size - 1)
    return gap[i] & (at > a[i]) & (at < a[i + 1])
