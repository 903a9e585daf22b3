"""Whether the friction runs fix the Stribeck hump of a fitted steady friction curve.

The static level is the curve's value at rest, reached through the hump
``(Fs - Fc) exp(-|v/vs|**delta)``; the runs show it only where they slide slowly enough to
see the rise towards it. A hump whose static level or Stribeck speed the fit leaves loose,
or whose Stribeck speed lies below every speed the fit reads, is an extrapolation: on runs
without slow plateaus a fit to the whole record put 1e14 N of static friction at
0.02 mm/s (bench R05's X from 5 mm/s up). :func:`without_undetermined_hump` holds such a
hump at the Coulomb level and says why; the curve records the cause under
``extra["static_held"]``, which the axis's uncertainty names as an open quantity
(:mod:`tcpmm.uncertainty.frictionranges`), and the warning for the user under
``extra["static_held_warning"]``, told once for the fit kept.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .estimate import ParameterEstimate

__all__ = ["HELD_STRIBECK_SPEED", "HUMP_KEEP_REL_STD", "without_undetermined_hump"]

#: Largest standard deviation of a static level, against its excess over the Coulomb
#: level, and of the Stribeck speed, against itself, for a fitted hump to be kept [-].
HUMP_KEEP_REL_STD = 0.5
#: Stribeck speed given to a curve whose hump is held and whose own Stribeck speed the runs
#: do not fix: that of the built-in machine's contacts, within the 1.4-2.7 mm/s the
#: reference machines' runs find. It leaves the held curve as it is (static and Coulomb
#: levels equal); it sets how fast the bristle damping fades and where the variants of an
#: open static level put their hump [m/s].
HELD_STRIBECK_SPEED = 2e-3


def _loose(v: dict, sd: dict, slowest: float) -> tuple[list, bool]:
    """The directions (``"+"``, ``"-"``) whose static level the runs leave open, and
    whether the Stribeck speed is open: known no better than :data:`HUMP_KEEP_REL_STD`, or
    below ``slowest``, the slowest speed the fit reads [m/s]."""
    loose = [d for d in "+-"
             if not sd[f"Fs{d}"] <= HUMP_KEEP_REL_STD * (v[f"Fs{d}"] - v[f"Fc{d}"])]
    speed_open = not sd["vs"] <= HUMP_KEEP_REL_STD * v["vs"] or v["vs"] < slowest
    if speed_open and v["Fs+"] + v["Fs-"] > v["Fc+"] + v["Fc-"]:
        loose = ["+", "-"]
    return [d for d in loose if v[f"Fs{d}"] != v[f"Fc{d}"]], speed_open


def without_undetermined_hump(est: ParameterEstimate, slowest: float = 0.0):
    """The fitted curve with its Stribeck hump taken out where the runs do not fix it.

    A static level known to no better than :data:`HUMP_KEEP_REL_STD` of its excess over
    the Coulomb level, or a Stribeck speed known as poorly or lying below ``slowest``, is
    an extrapolation of the fit: on runs that show no friction at all it reaches
    meganewtons. There the static levels are set to the Coulomb levels and their standard
    deviations to NaN; where the whole hump goes and its speed is open, the speed is
    :data:`HELD_STRIBECK_SPEED`.

    Parameters
    ----------
    est : ParameterEstimate
        ``Fc+, Fc-, Fs+, Fs-, vs, Fv`` as
        :func:`~tcpmm.ident.friction.stribeck.fit_stribeck` gives them [N, N, N, N, m/s, N s/m].
    slowest : float
        Slowest speed the fit reads: the slowest plateau, or the slowest sample a fit to
        the whole record takes as moving; 0 where not known [m/s].

    Returns
    -------
    tuple
        ``(ParameterEstimate, str)``: the curve kept, and ``""`` or what was taken out
        and why [-].
    """
    v = dict(zip(est.names, est.values, strict=True))
    sd = dict(zip(est.names, est.std, strict=True))
    loose, speed_open = _loose(v, sd, slowest)
    if not loose:
        return est, ""
    values, std = np.array(est.values, float), np.array(est.std, float)
    said = []
    for d in loose:
        i, j = est.names.index(f"Fs{d}"), est.names.index(f"Fc{d}")
        said.append(f"Fs{d} {values[i]:.4g} +- {std[i]:.2g} N against Fc{d} {values[j]:.4g} N")
        values[i], std[i] = values[j], np.nan
    below = (f", below the slowest speed the fit reads, {slowest * 1e3:.3g} mm/s"
             if v["vs"] < slowest else "")
    cause = (f"the friction runs do not determine a static level above Coulomb ("
             f"{'; '.join(said)}; Stribeck speed {v['vs'] * 1e3:.3g} +- "
             f"{sd['vs'] * 1e3:.2g} mm/s{below})")
    held_speed = ""
    n = est.names.index
    if speed_open and all(values[n(f"Fs{d}")] == values[n(f"Fc{d}")] for d in "+-"):
        i = n("vs")
        values[i], std[i] = HELD_STRIBECK_SPEED, np.nan
        held_speed = f" and a Stribeck speed of {HELD_STRIBECK_SPEED * 1e3:g} mm/s"
    none = all(v[f"Fc{d}"] <= 2.0 * sd[f"Fc{d}"] for d in "+-")
    why = ("the friction runs show no sliding friction (Coulomb levels "
           f"{v['Fc+']:.3g} +- {sd['Fc+']:.2g} and {v['Fc-']:.3g} +- {sd['Fc-']:.2g} N); "
           if none else "")
    why += (f"{cause}, so the model keeps the Coulomb level at rest there{held_speed}; "
            "record friction runs with plateaus slower than the Stribeck speed "
            "(0.1-0.5 mm/s) to fix the break-away level")
    extra = {**est.extra, "static_held": cause, "static_held_warning": why}
    return dataclasses.replace(est, values=values, std=std, extra=extra), why
