"""Two bounds a circle pair's reversal spikes are judged by beyond their ±95%
(:func:`.circle_spike_sigma.pair_spikes`): the move of a spike read with a take-up width
its interval cannot tell from a step, and whether any spike stands out of the noise at
the level that keeps all of the pair's within their bounds together."""

from __future__ import annotations

import numpy as np

from .circle_model import reversal_lead_deg
from .circle_spike_sigma import BEYOND, step_sides, widen_for_opened
from .circle_spikes import reversal_spikes
from .circle_takeup import spike_moves


def widened(fit, arcs, radius, shared, curves, terms, bounds, parts=None) -> None:
    """The spikes' ±95% widened for a take-up width left open after them
    (:func:`.circle_spike_sigma.widen_for_opened`, with ``parts`` of
    :func:`.circle_spike_sigma.pair_spikes`), then both ``bounds`` (the ±95% and the
    bound for the spikes together) for a width read that a step may be
    (:func:`widen_within_step`) [m]."""
    widen_for_opened(fit, arcs, radius, shared, curves, terms, bounds[0], parts)
    widen_within_step(fit, arcs, radius, shared, curves, bounds)


def widen_within_step(fit, arcs, radius, shared, curves, bounds) -> None:
    """Add to each spike's bounds in ``bounds`` (its ±95% and its bound for the spikes
    together) how far it moves from its axis' take-up width read to a step, where the
    width lies above 0 and its interval, within the search's step, holds 0
    (:func:`.circle_takeup.spike_moves`, ``within_step``): added whole, as a move over an
    interval is. Read with a width of 0.05 ± 0.09 um on a step of 0.19, a backlash of
    5 um and no spike left 3.66 ± 0.66 um at the first sample after the reversal, which a
    step reads at 0.5 [m].

    Parameters
    ----------
    fit, arcs, radius, shared, curves
        As for :func:`pair_spikes` [SI].
    bounds : tuple of dict
        The spikes' bounds, widened in place; NaN stays [m].
    """
    for i, (d, (a, e, model)) in enumerate(curves.items()):
        lead = reversal_lead_deg(a, fit.mu) if fit.mu else 0.0
        rest = step_sides(e, model)
        base = reversal_spikes(a, rest, d, lead)
        moves = spike_moves(fit, arcs[i], radius, arcs[i].positions(radius, None, e),
                            fit.centres[i] if fit.centres else (0.0, 0.0), base,
                            lambda dr, a=a, rest=rest, d=d, lead=lead: reversal_spikes(
                                a, rest + dr, d, lead), within_step=True)
        for q, v in moves.items():
            for bound in bounds:
                k = f"spike_{q}_{d}"
                if np.isfinite(bound.get(k, np.nan)):
                    bound[k] += v


def spikes_in_noise(terms: dict, together: dict) -> str:
    """Why the reversal spikes are not ranked, where no spike after the terms stands out of its
    bound for the spikes together (:func:`pair_spikes`), each at the level that keeps
    them all within theirs at 95 % where there is nothing but noise: a pair's eight each
    at 95 % let one past in a third of the circles of noise alone, which then ranked the
    reversal spikes first; empty where one stands out or none is given [-].

    Parameters
    ----------
    terms : dict
        The reported terms, ``spike_{P}_{direction} -> (value, unit)`` [SI].
    together : dict
        The spikes' bounds for the spikes together, by the same keys [m].
    """
    given = {k: (abs(terms[k][0]), b) for k, b in together.items()
             if k in terms and np.isfinite(terms[k][0]) and np.isfinite(b)}
    if not given or any(v > b for v, b in given.values()):
        return ""
    k, (v, b) = max(given.items(), key=lambda kv: kv[1][0] / kv[1][1] if kv[1][1] else 0)
    n = len(together)
    return (f"none of the {n} spikes after the terms stands out of the noise: each lies "
            f"within its bound at {100 * (1 - BEYOND / n):.1f} %, which keeps all {n} within "
            f"theirs at 95 % where there is nothing but noise (closest, {k.split('_')[1]} "
            f"{k.split('_')[2].upper()}: {v * 1e6:.2f} µm within {b * 1e6:.2f} µm): these "
            "circles cannot tell a reversal spike here from the noise")
