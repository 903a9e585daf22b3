"""The cyclic errors a circle fit found (:mod:`.circle_cyclic`) as reported terms: each
axis' amplitude and period, and why an axis reads none."""

from __future__ import annotations

import numpy as np

from .circle_cyclic import MIN_PERIODS


def at_longest(fit, k) -> bool:
    """Whether the wavenumber ``k`` [1/m] of ``fit`` lies at the long end of the band its
    search held (:func:`search_periods`), within a tenth of a step of its scan: the
    power may still rise towards the end, and the period may be longer, where the circle
    cannot tell it from its own terms. A 40 um dead band read at the scale as a cyclic
    error of 33.1 mm, the end at 33.3 mm (0.04 steps), ranked first; a pitch error of
    22 mm on a circle of R 35 mm, whose end is 23.3 mm, lies 0.36 steps from it [-]."""
    return bool(k is not None and fit.periods
                and k * fit.periods[0] < 1.0 + 0.05 / MIN_PERIODS)


def cyclic_terms(fit) -> dict:
    """Amplitude [m] and period [m] of each axis' cyclic error; both NaN where none stands
    out, or where it stands out at the longest period searched (:func:`at_longest`;
    :func:`cyclic_unresolved` says why)."""
    out = {}
    for name, k in zip("XY", fit.waves, strict=True):
        amp = period = float("nan")
        if k is not None and not at_longest(fit, k):
            amp = fit.cyclic_amplitude(name)
            period = 1.0 / k
        out[f"cyclic_amplitude_{name}"] = (amp, "m")
        out[f"cyclic_period_{name}"] = (period, "m")
    return out


def cyclic_unresolved(fit) -> dict:
    """Why each axis whose cyclic error the search did not find reads none, by term name
    (axes X and Y): not that it has none, but that one as small as what the fit leaves
    unexplained may hide in it, as a search that counts only what stands out of that
    residual cannot tell it (:mod:`.circle_cyclic`) [-]."""
    rms_um = fit.residual_rms * 1e6
    rms = f"{rms_um:.2f} µm rms" if rms_um >= 0.005 else "under 0.01 µm rms"
    why = (f"none stands out of what the terms leave unexplained ({rms}): one of about that "
           "size or less is not resolved, so the axis may still have one")
    if fit.periods:  # one of a period outside the band reads in part as the terms
        why += ("; periods from {:.3g} down to {:.2g} mm were searched, and a shorter one, "
                "unresolved at this feed, reads in part as the terms, which then move with "
                "the window after the reversals: said where they do, as uncertain by the "
                "reversals' tails. A longer one, fewer than three of its periods along the "
                "travel, is much like a scale error and a bow and reads as them and as "
                "backlash (said where it moves them, as uncertain by the reversals' tails "
                "or by what the terms leave unexplained): a circle of a larger radius "
                "brings it into the search").format(*np.multiply(fit.periods, 1e3))
    out = {f"cyclic_{q}_{name}": why for name, k in zip("XY", fit.waves, strict=True)
           if k is None for q in ("amplitude", "period")}
    longest = (f"one stands out at the longest period searched, {fit.periods[0] * 1e3:.3g} mm "
               "(a third of the diameter), towards which it still grows: its period may be "
               "longer, where over fewer than three periods along the travel it is much like "
               "a scale error and a bow, and its period and amplitude are not determined. "
               "It is fitted at that period, and the scale mismatch and bows read beside it "
               "may still hold part of it; a circle of a larger radius brings it into the "
               "search") if fit.periods else ""
    out.update({f"cyclic_{q}_{name}": longest for name, k in zip("XY", fit.waves, strict=True)
                if at_longest(fit, k) for q in ("amplitude", "period")})
    return out
