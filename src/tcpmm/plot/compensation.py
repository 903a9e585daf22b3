"""Plot of a compensation: the predicted TCP error before and after, and the factors."""

from __future__ import annotations

import numpy as np

from ..compensate.scores import before_after
from . import finish, panels


def plot_compensation(comp, path=None, ax=None):
    """The applied correction per axis and its share, with the samples where the draws of
    the model trust it; the figure.

    Parameters
    ----------
    comp : Compensation
        The compensation [-].
    path : str or Path, optional
        Also save the figure there [-].
    ax : array-like of two matplotlib Axes, optional
        Where to draw [-].
    """
    fig, axs, own = panels(ax, 2, 1, figsize=(8, 6), sharex=True)
    ax = axs[:, 0]
    t = comp.reference.time_s
    for a in comp.reference.axes:
        ax[0].plot(t, comp.correction[a] * comp.factors[a] * 1e6, label=f"{a} correction")
        ax[1].plot(t, comp.factors[a], label=f"{a} share")
    if comp.trusted is not None:
        ax[1].fill_between(t, 0, np.where(comp.trusted, 1.0, 0.0), alpha=0.15,
                           label="trusted")
    ax[0].set_ylabel("applied correction [µm]")
    ax[1].set_ylabel("share [-]")
    ax[1].set_xlabel("time [s]")
    for a in ax:
        a.legend(loc="best", fontsize=8)
    return finish(fig, path, own)


def plot_controller_compensation(cc, path=None, ax=None):
    """The predicted TCP figures before and after a controller-side compensation, as bars;
    the figure.

    Parameters
    ----------
    cc : ControllerCompensation
        The compensation with its scores [-].
    path : str or Path, optional
        Also save the figure there [-].
    ax : matplotlib Axes, optional
        Where to draw [-].
    """
    fig, axs, own = panels(ax, 1, 1, figsize=(6, 3.5))

    a = axs[0, 0]
    shown = before_after(cc.scores, ("contour_error_um", "largest_spike_um",
                                     "circular_deviation_um"))
    x = np.arange(len(shown))
    a.bar(x - 0.2, [s[1] for s in shown], 0.4, label="before")
    a.bar(x + 0.2, [s[2] for s in shown], 0.4, label="after")
    a.set_xticks(x, [s[0] for s in shown])
    a.set_ylabel("TCP [µm]")
    a.legend(loc="best", fontsize=8)
    return finish(fig, path, own)
