"""The result of a compensation: the programmed and the compensated command, what the
model predicts for each, and how far the compensation can be trusted."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..path.command import Command
from ..result import json_ready
from .bounds import scaled_within


@dataclass
class Compensation:
    """A pre-compensated position command.

    Parameters
    ----------
    reference : Command
        The programmed command, held at its end for the TCP to settle [m].
    target : Command
        The path the TCP is to follow: ``reference`` delayed by ``delay_s`` [m].
    correction : dict of str to ndarray
        Full correction per axis, as learned on the model [m].
    factors : dict of str to ndarray
        Share of the correction applied per axis and sample, in [0, 1] [-].
    delay_s : float
        Delay of the TCP path behind the programmed one [s].
    history : dict of str to list of float
        Largest predicted TCP error of each learning step per axis [m].
    bounds : dict of str to AxisBounds
        The limits the command keeps [-].
    settings : dict
        Learning gain, iterations, Q-filter corner [-].
    scores : dict
        Predicted figures before and after (:func:`.scores.predicted_scores`) [-].
    robustness : dict
        What the draws of the model say (:func:`.robust.robust_factors`) [-].
    trusted : ndarray or None
        Per sample: the compensation improves the error on every draw of the model [-].
    controller : dict of str to AxisController
        The controller-side parameters the command was learned with
        (:mod:`.combined`): the command is right only with them on the controller;
        empty for a command alone [-].
    """

    reference: Command
    target: Command
    correction: dict
    factors: dict
    delay_s: float
    history: dict
    bounds: dict
    settings: dict = field(default_factory=dict)
    scores: dict = field(default_factory=dict)
    robustness: dict = field(default_factory=dict)
    trusted: np.ndarray | None = None
    controller: dict = field(default_factory=dict)

    @property
    def applied(self) -> bool:
        """Whether any share of the correction is applied, on any axis [-]."""
        return any(bool(np.any(np.asarray(f) != 0.0)) for f in self.factors.values())

    @property
    def moved_axes(self) -> list:
        """The axes the programmed path moves: the others stand, with nothing to
        correct [-]."""
        return [a for a, p in self.reference.positions.items() if np.ptp(p) > 0]

    @property
    def command(self) -> Command:
        """The compensated command: programmed plus the applied share of the correction,
        within the axes' limits [m]."""
        return self.command_with(self.factors)

    def command_with(self, factors: dict) -> Command:
        """The command with the share ``factors`` (per axis and sample) of the correction,
        within the axes' limits, as :attr:`command` is with the shares applied [m]."""
        T = self.reference.period_s
        # the learned correction keeps the limits; what a share's ramp between regions adds
        # beyond them is scaled back whole, as the shares themselves scale it
        pos = {a: p + scaled_within(p, factors[a] * self.correction[a], T, self.bounds[a])
               for a, p in self.reference.positions.items()}
        return Command(self.reference.time_s, pos,
                       {**self.reference.meta, "compensated": True})

    def to_pandas(self):
        """Per sample: time, programmed and compensated command in mm, factor per axis and
        whether the compensation is trusted there."""
        import pandas as pd

        comp = self.command
        data = {"time_s": self.reference.time_s}
        for a in self.reference.axes:
            data[f"{a.lower()}_programmed_mm"] = self.reference.positions[a] * 1e3
            data[f"{a.lower()}_compensated_mm"] = comp.positions[a] * 1e3
            data[f"{a.lower()}_factor"] = self.factors[a]
        if self.trusted is not None:
            data["trusted"] = self.trusted
        return pd.DataFrame(data)

    def to_dict(self) -> dict:
        """JSON-ready summary: settings, limits, delay, the figures before and after, the
        correction's size per axis in um and the verdict of the draws; a figure left out
        (NaN) is ``None`` [-]."""
        corr = {a: {"max_um": float(np.max(np.abs(c)) * 1e6),
                    "applied_max_um": float(np.max(np.abs(self.factors[a] * c)) * 1e6),
                    "factor_min": float(np.min(self.factors[a])),
                    "last_step_error_um": float(self.history[a][-1] * 1e6),
                    "best_step_error_um": float(min(self.history[a]) * 1e6)}
                for a, c in self.correction.items()}
        out = {"settings": self.settings, "delay_s": self.delay_s,
               "bounds": {a: b.to_dict() for a, b in self.bounds.items()},
               "correction": corr, "scores": self.scores, "robustness": self.robustness}
        if self.trusted is not None:
            out["trusted_share"] = float(np.mean(self.trusted))
        if self.controller:
            out["controller"] = {a: c.to_dict() for a, c in self.controller.items()}
        return json_ready(out)

    def plot(self, ax=None, path=None):
        """The TCP error before and after along the path (polar for a circle) and the
        applied factor per axis; the figure.

        Parameters
        ----------
        ax : array-like of matplotlib Axes, optional
            Two: the errors and the factors; a new figure when omitted [-].
        path : str or Path, optional
            Also save it there (PNG/PDF/SVG) [-].
        """
        from ..plot.compensation import plot_compensation  # tcpmm.plot is a floor above this one

        return plot_compensation(self, path, ax=ax)
