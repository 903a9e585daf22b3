"""Circular test analysis (docs/formats.md section 4).

Quadrant points A, B, C, D are at 0, 90, 180, 270 deg counter-clockwise from the plane's
first axis (+X in XY, :mod:`tcpmm.analysis.plane`) about the nominal centre, whatever the
direction of travel. Radial error ``e = r - R`` (outward
positive); contour error ``max |e|`` over the full circle without the feed-in and
feed-out arcs; circular deviation G (ISO 230-4) ``max r - min r`` about the least-squares
centre; the reversal spike at a quadrant point P is the value of ``e - b`` with the
largest magnitude in the 20 deg that follow P in the direction of travel, where ``b`` is
the median of ``e`` over 30 deg to 5 deg before P. That raw spike holds every other error
that changes the radius there (a centre offset, a servo mismatch); the headline spike is
taken after them (:meth:`SensorCircle.spikes_after_terms`, :mod:`.circle_terms`).

A quadrant point whose windows do not both lie on the circle (a circle that starts or ends
at it) is left out: its spike is NaN and an :class:`InputWarning` names it.

Full circles are found from the command when the run has one (else from the first sensor
present): the stretches whose radius keeps within a tolerance of one level near R (a
command a controller's filter has pulled in counts, and its radial deviation is reported);
feed-in and feed-out arcs that join the circle tangentially are trimmed symmetrically so
that exactly the programmed turns remain. A run without a full circle is analysed on its
arcs (:mod:`tcpmm.analysis.circle_passes`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from .circle_after import after_terms, pair_diagnosis
from .circle_checks import check_sensor_path, present_sensors, warn_pass, warn_unresolved
from .circle_command import command_figures, radial_deviation, reference_stretches  # noqa: F401
from .circle_feeds import command_radius, other_feeds
from .circle_inputs import SENSORS, circle_arguments
from .circle_passes import (  # noqa: F401
    SENSOR_TOL_SHARE,
    circle_deviation,
    find_passes,
    find_stretches,
    lsq_circle,
    rate,
    steady_rate,
    within_span,
)
from .circle_settling import warn_unsettled
from .circle_spikes import (  # noqa: F401  (the spikes are part of this module's interface)
    QUADRANTS,
    reversal_lobes,
    reversal_spikes,
    spikes_and_lobes,
    uncrossed_quadrants,
)
from .circle_units import not_found_error


@dataclass
class SensorCircle:
    """Circular-test figures of one sensor over one pass.

    Parameters
    ----------
    angle_rad : ndarray
        Angle of each sample about the nominal centre, CCW from +X, unwrapped [rad].
    radial_error : ndarray
        ``r - R`` about the nominal centre [m].
    contour_error : float
        ``max |e|`` [m].
    circular_deviation : float
        ISO 230-4 G about the least-squares centre [m].
    lsq_centre : tuple
        Least-squares centre [m].
    spikes : dict
        Signed reversal spike per quadrant point [m].
    lobes : dict
        Per quadrant point ``(rise, fall)``: the largest and the smallest ``e - b`` in the
        window of the spike, which is whichever is larger in magnitude [m].
    direction : {"ccw", "cw"}
        Direction of travel [-].
    left_out : tuple of str
        Quadrant points whose windows the pass does not hold, in any of its sensors: no
        spike there, for any sensor [-].
    """

    angle_rad: np.ndarray
    radial_error: np.ndarray
    contour_error: float
    circular_deviation: float
    lsq_centre: tuple
    spikes: dict
    lobes: dict = field(default_factory=dict)
    direction: str = "ccw"
    _after: tuple | None = field(default=None, repr=False)
    left_out: tuple = ()
    _pair: tuple | None = field(default=None, repr=False)

    def spikes_after_terms(self) -> dict:
        """Signed reversal spike per quadrant point after the error terms: those of the
        pair where this circle has one in the other direction (:meth:`CircleResult.paired`:
        backlash, lateral play, bows and cyclic errors too, which one circle leaves in its
        spikes), else those fitted to this circle alone
        (:mod:`tcpmm.analysis.circle_terms`); ``spikes`` are the raw ``e - b`` [m]."""
        return self._after_terms()[0]

    def spike_uncertainty(self, sample_noise: bool = False) -> dict:
        """The 95 % uncertainty of each spike of :meth:`spikes_after_terms`
        (:mod:`tcpmm.analysis.circle_spike_sigma`); with ``sample_noise`` from the noise
        from sample to sample alone; NaN where there is no spike [m]."""
        return self._after_terms()[2 if sample_noise else 1]

    def _after_terms(self) -> tuple:
        if self._after is None:
            self._after = tuple({q: np.nan if q in self.left_out else v for q, v in d.items()}
                                for d in after_terms(self))
        return self._after

    @property
    def pair(self) -> tuple | None:
        """``(other circle, radius, rates, shared, plane, sensor)`` of the pair this circle
        belongs to (:meth:`CircleResult.paired`), None where it has none [-]."""
        return self._pair

    @property
    def after_pair(self) -> bool:
        """Whether :meth:`spikes_after_terms` are the pair's [-]."""
        return pair_diagnosis(self) is not None

    def leave_out(self, points) -> None:
        """Report no spike at ``points`` (a sensor that holds a point's windows where the
        pass's other sensors do not, by a fraction of a sample) [-]."""
        self.left_out = tuple(points)
        self.spikes = {q: np.nan if q in points else v for q, v in self.spikes.items()}
        self.lobes = {q: (np.nan, np.nan) if q in points else v for q, v in self.lobes.items()}
        self._after = None


@dataclass
class CirclePass:
    """One full circle of a run, in one direction.

    Parameters
    ----------
    direction : {"ccw", "cw"}
        Direction of travel [-].
    index : slice
        Samples of the run on the circle [-].
    sensors : dict of str to SensorCircle
        Results per sensor (``cmd``, ``motor``, ``scale``, ``tcp``) [-].
    rate_rad_s : float
        Mean angular speed about the nominal centre; NaN when unknown [rad/s].
    steady_rate_rad_s : float
        Median angular speed of its sample steps: the feed the pass is taken at, where the
        mean counts a ramp in or out; NaN when unknown [rad/s].
    command_radial_deviation : float
        Mean radius of the command minus the nominal: a controller's filter pulls a circle
        in, a radius offset moves it; NaN without a command [m].
    arc_deg : float
        Angle covered: 360 per turn for a full circle, less for an arc [deg].
    """

    direction: str
    index: slice
    sensors: dict = field(default_factory=dict)
    rate_rad_s: float = float("nan")
    command_radial_deviation: float = float("nan")
    arc_deg: float = 360.0
    steady_rate_rad_s: float = float("nan")

    @property
    def is_arc(self) -> bool:
        """Whether the pass is an arc, not a full circle [-]."""
        return self.arc_deg < 360.0

    @property
    def feed_rate_rad_s(self) -> float:
        """The angular speed of the feed the pass is taken at: the steady one where known,
        else the mean. The servo mismatch is the ellipse's angle over it, and the mean
        counts the ramps of an arc run from standstill (a ballbar's 220 deg arcs at
        0.5 m/s^2 read a mismatch of 1 ms as 1.04 ms) [rad/s]."""
        if np.isfinite(self.steady_rate_rad_s):
            return self.steady_rate_rad_s
        return self.rate_rad_s

    def table(self) -> list[dict]:
        """One row per sensor [um]: the reversal spikes A-D after the fitted terms
        (``spike_after_terms_A_um``...) and their 95 % uncertainty
        (``spike_after_terms_A_uncertainty_95_um``...), contour error, G, and the raw
        spikes ``e - b`` (``spike_A_um``..., which ``compare`` and the paper's Table 2
        take), and the command's radial deviation of the pass."""
        rows = []
        for name, s in self.sensors.items():
            row = {"direction": self.direction, "sensor": name}
            row.update({f"spike_after_terms_{k}_um": v * 1e6
                        for k, v in s.spikes_after_terms().items()})
            row.update({f"spike_after_terms_{k}_uncertainty_95_um": v * 1e6
                        for k, v in s.spike_uncertainty().items()})
            row["contour_error_um"] = s.contour_error * 1e6
            row["circular_deviation_um"] = s.circular_deviation * 1e6
            row.update({f"spike_{k}_um": v * 1e6 for k, v in s.spikes.items()})
            row["command_radial_deviation_um"] = self.command_radial_deviation * 1e6
            rows.append(row)
        return rows


@dataclass
class CircleResult:
    """Circular-test analysis of a run: every full-circle pass found.

    Parameters
    ----------
    radius : float
        Nominal radius [m].
    centre : tuple
        Nominal centre [m].
    passes : list of CirclePass
        The passes, in time order [-].
    plane : tuple of str
        The plane's first and second axis; angles from the first towards the second [-].
    """

    radius: float
    centre: tuple
    passes: list
    plane: tuple = ("X", "Y")

    def __post_init__(self):
        self.paired()

    def paired(self) -> None:
        """Give the k-th CCW and the k-th CW pass each other's sensors, so that their
        headline spikes are taken after the pair's terms: one circle's own fit leaves a
        bow (0.76 um), a cyclic error (0.99 um) and 15 % of the other axis's backlash in
        its spikes. A pass left without one (or at another feed) keeps its own terms [-]."""
        ccws, cws = ([p for p in self.passes if p.direction == d] for d in ("ccw", "cw"))
        for ccw, cw in zip(ccws, cws, strict=False):
            if other_feeds(ccw, cw, self.radius) is not None:
                continue  # two tests: each circle keeps its own terms
            rates = (ccw.feed_rate_rad_s, cw.feed_rate_rad_s)
            for name in set(ccw.sensors) & set(cw.sensors):
                shared = {"command_radius_m": command_radius(ccw, cw, self.radius)}
                for a, b in ((ccw, cw), (cw, ccw)):
                    sc = a.sensors[name]
                    sc._pair = (b.sensors[name], self.radius, rates, shared, tuple(self.plane),
                                name)
                    sc._after = None

    def to_pandas(self):
        """Table: one row per pass and sensor (um)."""
        import pandas as pd

        return pd.DataFrame([r for p in self.passes for r in p.table()])

    def to_dict(self) -> dict:
        """JSON-ready summary in um; a spike left out (NaN) is ``None``."""
        def clean(row):
            return {k: None if isinstance(v, float) and np.isnan(v) else v
                    for k, v in row.items()}

        return {"plane": "".join(self.plane), "radius_mm": self.radius * 1e3,
                "centre_mm": [c * 1e3 for c in self.centre],
                "passes": [{"direction": p.direction, "arc_deg": p.arc_deg,
                            "command_radial_deviation_um": clean(
                                {"v": p.command_radial_deviation * 1e6})["v"],
                            "sensors": [clean(r) for r in p.table()]}
                           for p in self.passes]}

    def pass_for(self, direction: str) -> CirclePass:
        """The first pass in a direction."""
        for p in self.passes:
            if p.direction == direction:
                return p
        raise InputError(f"no {direction.upper()} circle found in the run "
                         f"(found: {', '.join(p.direction for p in self.passes) or 'none'})")

    def plot(self, ax=None, path=None, magnification=None):
        """Polar plot of the paths with magnified radial error (paper Figs. 11-12); the
        figure.

        Parameters
        ----------
        ax : matplotlib Axes or array-like of Axes, optional
            One per pass; a new figure when omitted [-].
        path : str or Path, optional
            Also save it there (PNG/PDF/SVG) [-].
        magnification : float, optional
            Radial-error magnification, automatic when omitted [-].
        """
        from ..plot.circle import plot_circle  # tcpmm.plot is a floor above this one

        return plot_circle(self, path=path, magnification=magnification, ax=ax)


def analyse_sensor(x, y, radius, centre, direction) -> SensorCircle:
    """Figures of one sensor path over one full circle.

    Parameters
    ----------
    x, y : ndarray
        Path in the plane [m].
    radius : float
        Nominal radius [m].
    centre : tuple
        Nominal centre [m].
    direction : {"ccw", "cw"}
        Direction of travel [-].
    """
    dx, dy = x - centre[0], y - centre[1]
    ang = np.unwrap(np.arctan2(dy, dx))
    e = np.hypot(dx, dy) - radius
    g, centre = circle_deviation(x, y)
    return SensorCircle(ang, e, float(np.max(np.abs(e))), g, centre,
                        *spikes_and_lobes(ang, e, direction), direction)


def _sensors(X, Y, sl, present, reference, radius_m, centre_m, how) -> tuple[dict, list]:
    """Each sensor present over the pass ``sl`` of ``reference`` (name, unwrapped angle),
    checked against it first; the quadrant points some sensor gives no spike at, left out
    of every one. ``how``: the direction and the plane's axes [-]."""
    ref, ref_ang = reference
    d, out = how[0], {}
    for s in present:
        if s != ref:
            check_sensor_path(X.sensor(s)[sl], Y.sensor(s)[sl], (X.sensor(ref)[sl],
                              Y.sensor(ref)[sl]), centre_m, radius_m, (s, ref, *how[1:]), d)
        on = within_span(X.sensor(s), Y.sensor(s), sl, centre_m, ref_ang) if s != ref else sl
        out[s] = analyse_sensor(X.sensor(s)[on], Y.sensor(s)[on], radius_m, centre_m, d)
    missing = [q for q in QUADRANTS if any(np.isnan(sc.spikes[q]) for sc in out.values())]
    for sc in out.values():  # what the warning says holds for every sensor
        sc.leave_out(missing)
    return out, missing


def analyse_circle(run, radius_m, centre_m=(0.0, 0.0), plane=("X", "Y"), direction=None,
                   sensors=SENSORS, settling=True) -> CircleResult:
    """Circular-test analysis of a run: its full circles, else its arcs
    (:mod:`tcpmm.analysis.circle_passes`).

    Parameters
    ----------
    run : Run or str or Path or pandas.DataFrame
        Simulated or measured run, its file, or its table in the run-file layout (mm) [-].
    radius_m : float
        Nominal radius [m].
    centre_m : tuple of float
        Nominal centre, two coordinates in the plane [m].
    plane : tuple of str
        The two axes of the circle plane, e.g. ``("Z", "X")``; CCW turns the first into
        the second, the centre is given in them [-].
    direction : {"ccw", "cw"}, optional
        Keep only passes in this direction [-].
    sensors : tuple of str
        Sensors to analyse where present, of cmd, motor, scale, tcp [-].
    settling : bool
        Say where a pass starts before the servo has settled (:mod:`.circle_settling`) and
        where its figures hang on single samples; off for a prediction [-].
    """
    run, radius_m, centre_m, axes, sensors = circle_arguments(run, radius_m, centre_m, plane,
                                                              sensors)
    X, Y = run.axes[axes[0]], run.axes[axes[1]]
    present = present_sensors(run, axes, sensors)
    ref = "cmd" if "cmd" in present else present[0]
    tol = 1e-3 * radius_m if ref == "cmd" else SENSOR_TOL_SHARE * radius_m
    passes = []
    for st in reference_stretches(X.sensor(ref), Y.sensor(ref), radius_m, centre_m, tol,
                                  ref):
        if direction is not None and st.direction != direction:
            continue
        sl, d = st.index, st.direction
        ref_ang = np.unwrap(np.arctan2(Y.sensor(ref)[sl] - centre_m[1],
                                       X.sensor(ref)[sl] - centre_m[0]))
        cp = CirclePass(d, sl, rate_rad_s=rate(run.time_s[sl], ref_ang),
                        arc_deg=360.0 * st.turns if st.turns else st.span_deg,
                        steady_rate_rad_s=steady_rate(run.time_s[sl], ref_ang))
        if "cmd" in present:
            command_figures(cp, X.sensor("cmd")[sl], Y.sensor("cmd")[sl], radius_m, centre_m,
                            tol, bool(st.turns))
        cp.sensors, missing = _sensors(X, Y, sl, present, (ref, ref_ang), radius_m,
                                       centre_m, (d, *axes))
        warn_pass(run.time_s[sl], cp, cp.sensors[ref].angle_rad, missing, radius_m)
        if settling:
            warn_unsettled(X, Y, sl, present, ref_ang, d, cp.arc_deg)
            warn_unresolved(run.time_s[sl], cp, radius_m, centre_m)
        passes.append(cp)
    if not passes:
        raise not_found_error(radius_m, centre_m, axes, ref, direction, float(np.median(
            np.hypot(X.sensor(ref) - centre_m[0], Y.sensor(ref) - centre_m[1]))))
    return CircleResult(radius_m, tuple(centre_m), passes, axes)
