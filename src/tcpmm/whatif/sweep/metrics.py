"""Figures of one run of a sweep: circular-test metrics, or the contour error of a path.

All in metres; the results table gives them in um (:mod:`tcpmm.whatif.sweep.store`).
"""

from __future__ import annotations

import math

import numpy as np

from ...analysis.circular import QUADRANTS, analyse_circle

#: Directions of the circular test of a sweep, in the order it runs them [-].
DIRECTIONS = ("ccw", "cw")


def circle_metric_names() -> list[str]:
    """Names of the circle metrics: per direction the spikes A-D, the contour error and
    the circular deviation G, and the largest spike magnitude of all [-]."""
    names = [f"{d}_{m}" for d in DIRECTIONS
             for m in [*(f"spike_{q}" for q in QUADRANTS), "contour_error",
                       "circular_deviation"]]
    return [*names, "spike_max"]


def path_metric_names() -> list[str]:
    """Names of the metrics of an NC program: largest and RMS distance of the sensor's
    path from the commanded path [-]."""
    return ["contour_error", "contour_error_rms"]


def circle_metrics(run, radius_m: float, centre_m=(0.0, 0.0), sensor: str = "tcp") -> dict:
    """Circle metrics of a run of the circular test (:func:`circle_metric_names`).

    Parameters
    ----------
    run : Run
        Simulated run of the CCW and CW circle [-].
    radius_m : float
        Nominal radius [m].
    centre_m : tuple of float
        Nominal centre [m].
    sensor : str
        Sensor analysed [-].

    Returns
    -------
    dict of str to float
        The metrics; NaN for a direction without a full circle [m].
    """
    res = analyse_circle(run, radius_m, centre_m, sensors=("cmd", sensor), settling=False)
    out = dict.fromkeys(circle_metric_names(), math.nan)
    for d in DIRECTIONS:
        p = next((p for p in res.passes if p.direction == d), None)
        if p is None or sensor not in p.sensors:
            continue
        s = p.sensors[sensor]
        out.update({f"{d}_spike_{q}": float(v) for q, v in s.spikes.items()})
        out[f"{d}_contour_error"] = float(s.contour_error)
        out[f"{d}_circular_deviation"] = float(s.circular_deviation)
    spikes = [abs(v) for k, v in out.items() if "_spike_" in k and math.isfinite(v)]
    out["spike_max"] = max(spikes) if spikes else math.nan
    return out


def _segment_distance(ref, pts, s) -> np.ndarray:
    """Distance of each point from segment ``s[i]`` to ``s[i] + 1`` of ``ref`` [m]."""
    a, b = ref[s], ref[s + 1]
    ab = b - a
    t = np.clip(np.einsum("ij,ij->i", pts - a, ab) / np.einsum("ij,ij->i", ab, ab), 0, 1)
    return np.linalg.norm(pts - (a + t[:, None] * ab), axis=1)


def path_distance(ref, pts) -> np.ndarray:
    """Distance of each point from a polyline.

    Parameters
    ----------
    ref : array_like
        Vertices of the polyline, shape ``(n, d)`` [m].
    pts : array_like
        Points, shape ``(m, d)`` [m].

    Returns
    -------
    numpy.ndarray
        Distance per point to the nearest of the segments next to its four nearest
        vertices: exact for a path sampled finely against the points' distance [m].
    """
    from scipy.spatial import cKDTree

    ref, pts = np.asarray(ref, dtype=float), np.asarray(pts, dtype=float)
    moved = np.r_[True, np.any(np.diff(ref, axis=0) != 0.0, axis=1)]
    ref = ref[moved]
    if ref.shape[0] < 2:
        return np.linalg.norm(pts - ref[0], axis=1)
    _, idx = cKDTree(ref).query(pts, k=min(4, ref.shape[0]))
    best = np.full(pts.shape[0], np.inf)
    for j in range(idx.shape[1]):
        for s in (idx[:, j] - 1, idx[:, j]):
            best = np.minimum(best, _segment_distance(ref, pts, np.clip(s, 0, ref.shape[0] - 2)))
    return best


def path_metrics(run, axes, sensor: str = "tcp") -> dict:
    """Contour error of a run of an NC program (:func:`path_metric_names`).

    Parameters
    ----------
    run : Run
        Simulated run [-].
    axes : list of str
        Axes of the program [-].
    sensor : str
        Sensor whose path is measured against the command [-].

    Returns
    -------
    dict of str to float
        Largest and RMS distance of the sensor's path from the commanded path, as
        ``tcpmm contour`` and a study over programs measure it
        (:func:`tcpmm.analysis.contour.contour_error`, in the program's plane, else in
        3-D): each sample's to the command near it in time, G0 rapids left out and a
        sample after one measured from its own feed move; NaN where no sample is left [m].
    """
    import warnings

    from ...analysis.contour import contour_error

    with warnings.catch_warnings():  # what the contour says of the run, a sweep's rows do not
        warnings.simplefilter("ignore")
        res = contour_error(run, plane=tuple(axes) if len(axes) == 2 else None)
    d = res.summary().get(sensor, {})
    return {"contour_error": float(d.get("max_abs_m", math.nan)),
            "contour_error_rms": float(d.get("rms_m", math.nan))}
