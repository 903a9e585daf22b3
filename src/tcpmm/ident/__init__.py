"""Identification of a feed axis from servo excitation and friction runs.

The rooms, each a sub-package exporting its public functions:

* :mod:`~tcpmm.ident.excitation` -- excitation signals for the current command;
* :mod:`~tcpmm.ident.frf` -- spectra and frequency responses from records;
* :mod:`~tcpmm.ident.lti` -- rational transfer functions fitted to them;
* :mod:`~tcpmm.ident.physical` -- the physical (grey-box) fit of the axis mechanics;
* :mod:`~tcpmm.ident.friction` -- friction, its split, lost motion and the nut's play;
* :mod:`~tcpmm.ident.gates` -- what keeps a suspect model from passing silently;
* :mod:`~tcpmm.ident.chain` -- all of it, per axis and per bundle, as an ordered list of
  steps (:mod:`~tcpmm.ident.steps`) over one :class:`~tcpmm.ident.options.IdentifyOptions`,
  into the results of :mod:`~tcpmm.ident.identification`
  (:mod:`~tcpmm.ident.pipeline` keeps the names it had).

The main entry points are importable from here; they load on first use, so importing
``tcpmm.ident`` costs nothing until one is needed.
"""

from __future__ import annotations

import importlib

#: Entry point -> the module that defines it.
_ENTRY_POINTS = {
    "identify_bundle": "chain",
    "identify_axis": "chain",
    "Identification": "identification",
    "AxisIdentification": "identification",
    "design_excitation": "excitation",
    "Excitation": "excitation",
    "FRF": "frf",
    "estimate_frf": "frf",
    "frf_against_reference": "frf",
    "reduced_frfs": "frf",
    "fit_tf": "lti",
    "TFFit": "lti",
    "fit_frf": "lti",
    "FRFFit": "lti",
    "fit_physical": "physical",
    "PhysicalFit": "physical",
    "fit_stribeck": "friction",
    "identify_friction": "friction",
    "estimate_lost_motion": "friction",
    "SuspectModelError": "gates",
}

__all__ = sorted(_ENTRY_POINTS)


def __getattr__(name: str):
    if name in _ENTRY_POINTS:
        value = getattr(importlib.import_module(f".{_ENTRY_POINTS[name]}", __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_ENTRY_POINTS))
