"""Time plots of a run: following error of each sensor per axis."""

from __future__ import annotations

from . import SENSOR_STYLE, finish, panels


def plot_run(run, path=None, axes=None, ax=None):
    """Per axis: command and deviations (sensor - command) of motor, scale and TCP [µm].

    Parameters
    ----------
    run : Run
        The run [-].
    path : str or Path, optional
        Where to save [-].
    axes : list of str, optional
        Machine axes to show, default all [-].
    ax : matplotlib Axes or array-like of Axes, optional
        Axes to draw into, two per machine axis (command, deviations) in row order; a
        new figure when omitted [-].

    Returns
    -------
    matplotlib Figure
        The figure (saved too when ``path`` is given) [-].
    """
    names = [a.upper() for a in (axes or run.axes)]
    fig, axs, own = panels(ax, len(names), 2, figsize=(12, 2.6 * len(names)), sharex=True)
    t = run.time_s
    for k, name in enumerate(names):
        a = run.axes[name]
        axs[k, 0].plot(t, a.cmd * 1e3, color="black", lw=1)
        axs[k, 0].set_ylabel(f"{name} command [mm]")
        for s in ("motor", "scale", "tcp"):
            v = a.sensor(s)
            if v is not None and a.cmd is not None:
                axs[k, 1].plot(t, (v - a.cmd) * 1e6, lw=0.9, color=SENSOR_STYLE[s]["color"],
                               label=SENSOR_STYLE[s]["label"])
        axs[k, 1].set_ylabel(f"{name} sensor - command [µm]")
        axs[k, 1].legend(fontsize=7, loc="upper right")
        for a in axs[k]:
            a.grid(alpha=0.3)
    for a in axs[-1]:
        a.set_xlabel("time [s]")
    return finish(fig, path, own)
