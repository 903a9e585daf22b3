"""Contour error along any path, and corner metrics for square and step tests.

Contour error: the shortest distance from the actual point to the commanded path, the
polyline through the command samples. In a plane ``(a, b)`` it is signed: positive when
the point lies left of the direction of travel (seen with ``+a`` to the right and ``+b``
up), so positive is inside a CCW circle and outside a CW one, and an overshoot past a
left-hand corner is negative. In 3-D it is the distance, unsigned. The closest point is
sought among the command samples within ``window_s`` of the actual sample, so a path
that passes a place twice (CCW then CW) is matched with the pass being run; where passes
lie equally close (a pass back along the way out, a second lap), with the one nearest in
time. Equally close within the chords' sag: along a curve two passes are sampled at other
points, and each one's chords lie off the curve by up to ``L^2 / 8R``
(:func:`tcpmm.analysis.contour_windows.chord_sags`). The search
(:mod:`tcpmm.path.nearest`) passes over blocks of segments that lie too far to hold the
closest point, and gives what measuring every segment of the window gives, to the bit.

Corners are where the command's direction, over ``corner_span_m`` before and after a point,
turns by more than ``corner_deg``, most of it within a quarter of that span (an even curve,
a small arc or a spiral, is none); the end of the path counts as one (turn NaN), where a
step test overshoots and settles: there the distance to the end point settles, counted from
the command's arrival. Where the path runs back on itself (a reversal) the corner is the
turning point. Each corner is measured on the samples whose closest command point lies near
it: from ``corner_span_m`` before it to ``corner_span_m`` after it, or further while the
command runs straight on; at the end, once the command is there, also those within
``corner_span_m`` of the end point (a closed path's start lies closer to a tool running
past its end than the last leg). Per corner and sensor: overshoot, the largest distance the point
lies outside the path once past the corner, across the outgoing leg towards the side the
incoming direction points to (at a right angle, the travel past the corner along the
incoming direction), beyond where the point holds on the outgoing leg if that lies outside
the path (the median of the last quarter of the corner's samples, where they stay within
``settle_tol_m`` of it or, ringing about a sag, lie outside the band about the quarter
before's median); at the end, the travel past the end point, or past where the point comes
to rest if that lies beyond it (a static deflection is no overshoot), NaN where the run
stops before the machine comes to rest there (:attr:`ContourResult.unreached`); 0 when it
never passes; rounding, the closest approach to the corner point; settling, the time and the
command's path length from when the command leaves the corner until the contour error stays
within ``settle_tol_m`` of the level it ends at halfway (in time) to the command's arrival
at the next corner (the median of the last quarter of the stretch the corner owns; a static
deflection is no settling error); NaN unless it stays in the band all that quarter.

A run made from an NC program records which samples' commands are in G0 rapids: they are
left out of the summary, and the corners with a rapid within ``corner_span_m`` of them out
of the corners, unless counted (:mod:`tcpmm.analysis.rapids`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .._validate import instance_of
from ..errors import InputError
from ..io.runfile import as_run
from ..path.command import Command
from .contour_chords import off_chord
from .contour_corners import CornerStream, end_unreached
from .contour_distance import (  # noqa: F401  (part of this module's interface)
    distance_to_polyline,
    distances_to_polyline,
    polyline,
)
from .contour_inputs import command_flags, contour_axes, plane_left_out, run_signals
from .contour_lag import WINDOW_S, widened
from .contour_passes import whole_leaps
from .corners import path_length
from .rapids import RapidStretches, feed_only, rapids_json, since_rapid


@dataclass
class ContourResult:
    """Contour error of each sensor of a run, and its corners.

    Parameters
    ----------
    axes : tuple of str
        Axes the distance is measured in; two for a plane (signed error) [-].
    signed : bool
        Whether the error is signed (a plane) [-].
    time_s : ndarray
        Times of the actual samples [s].
    command : ndarray, shape (m, len(axes))
        The commanded path: the command samples [m].
    command_time_s : ndarray
        Times of the command samples [s].
    path_s_m : ndarray
        Command path length travelled at each command sample [m].
    errors : dict of str to ndarray
        Contour error per sensor at each actual sample [m].
    corners : list of dict
        Per corner: ``index`` (sample), ``point_m``, ``turn_rad``, and per sensor
        ``overshoot_m``, ``rounding_m``, ``settle_s``, ``settle_m`` [SI]; the corners in
        G0 rapids left out unless counted.
    settle_tol_m : float
        The band of the settling figures [m].
    actual : dict of str to ndarray
        Actual path per sensor, shape (n, len(axes)) [m].
    counted : ndarray of bool, optional
        The samples the summary counts; all when ``None`` [-].
    rapids : dict, optional
        The samples and corners in G0 rapids (:func:`tcpmm.analysis.rapids.feed_only`);
        ``None`` for a run that does not record them [-].
    nc_line : ndarray of int, optional
        The run's NC line of each sample, where it records them [-].
    unreached : dict of str to float
        Per sensor the run leaves on its way to the path's end point, its distance from
        it at the last sample; the end's overshoot and rounding of those are NaN [m].
    command_sag_m : float
        How far the command's samples cut the path's bends at most [m].
    curves : int
        Places where the command turns by more than the corners' least turn over their
        span, evenly (:meth:`tcpmm.analysis.corners.CornerFinder._curves`): not corners [-].
    left_out : dict of str to float
        Per axis outside the plane that moves substantially, its travel: its error is not
        in the signed error (:func:`tcpmm.analysis.plane.left_out_axes`) [m].
    off_chord : dict of int to tuple
        Per corner (number) whose chords stray off the command by more than
        :data:`~tcpmm.analysis.contour_chords.CHORD_STRAY` of the span (a feature shorter
        than the span: its turn and overshoot are the feature's): how far, and the path
        length over which the command runs straight from it [m].
    window_s : float
        The window each sample's closest command point was sought in [s].
    leaps : dict
        Per sensor whose closest command point leaps to another stretch of the path
        (:mod:`tcpmm.analysis.contour_passes`): how often, and the largest error read at
        such a leap [-, m].
    """

    axes: tuple
    signed: bool
    time_s: np.ndarray
    command: np.ndarray
    command_time_s: np.ndarray
    path_s_m: np.ndarray
    errors: dict
    corners: list = field(default_factory=list)
    settle_tol_m: float = 1e-6
    actual: dict = field(default_factory=dict, repr=False)
    counted: np.ndarray | None = field(default=None, repr=False)
    rapids: dict | None = None
    nc_line: np.ndarray | None = field(default=None, repr=False)
    unreached: dict = field(default_factory=dict)
    command_sag_m: float = 0.0
    curves: int = 0
    left_out: dict = field(default_factory=dict)
    off_chord: dict = field(default_factory=dict)
    window_s: float = WINDOW_S
    leaps: dict = field(default_factory=dict)

    def summary(self) -> dict:
        """Per sensor, of the samples counted: largest magnitude, RMS, largest and smallest
        value [m]; the time of the largest magnitude and, where the rapids are left out,
        the time since the last sample in one there (NaN for none) [s]."""
        t = self.time_s if self.counted is None else self.time_s[self.counted]
        since = (None if self.counted is None else
                 since_rapid(self.time_s, ~self.counted)[0][self.counted])
        out = {}
        for s, e in self.errors.items():
            e = e if self.counted is None else e[self.counted]
            i = int(np.argmax(np.abs(e)))
            out[s] = {"max_abs_m": float(np.abs(e[i])), "rms_m": float(np.sqrt(np.mean(e**2))),
                      "max_m": float(np.max(e)), "min_m": float(np.min(e)),
                      "max_abs_at_s": float(t[i]),
                      "max_abs_after_rapid_s": np.nan if since is None else float(since[i])}
        return out

    def to_pandas(self):
        """Per actual sample: time [s], the NC line where the run records it, each
        sensor's position [mm] and error [um]."""
        import pandas as pd

        data = {"time_s": self.time_s}
        if self.nc_line is not None:
            data["nc_line"] = self.nc_line
        for s, q in self.actual.items():
            for i, a in enumerate(self.axes):
                data[f"{a.lower()}_{s}_mm"] = q[:, i] * 1e3
        for s, e in self.errors.items():
            data[f"{s}_contour_um"] = e * 1e6
        return pd.DataFrame(data)

    def corner_rows(self, sensors=None, corners=None) -> list:
        """Per corner and sensor, a dict: position [mm], turn [deg], overshoot, rounding
        [um], settling [ms, mm] (NaN where there is none); of the ``sensors`` and
        ``corners`` given (default all: a long run's are many) [-]."""
        return [_corner_row(self.axes, c, s) for c in
                (self.corners if corners is None else corners)
                for s in (self.errors if sensors is None else sensors)]

    def corners_table(self):
        """:meth:`corner_rows` as a table."""
        import pandas as pd

        return pd.DataFrame(self.corner_rows())

    def to_dict(self, corners: bool = True) -> dict:
        """JSON-ready: axes, summary [um] and corners (um, ms, mm; NaN as ``None``); without
        the corners where ``corners`` is false (:meth:`json_rows` gives them one by one)."""
        head = {"axes": "".join(self.axes), "signed": self.signed,
                "settle_tol_um": self.settle_tol_m * 1e6, "rapids": rapids_json(self.rapids),
                "end_unreached_um": {s: d * 1e6 for s, d in self.unreached.items()},
                "command_sag_um": self.command_sag_m * 1e6, "curves": self.curves,
                "window_s": self.window_s,
                "closest_point_leaps": {k: {"leaps": v["leaps"],
                                            "max_abs_um": v["max_abs_m"] * 1e6}
                                        for k, v in self.leaps.items()},
                "left_out_travel_mm": {a: t * 1e3 for a, t in self.left_out.items()},
                "corners_off_chord": [{"corner": n, "stray_um": v * 1e6,
                                       "straight_mm": None if w != w else w * 1e3}
                                      for n, (v, w) in self.off_chord.items()],
                "sensors": {s: {**{k[:-2] + "_um": v * 1e6 for k, v in d.items()
                                   if k.endswith("_m")},
                                **{k: None if v != v else v for k, v in d.items()
                                   if k.endswith("_s")}}
                            for s, d in self.summary().items()}}
        return {**head, "corners": list(self.json_rows())} if corners else head

    def json_rows(self):
        """The corners of :meth:`to_dict`, one row at a time (a long run has millions) [-]."""
        for c in self.corners:
            for row in self.corner_rows(corners=[c]):
                yield {k: None if v != v else v for k, v in row.items()}  # NaN: None

    def plot(self, ax=None, path=None, sensor=None):
        """One sensor's path coloured by its contour error, and every sensor's error in
        time; the figure.

        Parameters
        ----------
        ax : matplotlib Axes or array-like of Axes, optional
            Two (coloured path, error in time), or one for the coloured path alone; a new
            figure when omitted [-].
        path : str or Path, optional
            Also save it there (PNG/PDF/SVG) [-].
        sensor : str, optional
            Sensor of the colours; default tcp, else scale, else motor [-].
        """
        from ..plot.contour import plot_contour

        return plot_contour(self, ax=ax, sensor=sensor, path=path)


def _corner_row(axes, c, s) -> dict:
    row = {"corner": c["number"], "sensor": s}
    row.update({f"{a.lower()}_mm": float(v * 1e3) for a, v in zip(axes, c["point_m"],
                                                                  strict=True)})
    m = c[s]
    row.update(turn_deg=float(np.degrees(c["turn_rad"])), overshoot_um=m["overshoot_m"] * 1e6,
               rounding_um=m["rounding_m"] * 1e6, settle_ms=m["settle_s"] * 1e3,
               settle_mm=m["settle_m"] * 1e3)
    return row


def contour_error(run, command=None, plane="auto", window_s=None, corner_deg=30.0,
                  corner_span_m=0.5e-3, settle_tol_m=1e-6, rapids=False) -> ContourResult:
    """Contour error of every sensor of a run along its commanded path, and corner metrics
    (module docstring: definitions and signs).

    Parameters
    ----------
    run : Run or str or Path or pandas.DataFrame
        Simulated or measured run, its file, or its table in the run-file layout (mm) [-].
    command : Command, optional
        The commanded path on the run's time line; default the run's command signals [-].
    plane : str or tuple of str or None
        ``"auto"``: the plane the command moves in (3-D when it is not plane or moves along
        one axis); ``"XY"``,
        ``("Z", "X")``, ...: that plane, signed; ``None`` or ``"3D"``: unsigned in 3-D [-].
    window_s : float, optional
        Time around each actual sample in which its closest command point is sought
        (default and too short a one: :mod:`tcpmm.analysis.contour_lag`) [s].
    corner_deg : float
        Least turn that makes a corner [deg].
    corner_span_m : float
        Path length before and after a point over which its turn is taken [m].
    settle_tol_m : float
        Band within which the error has settled after a corner [m].
    rapids : bool
        Count the samples and corners in G0 rapids, which a run made from an NC program
        records (its ``rapid`` column) and which are otherwise left out
        (:mod:`tcpmm.analysis.rapids`) [-].
    """
    _check_corner_options(corner_deg, corner_span_m, settle_tol_m)
    run, command = as_run(run), command if command is None else instance_of(
        "command", command, Command, "a Command (tcpmm.read_command, program_to_command)")
    axes, signed = contour_axes(run, plane, command, rapids)
    t, tc, cmd, actual = run_signals(run, command, axes)
    line = polyline(cmd)
    air = None if run.rapid is None or rapids else command_flags(run, command)
    found, window_s = widened(
        lambda w, cuts: distances_to_polyline(actual, cmd, t, tc, w, signed, line=line,
                                              air=air, cuts=cuts),
        t, window_s, None if run.rapid is None or rapids else np.asarray(run.rapid) == 0)
    errors, feet = ({s: v[i] for s, v in found.items()} for i in (0, 1))
    corners = CornerStream(corner_deg, corner_span_m, settle_tol_m, window_s)
    corners.add_command(tc, cmd)
    corners.add_samples(t, actual, errors, feet)
    stretches = RapidStretches(corner_span_m)
    if run.rapid is not None:
        stretches.add_command(cmd, command_flags(run, command))
    counted, kept, said = feed_only(run.rapid, rapids, corners.finish(), stretches)
    s_cmd = path_length(cmd)
    return ContourResult(tuple(axes), signed, t, cmd, tc, s_cmd, errors,
                         list(kept), settle_tol_m, actual, counted, said, run.nc_line,
                         end_unreached(corners, kept), float(np.max(line[4])),
                         corners.finder.curves,
                         plane_left_out(run, command, axes, rapids) if signed else {},
                         off_chord(corners, kept), window_s,
                         whole_leaps(actual, errors, feet, cmd, s_cmd, counted))


def _check_corner_options(corner_deg: float, corner_span_m: float, settle_tol_m: float):
    """Refuse a corner setting that is no positive number, or a turn of 180 deg or more
    [deg], [m], [m]."""
    for v, what in ((corner_span_m, "corner_span_m"), (settle_tol_m, "settle_tol_m"),
                    (corner_deg, "corner_deg")):
        if not (np.isfinite(v) and v > 0):
            raise InputError(f"{what} must be a positive number, got {v}")
    if not corner_deg < 180.0:
        raise InputError(f"corner_deg must be below 180 (a path turns by 180 deg at most), "
                         f"got {corner_deg}")
