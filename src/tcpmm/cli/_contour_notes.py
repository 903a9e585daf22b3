"""What ``tcpmm contour`` says on stderr beside its figures: the rapids and axes left
out, the end not reached, the command's sampling, the window widened and the closest
point's leaps between passes side by side."""

from __future__ import annotations

from pathlib import Path

from ..analysis.contour_passes import leap_notes
from ._app import console


def say_notes(res, rapids: bool, run_file: Path) -> None:
    """The notes on the rapids left out, the end not reached and the command's sampling,
    on stderr [-]."""
    _say_left_out(res, run_file)
    _say_rapids(res.rapids, rapids)
    _say_unreached(res.unreached)
    _say_sag(res, run_file)
    for line in leap_notes(res.leaps):
        console.print(f"warning: {run_file}: {line}", highlight=False)
    from ..analysis.contour_lag import WINDOW_S

    if res.window_s > WINDOW_S:
        console.print(f"note: samples lie closer to the command just outside {WINDOW_S:g} s "
                      "of them than within (a tool lagging by more, or the path coming back "
                      f"near): each one's closest point is sought within {res.window_s:g} s")


def _say_left_out(res, run_file: Path) -> None:
    """Warn (stderr, and ``--json``'s ``warnings``) of the axes outside the plane given
    that move substantially (:func:`tcpmm.analysis.plane.left_out_axes`): the signed error
    leaves theirs out, read as the whole [-]."""
    import warnings

    from ..analysis.plane import left_out_note
    from ..errors import InputWarning

    note = left_out_note(res.axes, res.left_out)
    if note is not None:
        warnings.warn(f"{run_file}: {note}", InputWarning, stacklevel=2)


def _say_rapids(rapids: dict | None, asked: bool) -> None:
    """Say on stderr what of the G0 rapids was left out
    (:func:`tcpmm.analysis.rapids.rapid_note`), and that ``--rapids`` (``asked``) does
    nothing to a run that does not record them [-]."""
    from ..analysis.rapids import rapid_note

    note = rapid_note(rapids)
    if rapids is None and asked:
        note = ("note: --rapids changes nothing here: the run records no G0 rapids (its "
                "rapid column, which a run made from an NC program has), and is measured "
                "whole")
    if note is not None:
        console.print(note, highlight=False)


def _say_unreached(unreached: dict) -> None:
    """Say on stderr that the run stops before the machine comes to rest at the path's end
    point, how far from it each sensor not settled is, and why their end figures are n/a
    [-]."""
    if unreached:
        far = ", ".join(f"{s} {d * 1e6:.2f} µm" for s, d in unreached.items())
        console.print(f"note: the run stops before the machine comes to rest at the path's "
                      f"end point (at the last sample {far} from it): the overshoot and "
                      "rounding at the end are not measured (n/a); end the program with a "
                      "dwell (G4 P0.5), or a longer one than it has, so that the run records "
                      "the axes coming to rest",
                      highlight=False)


def _say_sag(res, run_file: Path) -> None:
    """Warn on stderr where the run's command samples cut the path's bends by enough to
    move the contour error (:func:`tcpmm.analysis.contour_sampling.sag_note`), and leave
    the corners' overshoot and rounding out where they cut its corners [-]."""
    from ..analysis.contour_sampling import (
        CORNER_SAG_M,
        coarse_peaks,
        sag_note,
        unresolved_corners,
    )

    largest = max((d["max_abs_m"] for d in res.summary().values()), default=0.0)
    note = sag_note(res.command_sag_m, largest)
    if unresolved_corners(res) and res.corners:
        note = "; ".join(filter(None, (note, (
            f"the corners' overshoot and rounding are not given (n/a): the command's "
            f"samples cut the path's bends by up to {res.command_sag_m * 1e6:.3g} µm, more "
            f"than {CORNER_SAG_M * 1e6:g} µm"))))
    if note is not None:
        console.print(f"warning: {run_file}: {note}", highlight=False)
    if peaks := coarse_peaks(res):
        said = ", ".join(f"{s} at {t:.4g} s ({d * 1e6:.3g} µm)" for s, t, d in peaks)
        console.print(f"warning: {run_file}: the largest error is read on samples whose "
                      f"neighbours lie well below it: {said}; the peak between them may be "
                      "higher, by that or more: record the run more finely", highlight=False)
