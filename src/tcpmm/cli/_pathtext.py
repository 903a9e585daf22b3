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
