"""What ``tcpmm path`` says of a program's command: where the feed is held back and why,
and where a sharp corner's velocity step takes an axis beyond its acceleration."""

from __future__ import annotations

from ..path.limits import OVER_SHARE
from ..path.settings import AXES
from ._app import out
from ._tables import percent

#: what to change when a limit holds the feed back
_REMEDY = {"axis velocity": "axis_velocity_m_per_s, capped by rapid_m_per_s",
           "curvature (centripetal acceleration)": "axis_accel_m_per_s2, larger radii or G64 P",
           "filter tolerance on arcs": "corner_tolerance_m or a shorter filter",
           "corner: axis acceleration": "G64 P<tol> or blend_tolerance_m rounds corners off",
           "corner: filter tolerance": "corner_tolerance_m, G64 P<tol>",
           "exact stop": "G61/G9, reversals, dwells, rapids, start and end",
           "curvature of short blocks (centripetal acceleration)":
               "a curve posted as short G1 blocks runs as its arc would: axis_accel_m_per_s2, "
               "larger radii",
           "transition jerk (step of curvature)":
               "a tangent join into an arc of another curvature, a G64 blend's ends: "
               "transition_jerk_m_per_s3, larger radii or G64 P",
           "path acceleration": "blocks too short to reach the feed: path_accel_m_per_s2",
           "path jerk": "blocks too short to reach the feed: path_jerk_m_per_s3"}


def print_feed(limits) -> None:
    """Share of the path at the programmed feed, and per limit where it holds it back."""
    if limits.feed_length_m <= 0:
        out.print("no feed moves (G1, G2, G3): no programmed feed to reach")
        return
    out.print(f"at the programmed feed (within 1 %) on {percent(limits.share_at_feed(), 1, ' ')} "
              "of the path length of the feed moves")
    for r in limits.summary():
        a, b = r["first_line"], r["last_line"]
        # the blocks of a cause lie among others: a span of lines, not a run of them
        lines = "" if a is None else f", line {a}" if a == b else f", between lines {a} and {b}"
        out.print(f"  held back by {r['cause']}: {r['length_m'] * 1e3:.3g} mm in "
                  f"{r['blocks']} block{'s' * (r['blocks'] > 1)}{lines}, peak feed as low as "
                  f"{r['lowest_m_per_s'] * 6e4:.0f} mm/min ({_REMEDY[r['cause']]})",
                  highlight=False)
    if limits.ramp_length_m() > 1e-6:
        out.print(f"  below it where blocks that reach it speed up and slow down: "
                  f"{limits.ramp_length_m() * 1e3:.3g} mm (at corners, exact stops, start and "
                  "end)", highlight=False)


def print_corner_overload(peaks: dict, settings) -> None:
    """A line where the command's samples ask an axis for more than its acceleration: a
    sharp corner's velocity step, also at the corners of a curve posted as short blocks,
    comes on top of the braking into it or speeding up out of it (``docs/paths.md``).

    Parameters
    ----------
    peaks : dict
        Largest second difference of the command per axis
        (:class:`~tcpmm.path.limits.RunningPeak`) [m/s^2].
    settings : InterpolatorSettings
        The interpolator's settings it was planned with [-].
    """
    limit = dict(zip(AXES, settings.axis_accel(), strict=True))
    over = [f"{a} {most:.3g} m/s² (limit {limit[a]:.3g})" for a, most in peaks.items()
            if a in limit and most > limit[a] * (1 + OVER_SHARE)]
    if over:
        out.print("  beyond an axis's acceleration for a period at sharp corners (also the "
                  "corners of curves posted as short blocks), whose velocity step comes on "
                  "top of the braking into them: " + ", ".join(over)
                  + f" (corner_step_share {settings.corner_step_share:g} of the acceleration "
                  "for the step; 0 stops at each sharp corner and keeps within it)",
                  highlight=False)


#: Share of a program's feed moves held back by a limit of the machine above which its
#: figures are said to be at another feed than the programmed one [-]
HELD_SHARE = 0.5


def warn_feed_held(program, interp) -> None:
    """Warn where a limit of the machine holds the feed of more than :data:`HELD_SHARE` of
    a program's feed moves below the programmed feed: every figure computed from it is at
    the feed the machine runs, which a reader takes for the programmed one (a circle at
    F200000 runs at 9439 mm/min, held back by the axes' acceleration).

    Parameters
    ----------
    program : Path
        The NC program, for the message [-].
    interp : Interpolation
        It interpolated at the machine's full limits
        (:func:`tcpmm.path.program.program_to_interpolation`) [-].
    """
    import warnings

    from ..errors import InputWarning
    from ..path.limits import feed_limits

    limits = feed_limits(interp)
    rows = limits.summary()
    held = sum(r["length_m"] for r in rows)
    if limits.feed_length_m <= 0 or held <= HELD_SHARE * limits.feed_length_m:
        return
    worst = min(rows, key=lambda r: r["lowest_m_per_s"])
    warnings.warn(InputWarning(
        f"{program}: the machine holds the feed below the programmed one on "
        f"{percent(held / limits.feed_length_m, 1, ' ')} of the feed moves' path, by "
        f"{worst['cause']} down to {worst['lowest_m_per_s'] * 6e4:.0f} mm/min "
        f"({_REMEDY[worst['cause']]}): the figures here are at the feed it runs, not the "
        f"programmed one (tcpmm path {program} --model MODEL says where)"), stacklevel=2)
