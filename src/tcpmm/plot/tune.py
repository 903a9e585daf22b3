"""Open sampled velocity loops before and after tuning."""

from __future__ import annotations

import numpy as np

from ..servo.margins import velocity_loop_gain
from . import finish, panels


def plot_tuning(result, path=None, ax=None):
    """Magnitude and phase of the open velocity loop ``L_v`` of each axis, as given and as
    tuned, with the unit-gain and -180 deg lines where the margins are read.

    Parameters
    ----------
    result : TuneResult
        Result of :func:`tcpmm.whatif.tuning.tune_and_predict` [-].
    path : str or Path, optional
        Output file (PNG/PDF/SVG) [-].
    ax : matplotlib Axes or array-like of Axes, optional
        Axes to draw into, two per axis (magnitude over phase) in row order; a new figure
        when omitted [-].

    Returns
    -------
    matplotlib Figure
        The figure (saved too when ``path`` is given) [-].
    """
    names = list(result.axes)
    fig, axes, own = panels(ax, 2, len(names), figsize=(4.2 * len(names), 5.4), sharex="col")
    for k, name in enumerate(names):
        t = result.axes[name]
        mech = result.tuned.axes[name].mechanics
        f = np.logspace(0, np.log10(0.49 / t.before.T_v), 600)
        for servo, label, style in ((t.before, "before", "--"), (t.after, "after", "-")):
            L = velocity_loop_gain(mech, servo, f)
            axes[0][k].semilogx(f, 20 * np.log10(np.abs(L)), style, label=label)
            axes[1][k].semilogx(f, np.degrees(np.angle(L)), style, label=label)
        axes[0][k].axhline(0.0, color="0.5", lw=0.8)
        axes[1][k].axhline(-180.0, color="0.5", lw=0.8)
        axes[0][k].set_title(f"axis {name}: open velocity loop")
        axes[1][k].set_xlabel("frequency [Hz]")
        for a in (axes[0][k], axes[1][k]):
            a.grid(alpha=0.3)
    axes[0][0].set_ylabel("|L_v| [dB]")
    axes[1][0].set_ylabel("phase [deg]")
    axes[0][0].legend(fontsize=8)
    return finish(fig, path, own)
