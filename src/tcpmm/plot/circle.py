"""Circular-test plots with magnified radial error (paper Figs. 11-12)."""

from __future__ import annotations

import numpy as np

from . import SENSOR_STYLE, pyplot, save


def _auto_magnification(result) -> float:
    emax = max(np.max(np.abs(s.radial_error)) for p in result.passes for s in p.sensors.values())
    return float(10 ** np.floor(np.log10(0.25 * result.radius / max(emax, 1e-12))))


def plot_circle(result, path=None, magnification=None, sensors=None, overlay=None,
                title=None):
    """One polar panel per pass: ``R + M e`` for each sensor, quadrant points A-D.

    Parameters
    ----------
    result : CircleResult
        Analysis to show [-].
    path : str or Path, optional
        Where to save (PNG/PDF/SVG); the figure is returned open when omitted [-].
    magnification : float, optional
        Radial error magnification M; chosen automatically when omitted [-].
    sensors : list of str, optional
        Sensors to draw [-].
    overlay : CircleResult, optional
        A second analysis (e.g. prediction) drawn dotted over the first [-].
    title : str, optional
        Figure title [-].
    """
    plt = pyplot()
    M = magnification or _auto_magnification(result)
    n = len(result.passes)
    fig, axs = plt.subplots(1, n, figsize=(5.2 * n, 5.4), squeeze=False)
    R = result.radius
    a1, a2 = getattr(result, "plane", ("X", "Y"))
    for ax, p in zip(axs[0], result.passes, strict=True):
        th = np.linspace(0, 2 * np.pi, 361)
        ax.plot(R * np.cos(th) * 1e3, R * np.sin(th) * 1e3, **SENSOR_STYLE["cmd"])
        names = [s for s in (sensors or p.sensors) if s in p.sensors and s != "cmd"]
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
        for q, deg in zip("ABCD", (0, 90, 180, 270), strict=True):
            a = np.radians(deg)
            ax.annotate(q, (1.12 * R * np.cos(a) * 1e3, 1.12 * R * np.sin(a) * 1e3),
                        ha="center", va="center", fontsize=12, fontweight="bold")
        ax.set_aspect("equal")
        ax.set_xlim(-1.3 * R * 1e3, 1.3 * R * 1e3)
        ax.set_ylim(-1.3 * R * 1e3, 1.3 * R * 1e3)
        ax.set_xlabel(f"{a1} [mm]")
        ax.set_ylabel(f"{a2} [mm]")
        ax.set_title(f"{p.direction.upper()}  (radial error x{M:g})")
        ax.grid(alpha=0.3)
        ax.legend(loc="lower left", fontsize=7)
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    return save(fig, path) or fig


def plot_radial_error(result, path=None, overlay=None):
    """Radial error against angle per pass and sensor [um vs deg]."""
    plt = pyplot()
    n = len(result.passes)
    fig, axs = plt.subplots(n, 1, figsize=(9, 3.0 * n), squeeze=False)
    for ax, p in zip(axs[:, 0], result.passes, strict=True):
        for s, sc in p.sensors.items():
            if s == "cmd":
                continue
            ax.plot(np.degrees(np.mod(sc.angle_rad, 2 * np.pi)), sc.radial_error * 1e6, ".",
                    ms=1.5, color=SENSOR_STYLE[s]["color"], label=SENSOR_STYLE[s]["label"])
        if overlay is not None:
            po = next((q for q in overlay.passes if q.direction == p.direction), None)
            if po is not None and "tcp" in po.sensors:
                sc = po.sensors["tcp"]
                ax.plot(np.degrees(np.mod(sc.angle_rad, 2 * np.pi)), sc.radial_error * 1e6,
                        ".", ms=1.5, color="tab:orange", label="Sim-TCP")
        for q, deg in zip("ABCD", (0, 90, 180, 270), strict=True):
            ax.axvline(deg, color="gray", lw=0.6)
            ax.text(deg + 2, ax.get_ylim()[1] if ax.lines else 0, q, va="top")
        ax.set_xlim(0, 360)
        ax.set_xlabel(f"angle from +{getattr(result, 'plane', 'X')[0]} [deg]")
        ax.set_ylabel("radial error [µm]")
        ax.set_title(p.direction.upper())
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, markerscale=6)
    fig.tight_layout()
    return save(fig, path) or fig
