"""Bode plots of measured frequency responses and of transfer functions fitted to them."""

from __future__ import annotations

import numpy as np

from . import finish, panels


def _axes(ax, rows: int):
    fig, axs, own = panels(ax, rows, 1, figsize=(7.0, 2.2 + 1.7 * rows), sharex=True,
                           gridspec_kw={"height_ratios": [3, 2, 1.3][:rows]})
    return fig, axs[:, 0], own


def _finish(fig, axs, title, path, own):
    for a in axs:
        a.grid(alpha=0.3, which="both")
    axs[-1].set_xlabel("frequency [Hz]")
    if title:
        axs[0].set_title(title)
    return finish(fig, path, own)


def plot_frf(frf, path=None, ax=None, title=None):
    """Magnitude, phase and coherence of a measured frequency response.

    Parameters
    ----------
    frf : FRF
        The response [unit].
    path : str or Path, optional
        Where to save the figure [-].
    ax : sequence of 3 matplotlib Axes, optional
        Axes to draw into (magnitude, phase, coherence) [-].
    title : str, optional
        Title [-].
    """
    fig, axs, own = _axes(ax, 3)
    f = frf.freq_hz
    axs[0].semilogx(f, frf.magnitude_db, color="tab:blue", lw=1.0, label="measured")
    axs[1].semilogx(f, np.degrees(np.angle(frf.H)), color="tab:blue", lw=1.0)
    axs[2].semilogx(f, frf.coherence, color="gray", lw=1.0)
    axs[0].set_ylabel("magnitude [dB]")
    axs[1].set_ylabel("phase [deg]")
    axs[1].set_yticks([-180, -90, 0, 90, 180])
    axs[2].set_ylabel("coherence [-]")
    axs[2].set_ylim(0, 1.05)
    name = f"{frf.name}: {frf.output} / {frf.input}" if frf.input else frf.name
    return _finish(fig, axs, title or name, path, own)


def plot_frf_fit(f_hz, H, H_fit, coherence=None, band_hz=None, path=None, ax=None,
                 title=None):
    """Measured response against a fitted model, with the relative residual.

    Parameters
    ----------
    f_hz : ndarray
        Frequencies of the measurement [Hz].
    H : ndarray
        Measured response [unit].
    H_fit : ndarray
        Model response at ``f_hz`` [unit].
    coherence : ndarray, optional
        Coherence of the measurement, drawn in the residual panel [-].
    band_hz : tuple of float, optional
        Band fitted, shaded [Hz].
    path : str or Path, optional
        Where to save the figure [-].
    ax : sequence of 3 matplotlib Axes, optional
        Axes to draw into (magnitude, phase, residual) [-].
    title : str, optional
        Title [-].
    """
    fig, axs, own = _axes(ax, 3)
    db = lambda h: 20 * np.log10(np.abs(h) + 1e-300)  # noqa: E731
    axs[0].semilogx(f_hz, db(H), color="tab:blue", lw=1.0, label="measured")
    axs[0].semilogx(f_hz, db(H_fit), color="tab:red", lw=1.2, ls="--", label="fit")
    axs[1].semilogx(f_hz, np.degrees(np.angle(H)), color="tab:blue", lw=1.0)
    axs[1].semilogx(f_hz, np.degrees(np.angle(H_fit)), color="tab:red", lw=1.2, ls="--")
    with np.errstate(divide="ignore", invalid="ignore"):
        res = np.abs(H_fit / H - 1)
    axs[2].semilogx(f_hz, db(res), color="black", lw=0.8, label="|fit/measured - 1|")
    if coherence is not None:
        noise = np.sqrt(np.clip(1 - coherence, 1e-12, 1) / np.clip(coherence, 1e-12, 1))
        axs[2].semilogx(f_hz, db(noise), color="gray", lw=0.8,
                        label="sqrt((1-coh)/coh)")
    if band_hz is not None:
        for a in axs:
            a.axvspan(*band_hz, color="tab:green", alpha=0.06, lw=0)
    axs[0].set_ylabel("magnitude [dB]")
    axs[1].set_ylabel("phase [deg]")
    axs[1].set_yticks([-180, -90, 0, 90, 180])
    axs[2].set_ylabel("residual [dB]")
    axs[0].legend(fontsize=7)
    axs[2].legend(fontsize=7)
    return _finish(fig, axs, title, path, own)
