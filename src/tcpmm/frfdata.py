"""The frequency response function as data: a response with its coherence and random error.

It sits below both the readers of measured responses (:mod:`tcpmm.io.frffile`,
:mod:`tcpmm.io.sinumerik`) and the estimators and fits of identification
(:mod:`tcpmm.ident.frf`, :mod:`tcpmm.ident.lti`), which all make or take one.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from .errors import InputError

__all__ = ["FRF", "coherence_rel_std"]


def coherence_rel_std(coh: np.ndarray, n_eff: float) -> np.ndarray:
    """Random error of an FRF from its coherence (Bendat & Piersol, *Random Data*, ch. 9).

    Parameters
    ----------
    coh : ndarray
        Ordinary coherence gamma^2 per bin, 0..1 [-].
    n_eff : float
        Effective number of independent averages [-].

    Returns
    -------
    ndarray
        Standard deviation of ``|H|`` divided by ``|H|``, equal to the standard deviation
        of the phase in radians [-].
    """
    # n_d - 1 instead of n_d: estimated coherence is biased up by about (1 - gamma^2) / n_d
    c = np.clip(coh, 1e-12, 1.0)
    return np.sqrt((1.0 - c) / (2.0 * max(n_eff - 1.0, 1.0) * c))


@dataclass(frozen=True)
class FRF:
    """A frequency response function with its coherence and random error.

    Parameters
    ----------
    freq_hz : ndarray
        Frequencies, increasing, all > 0 [Hz].
    H : ndarray
        Complex frequency response, output per input in SI units [-].
    coherence : ndarray
        Ordinary coherence gamma^2 per bin, 0..1 [-].
    n_averages : float
        Effective number of independent averages behind each bin [-].
    rel_std : ndarray
        Standard deviation of ``|H|`` divided by ``|H|`` per bin; equal to the standard
        deviation of the phase in radians [-].
    name : str
        Short name, e.g. ``"G_M"`` [-].
    input : str
        Input signal label [-].
    output : str
        Output signal label [-].
    """

    freq_hz: np.ndarray
    H: np.ndarray
    coherence: np.ndarray
    n_averages: float
    rel_std: np.ndarray
    name: str = ""
    input: str = ""
    output: str = ""
    meta: dict = field(default_factory=dict, compare=False)

    def __post_init__(self):
        f = np.asarray(self.freq_hz, dtype=float)
        H = np.asarray(self.H, dtype=complex)
        coh = np.asarray(self.coherence, dtype=float)
        rs = np.asarray(self.rel_std, dtype=float)
        if f.ndim != 1 or f.size == 0:
            raise InputError("an FRF needs a 1-D, non-empty frequency vector")
        for label, a in (("H", H), ("coherence", coh), ("rel_std", rs)):
            if a.shape != f.shape:
                raise InputError(
                    f"FRF {label} has shape {a.shape}, frequency vector {f.shape}", column=label
                )
        if np.any(~np.isfinite(f)) or np.any(f <= 0) or np.any(np.diff(f) <= 0):
            raise InputError("FRF frequencies must be finite, > 0 and increasing", column="freq_hz")
        object.__setattr__(self, "freq_hz", f)
        object.__setattr__(self, "H", H)
        object.__setattr__(self, "coherence", coh)
        object.__setattr__(self, "rel_std", rs)

    @property
    def phase_std_rad(self) -> np.ndarray:
        """Standard deviation of the phase per bin [rad]."""
        return np.minimum(self.rel_std, np.pi)

    @property
    def magnitude_db(self) -> np.ndarray:
        """``20 log10 |H|`` per bin [dB]."""
        with np.errstate(divide="ignore"):
            return 20.0 * np.log10(np.abs(self.H))

    @property
    def phase_deg(self) -> np.ndarray:
        """Unwrapped phase per bin [deg]."""
        return np.degrees(np.unwrap(np.angle(self.H)))

    def band(self, fmin_hz: float | None = None, fmax_hz: float | None = None) -> FRF:
        """The bins with ``fmin_hz <= f <= fmax_hz``.

        Parameters
        ----------
        fmin_hz : float, optional
            Lower band edge, inclusive [Hz].
        fmax_hz : float, optional
            Upper band edge, inclusive [Hz].

        Returns
        -------
        FRF
            A new FRF restricted to the band [-].
        """
        lo = -np.inf if fmin_hz is None else fmin_hz
        hi = np.inf if fmax_hz is None else fmax_hz
        keep = (self.freq_hz >= lo) & (self.freq_hz <= hi)
        if not np.any(keep):
            raise InputError(
                f"FRF {self.name or ''} has no bins between {lo:g} Hz and {hi:g} Hz "
                f"(it covers {self.freq_hz[0]:g}..{self.freq_hz[-1]:g} Hz)"
            )
        return replace(
            self,
            freq_hz=self.freq_hz[keep],
            H=self.H[keep],
            coherence=self.coherence[keep],
            rel_std=self.rel_std[keep],
        )

    def differentiate(self, output: str | None = None, name: str | None = None) -> FRF:
        """The FRF of the time derivative of the output: ``H * j 2 pi f``.

        Parameters
        ----------
        output : str, optional
            Label of the differentiated output [-].
        name : str, optional
            Name of the result [-].

        Returns
        -------
        FRF
            Same coherence and relative error, response multiplied by ``j omega`` [-].
        """
        return replace(
            self,
            H=self.H * (2j * np.pi * self.freq_hz),
            output=output if output is not None else f"d({self.output})/dt",
            name=name if name is not None else self.name,
        )

    def __truediv__(self, other: FRF) -> FRF:
        """Ratio of two FRFs on the same grid, e.g. ``(y/r) / (u/r) = y/u``.

        Relative errors add in quadrature, the coherence is the smaller of the two and the
        number of averages the smaller of the two.
        """
        if not isinstance(other, FRF):
            return NotImplemented
        if self.freq_hz.shape != other.freq_hz.shape or not np.allclose(
            self.freq_hz, other.freq_hz, rtol=1e-9, atol=0.0
        ):
            raise InputError(
                f"cannot divide FRF {self.name!r} by {other.name!r}: different frequency grids"
            )
        with np.errstate(divide="ignore", invalid="ignore"):
            H = self.H / other.H
        same_input = self.input == other.input
        return FRF(
            freq_hz=self.freq_hz,
            H=H,
            coherence=np.minimum(self.coherence, other.coherence),
            n_averages=min(self.n_averages, other.n_averages),
            rel_std=np.hypot(self.rel_std, other.rel_std),
            name=f"({self.name})/({other.name})" if self.name or other.name else "",
            input=other.output if same_input else other.name,
            output=self.output if same_input else self.name,
            meta=dict(self.meta),
        )

    def to_pandas(self):
        """Table with one row per bin.

        Returns
        -------
        pandas.DataFrame
            Columns ``freq_hz, re, im, magnitude, magnitude_db, phase_deg, coherence,
            rel_std, phase_std_deg`` [-].
        """
        import pandas as pd

        return pd.DataFrame(
            {
                "freq_hz": self.freq_hz,
                "re": self.H.real,
                "im": self.H.imag,
                "magnitude": np.abs(self.H),
                "magnitude_db": self.magnitude_db,
                "phase_deg": self.phase_deg,
                "coherence": self.coherence,
                "rel_std": self.rel_std,
                "phase_std_deg": np.degrees(self.phase_std_rad),
            }
        )
