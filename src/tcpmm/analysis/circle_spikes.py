"""Reversal spikes and lobes at the quadrant points A-D of a circle (docs/formats.md
section 4): the radial error in the window after each point, against its median in the
window before it."""

from __future__ import annotations

import numpy as np

QUADRANTS = {"A": 0.0, "B": 90.0, "C": 180.0, "D": 270.0}
AFTER_DEG, BEFORE_DEG = (0.0, 20.0), (-30.0, -5.0)


#: the share of its steady speed below which a pass's path is taken as still speeding up
#: or already slowing down at its ends [-]; steps over which the speed at either end is
#: taken [-], and how many times the scatter of such speeds in the steady middle (a robust
#: standard deviation) it must fall below the steady speed by (a log's time stamps jitter)
STEADY_SHARE, _END_STEPS, _SCATTER = 0.99, 5, 5.0


def end_steps(n: int) -> int:
    """Steps over which a pass of ``n`` samples' speed at its ends is taken [-]."""
    return max(1, min(_END_STEPS, (n - 3) // 8))


def slower_than(span, level: float) -> float:
    """The speed below which the ``end_steps`` spans ``span`` of a pass whose steady speed
    is ``level`` are taken as not steady: below :data:`STEADY_SHARE` of it and below what
    the steady middle's own spans scatter to [as ``span``]."""
    mid = span[span.size // 4:3 * span.size // 4]
    return min(STEADY_SHARE * level,
               level - _SCATTER * 1.4826 * np.median(np.abs(mid - np.median(mid))))


def steady_travel(u) -> tuple[float, float]:
    """The first and last travel angle [deg] between which the path ``u`` (travel angles,
    increasing, of samples equally spaced in time) moves at its steady speed: a window
    reaching into a feed ramp at either end reads the servo's lag changing with the feed
    as a spike (a 220 deg arc whose command slowed to a stop 20 deg after D read a spike
    of -17.9 um there, where 4 um was injected). Only the ends are cut; a gap in the log
    is said where it is found."""
    if u.size < 8:
        return float(u.min()), float(u.max())
    m = end_steps(u.size)
    span = np.abs(u[m:] - u[:-m])
    on = np.flatnonzero(span >= slower_than(span, np.median(span)))
    steady = u[on[0]:on[-1] + m + 1] if on.size else u
    return float(steady.min()), float(steady.max())


def _travel(angle_rad, direction: str) -> tuple:
    """``(sign, u, first, last)``: the direction's sign, the travel-direction angle ``u`` of
    every sample and the first and last of the path where it moves at its steady speed
    (:func:`steady_travel`), which every quadrant point's crossings share [-, deg]."""
    sign = 1.0 if direction == "ccw" else -1.0
    u = sign * np.degrees(angle_rad)  # increasing along the travel
    return sign, u, *steady_travel(u)


def _crossings(travel, deg: float) -> list:
    """The travel-direction angles [deg] at which the path of ``travel`` (:func:`_travel`)
    crosses the point at ``deg`` with both the window before it and the window after it
    on the path where it moves at its steady speed [deg]."""
    sign, _, first, last = travel
    at = sign * deg
    lo = np.ceil((first - BEFORE_DEG[0] - at) / 360.0 - 1e-9)
    hi = np.floor((last - AFTER_DEG[1] - at) / 360.0 + 1e-9)
    return [at + 360.0 * k for k in np.arange(lo, hi + 1)]


def spike_windows(angle_rad, direction: str, lead_deg: float = 0.0, skip_deg: float = 0.0):
    """``(P, before, after)`` per quadrant point: the masks of the samples 30 to 5 deg
    before it and of the 20 deg after it (and ``lead_deg`` before it, or without the first
    ``skip_deg`` after it), pooled over every crossing of P whose windows both lie on the
    path; ``(P, None, None)`` where P is never crossed so (the path starts or ends at P)
    [-]."""
    travel = _travel(angle_rad, direction)
    u = travel[1]
    for name, deg in QUADRANTS.items():
        at = _crossings(travel, deg)
        if not at:
            yield name, None, None
            continue
        d = u[:, None] - np.asarray(at)[None, :]
        before = ((d >= BEFORE_DEG[0]) & (d <= BEFORE_DEG[1])).any(axis=1)
        after = ((d >= AFTER_DEG[0] - lead_deg) & (d > skip_deg if skip_deg > 0 else True)
                 & (d <= AFTER_DEG[1])).any(axis=1)
        if not (before.any() and after.any()):  # sampled too coarsely to hold the windows
            yield name, None, None
            continue
        yield name, before, after


def _after_reversal(angle_rad, e, direction: str, lead_deg: float = 0.0,
                    skip_deg: float = 0.0):
    """``(P, e - b)`` over the 20 deg after each quadrant point P (and ``lead_deg``
    before it, or without the first ``skip_deg`` after it), pooled over every crossing of
    P whose windows both lie on the path; ``None`` where P is never crossed so (the path
    starts or ends at P) [m]."""
    yield from _deviations(spike_windows(angle_rad, direction, lead_deg, skip_deg), e)


def _deviations(windows, e):
    """``(P, e - b)`` over the ``windows`` of :func:`spike_windows`, ``None`` where P is
    never crossed so [m]."""
    for name, before, after in windows:
        yield name, None if before is None else e[after] - np.median(e[before])


def uncrossed_quadrants(angle_rad, direction: str) -> list:
    """Quadrant points the path does not cross with 30 deg before and 20 deg after them on
    it, as when a circle starts or ends at one [-].

    Parameters
    ----------
    angle_rad : ndarray
        Angle about the nominal centre, CCW from +X, unwrapped [rad].
    direction : {"ccw", "cw"}
        Direction of travel [-].
    """
    travel = _travel(angle_rad, direction)
    return [name for name, deg in QUADRANTS.items() if not _crossings(travel, deg)]


def _spike(dev) -> float:
    return float("nan") if dev is None else float(dev[np.argmax(np.abs(dev))])


def _lobes(dev) -> tuple:
    nan = float("nan")
    return (nan, nan) if dev is None else (float(dev.max()), float(dev.min()))


def reversal_spikes(angle_rad, e, direction: str, lead_deg: float = 0.0,
                    skip_deg: float = 0.0) -> dict:
    """Signed reversal spike at A-D (docs/formats.md section 4); with ``lead_deg`` its
    window starts that much before the point, where an axis that leads the other by a
    servo mismatch reverses; with ``skip_deg`` it leaves out that much after the point,
    where the axis may reverse a little later than a fit placed its step [m]."""
    return spikes_in(spike_windows(angle_rad, direction, lead_deg, skip_deg), e)


def spikes_in(windows, e) -> dict:
    """:func:`reversal_spikes` of ``e`` over the ``windows`` of :func:`spike_windows` (as
    a list), which many radial errors over one path share [m]."""
    return {name: _spike(dev) for name, dev in _deviations(windows, e)}


def reversal_lobes(angle_rad, e, direction: str) -> dict:
    """Rise and fall after each quadrant point, ``{P: (max(e - b), min(e - b))}`` over
    the window of the reversal spike; the spike is the one larger in magnitude, so where
    the two are of similar size a small change turns its sign [m]."""
    return {name: _lobes(dev) for name, dev in _after_reversal(angle_rad, e, direction)}


def spikes_and_lobes(angle_rad, e, direction: str) -> tuple[dict, dict]:
    """:func:`reversal_spikes` and :func:`reversal_lobes` from one pass over the
    windows [m]."""
    devs = dict(_after_reversal(angle_rad, e, direction))
    return ({n: _spike(d) for n, d in devs.items()}, {n: _lobes(d) for n, d in devs.items()})
