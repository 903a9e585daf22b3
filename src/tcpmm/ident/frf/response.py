"""Frequency response functions from excitation records (Welch averaging).

The FRF of an output ``y`` against an input ``u`` is estimated from averaged auto- and
cross-spectra of overlapping windowed segments:

* ``H1 = S_uy / S_uu`` (noise on the output only: unbiased),
* ``H2 = S_yy / S_yu`` (noise on the input only: unbiased).

With the loops closed, the measured input of a plant is correlated with the sensor noise
fed back by the controller, and ``H1`` of output against measured input is biased. The
remedy is to estimate every signal against the injected excitation ``r`` (noise free, not
in the loop) and to take ratios, e.g. ``G_M = (omega_m/r) / (i_c/r)``:
:func:`frf_against_reference` and :func:`reduced_frfs`.

Random error (Bendat & Piersol, *Random Data*, ch. 9): for ``n_d`` independent averages and
ordinary coherence ``gamma^2``, the normalised standard deviation of ``|H|`` and the
standard deviation of the phase [rad] are both
``sqrt(1 - gamma^2) / (|gamma| sqrt(2 n_d))``. Overlapping segments are not independent:
``n_d`` is the effective number of averages of Welch's method for the window and overlap
used, and ``n_d - 1`` replaces ``n_d`` to undo the upward bias of estimated coherence.

The formula is exact to first order for random and periodic (multisine) excitation. For a
swept sine it is some 10-20 % optimistic in standard deviation (the excitation is
deterministic, so the noise of overlapping segments does not average as for random input),
and a sweep biases lightly damped resonances when the response outlasts a fair part of a
segment: keep segments long against the sweep's dwell in the resonance and against the
decay time ``1 / (zeta omega)`` of the slowest mode (the default segment length does).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from scipy import signal

from ...errors import InputError
from ...frfdata import FRF, coherence_rel_std
from ._spectral import (
    band_bins,
    checked_signal,
    detrend_order,
    effective_averages,
    remove_trend,
    sample_rate_hz,
    segmenting,
)
from .periodic import detect_period, periodic_frf

__all__ = [
    "FRF",
    "estimate_frf",
    "frf_against_reference",
    "reduced_frfs",
    "remove_trend",
    "sample_rate_hz",
]


# ----------------------------------------------------------------------------- estimators


def estimate_frf(u, y, fs_hz: float, nperseg: int | None = None, window: str = "hann",
                 overlap: float = 0.5, estimator: str = "H1", detrend="linear",
                 fmin_hz: float | None = None, fmax_hz: float | None = None, name: str = "",
                 input: str = "u", output: str = "y", file=None, period="auto") -> FRF:
    """FRF of ``y`` against ``u`` by Welch-averaged spectra, or from whole periods when
    the excitation is periodic (:mod:`tcpmm.ident.frf.periodic`).

    Parameters
    ----------
    u : array_like
        Input samples, uniformly sampled [SI unit of the input].
    y : array_like
        Output samples, same length [SI unit of the output].
    fs_hz : float
        Sample rate [Hz].
    nperseg : int, optional
        Segment length. Default: the largest power of two giving at least 8 segments, raised
        if needed so that ``fmin_hz`` lies at least 4 bins above 0 Hz [-].
    window : str
        Window name understood by :func:`scipy.signal.get_window` [-].
    overlap : float
        Segment overlap fraction, 0..<1 [-].
    estimator : {"H1", "H2"}
        ``H1 = S_uy/S_uu`` (output noise) or ``H2 = S_yy/S_yu`` (input noise) [-].
    detrend : str or int or None
        Polynomial trend removed from both signals over the whole record before segmenting:
        "constant", "linear" (default), "quadratic", "cubic", an order, or None. Each segment
        then has its mean removed [-].
    fmin_hz : float, optional
        Lowest frequency of interest; default the lowest excited bin [Hz].
    fmax_hz : float, optional
        Highest frequency of interest; default the highest excited bin [Hz].
    name : str
        Name of the FRF [-].
    input, output : str
        Input and output labels, also used as column names in errors [-].
    file : str or Path, optional
        Source file for error messages [-].
    period : "auto", int or None
        Period of a periodic excitation [samples]: ``"auto"`` detects it
        (:func:`~tcpmm.ident.frf.periodic.detect_period`) unless ``nperseg`` is given,
        ``None`` always averages windowed segments. With a period, whole periods give
        exact bins with no window, and only the excited bins are returned [-].

    Returns
    -------
    FRF
        Response, coherence and random error per bin [-].
    """
    fs_hz = _checked_rate(fs_hz)
    est = _checked_estimator(estimator)
    u = checked_signal(u, input, None, file)
    y = checked_signal(y, output, u.size, file)
    p = _excitation_period(u, period, nperseg)
    if p is not None:
        return periodic_frf(u, y, fs_hz, p, fmin_hz, fmax_hz, name=name, input=input,
                            output=output)
    return _welch_estimate(u, y, fs_hz, nperseg, window, overlap, est, detrend, fmin_hz,
                           fmax_hz, name or f"{output}/{input}", input, output, file)


def _checked_estimator(estimator: str) -> str:
    """``"H1"`` or ``"H2"`` in capitals; raises for any other estimator [-]."""
    est = estimator.upper()
    if est not in ("H1", "H2"):
        raise InputError(f"estimator must be 'H1' or 'H2', got {estimator!r}")
    return est


def _excitation_period(u, period, nperseg) -> int | None:
    """The period of the excitation ``u`` the FRF is taken over: detected for ``"auto"``
    unless a segment length is given, as given, or ``None`` for Welch averaging [samples]."""
    if period is None or (period == "auto" and nperseg is not None):
        return None
    return detect_period(u) if period == "auto" else int(period)


def _welch_estimate(u, y, fs_hz: float, nperseg, window: str, overlap: float, est: str,
                    detrend, fmin_hz, fmax_hz, name: str, input: str, output: str,
                    file) -> FRF:
    """The FRF by Welch-averaged spectra of the signals detrended over the whole record,
    with its coherence and random error [-]."""
    m, noverlap, k = segmenting(u.size, fs_hz, nperseg, fmin_hz, overlap, file)
    order = detrend_order(detrend)
    f, H, coh = _welch_frf(remove_trend(u, order), remove_trend(y, order), fs_hz, window, m,
                           noverlap, est, fmin_hz, fmax_hz, input, file)
    n_eff = effective_averages(signal.get_window(window, m), m - noverlap, k)
    return FRF(freq_hz=f, H=H, coherence=coh, n_averages=n_eff,
               rel_std=coherence_rel_std(coh, n_eff), name=name,
               input=input, output=output,
               meta={"nperseg": m, "n_segments": k, "window": window, "overlap": overlap,
                     "estimator": est, "fs_hz": fs_hz})


def _checked_rate(fs_hz) -> float:
    """The sample rate as a float; raises unless finite and positive [Hz]."""
    fs_hz = float(fs_hz)
    if not np.isfinite(fs_hz) or fs_hz <= 0:
        raise InputError(f"sample rate must be > 0, got {fs_hz}")
    return fs_hz


def _welch_frf(u, y, fs_hz, window, m, noverlap, est, fmin_hz, fmax_hz, input, file):
    """Frequencies, H1 or H2 response and coherence from Welch-averaged spectra of the
    detrended signals, in the band [Hz, -, -]."""
    kw = dict(fs=fs_hz, window=window, nperseg=m, noverlap=noverlap, detrend="constant")
    f, p_uu = signal.welch(u, **kw)
    _, p_yy = signal.welch(y, **kw)
    _, p_uy = signal.csd(u, y, **kw)
    keep = band_bins(f, p_uu, fmin_hz, fmax_hz, input, file)
    f, p_uu, p_yy, p_uy = f[keep], p_uu[keep], p_yy[keep], p_uy[keep]
    with np.errstate(divide="ignore", invalid="ignore"):
        H = p_uy / p_uu if est == "H1" else p_yy / np.conj(p_uy)
        coh = np.abs(p_uy) ** 2 / (p_uu * p_yy)
    return f, H, np.nan_to_num(np.clip(coh, 0.0, 1.0))


def frf_against_reference(r, signals: dict, fs_hz: float, nperseg: int | None = None,
                          window: str = "hann", overlap: float = 0.5, detrend="linear",
                          fmin_hz: float | None = None, fmax_hz: float | None = None,
                          reference: str = "r", file=None) -> dict[str, FRF]:
    """H1 of every signal against the injected excitation ``r``.

    ``r`` is generated, not measured, and enters the loop from outside, so H1 against it is
    unbiased even with the loops closed; ratios of these FRFs give plant FRFs.

    Parameters
    ----------
    r : array_like
        Injected excitation samples [SI unit of r, e.g. A].
    signals : dict of str to array_like
        Output signals by name, same length as ``r`` [SI unit of each signal].
    fs_hz : float
        Sample rate [Hz].
    nperseg : int, optional
        Segment length, see :func:`estimate_frf` [-].
    window : str
        Window name [-].
    overlap : float
        Segment overlap fraction [-].
    detrend : str or int or None
        Trend removed over the whole record, see :func:`estimate_frf` [-].
    fmin_hz : float, optional
        Lowest frequency of interest [Hz].
    fmax_hz : float, optional
        Highest frequency of interest [Hz].
    reference : str
        Name of ``r`` (column name in errors and labels) [-].
    file : str or Path, optional
        Source file for error messages [-].

    Returns
    -------
    dict of str to FRF
        ``signals[name] / r`` for every name, on one common frequency grid [-].
    """
    fs_hz = _checked_rate(fs_hz)
    r = checked_signal(r, reference, None, file)
    outs = {k: checked_signal(v, k, r.size, file) for k, v in signals.items()}
    order = detrend_order(detrend)
    m, noverlap, k = segmenting(r.size, fs_hz, nperseg, fmin_hz, overlap, file)
    r = remove_trend(r, order)
    kw = dict(fs=fs_hz, window=window, nperseg=m, noverlap=noverlap, detrend="constant")
    f, p_rr = signal.welch(r, **kw)
    keep = band_bins(f, p_rr, fmin_hz, fmax_hz, reference, file)
    n_eff = effective_averages(signal.get_window(window, m), m - noverlap, k)
    meta = {"nperseg": m, "n_segments": k, "window": window, "overlap": overlap,
            "estimator": "H1", "fs_hz": fs_hz, "detrend": order}
    result = {}
    for key, y in outs.items():
        H, coh = _h1_against(r, remove_trend(y, order), kw, keep, p_rr)
        result[key] = FRF(freq_hz=f[keep], H=H, coherence=coh, n_averages=n_eff,
                          rel_std=coherence_rel_std(coh, n_eff), name=f"{key}/{reference}",
                          input=reference, output=key, meta=dict(meta))
    return result


def _h1_against(r, y, kw: dict, keep, p_rr) -> tuple:
    """H1 of the detrended ``y`` against the detrended reference ``r`` of auto-spectrum
    ``p_rr``, and their coherence, at the bins ``keep`` of the band [SI, -]."""
    _, p_yy = signal.welch(y, **kw)
    _, p_ry = signal.csd(r, y, **kw)
    with np.errstate(divide="ignore", invalid="ignore"):
        H = p_ry[keep] / p_rr[keep]
        coh = np.abs(p_ry[keep]) ** 2 / (p_rr[keep] * p_yy[keep])
    return H, np.nan_to_num(np.clip(coh, 0.0, 1.0))


def reduced_frfs(excitation_A, current_A, motor_angle_rad, scale_m, tcp_m=None,
                 fs_hz: float | None = None, time_s=None, nperseg: int | None = None,
                 window: str = "hann", overlap: float = 0.5, detrend="linear",
                 fmin_hz: float | None = None, fmax_hz: float | None = None,
                 file=None) -> dict[str, FRF]:
    """The FRFs of the reduced models of one axis from a servo-excitation record.

    ``G_M = omega_m/i_c = (j 2 pi f theta_m/r) / (i_c/r)``, ``G_T = X_LS/theta_m =
    (X_LS/r) / (theta_m/r)``, ``G_tcp = X_TCP/X_LS = (X_TCP/r) / (X_LS/r)``. The motor
    speed comes from the motor angle in the frequency domain (no differencing of quantised
    samples). Position ramps are removed by the trend fitted over the whole record.

    Parameters
    ----------
    excitation_A : array_like
        Injected excitation r [A].
    current_A : array_like
        Current command i_c [A].
    motor_angle_rad : array_like
        Motor encoder angle theta_m [rad].
    scale_m : array_like
        Linear scale X_LS [m].
    tcp_m : array_like, optional
        TCP position X_TCP [m]; without it no ``G_tcp`` [m].
    fs_hz : float, optional
        Sample rate; give this or ``time_s`` [Hz].
    time_s : array_like, optional
        Sample times, checked for uniform sampling [s].
    nperseg : int, optional
        Segment length, see :func:`estimate_frf` [-].
    window : str
        Window name [-].
    overlap : float
        Segment overlap fraction [-].
    detrend : str or int or None
        Trend removed over the whole record [-].
    fmin_hz : float, optional
        Lowest frequency of interest [Hz].
    fmax_hz : float, optional
        Highest frequency of interest [Hz].
    file : str or Path, optional
        Source file for error messages [-].

    Returns
    -------
    dict of str to FRF
        ``"G_M"`` [rad/s/A], ``"G_T"`` [m/rad], and ``"G_tcp"`` [-] if TCP data exist.
    """
    fs_hz = _record_rate(time_s, fs_hz, excitation_A, file)
    signals = {"current_A": current_A, "motor_angle_rad": motor_angle_rad, "scale_m": scale_m}
    if tcp_m is not None:
        signals["tcp_m"] = tcp_m
    f = frf_against_reference(excitation_A, signals, fs_hz, nperseg=nperseg, window=window,
                              overlap=overlap, detrend=detrend, fmin_hz=fmin_hz,
                              fmax_hz=fmax_hz, reference="excitation_A", file=file)
    return _plant_ratios(f)


def _plant_ratios(f: dict) -> dict:
    """G_M, G_T and (with ``tcp_m``) G_tcp as ratios of the FRFs against the excitation;
    the motor speed from the motor angle in the frequency domain [SI]."""
    omega = f["motor_angle_rad"].differentiate(output="omega_m")
    out = {
        "G_M": replace(omega / f["current_A"], name="G_M", input="i_c", output="omega_m"),
        "G_T": replace(
            f["scale_m"] / f["motor_angle_rad"], name="G_T", input="theta_m", output="X_LS"
        ),
    }
    if "tcp_m" in f:
        out["G_tcp"] = replace(
            f["tcp_m"] / f["scale_m"], name="G_tcp", input="X_LS", output="X_TCP"
        )
    return out


def _record_rate(time_s, fs_hz, excitation_A, file) -> float:
    """Sample rate of a record from its time column, checked against ``fs_hz`` and the
    length of the excitation, or ``fs_hz`` without a time column [Hz]."""
    if time_s is not None:
        fs_t = sample_rate_hz(time_s, file=file)
        if fs_hz is not None and abs(fs_t - fs_hz) > 1e-3 * fs_hz:
            raise InputError(
                f"time column gives {fs_t:.6g} Hz, fs_hz says {fs_hz:.6g} Hz",
                file=file,
                column="time_s",
            )
        fs_hz = fs_t
        n_t = np.asarray(time_s).size
        if np.asarray(excitation_A).size != n_t:
            raise InputError(
                f"{np.asarray(excitation_A).size} excitation samples for {n_t} time samples",
                file=file,
                column="excitation_A",
            )
    if fs_hz is None:
        raise InputError("give the sample rate fs_hz or the time vector time_s")
    return fs_hz
