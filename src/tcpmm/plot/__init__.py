"""Plots for reports. The only place matplotlib is imported, and only when a plot is made."""

from __future__ import annotations

from pathlib import Path

from ..errors import InputError
from ..io.atomic import atomic_path

SENSOR_STYLE = {
    "cmd": dict(color="black", ls="--", lw=1.0, label="Reference"),
    "motor": dict(color="tab:green", ls="-", lw=1.0, label="ENC (motor encoder)"),
    "scale": dict(color="tab:red", ls=":", lw=1.4, label="LS (linear scale)"),
    "tcp": dict(color="tab:blue", ls="-", lw=1.2, label="TCP"),
}


def pyplot():
    """matplotlib.pyplot with a non-interactive backend."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    return plt


def plot_file(path) -> Path:
    """Check that ``path`` names a file format matplotlib writes; return it as a Path.

    Parameters
    ----------
    path : str or Path
        Plot file [-].
    """
    from matplotlib.backend_bases import FigureCanvasBase

    path = Path(path)
    kinds = FigureCanvasBase.get_supported_filetypes()
    if path.suffix.lower().lstrip(".") not in kinds:
        raise InputError(f"a plot file needs one of the extensions {', '.join(sorted(kinds))} "
                         "(e.g. .png, .pdf or .svg)", file=path)
    return path


def panels(ax, nrows: int, ncols: int, **subplots_kw):
    """The figure and its ``nrows x ncols`` panels: new ones, or those given as ``ax``.

    Parameters
    ----------
    ax : matplotlib Axes or array-like of Axes or None
        Axes to draw into, ``nrows * ncols`` of them in row order; ``None`` makes a new
        figure [-].
    nrows, ncols : int
        Panels the plot draws [-].
    **subplots_kw
        Passed to ``pyplot.subplots`` for a new figure [-].

    Returns
    -------
    fig : matplotlib Figure
        The figure the panels belong to [-].
    axs : ndarray of Axes
        Shape ``(nrows, ncols)`` [-].
    own : bool
        Whether the figure is new (then the plot lays it out) [-].
    """
    import numpy as np

    if ax is None:
        fig, axs = pyplot().subplots(nrows, ncols, squeeze=False, **subplots_kw)
        return fig, axs, True
    axs = np.asarray(ax, dtype=object).reshape(-1)
    if axs.size != nrows * ncols:
        raise ValueError(f"this plot draws {nrows * ncols} panels ({nrows} x {ncols}); "
                         f"ax holds {axs.size}")
    return axs[0].figure, axs.reshape(nrows, ncols), False


def save(fig, path, close: bool = True):
    """Save a figure atomically when ``path`` is given; return the figure.

    Parameters
    ----------
    fig : matplotlib Figure
        The figure [-].
    path : str or Path or None
        Plot file (PNG/PDF/SVG); ``None`` saves nothing [-].
    close : bool
        Release a saved figure from pyplot (it stays usable) [-].
    """
    if path is None:
        return fig

    try:
        path = plot_file(path)
    except Exception:
        if close:
            pyplot().close(fig)
        raise
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=130, bbox_inches="tight")
    if close:
        pyplot().close(fig)
    return fig


def finish(fig, path, own: bool):
    """Lay out a figure the plot made, save it when ``path`` is given; return it.

    Parameters
    ----------
    fig : matplotlib Figure
        The figure [-].
    path : str or Path or None
        Plot file [-].
    own : bool
        The plot made the figure (it lays it out and releases it once saved) [-].
    """
    if own:
        fig.tight_layout()
    return save(fig, path, close=own)
