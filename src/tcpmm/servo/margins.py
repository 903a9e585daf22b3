"""Gain and phase margins of the sampled velocity and position loops.

The loop gains are those of the package's exact sampled loop (:mod:`tcpmm.servo.sampled`):
ZOH plant, current-loop lag, computation delay, current-setpoint filters and the
sampling of each loop. The velocity loop is opened at the current setpoint (period
``T_v``), the position loop at the velocity command (lifted to ``T_p``, velocity loop
closed). Crossings are bracketed on a logarithmic grid up to the Nyquist frequency,
refined around every lightly damped pole to a tenth of its half-power width (a
resonance peak that crosses ``|L| = 1`` is not stepped over), then located by Brent's
method. Of several crossings the margin closest to instability is reported (smallest
``|log GM|``, smallest ``|PM|``), as ``control.margin`` does; the lowest gain crossover
is reported as well (the loop's bandwidth in the usual sense).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np
from scipy.optimize import brentq

from ..mechanics.lumped import AxisMechanics
from .freqresp import loop_response
from .params import ServoParams
from .sampled import position_open_loop, velocity_open_loop

#: Grid points per decade that bracket the crossings [-].
_PER_DECADE = 400
#: the lowest frequency a crossover is searched down to: a position gain of 6e-9 1/s
#: crosses there, far below any loop a machine runs [Hz]
LOWEST_HZ = 1e-9


@dataclass(frozen=True)
class LoopMargins:
    """Stability margins of one sampled loop.

    Parameters
    ----------
    gain_margin_db : float
        Gain margin, ``inf`` when the phase never reaches -180 deg [dB].
    phase_margin_deg : float
        Phase margin, ``inf`` when the gain never crosses 1 [deg].
    gain_crossover_hz : float
        Frequency of the phase margin (``|L| = 1``), ``nan`` if none [Hz].
    phase_crossover_hz : float
        Frequency of the gain margin (phase -180 deg), ``nan`` if none [Hz].
    bandwidth_hz : float
        Lowest gain crossover, ``nan`` if none [Hz].
    last_crossover_hz : float
        Highest gain crossover, ``nan`` if none: above it the loop gain stays below 1, and
        a mode below it lies inside the loop [Hz].
    """

    gain_margin_db: float
    phase_margin_deg: float
    gain_crossover_hz: float
    phase_crossover_hz: float
    bandwidth_hz: float
    last_crossover_hz: float = float("nan")

    def to_dict(self) -> dict:
        """Plain dict of floats; an infinite margin or a missing crossover is ``None``."""
        return {k: (float(v) if np.isfinite(v) else None) for k, v in asdict(self).items()}

    def meets(self, gm_db: float, pm_deg: float) -> bool:
        """Whether both margins reach the given ones [dB, deg]."""
        return self.gain_margin_db >= gm_db and self.phase_margin_deg >= pm_deg


def discrete_freqresp(Phi, Gam, C, D, dt: float, f_hz) -> np.ndarray:
    """Response of a SISO discrete system ``C (zI - Phi)^-1 Gam + D`` at ``z = e^(j w dt)``
    (:func:`.freqresp.loop_response`).

    Parameters
    ----------
    Phi, Gam, C, D : ndarray
        Discrete system [-].
    dt : float
        Sample period [s].
    f_hz : array_like
        Frequencies [Hz].
    """
    return loop_response(Phi, Gam, C, D, dt)(f_hz)


def _grid(f_nyquist: float, f_low: float, poles, dt: float) -> np.ndarray:
    """Logarithmic grid, refined around the discrete ``poles`` (sampled at ``dt``) [Hz]."""
    n = int(np.ceil(np.log10(f_nyquist / f_low) * _PER_DECADE))
    parts = [np.logspace(np.log10(f_low), np.log10(f_nyquist), n)]
    for p in np.asarray(poles):
        if abs(p) == 0 or p.imag <= 0:
            continue
        f_p = np.angle(p) / (2 * np.pi * dt)
        width = max(-np.log(abs(p)) / (2 * np.pi * dt), 1e-9 * f_p)
        parts.append(f_p + width * np.linspace(-40, 40, 801))
    f = np.unique(np.concatenate(parts))
    return f[(f >= f_low) & (f <= f_nyquist)]


def margins_of(L, f_nyquist: float, f_low: float = 1e-3, poles=(), dt: float = 0.0
               ) -> LoopMargins:
    """Margins of a loop gain given as a function of frequency.

    Parameters
    ----------
    L : callable
        ``L(f_hz)`` -> complex loop gain, negative feedback [-].
    f_nyquist : float
        Highest frequency (the loop's Nyquist frequency) [Hz].
    f_low : float
        Lowest frequency searched, taken down by decades (to :data:`LOWEST_HZ`) while the
        loop gain there is still below 1: a loop as slow as that crosses over lower [Hz].
    poles : array_like of complex
        Discrete poles of ``L`` around which the grid is refined [-].
    dt : float
        Sample period of ``poles`` [s].
    """
    while f_low > LOWEST_HZ and abs(L(np.array([f_low]))[0]) < 1.0:
        f_low /= 10.0
    f = _grid(f_nyquist, f_low, poles, dt or 0.5 / f_nyquist)
    f[-1] = f_nyquist
    h = L(f)
    with np.errstate(divide="ignore"):  # a filter's zero at the Nyquist frequency: -inf
        mag = np.log(np.abs(h))
    wc = [brentq(lambda x: float(np.log(np.abs(L(x)[0]))), f[i], f[i + 1], xtol=1e-12,
                 rtol=1e-13) for i in np.flatnonzero(np.diff(np.sign(mag)) != 0)]
    w180 = [brentq(lambda x: float(L(x)[0].imag), f[i], f[i + 1], xtol=1e-12, rtol=1e-13)
            for i in np.flatnonzero(np.diff(np.sign(h.imag[:-1])) != 0)]
    w180 = [w for w in w180 if L(w)[0].real < 0]
    if h[-1].real < 0:  # the response is real at the Nyquist frequency
        w180.append(f_nyquist)
    gm, f180 = np.inf, np.nan
    if w180:
        g = np.array([-20 * np.log10(abs(L(w)[0])) for w in w180])
        k = int(np.argmin(np.abs(g)))
        gm, f180 = float(g[k]), float(w180[k])
    pm, fc = np.inf, np.nan
    bw, last = (float(min(wc)), float(max(wc))) if wc else (np.nan, np.nan)
    if wc:
        p = np.array([np.remainder(np.degrees(np.angle(L(w)[0])), 360.0) - 180.0 for w in wc])
        k = int(np.argmin(np.abs(p)))
        pm, fc = float(p[k]), float(wc[k])
    return LoopMargins(gm, pm, fc, f180, bw, last)


def velocity_loop_gain(mech: AxisMechanics, servo: ServoParams, f_hz) -> np.ndarray:
    """Open sampled velocity loop ``L_v`` at frequencies [-] (see :func:`velocity_open_loop`)."""
    Phi, Gam, C, D = velocity_open_loop(mech, servo)
    return -discrete_freqresp(Phi, Gam, C, D, servo.T_v, f_hz)


def position_loop_gain(mech: AxisMechanics, servo: ServoParams, f_hz) -> np.ndarray:
    """Open sampled position loop ``L_p`` at frequencies [-] (see :func:`position_open_loop`)."""
    Phi, Gam, C, D = position_open_loop(mech, servo)
    return discrete_freqresp(Phi, Gam, C, D, servo.T_p, f_hz)


def velocity_margins(mech: AxisMechanics, servo: ServoParams) -> LoopMargins:
    """Margins of the sampled velocity loop (:func:`velocity_open_loop`)."""
    v = velocity_open_loop(mech, servo)
    response = loop_response(*v, servo.T_v)
    return margins_of(lambda f: -response(f), 0.5 / servo.T_v,
                      poles=np.linalg.eigvals(v[0]), dt=servo.T_v)


def position_margins(mech: AxisMechanics, servo: ServoParams) -> LoopMargins:
    """Margins of the sampled position loop (:func:`position_open_loop`)."""
    p = position_open_loop(mech, servo)
    return margins_of(loop_response(*p, servo.T_p), 0.5 / servo.T_p,
                      poles=np.linalg.eigvals(p[0]), dt=servo.T_p)


def axis_margins(mech: AxisMechanics, servo: ServoParams) -> dict[str, LoopMargins]:
    """Margins of the sampled velocity and position loops of one axis.

    Parameters
    ----------
    mech : AxisMechanics
        Mechanics [SI].
    servo : ServoParams
        Servo settings [SI].

    Returns
    -------
    dict
        ``{"velocity": LoopMargins, "position": LoopMargins}``.
    """
    return {"velocity": velocity_margins(mech, servo),
            "position": position_margins(mech, servo)}
