"""The command of a circular test: its passes, found within its tolerance or, where it
is corrected at its reversals, a sensor's; its mean radius and its centre against the
nominal ones.

Every radial figure of the circular test is taken about the nominal centre. A command
whose circle lies ``d`` off it puts ``d cos(angle - phi)`` into every sensor's radial
error, once around: bench C's circle shifted by 20 um reads its raw spikes up to 24 um
and its contour error 18 um off. The command's offset is read from its radial
deviation's first harmonic over its whole turns, which a controller's filter (a radius
pulled in evenly) leaves alone.
"""

from __future__ import annotations

import warnings

import numpy as np

from ..errors import InputError, InputWarning
from .circle_passes import SENSOR_TOL_SHARE, find_stretches

#: A command's centre further than this from the one given is said: the raw spikes move
#: by up to about half of it [m]
CENTRE_TOL_M = 1e-6
#: The command is a circle about its own centre where its radius about it spreads less
#: than this share of the offset; a compensated command's corrections at the reversals
#: are no offset [-]
CLEAN_SHARE = 0.5


def command_centre(x, y, centre) -> tuple[float, float, float]:
    """The command's offset from ``centre`` (the first harmonic of its radius over the
    angle it covers) and the spread of its radius about the centre so found [m].

    Parameters
    ----------
    x, y : ndarray
        The command over its whole turns [m].
    centre : tuple of float
        The centre given [m].
    """
    dx, dy = x - centre[0], y - centre[1]
    ox, oy = once_around(np.unwrap(np.arctan2(dy, dx)), np.hypot(dx, dy))
    rest = np.hypot(dx - ox, dy - oy)
    return ox, oy, float(rest.max() - rest.min())


def once_around(angle_rad, r) -> tuple[float, float]:
    """The first harmonic ``(a, b)`` of ``r`` over the angle, ``r = c + a cos + b sin``,
    each sample weighted by the angle it covers: the offset of a circle's centre from the
    one its radius ``r`` is taken about [m].

    Parameters
    ----------
    angle_rad : ndarray
        Angle of each sample, unwrapped [rad].
    r : ndarray
        Its radius, or radial error [m].
    """
    w = np.sqrt(np.abs(np.gradient(angle_rad)))
    basis = np.column_stack([np.ones_like(angle_rad), np.cos(angle_rad), np.sin(angle_rad)])
    coef = np.linalg.lstsq(basis * w[:, None], r * w, rcond=None)[0]
    return float(coef[1]), float(coef[2])


def check_command_centre(x, y, centre, direction: str, refuse_beyond_m: float) -> None:
    """Refuse a command that is a circle about a centre more than ``refuse_beyond_m`` from
    ``centre``; warn (:class:`InputWarning`) of one more than :data:`CENTRE_TOL_M` from it;
    say nothing of a command whose radius spreads about its own centre (a compensated
    command's corrections) [-].

    Parameters
    ----------
    x, y, centre
        As for :func:`command_centre` [m].
    direction : {"ccw", "cw"}
        Its direction of travel [-].
    refuse_beyond_m : float
        The offset beyond which the circle's passes were not found within the
        command's tolerance [m].
    """
    if x.size < 8:
        return
    ox, oy, spread = command_centre(x, y, centre)
    off = float(np.hypot(ox, oy))
    if off <= CENTRE_TOL_M or spread > CLEAN_SHARE * off:
        return
    cx, cy = (round((centre[i] + o) * 1e3, 4) + 0.0 for i, o in enumerate((ox, oy)))
    text = (f"the {direction.upper()} command runs its circle about ({cx:.4f}, {cy:.4f}) mm, "
            f"{off * 1e6:.1f} µm from the centre given ({centre[0] * 1e3:g}, "
            f"{centre[1] * 1e3:g}) mm: every radial figure taken about the centre given holds "
            f"that offset once around (the raw spikes up to about half of it, the contour "
            f"error all of it); give --centre {cx:.4f},{cy:.4f}")
    if off > refuse_beyond_m:
        raise InputError(text)
    warnings.warn(InputWarning(text), stacklevel=3)


def radial_deviation(x, y, radius, centre) -> float:
    """Mean radius of a path minus the nominal, weighted by the angle each sample covers:
    how far the command lies outside (+) or inside (-) the circle asked for [m].

    Parameters
    ----------
    x, y : ndarray
        Path [m].
    radius : float
        Nominal radius [m].
    centre : tuple
        Nominal centre [m].
    """
    dx, dy = x - centre[0], y - centre[1]
    ang = np.unwrap(np.arctan2(dy, dx))
    w = np.abs(np.gradient(ang)) if ang.size > 1 else np.ones_like(ang)
    r = np.hypot(dx, dy) - radius
    return float(np.sum(w * r) / np.sum(w)) if np.sum(w) > 0 else float(np.mean(r))


def reference_stretches(x, y, radius_m, centre_m, tol, ref) -> list:
    """The circle's passes in the reference path (:func:`find_stretches`); where a command
    holds arcs only within its tolerance and whole turns within a sensor's, those turns,
    said: a compensated command departs from the circle by its correction (some 70 um at
    a reversal of R 35 mm at F5000), which cut each turn into arcs between the
    reversals, with no spike reported [-]."""
    got = find_stretches(x, y, radius_m, centre_m, tol, settled=ref == "cmd")
    if ref != "cmd" or any(st.turns for st in got):
        return got
    wide = find_stretches(x, y, radius_m, centre_m, SENSOR_TOL_SHARE * radius_m, settled=True)
    if not any(st.turns for st in wide):
        return got
    for st in wide:
        if st.turns:
            check_command_centre(x[st.index], y[st.index], centre_m, st.direction, tol)
    warnings.warn(InputWarning(
        f"the command departs from the circle by more than {tol * 1e6:.0f} um (a command "
        "compensated for the machine's error, or another path): its whole turns are taken "
        f"within {SENSOR_TOL_SHARE * radius_m * 1e3:.2g} mm of it; measure the run against the "
        "program it was to follow (--command) where its time line is the run's"),
        stacklevel=3)
    return wide


def command_figures(cp, x, y, radius_m: float, centre_m, tol: float, turns: bool) -> None:
    """Set the pass ``cp``'s command radial deviation (:func:`radial_deviation`) from its
    command ``x``, ``y``, and, over whole ``turns``, check its centre
    (:func:`check_command_centre`, refused beyond ``tol``) [-].

    Parameters
    ----------
    cp : CirclePass
        The pass [-].
    x, y : ndarray
        Its command [m].
    radius_m : float
        Nominal radius [m].
    centre_m : tuple of float
        Nominal centre [m].
    tol : float
        The command's tolerance about the circle [m].
    turns : bool
        Whether the pass holds whole turns [-].
    """
    cp.command_radial_deviation = radial_deviation(x, y, radius_m, centre_m)
    if turns:
        check_command_centre(x, y, centre_m, cp.direction, tol)
