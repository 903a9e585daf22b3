"""Contour error along a path: the path coloured by the error, and the error in time."""

from __future__ import annotations

import numpy as np

from . import SENSOR_STYLE, pyplot, save

PREFERRED = ("tcp", "scale", "motor")


def plot_contour(res, ax=None, sensor=None, path=None):
    """One sensor's path coloured by its contour error; without ``ax`` also the
    error of every sensor along the path, corners marked.

    Parameters
    ----------
    res : ContourResult
        The analysis [-].
    ax : matplotlib Axes, optional
        Draw only the coloured path into it [-].
    sensor : str, optional
        Sensor of the colours; default tcp, else scale, else motor [-].
    path : str or Path, optional
        Where to save [-].
    """
    plt = pyplot()
    from matplotlib.collections import LineCollection

    sensor = sensor or next(s for s in PREFERRED if s in res.errors)
    if ax is None:
        fig, (ax, ax2) = plt.subplots(1, 2, figsize=(13, 5.2))
    else:
        fig, ax2 = ax.figure, None
    i, j = _shown_axes(res)
    xy = res.actual[sensor][:, [i, j]] * 1e3
    e = res.errors[sensor] * 1e6
    lim = float(np.max(np.abs(e))) or 1.0
    seg = np.stack([xy[:-1], xy[1:]], axis=1)
    lc = LineCollection(seg, cmap="coolwarm" if res.signed else "viridis", linewidths=2.5)
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
    if ax2 is not None:
        for s, err in res.errors.items():
            st = SENSOR_STYLE[s]
            ax2.plot(res.time_s, err * 1e6, color=st["color"], lw=1, label=st["label"])
        for c in res.corners:
            tc = res.command_time_s[c["index"]]
            ax2.axvline(tc, color="gray", lw=0.6)
            ax2.annotate(str(c["number"]), (tc, 1.0), fontsize=8,
                         xycoords=("data", "axes fraction"), va="top")
        ax2.set_xlabel("time [s]")
        ax2.set_ylabel("contour error [µm]")
        ax2.grid(alpha=0.3)
        ax2.legend(fontsize=7)
    fig.tight_layout()
    return save(fig, path) or fig


def _shown_axes(res):
    """The two axes to draw: the plane's, or in 3-D the two of largest travel."""
    if len(res.axes) == 2:
        return 0, 1
    order = np.argsort(-np.ptp(res.command, axis=0), kind="stable")
    return tuple(sorted(order[:2].tolist()))
