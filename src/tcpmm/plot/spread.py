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
        Result of :func:`tcpmm.spread.circle_spread` [-].
    path : str or Path, optional
        Output file (PNG/PDF/SVG) [-].
    ax : matplotlib Axes or array-like of Axes, optional
        Axes to draw into, one per pass in row order; a new figure when omitted [-].

    Returns
    -------
    matplotlib Figure
        The figure (saved too when ``path`` is given) [-].
    """
    rows, n_q = spread.rows(), spread.spikes.shape[2]
    n_pass = spread.spikes.shape[1]
    fig, axes, own = panels(ax, 1, n_pass, figsize=(4.2 * n_pass, 3.6), sharey=True)
    jitter = np.linspace(-0.12, 0.12, spread.spikes.shape[0])
    for k, a in enumerate(axes[0]):
        sel = rows[k * n_q:(k + 1) * n_q]
        for i, r in enumerate(sel):
            colour = ("tab:red" if not r["settled"] else
                      "tab:orange" if not r["firm"] else "tab:blue")
            a.vlines(i, r["low_um"], r["high_um"], color=colour, lw=6, alpha=0.25)
            a.plot(i + jitter, spread.spikes[:, k, i] * 1e6, ".", color=colour, ms=3,
                    alpha=0.7)
            a.plot(i, r["spike_um"], "o", color=colour)
            a.plot([i - 0.2, i + 0.2], [r["rise_um"]] * 2, color="0.4", lw=1)
            a.plot([i - 0.2, i + 0.2], [r["fall_um"]] * 2, color="0.4", lw=1)
        a.axhline(0.0, color="0.7", lw=0.8)
        a.set_xticks(range(len(sel)), [r["point"] for r in sel])
        a.set_title(f"{spread.directions[k].upper()}: {spread.sensor} spike")
        a.grid(alpha=0.3)
    axes[0][0].set_ylabel("spike [um] (dots: draws; ticks: rise, fall)")
    fig.suptitle(f"{spread.spikes.shape[0]} drawn machines; red: sign not settled; "
                 f"orange: size not within {spread.tolerance * 1e6:.3g} um", fontsize=9)
    return finish(fig, path, own)
