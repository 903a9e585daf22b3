"""A metric of a sweep against one of its parameters."""

from __future__ import annotations

from ..errors import InputError
from . import finish, panels


def plot_sweep(table, ax=None, x: str | None = None, y: str = "spike_max_um", path=None):
    """One point per variant: ``y`` against ``x``.

    Parameters
    ----------
    table : pandas.DataFrame
        The summary of a sweep (:meth:`tcpmm.whatif.sweep.SweepResult.to_pandas`) [-].
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure when omitted [-].
    x : str, optional
        Parameter column; default the first one, or the index [-].
    y : str
        Metric column [um].
    path : str or Path, optional
        Where to save (PNG/PDF/SVG) [-].

    Returns
    -------
    matplotlib Figure
        The figure (saved too when ``path`` is given) [-].
    """
    if y not in table.columns:
        metrics = [c for c in table.columns if c.endswith("_um")]
        raise InputError(f"no metric {y!r} in the sweep; metrics: {', '.join(metrics)}")
    if x is None:
        params = [c for c in table.columns if "." in c]
        x = params[0] if params else "index"
    fig, axs, own = panels(ax, 1, 1, figsize=(5.0, 3.6))
    ax = axs[0, 0]
    ax.plot(table[x], table[y], "o", ms=3)
    ax.set_xlabel(x)
    ax.set_ylabel(y.replace("_um", " [um]"))
    ax.grid(alpha=0.3)
    return finish(fig, path, own)
