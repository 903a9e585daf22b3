"""Plots of identification records (paper Fig. 7)."""

from __future__ import annotations

from . import pyplot, save


def plot_sweep(record, R_L, path=None, title=None):
    """Excitation and the three position responses against time, ramp removed [um].

    Parameters
    ----------
    record : SweepRecord
        The servo-excitation record [SI].
    R_L : float
        Screw ratio lead/2pi to show the motor angle at the table [m/rad].
    path : str or Path, optional
        Where to save [-].
    title : str, optional
        Title [-].
    """
    import numpy as np

    plt = pyplot()
    t = record.time_s
    rows = [("excitation [A]", record.excitation_A, 1.0),
            ("X_m (motor) [um]", record.motor_angle_rad * R_L, 1e6),
            ("X_LS (scale) [um]", record.scale_m, 1e6)]
    if record.tcp_m is not None:
        rows.append(("X_TCP [um]", record.tcp_m, 1e6))
    fig, axs = plt.subplots(len(rows), 1, figsize=(10, 1.9 * len(rows)), sharex=True)
    for ax, (label, y, k) in zip(axs, rows, strict=True):
        if k != 1.0:
            y = y - np.polyval(np.polyfit(t, y, 1), t)
        ax.plot(t, y * k, lw=0.4)
        ax.set_ylabel(label, fontsize=8)
        ax.grid(alpha=0.3)
    axs[-1].set_xlabel("time [s]")
    if title:
        axs[0].set_title(title)
    fig.tight_layout()
    return save(fig, path) or fig
