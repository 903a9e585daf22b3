"""Plot of an interpolated position command: the path in its plane, the axes against time,
and the feed along the path."""

from __future__ import annotations

import numpy as np

from . import pyplot, save


def plot_command(cmd, path=None, plane=None, limits=None):
    """Path in its plane, per-axis position and velocity against time, feed along the path.

    Parameters
    ----------
    cmd : Command
        The command [-].
    path : str or Path, optional
        Where to save [-].
    plane : tuple of str, optional
        The two axes of the path panel, e.g. ``("Z", "X")``; default X and Y [-].
    limits : FeedLimits, optional
        What holds the feed back per segment (:func:`tcpmm.path.limits.feed_limits`),
        drawn over the feed [-].
    """
    plt = pyplot()
    fig, axs = plt.subplots(2, 2, figsize=(12, 8))
    axs = axs.ravel()
    P = cmd.positions
    a, b = plane or ("X", "Y")
    if a in P and b in P:
        axs[0].plot(P[a] * 1e3, P[b] * 1e3, lw=1)
        axs[0].set_aspect("equal", adjustable="datalim")
    axs[0].set_xlabel(f"{a} [mm]")
    axs[0].set_ylabel(f"{b} [mm]")
    axs[0].set_title(f"path in the {a}{b} plane")
    for name, p in P.items():
        axs[1].plot(cmd.time_s, p * 1e3, label=name)
        axs[2].plot(cmd.time_s, np.gradient(p, cmd.time_s) * 6e4, label=name)
    axs[1].set_ylabel("position [mm]")
    axs[2].set_ylabel("axis velocity [mm/min]")
    for ax in axs[1:3]:
        ax.set_xlabel("time [s]")
        ax.legend()
    _feed_panel(axs[3], cmd, limits)
    for ax in axs:
        ax.grid(alpha=0.3)
    fig.tight_layout()
    return save(fig, path) or fig


def _feed_panel(ax, cmd, limits):
    """Path speed against the distance along the path, with the programmed feed and the
    limit of each segment coloured by what sets it [mm/min vs mm]."""
    s = cmd.meta.get("path_s_m")
    if s is None:
        v = np.sqrt(sum(np.gradient(p, cmd.time_s) ** 2 for p in cmd.positions.values()))
        ax.plot(cmd.time_s, v * 6e4, lw=1, color="black", label="feed")
        ax.set_xlabel("time [s]")
    else:
        s = np.asarray(s)
        v = np.gradient(s, cmd.time_s)
        ax.plot(s * 1e3, v * 6e4, lw=1, color="black", label="feed")
        ax.set_xlabel("distance along the path [mm]")
    if limits is not None:
        edges = np.concatenate([[0.0], np.cumsum(limits.length_m)]) * 1e3
        feed = np.where(limits.limit_m_per_s > 0, limits.feed_m_per_s, np.nan)  # no rapids
        ax.step(edges[:-1], feed * 6e4, where="post", color="gray", ls="--", lw=0.8,
                label="programmed")
        if np.any(np.isfinite(feed)):
            ax.set_ylim(0, 1.15 * np.nanmax(feed) * 6e4)
        colours = dict(zip(limits.CAUSES, pyplot().cm.tab10.colors, strict=False))
        for cause in np.unique(limits.cause[limits.held]):
            k = limits.held & (limits.cause == cause)
            ax.scatter(0.5 * (edges[:-1] + edges[1:])[k], limits.limit_m_per_s[k] * 6e4, s=6,
                       color=colours[cause], label=f"limit: {cause}")
    ax.set_ylabel("feed [mm/min]")
    ax.set_title("feed along the path")
    ax.legend(fontsize=7)
