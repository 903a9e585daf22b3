"""Circle diagnostics: radial error of the CCW and CW circles against angle, with the fit."""

from __future__ import annotations

import numpy as np

from ..analysis.circle_display import display_digits
from ..analysis.circle_sigma import shown_uncertainty
from ..analysis.circle_tails import sign_open
from . import finish, panels

STYLE = {"ccw": dict(color="tab:blue", label="CCW"), "cw": dict(color="tab:red", label="CW")}
SUMMARY = (("backlash_{X}", "backlash {X}", 1e6, "µm"), ("backlash_{Y}", "backlash {Y}", 1e6, "µm"),
           ("squareness", "squareness", 1e6, "µm/m"),
           ("squareness_or_servo", "squareness or servo", 1e6, "µm/m"),
           ("scale_mismatch", "scale mismatch", 1e6, "ppm"),
           ("servo_mismatch", "servo mismatch", 1e3, "ms"),
           ("circularity_pair", "G(b)", 1e6, "µm"))


def summary_lines(diag) -> list[str]:
    """The box's lines: each term of :data:`SUMMARY` the circles give, in the tables'
    digits with its ±95%; one the circles leave open, or whose sign the reversals' tails
    leave open, as the tables say it: not determined [-]."""
    names = {"X": diag.axes[0], "Y": diag.axes[1]}
    # the tables' predicate: a value the fit leaves open, or one the wider window turns
    open_ = {*diag.undetermined, *sign_open(diag.terms, diag.tail_shift, diag.radius)}
    lines = []
    for key, label, scale, unit in SUMMARY:
        term = key.format(**names)
        if term not in diag.terms:
            continue
        value, label = diag.terms[term][0], label.format(**names)
        if value != value or term in open_:
            lines.append(f"{label} not determined")
            continue
        n, pm = display_digits(term, unit), shown_uncertainty(diag, term)
        lines.append(f"{label} {value * scale:+.{n}f}"
                     + ("" if pm != pm else f" ± {pm:.{n}f}") + f" {unit}")
    return lines


def plot_circle_diagnostics(diag, ax=None, path=None):
    """Radial error [µm] of both circles against angle [deg], the fitted terms drawn over
    them, quadrant points A-D marked and the main terms in a box.

    Parameters
    ----------
    diag : CircleDiagnostics
        Diagnostics to show [-].
    ax : matplotlib Axes, optional
        Where to draw; a new figure when omitted [-].
    path : str or Path, optional
        Where to save (PNG/PDF/SVG) [-].

    Returns
    -------
    matplotlib Figure
        The figure (saved too when ``path`` is given) [-].
    """
    fig, axs, own = panels(ax, 1, 1, figsize=(9, 4))
    ax = axs[0, 0]
    for d, (angle, e, model) in diag.curves.items():
        deg = np.degrees(np.mod(angle, 2 * np.pi))
        order = np.argsort(deg)
        ax.plot(deg, e * 1e6, ".", ms=1.5, alpha=0.5, color=STYLE[d]["color"])
        line = model[order] * 1e6
        # an arc's model is not drawn across the angles the arc does not cover
        gap = np.r_[False, np.diff(deg[order]) > 2.0]
        ax.plot(deg[order], np.where(gap, np.nan, line), lw=1.2, **STYLE[d])
    for q, deg in zip("ABCD", (0, 90, 180, 270), strict=True):
        ax.axvline(deg, color="gray", lw=0.6)
        ax.annotate(q, (deg + 2, 0.98), xycoords=("data", "axes fraction"), va="top")
    ax.text(1.01, 1.0, "\n".join(summary_lines(diag)), transform=ax.transAxes, va="top",
            fontsize=8, family="monospace")
    ax.set_xlim(0, 360)
    ax.set_xlabel(f"angle from +{diag.axes[0]} [deg]")
    ax.set_ylabel("radial error [µm]")
    ax.set_title(f"circle diagnostics ({diag.sensor}): measured dots, fitted terms lines")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="lower left")
    return finish(fig, path, own)
