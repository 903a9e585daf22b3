"""Contour error along a path: the path coloured by the error, and the error in time."""

from __future__ import annotations

import numpy as np

from . import SENSOR_STYLE, finish, panels

PREFERRED = ("tcp", "scale", "motor")


def plot_contour(res, ax=None, sensor=None, path=None):
    """One sensor's path coloured by its contour error, and the error of every sensor in
    time with the corners marked.

    Parameters
    ----------
    res : ContourResult
        The analysis [-].
    ax : matplotlib Axes or array-like of Axes, optional
        Two axes (coloured path, error in time), or one for the coloured path alone; a new
        figure when omitted [-].
    sensor : str, optional
        Sensor of the colours; default tcp, else scale, else motor [-].
    path : str or Path, optional
        Also save it there (PNG/PDF/SVG) [-].
    """
    single = ax is not None and np.asarray(ax, dtype=object).size == 1
    fig, axs, own = panels(ax, 1, 1 if single else 2, figsize=(13, 5.2))
    sensor = sensor or next(s for s in PREFERRED if s in res.errors)
    _coloured_path(fig, axs[0, 0], res, sensor)
    if not single:
        _in_time(axs[0, 1], res)
    return finish(fig, path, own)


def _coloured_path(fig, ax, res, sensor):
    from matplotlib.collections import LineCollection

    i, j = _shown_axes(res)
    xy = res.actual[sensor][:, [i, j]] * 1e3
    e = res.errors[sensor] * 1e6
    lim = float(np.max(np.abs(e))) or 1.0
    lc = LineCollection(np.stack([xy[:-1], xy[1:]], axis=1),
                        cmap="coolwarm" if res.signed else "viridis", linewidths=2.5)
    lc.set_array(0.5 * (e[:-1] + e[1:]))
    lc.set_clim(-lim if res.signed else 0.0, lim)
    ax.add_collection(lc)
    ax.autoscale()
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel(f"{res.axes[i]} [mm]")
    ax.set_ylabel(f"{res.axes[j]} [mm]")
    sign = " (+: left of travel)" if res.signed else ""
    fig.colorbar(lc, ax=ax, label=f"{sensor} contour error [µm]{sign}")
    for c in res.corners:
        ax.annotate(str(c["number"]), (c["point_m"][i] * 1e3, c["point_m"][j] * 1e3),
                    fontsize=8, xytext=(4, 4), textcoords="offset points")
    ax.set_title(f"contour error of {sensor}")


def _in_time(ax, res):
    for s, err in res.errors.items():
        st = SENSOR_STYLE[s]
        ax.plot(res.time_s, err * 1e6, color=st["color"], lw=1, label=st["label"])
    for c in res.corners:
        tc = res.command_time_s[c["index"]]
        ax.axvline(tc, color="gray", lw=0.6)
        ax.annotate(str(c["number"]), (tc, 1.0), fontsize=8,
                    xycoords=("data", "axes fraction"), va="top")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("contour error [µm]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)


def _shown_axes(res):
    """The two axes to draw: the plane's, or in 3-D the two of largest travel."""
    if len(res.axes) == 2:
        return 0, 1
    order = np.argsort(-np.ptp(res.command, axis=0), kind="stable")
    return tuple(sorted(order[:2].tolist()))
