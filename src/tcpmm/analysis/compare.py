"""Measured against predicted circular tests: the paper's Table 2, and point by point."""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field, replace

import numpy as np

from ..errors import InputError, InputWarning
from .circle_command import CENTRE_TOL_M, once_around
from .circle_gaps import in_gaps
from .circular import QUADRANTS, CircleResult
from .compare_after import hidden_notes, hidden_spikes, warn_sampling


def raw_spike_named(figure: str, minus: str = "-") -> str:
    """A figure as a user reads it: ``spike A`` (also in ``R35 spike A``) is the raw radial
    error ``e - b`` at A, which ``tcpmm circle`` does not lead with (it leads with the
    spike after the fitted terms); ``minus`` is the sign written [-]."""
    for q in QUADRANTS:
        figure = figure.replace(f"spike {q}", f"raw spike {q} (e {minus} b)")
    return figure


@dataclass
class Comparison:
    """Differences measured minus predicted per direction and sensor.

    Parameters
    ----------
    rows : list of dict
        Per direction and sensor: spike differences A-D, contour error difference, and the
        RMS / max of the point-by-point radial-error difference, all [um].
    sign_flips : list of dict
        Quadrant points where measured and predicted spike have opposite signs, with the
        rise and fall after the reversal of both (:func:`sign_flips`) [um].
    measured, predicted : CircleResult or None
        The analyses compared, for :meth:`plot` [-].
    hidden : list of dict
        Spike differences the raw figures hide and the spikes after the terms show
        (:func:`.compare_after.hidden_spikes`) [um].
    """

    rows: list
    sign_flips: list = field(default_factory=list)
    measured: CircleResult | None = field(default=None, repr=False)
    predicted: CircleResult | None = field(default=None, repr=False)
    hidden: list = field(default_factory=list)

    def to_pandas(self):
        """The Table-2 layout (um)."""
        import pandas as pd

        return pd.DataFrame(self.rows)

    def to_dict(self) -> dict:
        """JSON-ready rows and sign flips (um)."""
        return {"rows": self.rows, "sign_flips": self.sign_flips,
                "hidden_by_raw_spikes": self.hidden}

    def plot(self, ax=None, path=None, sensor: str = "tcp"):
        """The measured circle of ``sensor`` with the predicted TCP dotted over it, one
        panel per pass; the figure.

        Parameters
        ----------
        ax : matplotlib Axes or array-like of Axes, optional
            One per pass; a new figure when omitted [-].
        path : str or Path, optional
            Also save it there (PNG/PDF/SVG) [-].
        sensor : str
            Measured sensor drawn [-].
        """
        from ..plot.circle import plot_circle  # tcpmm.plot is a floor above this one

        if self.measured is None:
            raise InputError("this comparison holds no circles to plot; make it with "
                             "compare_circles(measured, predicted)")
        return plot_circle(self.measured, path, sensors=[sensor], overlay=self.predicted,
                           ax=ax)

    def judged(self, verdict) -> list[dict]:
        """The TCP rows with each difference set against the predicted figure's 90 %
        interval (:func:`tcpmm.uncertainty.prediction_verdict` of the same circle): per
        figure the half-width, the verdict and whether the measurement lies inside [um].

        Parameters
        ----------
        verdict : Verdict
            The verdict on the predicted circle, one test [-].
        """
        by = {(f.direction, f.figure): f for f in verdict.figures}
        out = []
        for r in self.rows:
            if r["sensor"] != "tcp":
                continue
            row = dict(r)
            for col, fig in [(f"spike_{q}_um", f"spike {q}") for q in QUADRANTS] + [
                    ("contour_error_um", "contour error")]:
                f = by.get((r["direction"].lower(), fig))
                if f is None:
                    continue
                row[col.replace("_um", "_90_um")] = f.half_width * 1e6
                # a figure one of the circles does not give (a window in its feed ramp) is
                # neither inside nor outside: None, not a miss
                row[col.replace("_um", "_inside")] = (
                    bool(abs(r[col]) <= f.half_width * 1e6)
                    if r[col] is not None and np.isfinite(r[col]) else None)
                row[col.replace("_um", "_verdict")] = f.verdict
            out.append(row)
        return out

    @staticmethod
    def judged_long(judged: list) -> list[dict]:
        """The rows of :meth:`judged` a figure each: ``direction``, ``figure`` (``spike A``
        ... ``contour error``), ``measured_minus_predicted_um``, ``half_width_90_um``,
        ``inside`` and ``verdict``, for a table read across (the wide rows ran to 346
        columns) and a CSV file [um]."""
        out = []
        for r in judged:
            for col in [f"spike_{q}" for q in QUADRANTS] + ["contour_error"]:
                if f"{col}_90_um" not in r:
                    continue
                out.append({"direction": r["direction"], "figure": col.replace("_", " "),
                            "measured_minus_predicted_um": r[f"{col}_um"],
                            "half_width_90_um": r[f"{col}_90_um"],
                            "inside": r[f"{col}_inside"], "verdict": r[f"{col}_verdict"]})
        return out

    def notes(self) -> list[str]:
        """One sentence per sign flip: the spike difference there is the sum of two
        lobes, and how far apart the lobes themselves are."""
        out = []
        for f in self.sign_flips:
            lobes = [(f[f"{w}_rise_um"], f[f"{w}_fall_um"]) for w in ("measured", "predicted")]
            why = ("because rise and fall after the reversal are of similar size"
                   if any(_similar(*pair) for pair in lobes) else
                   "because the lobes after the reversal differ themselves")
            out.append(
                f"{f['direction']} {f['sensor']} at {f['point']}: the spike changes sign "
                f"(measured {f['measured_spike_um']:+.2f} um, predicted "
                f"{f['predicted_spike_um']:+.2f} um) {why} (rise/fall measured "
                f"{lobes[0][0]:+.2f}/{lobes[0][1]:+.2f} um, predicted {lobes[1][0]:+.2f}/"
                f"{lobes[1][1]:+.2f} um); lobe by lobe, measured and predicted "
                f"differ by at most {f['lobe_difference_um']:.2f} um")
        return out + hidden_notes(self.hidden)


#: Rise and fall after a reversal are of similar size where the smaller is at least this
#: share of the larger: a small change then makes the other the spike [-].
SIMILAR_LOBES = 0.5


#: The least spike that has a sign: below it, the sensors' noise when a circle is compared
#: with itself (the verdict's floor, :data:`tcpmm.uncertainty.CALIBRATION`) [m].
SIGNED_SPIKE_M = 0.15e-6


def _similar(rise: float, fall: float) -> bool:
    """Whether a rise and a fall are of similar size (:data:`SIMILAR_LOBES`) [-]."""
    big = max(abs(rise), abs(fall))
    return big > 0.0 and min(abs(rise), abs(fall)) >= SIMILAR_LOBES * big


def _on_grid(angle, e, direction, start, grid):
    """The error ``e`` at the travel angles ``grid`` from the angle ``start``, over one
    turn (a run that starts elsewhere on the circle is taken at the same places) [m]."""
    sgn = -1.0 if direction == "cw" else 1.0
    turn = (angle - angle[0]) * sgn < 2 * np.pi  # one turn of the run: no overlap mixed in
    a = np.mod((angle[turn] - start) * sgn, 2 * np.pi)
    # nothing is measured in a gap of the log: no error made up there by interpolation
    return np.where(in_gaps(a, grid, 2 * np.pi), np.nan,
                    np.interp(grid, a, e[turn], period=2 * np.pi))


def _travel(sc, direction, start):
    """Each sample's travel angle from ``start``, in the direction of travel, within one
    turn; where the pass's travel begins in that frame [rad]."""
    sgn = -1.0 if direction == "cw" else 1.0
    t = (sc.angle_rad - sc.angle_rad[0]) * sgn
    turn = t < 2 * np.pi
    return t[turn], sc.radial_error[turn], np.mod((sc.angle_rad[0] - start) * sgn, 2 * np.pi)


def _common_arc(sm, sp, direction) -> dict:
    """Measured minus predicted over the travel angles both passes hold (one at least an
    arc): the contour error (``max |e|``) of each over them, and the radial error point by
    point every half degree [um]; the angle they share [deg]. Where they share none, NaN."""
    tm, em, _ = _travel(sm, direction, sm.angle_rad[0])
    tp, ep, off = _travel(sp, direction, sm.angle_rad[0])
    # the predicted pass's samples in the measured pass's frame, and the other way round
    at_p = np.mod(tp + off, 2 * np.pi)
    at_m = np.mod(tm - off, 2 * np.pi)
    in_m, in_p = at_p <= tm[-1], at_m <= tp[-1]
    grid = np.arange(0.0, tm[-1], np.radians(0.5))
    grid = grid[np.mod(grid - off, 2 * np.pi) <= tp[-1]]
    grid = grid[~(in_gaps(tm, grid) | in_gaps(tp, np.mod(grid - off, 2 * np.pi)))]
    nan = float("nan")
    if not (grid.size and in_m.any() and in_p.any()):
        return {"contour_error_um": nan, "radial_rms_um": nan, "radial_max_um": nan,
                "common_deg": 0.0}
    d = np.interp(grid, tm, em) - np.interp(np.mod(grid - off, 2 * np.pi), tp, ep)
    return {"contour_error_um": float(np.max(np.abs(em[in_p])) - np.max(np.abs(ep[in_m])))
            * 1e6, "radial_rms_um": float(np.sqrt(np.mean(d**2)) * 1e6),
            "radial_max_um": float(np.max(np.abs(d)) * 1e6),
            "common_deg": float(np.degrees(grid[-1] - grid[0]))}


#: the most the two runs' speeds about the centre may differ for one test [-]
SAME_SPEED_TOL = 0.02


def _same_test(pm, pp) -> None:
    """Refuse a measured and a predicted circle run at different feeds: the prediction
    is of another test (an F10000 measurement against an F5000 prediction read as a
    contour error 207 um off, with spikes inside their intervals). Each pass's feed is its
    steady angular speed (:attr:`CirclePass.feed_rate_rad_s`): the mean counts the ramps,
    and two runs of one arc at one feed ramped at other accelerations differ by 13 % in
    it."""
    _same_command(pm, pp)
    a, b = pm.feed_rate_rad_s, pp.feed_rate_rad_s
    if np.isfinite(a) and np.isfinite(b) and abs(a - b) > SAME_SPEED_TOL * max(abs(a), abs(b)):
        what = "arc" if pm.is_arc or pp.is_arc else "circle"
        raise InputError(
            f"the measured {pm.direction.upper()} {what} runs at {abs(a):.4g} rad/s about "
            f"the centre at its steady feed, the predicted one at {abs(b):.4g} rad/s "
            f"({abs(a / b):.3g} times): the prediction is of another test; simulate the "
            "measured run's own command (tcpmm simulate MODEL --command MEASURED.csv)")


def _same_command(pm, pp) -> None:
    """Refuse a measured and a predicted circle whose commands run about centres more
    than :data:`.circle_command.CENTRE_TOL_M` apart (each over its whole turns): the
    prediction is of another command, and the offset would read as the machine's
    difference (20 um apart: the TCP's spike B -7.1 um, the contour error +18.5 um)."""
    cm, cp = pm.sensors.get("cmd"), pp.sensors.get("cmd")
    if cm is None or cp is None or pm.is_arc or pp.is_arc:
        return
    (am, bm), (ap, bp) = (once_around(c.angle_rad, c.radial_error) for c in (cm, cp))
    apart = float(np.hypot(am - ap, bm - bp))
    if apart > CENTRE_TOL_M:
        raise InputError(
            f"the measured {pm.direction.upper()} command runs its circle about a centre "
            f"{apart * 1e6:.1f} µm from the predicted one's ({(am - ap) * 1e6:+.1f}, "
            f"{(bm - bp) * 1e6:+.1f}) µm: the prediction is of another command; simulate "
            "the measured run's own command (tcpmm simulate MODEL --command MEASURED.csv)")


def cut_alike(measured, predicted):
    """The predicted run to analyse against ``measured``: without its command where the
    measured run has none (a TCP device's or a ballbar's record), so that the passes of
    both are found on their sensors. A pass cut on the command and one cut on the sensor
    end in different places, and the same signal compared with itself came out up to
    3.6 um apart.

    Parameters
    ----------
    measured, predicted : Run
        The runs compared [SI].

    Returns
    -------
    Run
        ``predicted``, or a copy without command signals [SI].
    """
    warn_sampling(measured, predicted)
    if (any(a.cmd is not None for a in measured.axes.values())
            or all(a.cmd is None for a in predicted.axes.values())):
        return predicted
    warnings.warn("the measured run has no command: the predicted run's passes are found on "
                  "its sensors, as the measured run's are, and not on its command",
                  InputWarning, stacklevel=2)
    return replace(predicted, axes={n: replace(a, cmd=None) for n, a in predicted.axes.items()})


def compare_circles(measured: CircleResult, predicted: CircleResult) -> Comparison:
    """Table 2: for every direction and sensor in both, measured minus predicted, and
    the points where the spike changes sign between the two (:func:`sign_flips`).

    Parameters
    ----------
    measured, predicted : CircleResult
        Analyses of the measured and the predicted run [-].
    """
    rows, flips, hidden = [], [], []
    for pm in measured.passes:
        try:
            pp = predicted.pass_for(pm.direction)
        except InputError:
            continue
        _same_test(pm, pp)
        for name, sm in pm.sensors.items():
            if name not in pp.sensors or name == "cmd":
                continue
            sp = pp.sensors[name]
            row = {"direction": pm.direction.upper(), "sensor": name}
            for q in QUADRANTS:
                row[f"spike_{q}_um"] = (sm.spikes[q] - sp.spikes[q]) * 1e6
            flips += sign_flips(sm, sp, pm.direction.upper(), name)
            if (sm.pair is None) == (sp.pair is None):  # else the terms are of other fits
                hidden += hidden_spikes(sm, sp, pm.direction, name)
            if pm.is_arc or pp.is_arc:  # only where both runs are: nothing filled in
                row.update(_common_arc(sm, sp, pm.direction))
                rows.append(row)
                continue
            row["contour_error_um"] = (sm.contour_error - sp.contour_error) * 1e6
            # Point by point on a common grid of travel angle from a common start angle.
            grid = np.linspace(0, 2 * np.pi, 721)[:-1]
            start = sm.angle_rad[0]
            em = _on_grid(sm.angle_rad, sm.radial_error, pm.direction, start, grid)
            ep = _on_grid(sp.angle_rad, sp.radial_error, pm.direction, start, grid)
            d = em - ep
            row["radial_rms_um"] = float(np.sqrt(np.nanmean(d**2)) * 1e6)
            row["radial_max_um"] = float(np.nanmax(np.abs(d)) * 1e6)
            rows.append(row)
    if not rows:
        raise InputError(_nothing_shared(measured, predicted))
    return Comparison(rows, flips, measured, predicted, hidden)


def _nothing_shared(measured: CircleResult, predicted: CircleResult) -> str:
    """Why two circle analyses have nothing to compare: the directions and sensors of
    each [-]."""
    def held(res):
        return "; ".join(f"{p.direction.upper()} ({', '.join(n for n in p.sensors if n != 'cmd')})"
                         for p in res.passes) or "none"

    return (f"the two runs share no circle direction and sensor to compare: the measured "
            f"run holds {held(measured)}, the predicted {held(predicted)}; predict the "
            f"measured run's own command (tcpmm simulate MODEL --command MEASURED.csv)")


def sign_flips(measured, predicted, direction: str = "", sensor: str = "") -> list[dict]:
    """Quadrant points where the measured and the predicted reversal spike have opposite
    signs, each at least :data:`SIGNED_SPIKE_M` (a spike of zero has no sign to change).

    The spike is the larger in magnitude of the rise and the fall after the reversal
    (docs/formats.md section 4); where the two are of similar size, measured and predicted
    may pick different ones and their difference is then the sum of both lobes. The
    lobe difference (the larger of rise minus rise and fall minus fall) says whether the
    shape after the reversal is predicted nonetheless.

    Parameters
    ----------
    measured, predicted : SensorCircle
        One sensor over one pass, measured and predicted [m].
    direction : str
        Direction of travel, for the record [-].
    sensor : str
        Sensor name, for the record [-].

    Returns
    -------
    list of dict
        Per flip: point, spikes, rises, falls and the lobe difference [um].
    """
    out = []
    for q in QUADRANTS:
        a, b = measured.spikes[q], predicted.spikes[q]
        if (not (a * b < 0) or min(abs(a), abs(b)) < SIGNED_SPIKE_M
                or q not in measured.lobes or q not in predicted.lobes):
            continue
        (mr, mf), (pr, pf) = measured.lobes[q], predicted.lobes[q]
        out.append({"direction": direction, "sensor": sensor, "point": q,
                    "measured_spike_um": a * 1e6, "predicted_spike_um": b * 1e6,
                    "measured_rise_um": mr * 1e6, "measured_fall_um": mf * 1e6,
                    "predicted_rise_um": pr * 1e6, "predicted_fall_um": pf * 1e6,
                    "lobe_difference_um": lobe_difference(measured.lobes[q],
                                                          predicted.lobes[q]) * 1e6})
    return out


def lobe_difference(measured, predicted) -> float:
    """The larger of rise minus rise and fall minus fall after a reversal: unlike the
    spike difference, it does not jump when the spike changes sign.

    Parameters
    ----------
    measured, predicted : tuple of float
        ``(rise, fall)`` after the quadrant point (``SensorCircle.lobes``) [m].

    Returns
    -------
    float
        ``max(|rise_m - rise_p|, |fall_m - fall_p|)`` [m].
    """
    (mr, mf), (pr, pf) = measured, predicted
    return max(abs(mr - pr), abs(mf - pf))
