"""Bode plots of transfer functions (paper Figs. 8-10)."""

from __future__ import annotations

import numpy as np

from ..servo.closedloop import TF_MEANING
from . import finish, panels

#: Measured bins below this coherence are not drawn.
MIN_COHERENCE = 0.5


def _phase_deg(H) -> np.ndarray:
    """Phase in (-180, 180] [deg], NaN after each jump across ±180 deg so that the line
    breaks there rather than drawing the wrap as a vertical stroke."""
    ph = np.degrees(np.angle(H))
    jump = np.r_[False, np.abs(np.diff(ph)) > 180.0]
    return np.where(jump, np.nan, ph)


def plot_bode(curves, path=None, title=None, ax=None):
    """Magnitude (dB) and phase per transfer function, one column each.

    Parameters
    ----------
    curves : dict
        ``{tf_name: [(label, f_hz, H, style_dict), ...]}``; an optional coherence can be
        given as a fifth element: it is drawn under the magnitude, and bins below
        :data:`MIN_COHERENCE` are left out [-].
    path : str or Path, optional
        Where to save [-].
    title : str, optional
        Figure title [-].
    ax : matplotlib Axes or array-like of Axes, optional
        Axes to draw into, two per transfer function (the magnitudes, then the phases);
        a new figure when omitted [-].

    Returns
    -------
    matplotlib Figure
        The figure (saved too when ``path`` is given) [-].
    """
    names = list(curves)
    fig, axs, own = panels(ax, 2, len(names), figsize=(4.6 * len(names), 6.0), sharex="col")
    for k, name in enumerate(names):
        am, ap = axs[0, k], axs[1, k]
        for item in curves[name]:
            label, f, H, style = item[:4]
            coh = item[4] if len(item) > 4 else None
            if coh is not None:  # measured: hide bins the excitation did not reach
                H = np.where(coh >= MIN_COHERENCE, H, np.nan)
            am.semilogx(f, 20 * np.log10(np.abs(H) + 1e-300), label=label, **style)
            ap.semilogx(f, _phase_deg(H), **style)
            if coh is not None:
                ac = am.twinx()
                ac.semilogx(f, item[4], color="gray", lw=0.6, alpha=0.6)
                ac.set_ylim(0, 4)
                ac.set_yticks([0, 0.5, 1])
                ac.set_ylabel("coherence", fontsize=7, color="gray")
        am.set_title(name)
        unit = TF_MEANING.get(name, ("", ""))[1]
        am.set_ylabel(f"|{name}| [dB re 1 {unit}]" if unit else f"|{name}| [dB]")
        ap.set_ylabel("phase [deg]")
        ap.set_ylim(-185, 185)
        ap.set_yticks([-180, -90, 0, 90, 180])
        ap.set_xlabel("frequency [Hz]")
        for a in (am, ap):
            a.grid(alpha=0.3, which="both")
        am.legend(fontsize=7)
    if title:
        fig.suptitle(title)
    return finish(fig, path, own)
