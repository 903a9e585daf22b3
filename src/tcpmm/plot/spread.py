"""Reversal spikes of a circle with their spread over drawn machines."""

from __future__ import annotations

from . import pyplot, save


def plot_spike_spread(spread, path=None):
    """Nominal spike, rise and fall per quadrant point, and the range of the spike over the
    draws; points whose sign the draws do not settle in red.

    Parameters
    ----------
    spread : SpikeSpread
        Result of :func:`tcpmm.spread.circle_spread` [-].
    path : str or Path, optional
        Output file; ``None`` returns the open figure [-].
    """
    plt = pyplot()
    rows = spread.rows()
    directions = list(dict.fromkeys(r["direction"] for r in rows))
    fig, axes = plt.subplots(1, len(directions), figsize=(4.2 * len(directions), 3.6),
                             sharey=True, squeeze=False)
    for ax, d in zip(axes[0], directions, strict=True):
        sel = [r for r in rows if r["direction"] == d]
        for i, r in enumerate(sel):
            colour = "tab:blue" if r["settled"] else "tab:red"
            ax.vlines(i, r["low_um"], r["high_um"], color=colour, lw=6, alpha=0.35)
            ax.plot(i, r["spike_um"], "o", color=colour)
            ax.plot([i - 0.2, i + 0.2], [r["rise_um"]] * 2, color="0.4", lw=1)
            ax.plot([i - 0.2, i + 0.2], [r["fall_um"]] * 2, color="0.4", lw=1)
        ax.axhline(0.0, color="0.7", lw=0.8)
        ax.set_xticks(range(len(sel)), [r["point"] for r in sel])
        ax.set_title(f"{d.upper()}: {spread.sensor} spike")
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel("spike [um] (bar: range over draws; ticks: rise, fall)")
    fig.suptitle(f"{spread.spikes.shape[0]} drawn machines; red: sign not settled",
                 fontsize=9)
    fig.tight_layout()
    return save(fig, path) or fig
