"""What the diagnostics of a CCW and a CW circle, or of one direction, give: the terms, what
the circles leave undetermined and why, the ranking and the uncertainties
(:func:`.diagnostics.diagnose_pair`, :func:`.circle_single.diagnose_single`)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass
class CircleDiagnostics:
    """Error terms of a CCW and a CW circle (:mod:`.diagnostics`: conventions), or of one
    direction (:mod:`.circle_single`).

    Parameters
    ----------
    radius : float
        Nominal radius [m].
    axes : tuple of str
        The plane's first and second axis, named X and Y in the term names [-].
    sensor : str
        Sensor whose path was analysed [-].
    terms : dict
        ``name -> (value, unit)`` in SI: ``m``, ``s``, ``rad``, ``m/m`` (a slope), ``-``
        (a ratio); NaN for a term not determined [SI].
    curves : dict
        ``direction -> (angle [rad], radial error [m], fitted model [m])`` [SI].
    undetermined : dict
        ``term -> why`` for the terms the circles do not determine [-].
    ranking : list of dict
        The terms by their contribution (:func:`.circle_display.ranking_rows`) [SI].
    tail_shift : dict
        ``term -> change`` of each term when the fit leaves out 40 deg after each reversal
        instead of 20 (:mod:`.circle_tails`) [SI].
    aliases : dict
        ``left-out term -> {term: change per unit of it}`` for the terms that depend on a
        term the circles do not determine (:mod:`.circle_alias`) [SI/SI].
    sigma : dict
        ``term -> standard uncertainty`` from the noise (:mod:`.circle_sigma`) [SI].
    spike_u95 : dict
        ``spike_{P}_{direction} -> 95 % uncertainty`` of each spike after the terms
        (:mod:`.circle_spike_sigma`) [m].
    spike_u95_sample : dict
        The same from the noise from sample to sample alone (``sample_noise`` of
        :func:`.circle_spike_sigma.spike_uncertainty`) [m].
    tails : str
        What the reversals' tails are, one of
        :data:`.circle_tail_terms.TAIL_STATES`; empty where the fit has none to try
        (arcs, one direction) [-].
    quiet_spikes : str
        Why the reversal spikes are not ranked, where none of them stands out of the
        noise (:func:`.circle_spike_bounds.spikes_in_noise`); empty where one does [-].
    """

    radius: float
    axes: tuple
    sensor: str
    terms: dict
    curves: dict = field(default_factory=dict, repr=False)
    undetermined: dict = field(default_factory=dict)
    ranking: list = field(default_factory=list)
    tail_shift: dict = field(default_factory=dict)
    aliases: dict = field(default_factory=dict)
    sigma: dict = field(default_factory=dict)
    spike_u95: dict = field(default_factory=dict)
    spike_u95_sample: dict = field(default_factory=dict)
    tails: str = ""
    quiet_spikes: str = ""

    def __getitem__(self, name: str) -> float:
        return self.terms[name][0]

    @property
    def directions(self) -> tuple:
        """The directions of the circles diagnosed [-]."""
        return tuple(self.curves)

    def to_pandas(self):
        """Tidy table: one row per term, columns ``term``, ``value``, ``unit`` (SI)."""
        import pandas as pd

        return pd.DataFrame([(k, v, u) for k, (v, u) in self.terms.items()],
                            columns=["term", "value", "unit"])

    def to_dict(self) -> dict:
        """JSON-ready: radius, axes, sensor, the terms in SI (NaN as ``None``), the terms
        not determined and why, the ranking, each term's change with the wider window
        after the reversals, per term not determined the change of those that depend
        on it per unit of it, each term's standard uncertainty (``sigma``), each
        spike's 95 % uncertainty (``spike_u95``), what the reversals' tails are
        (``reversal_tails``, None where none were tried) and why the reversal spikes are
        not ranked (``spikes_in_noise``, None where they are)."""
        return {"radius_m": self.radius, "axes": list(self.axes), "sensor": self.sensor,
                "directions": list(self.directions),
                "terms": [{"term": k, "value": None if np.isnan(v) else float(v), "unit": u}
                          for k, (v, u) in self.terms.items()],
                "undetermined": dict(self.undetermined),
                "ranking": [{k: None if isinstance(v, float) and np.isnan(v) else v
                             for k, v in r.items()} for r in self.ranking],
                "tail_shift": dict(self.tail_shift),
                "aliases": {k: dict(v) for k, v in self.aliases.items()},
                "sigma": dict(self.sigma),
                "spike_u95": {k: None if np.isnan(v) else v for k, v in self.spike_u95.items()},
                "reversal_tails": self.tails or None,
                "spikes_in_noise": self.quiet_spikes or None}

    def plot(self, ax=None, path=None):
        """Radial error of the circles against angle with the fitted terms; the figure.

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Where to draw; a new figure when omitted [-].
        path : str or Path, optional
            Also save it there (PNG/PDF/SVG) [-].
        """
        from ..plot.diagnostics import (
            plot_circle_diagnostics,  # tcpmm.plot is a floor above this one
        )

        return plot_circle_diagnostics(self, ax=ax, path=path)
