"""Circular-test plots with magnified radial error (paper Figs. 11-12)."""

from __future__ import annotations

import numpy as np

from . import SENSOR_STYLE, finish, panels


def _auto_magnification(result) -> float:
    """The largest 1-2-5 step that draws the largest radial error within a quarter of R."""
    emax = max(np.max(np.abs(s.radial_error)) for p in result.passes for s in p.sensors.values())
    raw = 0.25 * result.radius / max(emax, 1e-12)
    decade = 10 ** np.floor(np.log10(raw))
    return float(max(k for k in (1, 2, 5, 10) if k * decade <= raw * (1 + 1e-9)) * decade)


def _ring_step_um(lo_um: float, hi_um: float, min_step_um: float = 0.0) -> float:
    """The smallest 1-2-5 ring spacing of at least ``min_step_um`` that gives at most four
    intervals over ``lo_um``..``hi_um`` [µm]."""
    span = max(hi_um - lo_um, 1e-3)
    for step in (k * 10.0 ** e for e in range(-3, 6) for k in (1, 2, 5)):
        if step >= min_step_um and span / step <= 4:
            return step
    return span


#: Angles the ring labels may stand at, the first of equals first: at least 20 deg from
#: each quadrant point, where the reversals' spikes are, and clear of the legend (lower
#: left) [deg].
LABEL_ANGLES_DEG = (*range(25, 70, 5), *range(295, 340, 5), *range(115, 160, 5))


def _label_box(ax, R, labels) -> tuple[np.ndarray, float]:
    """Half each ring label's length along its ring and half its height across it, a 7 pt
    font's, in the panel's mm (the panel spans ±1.3 R) [mm]."""
    width_pt = ax.get_position().width * ax.figure.get_figwidth() * 72.0
    mm_per_pt = 2.6 * R * 1e3 / width_pt
    along = np.array([0.3 * 7 * len(t) + 2 for _, t in labels]) * mm_per_pt
    return along, (0.6 * 7 + 1) * mm_per_pt


def _polar_paths(R, M, paths) -> tuple[np.ndarray, np.ndarray]:
    """Every path's samples as drawn: angle [deg] and radius [mm]."""
    deg = np.degrees(np.concatenate([np.asarray(a, float) for a, _ in paths]))
    r_path = np.concatenate([(R + M * np.asarray(e, float)) * 1e3 for _, e in paths])
    return deg, r_path


def _label_angle(box, drawn, labels) -> float:
    """The angle of :data:`LABEL_ANGLES_DEG` at which the paths drawn cross the ring
    labels least (each written along its ring), and among equals pass farthest from
    them [deg].

    Parameters
    ----------
    box : tuple
        Half each label's length along its ring and half its height (:func:`_label_box`)
        [mm].
    drawn : tuple of ndarray
        Every path's samples as drawn, angle and radius (:func:`_polar_paths`) [deg, mm].
    labels : list of tuple
        ``(ring radius as drawn [mm], text)`` [-].
    """
    (along, across), (deg, r_path) = box, drawn
    radii = np.array([r for r, _ in labels])

    def crowding(at):
        off = np.radians(np.abs((deg - at + 180.0) % 360.0 - 180.0))
        d_along = np.maximum(radii[:, None] * off[None, :] - along[:, None], 0.0)
        d_across = np.maximum(np.abs(r_path[None, :] - radii[:, None]) - across, 0.0)
        gap = np.hypot(d_along, d_across)
        return int(np.sum(gap == 0.0)), -float(np.min(gap))

    return float(min(LABEL_ANGLES_DEG, key=crowding))


def _hidden(box, drawn, labels, at) -> list[bool]:
    """Whether a path runs along each ring label at ``at`` over more than half its length,
    so that a label drawn under the paths could not be read (a path on its ring all the
    way round, as a sensor reading the nominal circle is on the 0 µm ring); ``box`` and
    ``drawn`` as :func:`_label_angle` takes them [-]."""
    (along, across), (deg, r_path) = box, drawn
    off = np.radians((deg - at + 180.0) % 360.0 - 180.0)
    out = []
    for (r, _), half in zip(labels, along, strict=True):
        inside = (np.abs(r * off) < half) & (np.abs(r_path - r) < across)
        out.append(bool(inside.any()) and float(np.ptp(r * off[inside])) > half)
    return out


def _scale_rings(ax, R, M, paths) -> None:
    """Rings at whole steps of radial error about the nominal radius, labelled in µm along
    each ring where the paths drawn cross the labels least (:func:`_label_angle`), and the
    magnification written on the plot.

    Parameters
    ----------
    ax : matplotlib Axes
        The panel [-].
    R : float
        Nominal radius [m].
    M : float
        Radial error magnification [-].
    paths : list of tuple of ndarray
        ``(angle, radial error)`` of each path drawn in the panel [rad, m].
    """
    lo = min(0.0, *(float(np.min(e)) for _, e in paths)) * 1e6
    hi = max(0.0, *(float(np.max(e)) for _, e in paths)) * 1e6
    step = _ring_step_um(lo, hi, 0.08 * R / M * 1e6)  # rings at least 8 % of R apart
    th = np.linspace(0, 2 * np.pi, 361)
    rings = [((R + M * k * step * 1e-6) * 1e3, f"{k * step:+g} µm" if k else "0 µm")
             for k in range(int(np.floor(lo / step)), int(np.ceil(hi / step)) + 1)]
    box, drawn = _label_box(ax, R, rings), _polar_paths(R, M, paths)
    at = _label_angle(box, drawn, rings)
    along = (at + 90.0) % 180.0  # the ring's direction there, written upright
    for (r, text), hidden in zip(rings, _hidden(box, drawn, rings, at), strict=True):
        if text != "0 µm":
            ax.plot(r * np.cos(th), r * np.sin(th), color="0.55", lw=0.6, ls=(0, (2, 3)),
                    zorder=1)
        # under the traces, whose white box would blank a piece of one crossing it and
        # read as a gap in the path; over a trace running along it, through a box it
        # shows through
        ax.annotate(text, (r * np.cos(np.radians(at)), r * np.sin(np.radians(at))),
                    ha="center", va="center", fontsize=7, color="0.3",
                    rotation=along - 180.0 if along > 90.0 else along, rotation_mode="anchor",
                    bbox=dict(boxstyle="round,pad=0.15", fc="white", ec="none",
                              alpha=0.6 if hidden else 0.85),
                    zorder=3.5 if hidden else 1.5)
    ax.text(0.02, 0.98, f"radial error ×{M:g}\nrings every {step:g} µm", transform=ax.transAxes,
            va="top", fontsize=8, bbox=dict(boxstyle="round", fc="white", ec="0.7"))


def plot_circle(result, path=None, magnification=None, sensors=None, overlay=None,
                title=None, ax=None):
    """One polar panel per pass: ``R + M e`` for each sensor, quadrant points A-D.

    Parameters
    ----------
    result : CircleResult
        Analysis to show [-].
    path : str or Path, optional
        Where to save (PNG/PDF/SVG) [-].
    magnification : float, optional
        Radial error magnification M; chosen automatically when omitted [-].
    sensors : list of str, optional
        Sensors to draw [-].
    overlay : CircleResult, optional
        A second analysis (e.g. prediction) drawn dotted over the first [-].
    title : str, optional
        Figure title [-].
    ax : matplotlib Axes or array-like of Axes, optional
        Axes to draw into, one per pass in row order; a new figure when omitted [-].

    Returns
    -------
    matplotlib Figure
        The figure (saved too when ``path`` is given) [-].
    """
    M = magnification or _auto_magnification(result)
    n = len(result.passes)
    fig, axs, own = panels(ax, 1, n, figsize=(5.2 * n, 5.4))
    R = result.radius
    plane = getattr(result, "plane", ("X", "Y"))
    for a, p in zip(axs[0], result.passes, strict=True):
        _circle_panel(a, p, R, M, sensors, overlay, plane)
    if title:
        fig.suptitle(title)
    return finish(fig, path, own)


def _circle_panel(ax, p, R, M, sensors, overlay, plane=("X", "Y")):
    """One pass: ``R + M e`` per sensor, the overlay's TCP dotted, µm scale rings, A-D."""
    th = np.linspace(0, 2 * np.pi, 361)
    # the nominal circle is the 0 µm ring: under its label, which breaks it as a map's
    # contour label breaks its line, and over the other rings
    ax.plot(R * np.cos(th) * 1e3, R * np.sin(th) * 1e3, **SENSOR_STYLE["cmd"], zorder=1.2)
    names = [s for s in (sensors or p.sensors) if s in p.sensors and s != "cmd"]
    drawn = [(p.sensors[s].angle_rad, p.sensors[s].radial_error) for s in names]
    for s in names:
        sc = p.sensors[s]
        r = R + M * sc.radial_error
        ax.plot(r * np.cos(sc.angle_rad) * 1e3, r * np.sin(sc.angle_rad) * 1e3,
                **SENSOR_STYLE[s])
    if overlay is not None:
        try:
            po = overlay.pass_for(p.direction)
        except Exception:  # no such direction in the overlay
            po = None
        if po is not None and "tcp" in po.sensors:
            sc = po.sensors["tcp"]
            r = R + M * sc.radial_error
            ax.plot(r * np.cos(sc.angle_rad) * 1e3, r * np.sin(sc.angle_rad) * 1e3,
                    color="tab:orange", ls="--", lw=1.2, label="Sim-TCP")
            drawn.append((sc.angle_rad, sc.radial_error))
    _scale_rings(ax, R, M, drawn or [(np.zeros(1), np.zeros(1))])
    for q, deg in zip("ABCD", (0, 90, 180, 270), strict=True):
        a = np.radians(deg)
        ax.annotate(q, (1.12 * R * np.cos(a) * 1e3, 1.12 * R * np.sin(a) * 1e3),
                    ha="center", va="center", fontsize=12, fontweight="bold")
    ax.set_aspect("equal")
    ax.set_xlim(-1.3 * R * 1e3, 1.3 * R * 1e3)
    ax.set_ylim(-1.3 * R * 1e3, 1.3 * R * 1e3)
    ax.set_xlabel(f"{plane[0]} [mm]")
    ax.set_ylabel(f"{plane[1]} [mm]")
    ax.set_title(f"{p.direction.upper()}: radial error ×{M:g}, rings in µm")
    ax.legend(loc="lower left", fontsize=7)


def plot_radial_error(result, path=None, overlay=None, ax=None):
    """Radial error against angle per pass and sensor [um vs deg].

    Parameters
    ----------
    result : CircleResult
        Analysis to show [-].
    path : str or Path, optional
        Where to save (PNG/PDF/SVG) [-].
    overlay : CircleResult, optional
        A second analysis whose TCP error is drawn over the first [-].
    ax : matplotlib Axes or array-like of Axes, optional
        Axes to draw into, one per pass in row order; a new figure when omitted [-].

    Returns
    -------
    matplotlib Figure
        The figure (saved too when ``path`` is given) [-].
    """
    n = len(result.passes)
    fig, axs, own = panels(ax, n, 1, figsize=(9, 3.0 * n))
    for a, p in zip(axs[:, 0], result.passes, strict=True):
        for s, sc in p.sensors.items():
            if s == "cmd":
                continue
            a.plot(np.degrees(np.mod(sc.angle_rad, 2 * np.pi)), sc.radial_error * 1e6, ".",
                   ms=1.5, color=SENSOR_STYLE[s]["color"], label=SENSOR_STYLE[s]["label"])
        if overlay is not None:
            po = next((q for q in overlay.passes if q.direction == p.direction), None)
            if po is not None and "tcp" in po.sensors:
                sc = po.sensors["tcp"]
                a.plot(np.degrees(np.mod(sc.angle_rad, 2 * np.pi)), sc.radial_error * 1e6,
                       ".", ms=1.5, color="tab:orange", label="Sim-TCP")
        for q, deg in zip("ABCD", (0, 90, 180, 270), strict=True):
            a.axvline(deg, color="gray", lw=0.6)
            a.text(deg + 2, a.get_ylim()[1] if a.lines else 0, q, va="top")
        a.set_xlim(0, 360)
        a.set_xlabel(f"angle from +{getattr(result, 'plane', 'X')[0]} [deg]")
        a.set_ylabel("radial error [µm]")
        a.set_title(p.direction.upper())
        a.grid(alpha=0.3)
        a.legend(fontsize=7, markerscale=6)
    return finish(fig, path, own)
