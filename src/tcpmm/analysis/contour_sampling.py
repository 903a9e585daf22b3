"""How finely a run's command samples its path.

The contour error is measured against the polyline through the command's samples. Where
the path bends between two samples the polyline cuts the bend, by up to its chords' sag
(:func:`.contour_windows.chord_sags`: ``L sin(phi / 2) / 4`` for a chord of length ``L``
turning by ``phi``). At the position loop's period that is a fraction of a micrometre; a
run recorded every second cuts a square's corners by millimetres, and its contour error
is measured against corners it cut off. The search for the closest command point works
the sags out (:func:`.contour.polyline`); the run's largest is kept with its result.
"""

from __future__ import annotations

import math

import numpy as np

#: A sag that may move the contour error by this much or more is said, or by this share
#: of its largest value where that is more [m], [-].
SAG_SAID_M = 1e-6
SAG_SAID_SHARE = 0.05


def sag_note(sag_m: float, largest_error_m: float) -> str | None:
    """A note where the command's samples cut its bends by enough to move the contour
    error (:data:`SAG_SAID_M`, :data:`SAG_SAID_SHARE`); None where they do not.

    Parameters
    ----------
    sag_m : float
        The command's largest chord sag (:attr:`.contour.ContourResult.command_sag_m`) [m].
    largest_error_m : float
        The largest contour error of any sensor [m].
    """
    if not sag_m > max(SAG_SAID_M, SAG_SAID_SHARE * largest_error_m):
        return None
    return (f"the run's command samples cut the path's bends by up to {sag_m * 1e6:.3g} µm "
            f"(a chord's sag): the contour error is measured against the polyline through "
            f"them and may be off by as much; record the run at the position loop's period "
            f"(tcpmm simulate --record-period-s)")


#: A chord sag beyond which the corners' overshoot and rounding are not given: the command
#: cuts its own corners by more, and the figures read the samples the run happens to hold
#: (a square at F3000 recorded every 50 ms, sag 223 um: rounding 1133 um where a sample
#: passed 51 um from the corner; 38 um recorded every millisecond) [m].
CORNER_SAG_M = 10e-6


def unresolved_corners(res) -> bool:
    """Make every corner's overshoot and rounding NaN (n/a) where the command's samples cut
    its bends by more than :data:`CORNER_SAG_M`, in place; whether they were [-].

    Parameters
    ----------
    res : ContourResult or its streamed counterpart
        The contour error, with ``command_sag_m``, ``corners`` and ``errors`` [-].
    """
    if not res.command_sag_m > CORNER_SAG_M:
        return False
    if hasattr(res.corners, "blank"):  # a streamed run's, kept as columns
        res.corners.blank(tuple(res.errors), ("overshoot_m", "rounding_m"))
        return True
    for c in res.corners:
        for s in res.errors:
            if s in c:
                c[s]["overshoot_m"] = c[s]["rounding_m"] = math.nan
    return True


#: Share of the largest error by which a neighbouring sample lies below it beyond which the
#: peak is said to be read on too few samples, and the least such drop said [-], [m].
PEAK_DROP_SHARE = 0.1
PEAK_DROP_M = 1e-6


def coarse_peaks(res) -> list:
    """Each sensor whose largest error is read on samples too coarse for its peak: the
    sensor, the time of the peak, and how far its neighbours lie below it (the peak
    between the samples may be higher, by up to about that); empty where every peak has a
    neighbour within :data:`PEAK_DROP_SHARE` of it or :data:`PEAK_DROP_M`. A square at
    F3000 recorded every 5 ms read 48.0 um of a 55.5 um peak the millisecond record shows,
    with no word [-], [s], [m].

    Parameters
    ----------
    res : ContourResult or its streamed counterpart
        The contour error of a run read whole or in chunks; the peak is the largest error
        of the samples counted (the summary's), its neighbours the samples either side of
        it in the run [-].
    """
    out = []
    for s, (top, at, near, n) in _peaks(res).items():
        drop = top - max((x for x in near if np.isfinite(x)), default=top)
        if n >= 3 and drop > max(PEAK_DROP_SHARE * top, PEAK_DROP_M):
            out.append((s, at, float(drop)))
    return out


def _peaks(res) -> dict:
    """Per sensor: the largest magnitude of the samples counted [m], its time [s], the
    magnitudes of the samples either side of it [m] and the samples counted [-]."""
    sums = getattr(res, "sums", None)
    if sums is not None:  # a run read in chunks keeps them as it goes
        return {s: (v.top, v.at, v.near, v.n) for s, v in sums.items()}
    out = {}
    for s, e in res.errors.items():
        e = np.abs(np.asarray(e, dtype=float))
        idx = np.arange(e.size) if res.counted is None else np.flatnonzero(res.counted)
        if not np.isfinite(e[idx]).any():
            continue
        i = int(idx[np.nanargmax(e[idx])])
        out[s] = (float(e[i]), float(res.time_s[i]),
                  [e[j] for j in (i - 1, i + 1) if 0 <= j < e.size], idx.size)
    return out
