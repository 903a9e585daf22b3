"""Plot of an interpolated position command."""

from __future__ import annotations

import numpy as np

from . import finish, panels


def plot_command(cmd, path=None, ax=None):
    """Path in the XY plane and per-axis position and velocity against time.

    Parameters
    ----------
    cmd : Command
        The command [-].
    path : str or Path, optional
        Where to save (PNG/PDF/SVG) [-].
    ax : matplotlib Axes or array-like of Axes, optional
        Axes to draw into, three (XY path, position, velocity); a new figure when
        omitted [-].

    Returns
    -------
    matplotlib Figure
        The figure (saved too when ``path`` is given) [-].
    """
    fig, axs, own = panels(ax, 1, 3, figsize=(14, 4.2))
    axs = axs[0]
    P = cmd.positions
    if "X" in P and "Y" in P:
        axs[0].plot(P["X"] * 1e3, P["Y"] * 1e3, lw=1)
        axs[0].set_aspect("equal")
        axs[0].set_xlabel("X [mm]")
        axs[0].set_ylabel("Y [mm]")
    for name, p in P.items():
        axs[1].plot(cmd.time_s, p * 1e3, label=name)
        axs[2].plot(cmd.time_s, np.gradient(p, cmd.time_s) * 6e4, label=name)
    axs[1].set_ylabel("position [mm]")
    axs[2].set_ylabel("velocity [mm/min]")
    for a in axs[1:]:
        a.set_xlabel("time [s]")
        a.legend()
    for a in axs:
        a.grid(alpha=0.3)
    return finish(fig, path, own)
