"""Plots of identification records (paper Fig. 7)."""

from __future__ import annotations

from . import finish, panels


def plot_sweep(record, R_L, path=None, title=None, ax=None):
    """Excitation and the three position responses against time, ramp removed [µm].

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
    ax : array-like of matplotlib Axes, optional
        Axes to draw into, one per signal (excitation, motor, scale and, when recorded,
        TCP); a new figure when omitted [-].

    Returns
    -------
    matplotlib Figure
        The figure (saved too when ``path`` is given) [-].
    """
    import numpy as np

    t = record.time_s
    rows = [("excitation [A]", record.excitation_A, 1.0),
            ("X_m (motor) [µm]", record.motor_angle_rad * R_L, 1e6),
            ("X_LS (scale) [µm]", record.scale_m, 1e6)]
    if record.tcp_m is not None:
        rows.append(("X_TCP [µm]", record.tcp_m, 1e6))
    fig, axs, own = panels(ax, len(rows), 1, figsize=(10, 1.9 * len(rows)), sharex=True)
    axs = axs[:, 0]
    for a, (label, y, k) in zip(axs, rows, strict=True):
        if k != 1.0:
            y = y - np.polyval(np.polyfit(t, y, 1), t)
        a.plot(t, y * k, lw=0.4)
        a.set_ylabel(label, fontsize=8)
        a.grid(alpha=0.3)
    axs[-1].set_xlabel("time [s]")
    if title:
        axs[0].set_title(title)
    return finish(fig, path, own)


def plot_lost_motion(estimate, path=None, title=None, ax=None):
    """Nut deflection of the constant-speed plateaus against speed, measured and fitted,
    forward and back on a logarithmic speed axis.

    Parameters
    ----------
    estimate : LostMotionEstimate
        Result of :func:`tcpmm.ident.lostmotion.estimate_lost_motion` [-].
    path : str or Path, optional
        Where to save [-].
    title : str, optional
        Title [-].
    ax : matplotlib Axes, optional
        Axes to draw into; a new figure when omitted [-].

    Returns
    -------
    matplotlib Figure
        The figure (saved too when ``path`` is given) [-].
    """
    import numpy as np

    e = estimate
    fig, axs, own = panels(ax, 1, 1, figsize=(7, 4))
    ax = axs[0, 0]
    for sign, label, color in ((1, "forward", "tab:blue"), (-1, "back", "tab:orange")):
        sel = np.flatnonzero(np.sign(e.velocity) == sign)
        sel = sel[np.argsort(np.abs(e.velocity[sel]))]
        if not sel.size:
            continue
        speed = np.abs(e.velocity[sel]) * 1e3
        ax.errorbar(speed, e.nut_deflection[sel] * 1e6, yerr=e.deflection_std[sel] * 1e6,
                    fmt="o", ms=4, color=color, label=f"measured, {label}")
        ax.plot(speed, e.fitted[sel] * 1e6, "--", color=color, lw=1)
    ax.axhline(0.0, color="k", lw=0.5)
    ax.set_xscale("log")
    ax.set_xlabel("table speed [mm/s]")
    ax.set_ylabel("nut deflection [µm]")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8, title=f"fit (dashed): share {e.guideway_share:.2f} "
              f"± {e.guideway_share_std:.2f}, lost motion {e.backlash * 1e6:.2f} µm",
              title_fontsize=8)
    ax.set_title(title or ("split determined" if e.determined else "split not determined"),
                 fontsize=9)
    return finish(fig, path, own)
