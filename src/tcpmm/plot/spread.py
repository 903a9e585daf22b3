"""Reversal spikes of a circle with their spread over drawn machines."""

from __future__ import annotations

import numpy as np

from . import finish, panels


def plot_spike_spread(spread, path=None, ax=None):
    """Nominal spike, rise and fall per quadrant point and pass, and the spike of each draw
    with their range; points whose sign the draws do not settle in red, those whose size
    they do not hold within the tolerance in orange.

    Parameters
    ----------
    spread : SpikeSpread
        Result of :func:`tcpmm.whatif.spread.circle_spread` [-].
    path : str or Path, optional
        Output file (PNG/PDF/SVG) [-].
    ax : matplotlib Axes or array-like of Axes, optional
        Axes to draw into, one per pass in row order; a new figure when omitted [-].

    Returns
    -------
    matplotlib Figure
        The figure (saved too when ``path`` is given) [-].
    """
    return plot_spread_rows(spread.rows(), spread.sensor, spread.tolerance,
                            spread.spikes.shape[0], spread.spikes, path, ax)


def plot_spread_rows(rows, sensor, tolerance, draws, spikes=None, path=None, ax=None):
    """:func:`plot_spike_spread` from the rows of a spread (``SpikeSpread.rows()``, or the
    ``spikes`` of ``tcpmm spread --json``); without the spike of each draw, only their
    range is drawn.

    Parameters
    ----------
    rows : list of dict
        Per pass and quadrant point A-D, in that order: ``direction``, ``point``,
        ``spike_um``, ``rise_um``, ``fall_um``, ``low_um``, ``high_um``, ``settled``,
        ``firm`` [µm].
    sensor : str
        The sensor analysed [-].
    tolerance : float
        Distance from the nominal spike within which a draw agrees with it [m].
    draws : int
        Number of drawn machines [-].
    spikes : numpy.ndarray, optional
        Spike per draw, pass and quadrant point, shape ``(draws, passes, 4)`` [m].
    path : str or Path, optional
        Output file (PNG/PDF/SVG) [-].
    ax : matplotlib Axes or array-like of Axes, optional
        Axes to draw into, one per pass in row order; a new figure when omitted [-].

    Returns
    -------
    matplotlib Figure
        The figure (saved too when ``path`` is given) [-].
    """
    n_q = 4
    n_pass = len(rows) // n_q
    fig, axes, own = panels(ax, 1, n_pass, figsize=(4.2 * n_pass, 3.6), sharey=True)
    jitter = np.linspace(-0.12, 0.12, draws)
    for k, a in enumerate(axes[0]):
        sel = rows[k * n_q:(k + 1) * n_q]
        for i, r in enumerate(sel):
            colour = ("tab:red" if not r["settled"] else
                      "tab:orange" if not r.get("draws_agree", r["firm"]) else "tab:blue")
            a.vlines(i, r["low_um"], r["high_um"], color=colour, lw=6, alpha=0.25)
            if spikes is not None:
                a.plot(i + jitter, spikes[:, k, i] * 1e6, ".", color=colour, ms=3,
                       alpha=0.7)
            a.plot(i, r["spike_um"], "o", color=colour)
            a.plot([i - 0.2, i + 0.2], [r["rise_um"]] * 2, color="0.4", lw=1)
            a.plot([i - 0.2, i + 0.2], [r["fall_um"]] * 2, color="0.4", lw=1)
        a.axhline(0.0, color="0.7", lw=0.8)
        a.set_xticks(range(len(sel)), [r["point"] for r in sel])
        a.set_title(f"{sel[0]['direction'].upper()}: {sensor} spike")
        a.grid(alpha=0.3)
    axes[0][0].set_ylabel("spike [µm] (" + ("dots: draws; " if spikes is not None else
                                             "bar: range of the draws; ")
                          + "ticks: rise, fall)")
    fig.suptitle(f"{draws} drawn machines; red: sign not settled; "
                 f"orange: size not within {tolerance * 1e6:.3g} µm", fontsize=9)
    return finish(fig, path, own)
