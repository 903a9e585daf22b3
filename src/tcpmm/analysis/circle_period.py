"""The uncertainty of a cyclic error's period (:mod:`.circle_cyclic` finds it): how far
what the fit leaves moves the peak the scan found, to first order, and the frame the
period is read in, the tool's travel rather than the axis' own. Whether a peak of
another period could stand in for it is the scan's test of the halves, not this."""

from __future__ import annotations

import numpy as np

from .circle_noise import coef_covariance


def wave_sigma(pb, waves, names, A, coef, res) -> tuple:
    """Standard uncertainty of each axis' wavenumber, NaN where it has no cyclic error
    [1/m]: the fit linearised in the wavenumber at the one found (a sine's change with it
    is ``2 pi x`` times its cosine), its covariance from what the fit leaves as the terms'
    own (:func:`.circle_noise.coef_covariance`), and the frame it is read in
    (:func:`_frame`).

    Parameters
    ----------
    pb : FitProblem
        The arcs and their fitted samples [-].
    waves : tuple
        Wavenumber of each axis' cyclic error, None for none [1/m].
    names, A, coef, res
        The fit's column names [-], design matrix [m/unit], coefficients (NaN where not
        fitted) [SI] and what it leaves over [m].
    """
    kept, slopes, axes = np.isfinite(coef), [], []
    for ax, (name, k) in enumerate(zip("XY", waves, strict=True)):
        i, j = (names.index(f"cyclic_{q}_{name}") if k is not None else -1
                for q in ("sin", "cos"))
        if k is not None and kept[i] and kept[j]:
            x = np.concatenate([p[ax] for p in pb.pos])
            slopes.append(2 * np.pi * x * (coef[i] * A[:, j] - coef[j] * A[:, i]))
            axes.append(ax)
    out = [float("nan")] * 2
    # each slope to unit length: a small cyclic error's is some 1e-8 of the columns', and
    # the covariance's pseudo-inverse would take it for none
    norms = [float(np.linalg.norm(d)) for d in slopes]
    if slopes and min(norms) > 0.0:
        cov = coef_covariance(np.column_stack([A[:, kept], *np.divide(slopes, np.c_[norms])]),
                              res, [m.sum() for m in pb.masks])
        for n, (ax, size) in enumerate(zip(axes, norms, strict=True), start=int(kept.sum())):
            k = waves[ax] * _frame(pb, names, coef, "XY"[ax])
            out[ax] = float(np.hypot(np.sqrt(max(cov[n, n], 0.0)) / size, k))
    return tuple(out)


def _frame(pb, names, coef, axis) -> float:
    """The share by which the tool's travel, in which the fit reads a period, may differ
    from the axis' own, in which a screw's pitch error repeats: the circles' mean radial
    deviation over the radius, the scale mismatch (the circle sees one axis' scale
    against the other's only) and half the axis' backlash over the radius, each taken as
    a standard uncertainty [-]."""
    def value(name):
        return float(np.nan_to_num(coef[names.index(name)])) if name in names else 0.0

    radii = [value(f"radius_{i}") for i in range(len(pb.arcs))]
    return float(np.sqrt((np.mean(radii) / pb.radius) ** 2 + value("scale_mismatch") ** 2
                         + (value(f"backlash_{axis}") / (2 * pb.radius)) ** 2))
