"""Which frequencies a sweep's excitation reaches, and what the FRFs' band leaves out of them.

A bin the excitation does not reach holds noise, however coherent leakage makes it look:
a check that reads a static gain there judges the noise. And where the FRFs' band
(``--band``) leaves out frequencies the sweep excites, the fit sees nothing of a mode that
lies there: the fitted mechanics place it where the data do not constrain them, and what
follows from them (the sampled loop's stability, the structure's static deflection) can be
absurd with the servo settings and the sensors right. :class:`BandCover` holds the two
spans and says so in words a message can carry.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import signal

from ...mechanics.statespace import oscillating_modes
from ._spectral import remove_trend, segmenting

__all__ = ["BEYOND_REACH", "EXCITED_SHARE", "BandCover", "band_cover", "excited_bins",
           "lowest_band_hz", "mode_frequencies_hz"]

#: Share of its peak power above which a frequency counts as excited by the sweep (30 dB;
#: a log sweep of 2-1000 Hz spans 27 dB) [-].
EXCITED_SHARE = 1e-3
#: Lowest frequency of the FRFs' band by default [Hz]: below the modes of feed axes, and
#: what a sweep's excitation holds below it is mostly the leakage of its start.
LOWEST_BAND_HZ = 2.0


def lowest_band_hz(duration_s: float) -> float:
    """Lowest frequency the FRFs' band starts at by default: :data:`LOWEST_BAND_HZ`, or
    eight periods over the record, whichever is higher [Hz].

    Parameters
    ----------
    duration_s : float
        Length of the sweep record [s].
    """
    return max(LOWEST_BAND_HZ, 8.0 / duration_s)


def _excitation_power(frf, excitation) -> tuple[np.ndarray, np.ndarray] | None:
    """Welch spectrum of the excitation, segmented as the FRF was, and whether each of its
    bins above 0 Hz holds more than :data:`EXCITED_SHARE` of the peak; ``None`` where the
    FRF does not say how it was segmented [Hz, -]."""
    meta = getattr(frf, "meta", None) or {}
    if excitation is None or not {"nperseg", "fs_hz", "window", "overlap"} <= meta.keys():
        return None
    m, fs_hz = int(meta["nperseg"]), float(meta["fs_hz"])
    r = remove_trend(np.asarray(excitation, dtype=float), meta.get("detrend", 1))
    if r.size < m:
        return None
    _, noverlap, _ = segmenting(r.size, fs_hz, m, None, float(meta["overlap"]))
    f, p = signal.welch(r, fs=fs_hz, window=meta["window"], nperseg=m, noverlap=noverlap,
                        detrend="constant")
    p = np.where(f > 0.0, p, 0.0)
    return f, p > EXCITED_SHARE * float(np.max(p))


def excited_bins(frf, excitation) -> np.ndarray:
    """Whether the excitation reaches each bin of an FRF (:data:`EXCITED_SHARE`); every bin
    where the FRF does not say how it was segmented.

    Parameters
    ----------
    frf : FRF
        An FRF of the sweep, estimated against ``excitation`` [-].
    excitation : array_like or None
        The sweep's excitation, the record's samples [A].

    Returns
    -------
    ndarray of bool
        Mask over the FRF's bins [-].
    """
    found = _excitation_power(frf, excitation)
    f_hz = np.asarray(frf.freq_hz, dtype=float)
    if found is None:
        return np.ones(f_hz.shape, dtype=bool)
    f, excited = found
    k = np.clip(np.searchsorted(f, f_hz - 0.5 * (f[1] - f[0])), 0, f.size - 1)
    return excited[k]


def mode_frequencies_hz(mechanics) -> np.ndarray:
    """Natural frequencies of the mechanics' oscillating modes, increasing [Hz].

    Parameters
    ----------
    mechanics : AxisMechanics
        The axis' mechanics [SI].
    """
    return np.unique(np.abs(oscillating_modes(mechanics))) / (2.0 * np.pi)


#: How far above the top of the sweep's excitation a fitted mode lies for the FRFs to show
#: nothing of it: the response a mode puts below itself reaches the sweep's top where it
#: lies within about twice it (bench D's axial mode at 867 Hz, 1.1 times the 774 Hz its
#: sweep reaches, was fitted at 871 Hz) [-].
BEYOND_REACH = 2.0


@dataclass(frozen=True)
class BandCover:
    """The band of a sweep's FRFs and the span its excitation reaches.

    Parameters
    ----------
    band_hz : tuple of float
        Lowest and highest bin of the FRFs [Hz].
    excited_hz : tuple of float
        Lowest and highest frequency the excitation reaches (:data:`EXCITED_SHARE`) [Hz].
    asked : tuple of bool
        Whether the user set the band's lower end, its upper end; an end the user did not
        set leaves out nothing [-].
    floor_hz : float
        Lowest frequency a band may start at (:func:`lowest_band_hz`): what the sweep's
        leakage excites below it is left out of any band [Hz].
    """

    band_hz: tuple[float, float]
    excited_hz: tuple[float, float]
    asked: tuple[bool, bool] = (True, True)
    floor_hz: float = 0.0

    def left_out(self, below: bool = True, above: bool = True) -> list[tuple[float, float]]:
        """The spans the sweep excites outside the band, below it and above it [Hz]."""
        (lo, hi), (e_lo, e_hi) = self.band_hz, self.excited_hz
        e_lo = max(e_lo, self.floor_hz)
        below, above = below and self.asked[0], above and self.asked[1]
        return ([(e_lo, lo)] if below and e_lo < lo else []) + (
            [(hi, e_hi)] if above and e_hi > hi else [])

    def words(self, mechanics, below: bool = True, above: bool = True) -> str | None:
        """Why the band, not the settings, is the likely cause of what follows from
        ``mechanics``: the sweep excites frequencies the band leaves out, and the fitted
        mechanics put modes on that side of the band, which the FRFs therefore do not show
        (where the band sees no mode, the fit places them anywhere, beyond the excitation
        too); ``None`` where there are none.

        Parameters
        ----------
        mechanics : AxisMechanics
            The fitted mechanics [SI].
        below, above : bool
            Look below the band, above it [-].
        """
        lo, hi = self.band_hz
        modes = mode_frequencies_hz(mechanics)
        spans, outside = [], []
        for a, b in self.left_out(below, above):
            side = modes[modes < lo] if b <= lo else modes[modes > hi]
            if side.size:
                spans.append((a, b))
                outside += list(side)
        if not outside:
            return None
        out = " and ".join(f"{a:.4g}-{b:.4g} Hz" for a, b in spans)
        one = len(outside) == 1
        at = ", ".join(f"{f:.4g}" for f in outside[:3]) + (", ..." if len(outside) > 3 else "")
        return (f"the FRFs' band {lo:.4g}-{hi:.4g} Hz (--band) leaves out {out}, which the "
                f"sweep excites, and the fitted mechanics put {'a mode' if one else 'modes'} "
                f"({at} Hz) outside the band, where the FRFs do not show "
                f"{'it' if one else 'them'}: that is the likely cause; widen --band to take "
                f"in {out}")

    def reach_words(self, mechanics, servo) -> str | None:
        """Why the sweep, not the settings, is the likely cause of what follows from the
        fitted mechanics: its excitation stops below the velocity loop's crossover on the
        axis' inertia, so the FRFs show nothing of the band where the loop's stability is
        decided (a sweep cut short, or of too narrow a span), and the fit places the modes
        there where nothing constrains them; or the fitted mechanics put a mode far above
        its reach (:meth:`_beyond_reach_words`); ``None`` where neither.

        Parameters
        ----------
        mechanics : AxisMechanics
            The fitted mechanics [SI].
        servo : ServoParams
            The axis' servo settings [SI].
        """
        top = self.excited_hz[1]
        crossover_hz = servo.K_vp * mechanics.K_tc / (2.0 * math.pi * mechanics.J_total)
        if not top < crossover_hz:
            return self._beyond_reach_words(mechanics)
        return (f"the sweep's excitation reaches only {top:.4g} Hz, below the velocity "
                f"loop's crossover (about {crossover_hz:.4g} Hz on the axis' inertia), so "
                "the FRFs show nothing of the band where the loop's stability is decided "
                "and the fit places the modes there where nothing constrains them: that is "
                "the likely cause; record a sweep that runs well past the crossover")

    def _beyond_reach_words(self, mechanics) -> str | None:
        """Where the fitted mechanics put a mode more than :data:`BEYOND_REACH` times above
        the top of the sweep's excitation: the FRFs show nothing of it, and the fit placed
        it where nothing constrains it (a sweep cut short of bench D's axial mode at
        867 Hz, reaching 179 Hz, had it at 3965 Hz, and the loop unstable); ``None``
        where none is [-]."""
        top = self.excited_hz[1]
        modes = mode_frequencies_hz(mechanics)
        far = modes[modes > BEYOND_REACH * top]
        if not far.size:
            return None
        at = ", ".join(f"{f:.4g}" for f in far[:3]) + (", ..." if far.size > 3 else "")
        one = far.size == 1
        return (f"the sweep's excitation reaches only {top:.4g} Hz, and the fitted "
                f"mechanics put {'a mode' if one else 'modes'} at {at} Hz, far above it, "
                f"where the FRFs show nothing of {'it' if one else 'them'} and the fit "
                "places the modes where nothing constrains them: that is the likely cause; "
                "record a sweep that runs past the axis' modes")


def band_cover(frf, excitation, asked: tuple[bool, bool] = (True, True),
               floor_hz: float = 0.0) -> BandCover | None:
    """The band of an FRF and the span its sweep's excitation reaches; ``None`` where the
    FRF does not say how it was segmented or nothing is excited.

    Parameters
    ----------
    frf : FRF
        An FRF of the sweep, estimated against ``excitation`` [-].
    excitation : array_like or None
        The sweep's excitation, the record's samples [A].
    asked : tuple of bool
        Whether the user set the band's lower end, its upper end [-].
    floor_hz : float
        Lowest frequency a band may start at (:func:`lowest_band_hz`) [Hz].
    """
    found = _excitation_power(frf, excitation)
    if found is None or not np.any(found[1]):
        return None
    f = found[0][found[1]]
    f_hz = np.asarray(frf.freq_hz, dtype=float)
    return BandCover((float(f_hz[0]), float(f_hz[-1])), (float(f[0]), float(f[-1])),
                     (bool(asked[0]), bool(asked[1])), float(floor_hz))
