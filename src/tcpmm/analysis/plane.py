"""The plane of a test: its two axes, by name, from the program or from the motion of a run.

A plane is an ordered pair of axes ``(a, b)``: angles are counted from ``+a`` towards
``+b``, and counter-clockwise (CCW) turns ``+a`` into ``+b``. The planes of G17, G18 and
G19 are ``XY``, ``ZX`` and ``YZ`` (right-handed, seen from the third axis), so that a G3
reads as CCW in all three. ``XZ`` is the same plane seen from -Y: X horizontal, a G3 of
G18 is then CW.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError

AXES = ("X", "Y", "Z")
#: the plane of G17, G18, G19 for each pair of axes
GCODE_PLANES = {frozenset("XY"): ("X", "Y"), frozenset("XZ"): ("Z", "X"),
                frozenset("YZ"): ("Y", "Z")}
#: the third axis moving more than this share of the smaller plane axis' travel makes
#: the motion not plane
OUT_OF_PLANE_SHARE = 0.1
#: an axis outside a plane given that travels no more than this stays within a count of a
#: glass scale of 1 um (the built-in machine's): the error it leaves out is no larger than
#: the sensors resolve, whatever the plane's own travel [m]
LEFT_OUT_FLOOR_M = 1e-6


def plane_axes(name) -> tuple[str, str]:
    """The two axes of a plane given by name, e.g. ``"XZ"`` or ``("Z", "X")`` [-].

    Parameters
    ----------
    name : str or tuple of str
        Two different axes of X, Y, Z, in order [-].
    """
    given = (name.strip() if isinstance(name, str) else
             name if isinstance(name, tuple | list) else ())  # a number is no plane
    axes = tuple(str(a).upper() for a in given)
    if len(axes) != 2 or axes[0] == axes[1] or any(a not in AXES for a in axes):
        shown = "".join(map(str, given)) if given else str(name)
        raise InputError(f"plane {shown!r} must be two different axes of "
                         "X, Y, Z, e.g. XY, XZ, YZ (or ZX as G18 has it)")
    return axes


def plane_name(axes) -> str:
    """``"XY"`` for ``("X", "Y")`` [-]."""
    return "".join(axes)


def motion_plane(positions: dict, where: str = "") -> tuple[tuple[str, str], str, bool]:
    """The plane in which positions move: the two axes of largest travel, in the order of
    G17, G18, G19 (XY, ZX, YZ).

    Parameters
    ----------
    positions : dict of str to ndarray
        Position per axis name [m].
    where : str
        Where the positions come from, said after their travel (" in the cmd signals") [-].

    Returns
    -------
    axes : tuple of str
        The plane [-].
    why : str
        How it was found, for the user [-].
    flat : bool
        Whether the third axis stays within ``OUT_OF_PLANE_SHARE`` of the plane's [-].
    """
    travel = _travel(positions)
    moving = sorted((a for a in travel if travel[a] > 0.0), key=lambda a: -travel[a])
    if len(moving) < 2:
        raise InputError("the motion is not in a plane: fewer than two of the axes X, Y, Z "
                         f"move (travel {_mm(travel)}); give --plane")
    a, b = moving[:2]
    axes = GCODE_PLANES[frozenset((a, b))]
    # named in the plane's order, as the plane is, not by their travel
    why = f"the axes moving most are {axes[0]} and {axes[1]} (travel {_mm(travel)}){where}"
    flat = not (len(moving) > 2 and travel[moving[2]] > OUT_OF_PLANE_SHARE * travel[b])
    if not flat:
        why += f"; {moving[2]} moves too, so the path is not plane: give --plane to choose"
    return axes, why, flat


def command_plane(cmd) -> tuple[str, str]:
    """The plane of a command: that of its program's arcs (G17, G18, G19), else the one
    it moves in (:func:`motion_plane`), else XY for a move along one axis [-].

    Parameters
    ----------
    cmd : Command
        The command [m].
    """
    if cmd.meta.get("plane_axes"):
        return tuple(cmd.meta["plane_axes"])
    try:
        return motion_plane(cmd.positions)[0]
    except InputError:  # a move along one axis: any plane holding it will do
        return ("X", "Y")


def _travel(positions: dict) -> dict:
    """Travel of each axis of X, Y, Z among ``positions``, by its upper-case name [m]."""
    return {a.upper(): float(np.ptp(p)) for a, p in positions.items()
            if a.upper() in AXES and p is not None and np.size(p)}


def plane_misses(axes, positions: dict) -> str:
    """Why a plane given by name misses the motion: an axis of it moves less than
    :data:`OUT_OF_PLANE_SHARE` of an axis outside it (a G18 circle taken in XY, whose
    error there is that of a line: 0.00 um); empty where it holds the motion [-].

    Parameters
    ----------
    axes : tuple of str
        The plane [-].
    positions : dict of str to ndarray
        Position per axis name [m].
    """
    travel = _travel(positions)
    out = {a: t for a, t in travel.items() if a not in axes}
    if not out:
        return ""
    far = max(out, key=out.get)
    near = min(axes, key=lambda a: travel.get(a, 0.0))
    if not travel.get(near, 0.0) < OUT_OF_PLANE_SHARE * out[far]:
        return ""
    text = (f"the plane {plane_name(axes)} leaves out {far}, which moves "
            f"{out[far] * 1e3:.3g} mm, where {near} moves {travel.get(near, 0.0) * 1e3:.3g} mm")
    try:
        return text + f": the path runs in the {plane_name(motion_plane(positions)[0])} plane"
    except InputError:
        return text


def left_out_axes(axes, positions: dict) -> dict:
    """The axes outside a plane given that move substantially, with their travel: more
    than :data:`OUT_OF_PLANE_SHARE` of the travel of the plane's axis that moves less (what
    makes :func:`motion_plane` call a path not plane, so that a plane it finds leaves none
    out) and more than :data:`LEFT_OUT_FLOOR_M`. A signed error in the plane leaves their
    error out [m].

    Parameters
    ----------
    axes : tuple of str
        The plane [-].
    positions : dict of str to ndarray
        Position per axis name; two samples, the least and the largest, will do [m].
    """
    travel = _travel(positions)
    least = min(travel.get(a, 0.0) for a in axes)
    bar = max(OUT_OF_PLANE_SHARE * least, LEFT_OUT_FLOOR_M)
    return {a: t for a, t in travel.items() if a not in axes and t > bar}


#: What a user of the contour error can do where a plane given leaves axes out
CONTOUR_REMEDY = "omit --plane (or give --plane 3D) for the 3-D error"


def left_out_note(axes, left: dict, remedy: str = CONTOUR_REMEDY) -> str | None:
    """What a user is told of the axes a plane given leaves out (:func:`left_out_axes`); ``None``
    where it leaves out none [-].

    Parameters
    ----------
    axes : tuple of str
        The plane [-].
    left : dict of str to float
        Travel per axis left out [m].
    remedy : str
        What to do about it, said last [-].
    """
    if not left:
        return None
    moves = " and ".join(f"{a}, which moves {t * 1e3:.3g} mm" for a, t in left.items())
    its = "its" if len(left) == 1 else "their"
    return (f"the plane {plane_name(axes)} leaves out {moves} (more than "
            f"{OUT_OF_PLANE_SHARE * 100:g} % of the plane's smaller travel): {its} contour error "
            f"is left out of every figure; {remedy}")


def run_plane(run, sensor: str | None = None) -> tuple[tuple[str, str], str, bool]:
    """The plane in which a run's command moves (else its first position sensor).

    Parameters
    ----------
    run : Run
        Simulated or measured run [-].
    sensor : str, optional
        Sensor to look at; default ``cmd`` where every axis has it [-].

    Returns
    -------
    axes : tuple of str
        The plane [-].
    why : str
        How it was found [-].
    flat : bool
        Whether the motion lies in the plane (:func:`motion_plane`) [-].
    """
    s, pos = run_positions(run, sensor)
    if s is None:
        raise InputError("the run has no position signal of two axes to find the plane from")
    return motion_plane(pos, f" in the {s} signals")


def run_positions(run, sensor: str | None = None) -> tuple:
    """``(sensor, positions per axis)`` of a run's command, else of its first position
    sensor that two axes have; ``(None, {})`` where none has [-, m].

    Parameters
    ----------
    run : Run
        Simulated or measured run [-].
    sensor : str, optional
        Sensor to look at; default ``cmd`` where every axis has it [-].
    """
    for s in (sensor,) if sensor else ("cmd", "scale", "motor", "tcp"):
        pos = {a: r.sensor(s) for a, r in run.axes.items()}
        pos = {a: p for a, p in pos.items() if p is not None}
        if len(pos) >= 2:
            return s, pos
    return None, {}


def _mm(travel: dict) -> str:
    return ", ".join(f"{a} {v * 1e3:.3g} mm" for a, v in travel.items())
