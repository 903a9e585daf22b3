"""tcpmm contour: contour error along any path, and corner metrics."""

from __future__ import annotations

from enum import StrEnum
from pathlib import Path

import typer

from ._app import app, checked_plot, console, emit_json_rows, esc, in_file, out, positive
from ._contour_notes import say_notes
from ._plane import COMMAND_HELP, run_plane_said, with_given_command
from ._stream import STREAM_ABOVE_ROWS, contour_streamed, streamed
from ._tables import fixed, plain_table, print_plain


class MeasuredSensor(StrEnum):
    """Sensors whose error from the command is measured (the command has none)."""

    tcp = "tcp"
    scale = "scale"
    motor = "motor"


SPAN_HELP = ("Path before and after a point over which its turn is taken [mm]: a corner "
             "turns within a quarter of it, a curve evenly.")


@app.command()
def contour(run_file: Path = typer.Argument(..., help="RUN.csv (simulated or measured)"),
            plane: str = typer.Option(
                None, "--plane", help="XY, XZ, YZ (or ZX): signed error in that plane "
                                      "(+: left of travel); 3D: unsigned distance. Default: "
                                      "the plane the command moves in, else 3D."),
            sensor: MeasuredSensor = typer.Option(
                None, "--sensor", help="Sensor of the corner table and the plot colours "
                                       "(default tcp, scale, motor)."),
            settle_um: float = typer.Option(1.0, "--settle-um",
                                            help="Settling band after a corner [um]."),
            corner_deg: float = typer.Option(30.0, "--corner-deg",
                                             help="Least turn that makes a corner [deg]."),
            span_mm: float = typer.Option(0.5, "--corner-span-mm", help=SPAN_HELP),
            window_s: float = typer.Option(
                None, "--window-s", help="Time around each sample in which its closest command "
                "point is sought [s]. Default 0.2 s, widened where the tool lags more (said)."),
            chunk_rows: int = typer.Option(
                None, "--chunk-rows", min=2,
                help="Read a Parquet run this many rows at a time (bounded memory; the "
                     "error summary and the corners, no plot). Default: whole, unless it "
                     f"has more than {STREAM_ABOVE_ROWS} rows."),
            command: Path = typer.Option(None, "--command", help=COMMAND_HELP),
            rapids: bool = typer.Option(
                False, "--rapids", help="Count the G0 rapids too: a run made from an NC "
                                        "program records them, and they are left out of "
                                        "the error and the corners by default."),
            model: str = typer.Option(
                None, "--model", help="MODEL.yaml that predicted the run: the tcp's largest "
                                      "and RMS contour error with their 90 % interval over "
                                      "what identification leaves uncertain."),
            as_json: bool = typer.Option(False, "--json"),
            plot: Path = typer.Option(None, "--plot", help="Save the contour plot (PNG/PDF/SVG).")):
    """Contour error along any program: the shortest distance from each sensor's path to the
    commanded path, signed in a plane; corner overshoot, rounding and settling. The G0
    rapids of a run made from an NC program are left out (--rapids counts them)."""
    _check_options(settle_um, corner_deg, window_s, sensor, plot, model, command, span_mm)
    corners = {"corner_deg": corner_deg, "corner_span_m": span_mm * 1e-3,
               "settle_tol_m": settle_um * 1e-6, "rapids": rapids}
    if streamed(run_file, chunk_rows):
        _check_streamed(model=model, command=command, plot=plot)
        with in_file(run_file):
            run, res = None, contour_streamed(run_file, plane, window_s, chunk_rows, **corners)
    else:
        run, res = _whole(run_file, plane, chunk_rows, command, window_s=window_s, **corners)
    say_notes(res, rapids, run_file)
    _say_curves(res, corner_deg, span_mm)
    name = sensor.value if sensor else next(s for s in ("tcp", "scale", "motor")
                                            if s in res.errors)
    if name not in res.errors:
        raise typer.BadParameter(f"the run has no {name} signals of {', '.join(res.axes)}",
                                 param_hint="--sensor")
    verdict = None
    if model is not None:
        from ._contour_model import contour_verdict

        with in_file(run_file):
            verdict = contour_verdict(model, run_file, run, res, window_s, rapids)
    if plot is not None:
        res.plot(sensor=name, path=plot)
    _emit(res, name, run_file, verdict, as_json, span_mm)


#: why a streamed run does not take an option, per option [-]
_NOT_STREAMED = {"model": "is not judged; --model takes a run read whole",
                 "command": "is measured against its own command",
                 "plot": "is not plotted"}


def _check_streamed(**given) -> None:
    """Refuse the options a run read in chunks does not take, saying why [-]."""
    for name, value in given.items():
        if value is not None:
            raise typer.BadParameter(f"a run streamed (--chunk-rows, or more than "
                                     f"{STREAM_ABOVE_ROWS} rows) {_NOT_STREAMED[name]}",
                                     param_hint=f"--{name}")


def _emit(res, sensor: str, run_file: Path, verdict, as_json: bool, span_mm: float) -> None:
    """The summary, the corners and the verdict where there is one, as JSON or tables."""
    if as_json:  # the corners as they are written: a CAM run has hundreds of thousands
        head = res.to_dict(corners=False)
        if verdict is not None:
            head["tcp_verdict"] = [f.to_dict() for f in verdict.figures]
        emit_json_rows(head, "corners", res.json_rows(), len(res.corners) * len(res.errors))
        return
    _print(res, sensor, f"{run_file}", span_mm)
    if verdict is not None:
        from ._contour_model import print_verdict

        print_verdict(verdict)


def _check_options(settle_um: float, corner_deg: float, window_s: float, sensor,
                   plot, model=None, command=None, span_mm: float = 0.5) -> None:
    """Refuse the options that measure nothing, or nothing together, before the run is
    read [-]."""
    if model is not None and command is not None:
        raise typer.BadParameter("--model judges a prediction on the command it was run "
                                 "with; leave out --command", param_hint="--model")
    for v, what in ((settle_um, "--settle-um [um]"), (corner_deg, "--corner-deg [deg]"),
                    (window_s, "--window-s [s]"), (span_mm, "--corner-span-mm [mm]")):
        if v is not None:
            positive(v, what)
    if not corner_deg < 180.0:
        raise typer.BadParameter(f"a path turns by 180 deg at most, so {corner_deg:g} deg "
                                 "would find no corner; give less than 180",
                                 param_hint="--corner-deg")
    checked_plot(plot)


def _whole(run_file: Path, plane, chunk_rows, command=None, **options):
    """The run read whole and its contour error, against ``--command`` where given, in the
    plane of ``--plane`` or the one it moves in (said); ``--chunk-rows``, which does
    nothing to a CSV run, said too."""
    from ..analysis.contour import contour_error
    from ..analysis.contour_lag import WINDOW_S
    from ..analysis.rapids import feed_commands
    from ..io.runfile import read_run

    if chunk_rows is not None:
        console.print(f"note: --chunk-rows reads a Parquet run in chunks; "
                      f"{esc(str(run_file))} is read whole", highlight=False)
    run = with_given_command(read_run(run_file), command, options.get("window_s") or WINDOW_S)
    with in_file(run_file):
        how = run_plane_said(plane, feed_commands(run, options.get("rapids", False)),
                             run_file, allow_3d=True)
        return run, contour_error(run, plane=how, **options)


#: corners a terminal lists at most: a CAM program has thousands, ``--json`` gives them all
CORNER_ROWS = 20


def _print(res, sensor: str, title: str, span_mm: float = 0.5) -> None:
    """Error per sensor and the corner table of one sensor, 80 columns wide."""
    sign = ("signed, +: left of travel" if res.signed
            else f"unsigned: the distance in {''.join(res.axes)} (3D)")
    # the run's name on a line of its own: as a table's title a long one was wrapped to
    # the table's width, in a pipe too, where no line is wrapped
    out.print(esc(f"{title}: contour error in {''.join(res.axes)} [µm]"), soft_wrap=True,
              highlight=False)
    t = plain_table(("sensor", "max |e|", "RMS", "max", "min", "max |e| at s"),
                    left=("sensor",))
    summary = res.summary()  # of every sample of a whole run: taken once
    for s, d in summary.items():
        t.add_row(s, *[fixed(d[k] * 1e6) for k in ("max_abs_m", "rms_m", "max_m", "min_m")],
                  fixed(d["max_abs_at_s"], 3))
    print_plain(t, out, caption=sign)
    _say_after_rapid(summary)
    if not res.signed:
        _say_offsets(summary)
    if not res.corners:
        return
    shown, more = _shown_corners(res.corners, sensor)
    rows = res.corner_rows([sensor], shown)
    t = plain_table(("#", f"at {', '.join(res.axes)} mm", "turn", "over µm", "round µm",
                     "settle ms", "settle mm"))
    for row in rows:
        at = ", ".join(fixed(row[f"{a.lower()}_mm"], 3) for a in res.axes)
        turn = "end" if row["turn_deg"] != row["turn_deg"] else f"{row['turn_deg']:.0f}°"
        t.add_row(str(row["corner"]), at, turn,
                  *[_num(row[k]) for k in ("overshoot_um", "rounding_um", "settle_ms",
                                           "settle_mm")])
    example = ": 88° for 90° at P0.01" if span_mm == 0.5 else ""
    print_plain(t, out, f"corners, {sensor}", f"turn: of the command over {span_mm:g} mm "
                "before and after (a corner blended over part of that, G64, reads less than "
                f"programmed{example}); overshoot: outside the path past the corner, "
                "rounding: closest approach [µm]; settle ms, settle mm: the time and the "
                "commanded path length from the corner until the error has settled within "
                f"{res.settle_tol_m * 1e6:g} µm, n/a where it has not by halfway to the next "
                f"corner or by the run's end{more}")


def _say_curves(res, corner_deg: float, span_mm: float) -> None:
    """Say on stderr where the command turns by more than ``--corner-deg`` over the span
    evenly, so that the corner table leaves it out: a curve, or a corner blended over more
    than a quarter of the span, which a longer span takes in; and which corners the span
    is too long for (:func:`_say_off_chord`) [-]."""
    _say_off_chord(res.off_chord, span_mm)
    if curves := res.curves:
        console.print(
            f"note: the command turns by more than {corner_deg:g}° over {span_mm:g} mm evenly "
            f"at {curves} place{'s' if curves > 1 else ''}, not in the corner table: a curve, "
            f"or a corner blended over more than {span_mm / 4:g} mm (a square's under G64 "
            f"P0.1); --corner-span-mm {4 * span_mm:g} takes such a corner in",
            highlight=False)


def _say_off_chord(off: dict, span_mm: float) -> None:
    """Say on stderr which corners are measured over chords that stray off the command (a
    feature shorter than the span: a notch, a step-over, a small loop), so that their
    turn and overshoot are the feature's, and a span that takes them apart: the 1-2-5
    step at or below the shortest straight stretch from them [-]."""
    if not off:
        return
    nums = sorted(off)
    named = ", ".join(str(n) for n in nums[:10]) + (f" and {len(nums) - 10} more"
                                                     if len(nums) > 10 else "")
    straight = min(w for _, w in off.values()) * 1e3
    span = _step_below(min(straight, 0.8 * span_mm))
    console.print(
        f"note: corner{'s' if len(nums) > 1 else ''} {named}: the command strays from the "
        f"chords over {span_mm:g} mm before and after by up to "
        f"{max(v for v, _ in off.values()) * 1e6:.0f} µm (a notch, step-over or loop "
        f"shorter than the span): their turn and the direction their overshoot is taken "
        f"in are those of the feature, not of the legs into and out of each corner (a "
        f"U-turn's across a tilted line, a notch's corners placed and turned short); "
        f"--corner-span-mm {span:g} measures them one by one (the command runs straight "
        f"for {straight:.3g} mm from them)", highlight=False)


def _step_below(x_mm: float) -> float:
    """The largest of 1, 2, 5 times a power of ten at or below ``x_mm`` [mm]."""
    import math

    e = math.floor(math.log10(x_mm))
    return max(m * 10.0 ** e for m in (1, 2, 5) if m * 10.0 ** e <= x_mm * (1 + 1e-9))


#: a largest error this soon after a rapid is the servo's lag the rapid carries into the
#: feed move, largest within a time constant of the position loop (1/K_pp: 25 ms at
#: 40 1/s, 0.1 s at 10 1/s); a feed move's own start from rest peaks later (0.35 s into a
#: circle at F5000 after a dwell) [s]
AFTER_RAPID_S = 0.1


def _say_after_rapid(summary: dict) -> None:
    """Say on stderr the sensors whose largest error lies within :data:`AFTER_RAPID_S` of a
    G0 rapid's end: the lag the servo carries into the feed move, which does not depend on
    the feed, is that figure, not the path's own error."""
    soon = {s: d["max_abs_after_rapid_s"] for s, d in summary.items()
            if d["max_abs_after_rapid_s"] <= AFTER_RAPID_S}
    if soon:
        when = ", ".join(f"{s} {v:.3f} s" for s, v in soon.items())
        console.print(
            f"note: the largest error ({when} after a G0 rapid ends) is the servo's lag the "
            "rapid carries into the feed move, not the path's own error: a G4 dwell after "
            "the G0 lets it settle in the air", highlight=False)


#: an unsigned error that never falls below this, and half its largest, is mostly an
#: offset the run holds throughout [m]
OFFSET_M = 1e-6


def _say_offsets(summary: dict) -> None:
    """Say on stderr the sensors whose 3-D error never falls below :data:`OFFSET_M` and half
    its largest: an offset held throughout, as a measured sensor of an axis standing still
    that was zeroed under another load, is in every figure of a move along one axis."""
    for s, d in summary.items():
        low = d["min_m"]
        if low > OFFSET_M and low > 0.5 * d["max_abs_m"]:
            console.print(
                f"note: {s}: the error never falls below {low * 1e6:.2f} um: an offset held "
                "throughout (an axis standing still deflected under its weight, say) is in "
                "every figure; --plane of the moving axes leaves the others out",
                highlight=False)


def _shown_corners(corners: list, sensor: str) -> tuple:
    """The corners a terminal shows, and what the caption adds: all of them, or those of
    the :data:`CORNER_ROWS` largest overshoots of ``sensor`` in their order, with the
    count and the overshoots' median and largest [-]. Only the corners shown become
    table rows (a CAM run has hundreds of thousands)."""
    if len(corners) <= CORNER_ROWS:
        return corners, ""
    import numpy as np

    over = getattr(corners, "figure", lambda *_: None)(sensor, "overshoot_m")
    if over is None:  # a list of dicts
        over = np.array([c[sensor]["overshoot_m"] for c in corners], float)
    over = over * 1e6
    worst = np.sort(np.argsort(-np.where(np.isnan(over), -np.inf, over),
                               kind="stable")[:CORNER_ROWS])
    seen = over[~np.isnan(over)]
    spread = (f"; overshoot median {np.median(seen):.2f}, largest {np.max(seen):.2f} µm"
              if seen.size else "")
    some = int(np.sum(seen >= 0.005))  # an overshoot the table shows as more than 0.00
    which = (f"the {CORNER_ROWS} of largest overshoot" if some >= CORNER_ROWS else
             f"none overshoots, the first {CORNER_ROWS}" if some == 0 else
             f"the {some} that overshoot and the first of the others")
    return ([corners[i] for i in worst], f"; {len(corners)} corners, {which} shown (all "
            f"with --json){spread}")


def _num(v: float) -> str:
    return "n/a" if v != v else fixed(v)
