"""Terms a circle's samples do not determine, left open.

A term the data bound no better than the error itself is reported as NaN with the reason,
never as a value: its uncertainties are NaN too, and so are the fit's columns it is
reported from, so that the ranking (which reads the columns) leaves it out.
"""

from __future__ import annotations

import numpy as np

#: The fit's column of a reported term where its name differs (a centre offset is the mean
#: of each circle's centre column)
FITTED_AS = {"servo_mismatch": "servo_angle", "servo_mismatch_angle": "servo_angle",
             "squareness_or_servo": "squareness"}


def fitted_columns(names, term: str) -> list:
    """The indices of the columns of a fit (its column ``names``) that the reported
    ``term`` is read from [-]."""
    return [j for j, n in enumerate(names) if n == term or n == FITTED_AS.get(term) or (
        term.startswith("centre_offset_") and n.startswith(f"centre_{term[-1]}_"))]


def open_terms(terms: dict, keys, reason: str, *uncertainties: dict, fit=None) -> dict:
    """Leave the reported terms ``keys`` open (module docstring): their values in
    ``terms`` (``name -> (value, unit)``) and in each of ``uncertainties`` NaN, and, with
    a ``fit`` (a ``TermFit``), the columns they are read from; all changed in place. The
    reasons, ``key -> reason`` [-]."""
    keys = list(keys)
    for k in keys:
        terms[k] = (float("nan"), terms[k][1])
        for u in uncertainties:
            u[k] = float("nan")
        if fit is not None:
            for j in fitted_columns(fit.names, k):
                fit.coef[j] = np.nan
    return dict.fromkeys(keys, reason)
