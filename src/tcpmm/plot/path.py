"""Plot of an interpolated position command: the path in its plane, the axes against time,
and the feed along the path."""

from __future__ import annotations

import numpy as np

from . import finish, panels, pyplot


def plot_command(cmd, path=None, ax=None, plane=None, limits=None):
    """Path in its plane, per-axis position and velocity against time, feed along the path.

    Parameters
    ----------
    cmd : Command
        The command [-].
    path : str or Path, optional
        Where to save (PNG/PDF/SVG) [-].
    ax : array-like of matplotlib Axes, optional
        Axes to draw into, four in row order (path, position, velocity, feed); a new
        figure when omitted [-].
    plane : tuple of str, optional
        The two axes of the path panel, e.g. ``("Z", "X")``; default the plane of the
        program's arcs (``meta["plane_axes"]``), else X and Y [-].
    limits : FeedLimits, optional
        What holds the feed back per block (:func:`tcpmm.path.limits.feed_limits`), drawn
        over the feed [-].

    Returns
    -------
    matplotlib Figure
        The figure (saved too when ``path`` is given) [-].
    """
    fig, axs, own = panels(ax, 2, 2, figsize=(12, 8))
    axs = axs.ravel()
    P = cmd.positions
    a, b = plane or cmd.meta.get("plane_axes") or ("X", "Y")
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
    for ax_ in axs[1:3]:
        ax_.set_xlabel("time [s]")
        ax_.legend()
    _feed(axs[3], cmd)
    if limits is not None:
        _limits(axs[3], limits)
    for ax_ in axs:
        ax_.grid(alpha=0.3)
    return finish(fig, path, own)


def plot_feed_limits(limits, ax=None, path=None):
    """Per block: the programmed feed and the highest speed reached, coloured by what holds
    it back, against the distance along the path [mm/min vs mm].

    Parameters
    ----------
    limits : FeedLimits
        :func:`tcpmm.path.limits.feed_limits` of an interpolated program [-].
    ax : matplotlib Axes, optional
        Where to draw; a new figure when omitted [-].
    path : str or Path, optional
        Also save it there (PNG/PDF/SVG) [-].
    """
    fig, axs, own = panels(ax, 1, 1, figsize=(8, 4.2))
    edges = np.concatenate([[0.0], np.cumsum(limits.length_m)]) * 1e3
    axs[0, 0].step(edges[:-1], limits.limit_m_per_s * 6e4, where="post", color="black",
                   lw=1, label="reached")
    _limits(axs[0, 0], limits)
    axs[0, 0].set_xlabel("distance along the path [mm]")
    axs[0, 0].grid(alpha=0.3)
    return finish(fig, path, own)


def _feed(ax, cmd):
    """Path speed against the distance along the path (against time without it)."""
    s = cmd.meta.get("path_s_m")
    if s is None:
        v = np.sqrt(sum(np.gradient(p, cmd.time_s) ** 2 for p in cmd.positions.values()))
        ax.plot(cmd.time_s, v * 6e4, lw=1, color="black", label="feed")
        ax.set_xlabel("time [s]")
    else:
        s = np.asarray(s)
        ax.plot(s * 1e3, np.gradient(s, cmd.time_s) * 6e4, lw=1, color="black", label="feed")
        ax.set_xlabel("distance along the path [mm]")
    ax.set_ylabel("feed [mm/min]")
    ax.set_title("feed along the path")
    ax.legend(fontsize=7)


def _limits(ax, limits):
    """The programmed feed per feed block and, where held back, the speed reached coloured
    by the cause."""
    edges = np.concatenate([[0.0], np.cumsum(limits.length_m)]) * 1e3
    feed = np.where(limits.limit_m_per_s > 0, limits.feed_m_per_s, np.nan)  # no rapids
    ax.step(edges[:-1], feed * 6e4, where="post", color="gray", ls="--", lw=0.8,
            label="programmed")
    if np.any(np.isfinite(feed)):
        ax.set_ylim(0, 1.15 * np.nanmax(feed) * 6e4)
    colours = dict(zip(limits.CAUSES, pyplot().cm.tab10.colors, strict=False))
    for cause in dict.fromkeys(limits.cause[limits.held]):
        k = limits.held & (limits.cause == cause)
        ax.scatter(0.5 * (edges[:-1] + edges[1:])[k], limits.limit_m_per_s[k] * 6e4, s=6,
                   color=colours[cause], label=f"limit: {cause}")
    ax.set_ylabel("feed [mm/min]")
    ax.legend(fontsize=7)
