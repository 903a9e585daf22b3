"""The circle a command holds, where no radius is given: a circular test's command, found
from the command alone.

A circular test is judged by its reversal spikes and its circular deviation G, about the
circle it was programmed on. A command file holds only positions, so the circle is taken
from them: a least-squares circle fitted to the samples that lie on it (the feed-in line,
a lead-out and a filter's start and stop transients set aside by trimming), kept only where
the path runs at least one whole turn on it (:func:`.circle_passes.find_stretches`) and
that turn holds most of the motion. A square, a spiral or a program that merely contains a
small circle is no circular test and gives ``None``.
"""

from __future__ import annotations

import numpy as np

from .circle_command import command_centre
from .circle_passes import algebraic_circle, find_stretches

__all__ = ["circle_said", "circle_where", "command_circle", "judged_circle"]

#: Radial distance from the fitted circle, as a share of its radius, within which a sample
#: counts as on it while the fit is trimmed: a controller's filter pulls a circle in by
#: 0.1-0.15 % at speed, and its start and stop lie further off [-].
TRIM_SHARE = 5e-3
#: The same, last, about the circle so fitted: its steady part alone, where a filtered
#: command has settled on its radius [-].
STEADY_SHARE = 2e-4
#: Share of the moving samples the whole turns must hold: the circle is the program [-].
HELD_SHARE = 0.5
#: The centre and radius are given to this [m]: a command's own rounding is below it.
ROUND_M = 1e-7


def _seed(x: np.ndarray, y: np.ndarray, moving: np.ndarray) -> tuple:
    """Centre and radius most of the path turns about: the median of the circles through
    three points a few degrees apart along it (a straight stretch's are at infinity), so
    that a feed-in, a lead-out or a semicircle into the circle does not pull the first fit
    off it, as it pulls a least-squares circle of every point [m]."""
    k = max(1, moving.size // 400)
    i = moving[: moving.size - 2 * k]
    ax, ay, bx, by = x[i], y[i], x[i + k], y[i + k]
    cx_, cy_ = x[i + 2 * k], y[i + 2 * k]
    d = 2.0 * (ax * (by - cy_) + bx * (cy_ - ay) + cx_ * (ay - by))
    with np.errstate(divide="ignore", invalid="ignore"):
        ux = ((ax**2 + ay**2) * (by - cy_) + (bx**2 + by**2) * (cy_ - ay)
              + (cx_**2 + cy_**2) * (ay - by)) / d
        uy = ((ax**2 + ay**2) * (cx_ - bx) + (bx**2 + by**2) * (ax - cx_)
              + (cx_**2 + cy_**2) * (bx - ax)) / d
    r = np.where(np.isfinite(ux) & np.isfinite(uy), np.hypot(ax - ux, ay - uy), np.inf)
    if r.size == 0 or not np.isfinite(np.median(r)):
        return (0.0, 0.0), np.inf
    finite = np.isfinite(r)
    return (float(np.median(ux[finite])), float(np.median(uy[finite]))), float(np.median(r))


def command_circle(positions: dict, plane: tuple) -> tuple | None:
    """``(radius, centre)`` of the circle the command runs in ``plane``, where it is a
    circular test (module docstring), else ``None`` [m, m].

    Parameters
    ----------
    positions : dict of str to ndarray
        Command position per axis, sampled [m].
    plane : tuple of str
        The plane's two axes [-].
    """
    if not all(a in positions for a in plane):  # a command of fewer axes runs no circle
        return None
    x, y = (np.asarray(positions[a], dtype=float) for a in plane)
    step = np.hypot(np.diff(x), np.diff(y))
    moving = np.flatnonzero(step > 0.0)
    if moving.size < 8:
        return None
    centre, radius = _seed(x, y, moving)
    for share in (TRIM_SHARE, TRIM_SHARE, STEADY_SHARE):  # what lies on it, fitted again
        if not 0.0 < radius < np.inf:
            return None
        r = np.hypot(x[moving] - centre[0], y[moving] - centre[1])
        on = moving[np.abs(r - radius) <= share * radius]
        if on.size < 8:
            return None
        *centre, radius = algebraic_circle(x[on], y[on])
    centre = tuple(round(c / ROUND_M) * ROUND_M + 0.0 for c in centre)
    radius = round(radius / ROUND_M) * ROUND_M
    turns = [s for s in find_stretches(x, y, radius, centre) if s.turns >= 1]
    held = sum(s.index.stop - s.index.start for s in turns)
    if not turns or held < HELD_SHARE * moving.size:
        return None
    settled = [s for s in find_stretches(x, y, radius, centre, settled=True) if s.turns >= 1]
    return radius, own_centre(x, y, settled, centre) if settled else centre


def own_centre(x, y, turns, centre) -> tuple[float, float]:
    """The centre the command's whole turns run about, as the circle analysis reads a
    command's (:func:`.circle_command.command_centre`: the first harmonic of the radius
    over them): a controller's filter pulls the circle in where it speeds up and slows
    down, which a least-squares fit takes for an offset (4.2 µm on bench H's circle at
    F10000), and every radial figure would hold it once around [m].

    Parameters
    ----------
    x, y : ndarray
        The command in the plane [m].
    turns : list of Stretch
        Its passes of one turn or more that it has settled on, a filter's transient out
        of the feed-in left out (:func:`.circle_passes.find_stretches`) [-].
    centre : tuple of float
        The fitted centre they were found about [m].
    """
    offsets = [command_centre(x[s.index], y[s.index], centre)[:2] for s in turns]
    size = [s.index.stop - s.index.start for s in turns]  # each pass by its samples
    off = np.average(np.array(offsets), axis=0, weights=size)
    return tuple(round((c + o) / ROUND_M) * ROUND_M + 0.0
                 for c, o in zip(centre, off, strict=True))


def judged_circle(cmd, radius_m=None, centre_m=(0.0, 0.0), plane=None) -> tuple | None:
    """``(radius, centre, plane)`` of the circle a command is judged on: the one given,
    else the one the command runs where it is a circular test (:func:`command_circle`);
    None where there is none [m, m, -].

    Parameters
    ----------
    cmd : Command
        The command [m].
    radius_m : float, optional
        Radius of the nominal circle [m].
    centre_m : tuple of float
        Its centre in the plane's axes, with ``radius_m`` [m].
    plane : tuple of str, optional
        The plane; default the command's (:func:`.plane.command_plane`) [-].
    """
    from .plane import command_plane

    plane = tuple(plane) if plane is not None else command_plane(cmd)
    if radius_m is not None:
        return float(radius_m), tuple(centre_m), plane
    found = command_circle(cmd.positions, plane)
    return None if found is None else (*found, plane)


def circle_said(circle, found: bool) -> dict | None:
    """The circle of :func:`judged_circle` for a result's record: radius, centre and
    plane, and ``"from"``: ``"command"`` where it was taken from the command, ``"given"``
    where the user gave it; None where there is none [m, -]."""
    if circle is None:
        return None
    radius, centre, plane = circle
    return {"radius_m": float(radius), "centre_m": [float(c) for c in centre],
            "plane": "".join(plane), "from": "command" if found else "given"}


def circle_where(circle) -> dict:
    """``radius_m``, ``centre_m`` and ``plane`` of the circle of :func:`judged_circle`, as
    the compensation's functions take them; no radius (the path judged alone) where there
    is no circle [m, m, -]."""
    radius, centre, plane = circle or (None, (0.0, 0.0), ("X", "Y"))
    return {"radius_m": radius, "centre_m": centre, "plane": plane}
