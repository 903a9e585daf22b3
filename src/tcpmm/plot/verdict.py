"""The verdict on predicted figures: each figure's 90 % interval against its target."""

from __future__ import annotations

from . import finish, panels

_COLOURS = {"firm": "tab:green", "uncertain": "tab:orange", "undetermined": "tab:red"}


def plot_verdict(verdict, path=None, ax=None):
    """Half-width of each figure's 90 % interval (bars, coloured by verdict) and its
    target (ticks), on a logarithmic axis in um.

    Parameters
    ----------
    verdict : Verdict
        Result of :func:`tcpmm.uncertainty.prediction_verdict` [-].
    path : str or Path, optional
        Output file (PNG/PDF/SVG) [-].
    ax : matplotlib Axes, optional
        Axes to draw into; a new figure when omitted [-].

    Returns
    -------
    matplotlib Figure
        The figure (saved too when ``path`` is given) [-].
    """
    figs = verdict.figures
    fig, axes, own = panels(ax, 1, 1, figsize=(8, 0.22 * len(figs) + 1.5))
    a = axes[0, 0]
    y = range(len(figs))
    a.barh(list(y), [f.half_width * 1e6 for f in figs],
           color=[_COLOURS[f.verdict] for f in figs])
    a.plot([f.target * 1e6 for f in figs], list(y), "k|", markersize=10, label="target")
    a.set_yticks(list(y), [f"{f.test} {f.direction} {f.figure}" for f in figs], fontsize=7)
    a.set_xscale("log")
    a.invert_yaxis()
    a.set_xlabel("half-width of the 90 % interval [um]")
    a.legend(loc="lower right")
    return finish(fig, path, own)
