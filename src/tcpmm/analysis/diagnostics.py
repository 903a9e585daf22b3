"""Circle diagnostics from a CCW and a CW circle (ISO 230-4 and the ballbar decomposition).

The radial error ``e(theta) = r - R`` of both circles about the nominal centre (angles CCW
from the first plane axis X, the second is Y; ``s = +1`` CCW, ``-1`` CW) is fitted by linear
least squares to a sum of error terms, each the first-order radial effect
``e = dx cos(theta) + dy sin(theta)`` of a position error ``(dx, dy)`` of the tool relative
to the table. ``sx = sign(vx) = -s sign(sin theta)`` and ``sy = sign(vy) = s sign(cos theta)``
are the signs of the axis velocities; X reverses at A and C, Y at B and D.

=====================  ================================  =====================================
term                   position error                    radial error
=====================  ================================  =====================================
radius (per circle)    ``r0`` along the radius           ``r0``
centre (per circle)    ``(cx, cy)``                      ``cx cos + cy sin``
backlash X, Y          ``dx = -bx/2 sx``                 ``-bx/2 sx cos``, ``-by/2 sy sin``
lateral play X, Y      ``dy = +px/2 sx`` (X moves in Y)  ``px/2 sx sin``, ``py/2 sy cos``
squareness             ``dx = -a y``                     ``-a R sin cos``
servo mismatch         ``dx = -tx vx``, ``dy = -ty vy``  ``-s w R (ty - tx) sin cos``
scale mismatch         ``dx = +m/2 x``, ``dy = -m/2 y``  ``m R/2 cos 2theta``
cyclic error X         ``dx = c sin(2 pi x / L + phi)``  ``dx cos`` (Y alike with ``dy sin``)
=====================  ================================  =====================================

Signs: backlash ``b > 0`` is lost motion, the tool lagging the command along the travel by
``b/2``, so the radius steps outward by ``b`` at the axis' reversal points in the direction of
travel (negative: overcompensated). Lateral play ``p > 0``: moving +X shifts the X axis by
``p/2`` towards +Y (+Y shifts Y towards +X). Squareness ``a > 0``: the angle between +X and
+Y travel exceeds 90 deg, so the radius is short at 45 and 225 deg in both directions.
Servo mismatch ``ty - tx > 0``: Y lags X, an ellipse at 45 deg of opposite sign in CCW and
CW (``w`` the angular speed; ``w (ty - tx)`` is reported too, as an angle, for circles whose
speed is not known). Scale mismatch ``m = ex - ey > 0``: X travels further than Y,
the circle is long along X; the mean of the two scale errors shows only in the radius.
Cyclic error: amplitude ``c`` and period ``L`` per axis, the period found by a scan.

The 20 deg after each quadrant point in the direction of travel (the reversal spike, whose
transient no term models) are left out of the fit. Reported besides: reversal spikes
(docs/formats.md section 4) of the residual, which the backlash step no longer enters; radial
deviation, the mean radius minus the nominal of the fitted circle; circular deviation G per
direction and bidirectional G(b) about the least-squares centre of both (ISO 230-4);
circular hysteresis H, the largest radial difference between the two circles.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .._threads import limit_blas_threads
from ..errors import InputError
from .circular import AFTER_DEG, QUADRANTS, lsq_circle, reversal_spikes

SIGN = {"ccw": 1.0, "cw": -1.0}
SHARED = ("backlash_X", "backlash_Y", "lateral_play_X", "lateral_play_Y", "squareness",
          "servo_angle", "scale_mismatch")
PREFERRED_SENSORS = ("tcp", "scale", "motor", "cmd")
#: SI unit -> (display unit, factor); the cyclic periods are shown in mm
DISPLAY_UNITS = {"m": ("µm", 1e6), "s": ("ms", 1e3), "m/m": ("µm/m", 1e6), "-": ("ppm", 1e6),
                 "rad": ("µrad", 1e6)}
#: What the sign of a term means, by term name or its name without the axis
TERM_NOTES = {"hysteresis": "largest CCW-CW radial difference",
              "centre_offset": "circle centre - nominal",
              "backlash": "+: radius steps out at reversal",
              "lateral_play_X": "+: moving +X shifts X to +Y",
              "lateral_play_Y": "+: moving +Y shifts Y to +X",
              "servo_mismatch": "+: Y lags X", "squareness": "+: angle +X to +Y over 90 deg",
              "scale_mismatch": "+: X travels further than Y",
              "cyclic_amplitude": "e.g. screw pitch error",
              "residual_rms": "what the terms leave unexplained"}


@dataclass
class CircleDiagnostics:
    """Error terms of a CCW and a CW circle (module docstring: conventions).

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
        (a ratio) [SI].
    curves : dict
        ``direction -> (angle [rad], radial error [m], fitted model [m])`` [SI].
    """

    radius: float
    axes: tuple
    sensor: str
    terms: dict
    curves: dict = field(default_factory=dict, repr=False)

    def __getitem__(self, name: str) -> float:
        return self.terms[name][0]

    def to_pandas(self):
        """Tidy table: one row per term, columns ``term``, ``value``, ``unit`` (SI)."""
        import pandas as pd

        return pd.DataFrame([(k, v, u) for k, (v, u) in self.terms.items()],
                            columns=["term", "value", "unit"])

    def to_dict(self) -> dict:
        """JSON-ready: radius, axes, sensor and the terms in SI (NaN as ``None``)."""
        return {"radius_m": self.radius, "axes": list(self.axes), "sensor": self.sensor,
                "terms": [{"term": k, "value": None if np.isnan(v) else float(v), "unit": u}
                          for k, (v, u) in self.terms.items()]}

    def plot(self, ax=None, path=None):
        """Radial error of both circles against angle with the fitted terms; the figure.

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Where to draw; a new figure when omitted [-].
        path : str or Path, optional
            Also save it there (PNG/PDF/SVG) [-].
        """
        from ..plot.diagnostics import plot_circle_diagnostics

        return plot_circle_diagnostics(self, ax=ax, path=path)


def display_terms(diag, ascii_units: bool = False) -> list[tuple]:
    """``(term, value, unit)`` of the diagnostics in display units: µm, ms, µm/m, ppm,
    µrad, and mm for the cyclic periods.

    Parameters
    ----------
    diag : CircleDiagnostics
        The diagnostics [SI].
    ascii_units : bool
        Write µ as u [-].
    """
    rows = []
    for term, (value, unit) in diag.terms.items():
        shown, k = ("mm", 1e3) if term.startswith("cyclic_period") else DISPLAY_UNITS[unit]
        rows.append((term, value * k, shown.replace("µ", "u") if ascii_units else shown))
    return rows


def term_note(term: str) -> str:
    """What the sign of a diagnostics term means; empty when nothing needs saying [-]."""
    return TERM_NOTES.get(term) or TERM_NOTES.get(term.rsplit("_", 1)[0], "")


def _shared(angle, s, radius, ratio):
    """Columns of the terms common to both circles, in the order of ``SHARED`` [m/unit]."""
    c, n = np.cos(angle), np.sin(angle)
    sx, sy = -s * np.sign(n), s * np.sign(c)
    return [-0.5 * sx * c, -0.5 * sy * n, 0.5 * sx * n, 0.5 * sy * c, -radius * n * c,
            -s * ratio * radius * n * c, 0.5 * radius * (c * c - n * n)]


def _cyclic(angle, radius, axis, wavenumber):
    """Sine and cosine columns of a cyclic error of ``axis`` (0: X, 1: Y) [m/m]."""
    w = np.cos(angle) if axis == 0 else np.sin(angle)
    phase = 2 * np.pi * wavenumber * radius * w
    return [w * np.sin(phase), w * np.cos(phase)]


def _design(angle, i, s, radius, ratio, waves):
    """Design matrix of circle ``i`` (0: CCW, 1: CW) [m/unit]."""
    own = np.zeros((angle.size, 6))
    own[:, 3 * i:3 * i + 3] = np.c_[np.ones_like(angle), np.cos(angle), np.sin(angle)]
    cols = _shared(angle, s, radius, ratio)
    for axis, k in enumerate(waves):
        if k is not None:
            cols += _cyclic(angle, radius, axis, k)
    return np.column_stack([own, *cols])


def _fit_mask(angle, s):
    """Samples outside the 20 deg after every quadrant point in the travel direction."""
    u = s * np.degrees(angle)
    keep = np.ones(angle.size, bool)
    for deg in QUADRANTS.values():
        d = (u - s * deg) % 360.0
        keep &= ~((d >= AFTER_DEG[0]) & (d <= AFTER_DEG[1]))
    return keep


def _scan(angle, resid, basis, radius, axis, band, spacing):
    """``(power, wavenumber)`` of the strongest cyclic error of ``axis`` in the residual
    of a fit whose columns span the orthonormal ``basis``: the drop of the sum of squares
    that adding it to that fit brings [m^2] and its wavenumber [1/m], searched over
    ``band`` (``None``: periods from the radius down to ten sample spacings)."""
    w = np.cos(angle) if axis == 0 else np.sin(angle)
    pos = radius * w
    step = 1.0 / (4.0 * radius)  # a quarter of the peak's width over the diameter
    lo, hi = band if band is not None else (1.0 / radius, 1.0 / (10.0 * spacing))

    def power(ks):
        ph = 2 * np.pi * np.outer(ks, pos)
        S, C = w * np.sin(ph), w * np.cos(ph)
        S, C = S - (S @ basis) @ basis.T, C - (C @ basis) @ basis.T
        ss, cc, sc = (S * S).sum(1), (C * C).sum(1), (S * C).sum(1)
        bs, bc = S @ resid, C @ resid
        det = ss * cc - sc * sc
        return (cc * bs * bs - 2 * sc * bs * bc + ss * bc * bc) / np.where(det > 0, det, np.inf)

    ks = np.arange(lo, hi, step)
    if ks.size == 0:
        return 0.0, None
    p = np.concatenate([power(ks[j:j + 64]) for j in range(0, ks.size, 64)])
    best = ks[np.argmax(p)]
    for _ in range(3):
        fine = np.linspace(best - step, best + step, 21)
        best, step = fine[np.argmax(power(fine))], step / 10.0
    return float(power(np.array([best]))[0]), best


def _solve(data, radius, ratios, waves):
    """Least-squares coefficients over the fitted samples of both circles, the residual
    and an orthonormal basis of the columns."""
    A = np.vstack([_design(a[m], i, s, radius, ratios[i], waves)
                   for i, (a, e, s, m) in enumerate(data)])
    y = np.concatenate([e[m] for a, e, s, m in data])
    q, r = np.linalg.qr(A)
    coef = np.linalg.lstsq(A, y, rcond=None)[0]
    return coef, y - A @ coef, q[:, np.abs(np.diag(r)) > 1e-12 * np.abs(r).max()]


def _noise(data):
    """Sample noise from successive differences, robust to steps and spikes [m]."""
    d = np.concatenate([np.diff(e) for a, e, s, m in data])
    return 1.4826 * np.median(np.abs(d - np.median(d))) / np.sqrt(2)


def _fit(data, radius, ratios):
    """Coefficients, residual and cyclic wavenumbers: the stronger cyclic error is taken
    first, the other scanned with it fitted, then the first again with the second fitted
    (a cyclic error counts when it lowers the sum of squares by 30 noise variances)."""
    coef, res, basis = _solve(data, radius, ratios, (None, None))
    ang = np.concatenate([a[m] for a, e, s, m in data])
    floor = 30.0 * _noise(data) ** 2
    spacing = radius * max(np.median(np.abs(np.diff(a))) for a, e, s, m in data)
    waves = [None, None]
    for _ in range(2):
        found = [(0.0, None) if waves[ax] is not None else
                 _scan(ang, res, basis, radius, ax, None, spacing) for ax in (0, 1)]
        ax = int(np.argmax([f[0] for f in found]))
        if found[ax][0] <= floor:
            break
        waves[ax] = found[ax][1]
        coef, res, basis = _solve(data, radius, ratios, waves)
    if all(k is not None for k in waves):  # each period again, the other one fitted
        for ax in (0, 1):
            others = [k if i != ax else None for i, k in enumerate(waves)]
            _, res_o, basis_o = _solve(data, radius, ratios, others)
            band = (waves[ax] - 1.0 / (2 * radius), waves[ax] + 1.0 / (2 * radius))
            waves[ax] = _scan(ang, res_o, basis_o, radius, ax, band, spacing)[1]
        coef, res, _ = _solve(data, radius, ratios, waves)
    return coef, res, tuple(waves)


def _deviations(paths, radius):
    """Circular deviation G per circle and G(b), hysteresis H of the pair [m]."""
    xy = [(radius + e) * np.array([np.cos(a), np.sin(a)]) for a, e in paths]
    g = []
    for p in xy:
        cx, cy, _ = lsq_circle(*p)
        r = np.hypot(p[0] - cx, p[1] - cy)
        g.append(float(r.max() - r.min()))
    both = np.hstack(xy)
    cx, cy, _ = lsq_circle(*both)
    rb = [np.hypot(p[0] - cx, p[1] - cy) for p in xy]
    allr = np.concatenate(rb)
    grid = np.linspace(0, 2 * np.pi, 3600, endpoint=False)
    on = [np.interp(grid, np.mod(np.arctan2(p[1] - cy, p[0] - cx), 2 * np.pi), r,
                    period=2 * np.pi) for p, r in zip(xy, rb, strict=True)]
    return g, float(allr.max() - allr.min()), float(np.max(np.abs(on[0] - on[1])))


def _check(angle, e, what):
    """The arrays of one circle, checked [rad, m]."""
    angle, e = np.asarray(angle, float), np.asarray(e, float)
    if angle.shape != e.shape or angle.ndim != 1 or angle.size < 100:
        raise InputError(f"the {what} circle needs angle and radial error of the same length, "
                         f"at least 100 samples (got {angle.shape} and {e.shape})")
    if not (np.all(np.isfinite(angle)) and np.all(np.isfinite(e))):
        raise InputError(f"the {what} circle has non-finite angles or radial errors")
    if abs(angle[-1] - angle[0]) < 2 * np.pi * (1 - 1e-3):
        raise InputError(f"the {what} circle covers {np.degrees(abs(angle[-1] - angle[0])):.0f}"
                         " deg; the diagnostics need a full turn")
    if (angle[-1] > angle[0]) != (what == "CCW"):
        runs = "counter-clockwise" if angle[-1] > angle[0] else "clockwise"
        raise InputError(f"the {what} circle runs {runs}; give the CCW circle first")
    return angle, e


def diagnose_pair(ccw, cw, radius_m, rates_rad_s=(float("nan"), float("nan")),
                  axes=("X", "Y"), sensor="tcp") -> CircleDiagnostics:
    """Error terms of a CCW and a CW circle by least squares (module docstring).

    Parameters
    ----------
    ccw, cw : tuple of ndarray
        ``(angle, radial error)`` of each circle about the nominal centre, the angle CCW
        from the first axis and unwrapped, one full turn or more [rad, m].
    radius_m : float
        Nominal radius [m].
    rates_rad_s : tuple of float
        Angular speed of each circle, for the servo mismatch as a time; NaN leaves it
        unknown (its angle is still given) [rad/s].
    axes : tuple of str
        Names of the first and second axis of the plane [-].
    sensor : str
        Sensor the paths are from, for the record [-].
    """
    if not radius_m > 0:
        raise InputError(f"the circle radius must be positive (got {radius_m})")
    paths = [_check(*ccw, "CCW"), _check(*cw, "CW")]
    limit_blas_threads()
    rates = np.asarray(rates_rad_s, float)
    mean_rate = float(rates.mean()) if np.all(rates > 0) else float("nan")
    ratios = rates / mean_rate if np.isfinite(mean_rate) else np.ones(2)
    data = [(a, e, s, _fit_mask(a, s)) for (a, e), s in zip(paths, (1.0, -1.0), strict=True)]
    coef, res, waves = _fit(data, radius_m, ratios)
    grid = np.linspace(0, 2 * np.pi, 3600, endpoint=False)
    curves, mean = {}, {}
    for i, (d, (a, e, s, _)) in enumerate(zip(SIGN, data, strict=True)):
        curves[d] = (a, e, _design(a, i, s, radius_m, ratios[i], waves) @ coef)
        mean[d] = float(np.mean(_design(grid, i, s, radius_m, ratios[i], waves) @ coef))
    terms = _terms(coef, waves, mean, _deviations(paths, radius_m), curves, mean_rate)
    terms["residual_rms"] = (float(np.sqrt(np.mean(res**2))), "m")
    names = {"X": axes[0], "Y": axes[1]}
    renamed = {(k[:-1] + names[k[-1]] if k[-2:] in ("_X", "_Y") else k): v
               for k, v in terms.items()}
    return CircleDiagnostics(float(radius_m), tuple(axes), sensor,
                             {k: (float(v), u) for k, (v, u) in renamed.items()}, curves)


def _terms(coef, waves, mean, deviations, curves, mean_rate):
    """The reported terms, ``name -> (value, unit)``, axes named X and Y [SI]."""
    g, gb, h = deviations
    shared = dict(zip(SHARED, coef[6:6 + len(SHARED)], strict=True))
    terms = {f"radial_deviation_{d}": (v, "m") for d, v in mean.items()}
    terms["radial_deviation_pair"] = ((mean["ccw"] + mean["cw"]) / 2, "m")
    terms.update({"circularity_ccw": (g[0], "m"), "circularity_cw": (g[1], "m"),
                  "circularity_pair": (gb, "m"), "hysteresis": (h, "m")})
    terms["centre_offset_X"] = ((coef[1] + coef[4]) / 2, "m")
    terms["centre_offset_Y"] = ((coef[2] + coef[5]) / 2, "m")
    terms.update({k: (shared[k], "m") for k in SHARED[:4]})
    for d, (a, e, model) in curves.items():
        spikes = reversal_spikes(a, e - model, d)
        terms.update({f"spike_{q}_{d}": (v, "m") for q, v in spikes.items()})
    mu = shared["servo_angle"]
    terms["servo_mismatch"] = (mu / mean_rate, "s")
    terms["servo_mismatch_angle"] = (mu, "rad")
    terms["squareness"] = (shared["squareness"], "m/m")
    terms["scale_mismatch"] = (shared["scale_mismatch"], "-")
    terms.update(_cyclic_terms(coef[6 + len(SHARED):], waves, ("X", "Y")))
    return terms


def _cyclic_terms(coef, waves, names):
    """Amplitude [m] and period [m] of each axis' cyclic error; the period NaN and the
    amplitude 0 where none stands out of the noise."""
    out, j = {}, 0
    for name, k in zip(names, waves, strict=True):
        amp, period = 0.0, float("nan")
        if k is not None:
            amp, period = float(np.hypot(coef[j], coef[j + 1])), 1.0 / k
            j += 2
        out[f"cyclic_amplitude_{name}"] = (amp, "m")
        out[f"cyclic_period_{name}"] = (period, "m")
    return out


def circle_diagnostics(result, other=None, sensor=None, axes=("X", "Y")) -> CircleDiagnostics:
    """Diagnostics of the first CCW and the first CW circle of circular-test analyses.

    Parameters
    ----------
    result : CircleResult
        Analysis holding the CCW circle, or both [-].
    other : CircleResult, optional
        Analysis holding the CW circle (a second run); each direction falls back to the
        other analysis when its own has none [-].
    sensor : str, optional
        Sensor to diagnose; default the first of tcp, scale, motor, cmd in both [-].
    axes : tuple of str
        The plane the circles were analysed in, for the term names [-].
    """
    first, second = (result, other or result), (other or result, result)
    pick = {}
    for d, order in (("ccw", first), ("cw", second)):
        found = [p for r in order for p in r.passes if p.direction == d]
        if not found:
            raise InputError(f"circle diagnostics need a CCW and a CW circle; no {d.upper()} "
                             "circle was found; give the run of the other direction too")
        pick[d] = found[0]
    both = [s for s in PREFERRED_SENSORS if all(s in p.sensors for p in pick.values())]
    sensor = sensor or (both[0] if both else None)
    if sensor not in both:
        raise InputError(f"the sensor {sensor} is not in both circles (in both: "
                         f"{', '.join(both) or 'none'})")
    sc = {d: p.sensors[sensor] for d, p in pick.items()}
    return diagnose_pair((sc["ccw"].angle_rad, sc["ccw"].radial_error),
                         (sc["cw"].angle_rad, sc["cw"].radial_error), result.radius,
                         (pick["ccw"].rate_rad_s, pick["cw"].rate_rad_s), axes=axes,
                         sensor=sensor)
