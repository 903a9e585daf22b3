"""Goodness-of-fit figures for frequency responses."""

from __future__ import annotations

import warnings

import numpy as np

from ...errors import InputWarning


def fit_percent(H, H_model) -> float:
    """NRMSE fit as system-identification tools report it: 100 (1 - |H - Ĥ| / |H - mean H|) [%]."""
    H, h = np.asarray(H), np.asarray(H_model)
    return float(100.0 * (1.0 - np.linalg.norm(H - h) / np.linalg.norm(H - np.mean(H))))


def rel_error(H, H_model) -> float:
    """RMS relative complex error ``sqrt(mean |Ĥ/H - 1|^2)`` [-]."""
    return float(np.sqrt(np.mean(np.abs(np.asarray(H_model) / np.asarray(H) - 1.0) ** 2)))


def warn_if_off(name: str, n_poles: int, H_model, H, auto: bool = False,
                delay="fit") -> None:
    """Say so where a fit of ``n_poles`` explains less than half of the measured response
    ``H`` by either measure of its error, the relative RMS ``|Ĥ/H - 1|`` and the total
    ``sum |Ĥ - H|^2 / sum |H|^2`` (a response of zero leaves 1 of each): a fit chosen for
    one may leave much of the other, not both. The advice follows what the fit was given:
    ``auto``, its pole count chosen by the data; ``delay``, ``"fit"``, ``None`` (none) or
    a delay fixed [s] [-]."""
    H, h = np.asarray(H), np.asarray(H_model)
    rel = rel_error(H, h)
    total = float(np.sum(np.abs(h - H) ** 2) / np.sum(np.abs(H) ** 2))
    if min(rel, total) > 0.5:
        warnings.warn(InputWarning(
            f"{name or 'the response'}: the fit of {n_poles} pole"
            f"{'s' if n_poles != 1 else ''} leaves a relative RMS of {rel:.3g} and a total "
            f"error of {total:.3g}, where a response of zero leaves 1 of each: it does not "
            f"describe the measurement; {_advice(auto, delay)}"), stacklevel=3)


def warn_if_misfit(name: str, chi2_ratio: float, describes: bool) -> None:
    """Say so where the residual is so far above the noise (``describes`` False, see
    :data:`tfsd.MISFIT`) that the fit's standard deviations are withheld: a ``±`` on a
    model that misses the data would bound nothing [-]."""
    if not describes:
        warnings.warn(InputWarning(
            f"{name or 'the response'}: the fit does not describe the data (chi2 ratio "
            f"{chi2_ratio:.3g} against the noise): no value it gives carries a standard "
            "deviation, all are undetermined"), stacklevel=3)


def _advice(auto: bool, delay) -> str:
    """What to change where a fit describes nothing: a delay given is the likeliest cause,
    as no pole count makes up for a wrong one; more poles only where the data did not
    choose them [-]."""
    fixes = []
    if delay != "fit":
        given = "no delay" if delay is None else f"the delay of {delay * 1e3:.4g} ms"
        fixes.append(f"leave the delay free (--delay fit): {given} given may be what the "
                     "response does not have")
    if auto:
        fixes.append("widen the band (--band): the poles were already chosen by the data, "
                     "so the band may hold no dynamics to fit")
    else:
        fixes.append("fit more poles (--poles auto chooses them)")
    return "; or ".join(fixes)
