"""The contour error's summary of a run read in chunks, kept as the chunks come
(:mod:`tcpmm.analysis.contour_stream`): the whole run's figures without its errors."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass
class RunningSummary:
    """Running largest, smallest and largest magnitude of the error, sum of squares [m];
    the time of the largest magnitude, and the time since a rapid there [s]; the
    magnitudes of the samples either side of it in the run, counted or not, and whether
    the one after is still to come (it opens the next chunk) [m]."""

    n: int = 0
    sq: float = 0.0
    hi: float = -np.inf
    lo: float = np.inf
    top: float = 0.0
    at: float = np.nan
    after: float = np.nan
    near: list = field(default_factory=list)
    awaited: bool = False
    last: list = field(default_factory=list)

    def add(self, e: np.ndarray, t: np.ndarray, since=None, counted=None) -> None:
        """The errors ``e`` [m] of the next samples of the run, at ``t`` [s], ``since``
        the time since a rapid [s], of which those ``counted`` count (all where ``None``)."""
        if self.awaited and e.size:
            self.near.append(abs(float(e[0])))
            self.awaited = False
        idx = None if counted is None else np.flatnonzero(counted)
        c = e if idx is None else e[idx]
        if c.size:
            self.n += c.size
            self.sq += float(np.sum(c * c))
            self.hi, self.lo = max(self.hi, float(np.max(c))), min(self.lo, float(np.min(c)))
            i = int(np.argmax(np.abs(c)))
            if abs(c[i]) > self.top:  # the first of equal magnitudes, as a whole run's
                j = i if idx is None else int(idx[i])
                self.top, self.at = float(abs(c[i])), float(t[j])
                self.after = np.nan if since is None else float(since[j])
                self.near = [abs(float(e[j - 1]))] if j else list(self.last)
                self.awaited = j + 1 == e.size
                if not self.awaited:
                    self.near.append(abs(float(e[j + 1])))
        if e.size:
            self.last = [abs(float(e[-1]))]

    def result(self) -> dict:
        return {"max_abs_m": self.top, "rms_m": float(np.sqrt(self.sq / self.n)),
                "max_m": self.hi, "min_m": self.lo, "max_abs_at_s": self.at,
                "max_abs_after_rapid_s": self.after}
