"""The contour error's summary of a run read in chunks, kept as the chunks come
(:mod:`tcpmm.analysis.contour_stream`): the whole run's figures without its errors."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass
class RunningSummary:
    """Running largest, smallest and largest magnitude of the error, sum of squares [m];
    the time of the largest magnitude, and the time since a rapid there [s]."""

    n: int = 0
    sq: float = 0.0
    hi: float = -np.inf
    lo: float = np.inf
    top: float = 0.0
    at: float = np.nan
    after: float = np.nan

    def add(self, e: np.ndarray, t: np.ndarray, since=None) -> None:
        if e.size:
            self.n += e.size
            self.sq += float(np.sum(e * e))
            self.hi, self.lo = max(self.hi, float(np.max(e))), min(self.lo, float(np.min(e)))
            i = int(np.argmax(np.abs(e)))
            if abs(e[i]) > self.top:  # the first of equal magnitudes, as a whole run's
                self.top, self.at = float(abs(e[i])), float(t[i])
                self.after = np.nan if since is None else float(since[i])

    def result(self) -> dict:
        return {"max_abs_m": self.top, "rms_m": float(np.sqrt(self.sq / self.n)),
                "max_m": self.hi, "min_m": self.lo, "max_abs_at_s": self.at,
                "max_abs_after_rapid_s": self.after}
