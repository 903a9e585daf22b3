"""The time windows in which the contour seeks each sample's closest command point,
reaching over the command's rests: a window of ``window_s`` holds that much of the
command's motion either side of the sample, however long the command dwells between."""

from __future__ import annotations

import numpy as np

from ..result import motion_time


def over_rests(lo, hi, t_p, t_q, moves, window_s: float):
    """The windows ``lo:hi`` widened over the command's rests, to hold ``window_s`` of its
    motion either side of each sample: while the command dwells at a corner, the tool
    still on its way there is measured against the path it is on, not against the corner
    (0.5 s dwells at a square's corners read a TCP 19 um short of the corner, along the
    path, as contour error) [-]."""
    tau_p, rest = motion_time(t_p, moves)
    tau_q = t_q - np.interp(t_q, t_p, rest)
    return (np.minimum(lo, np.searchsorted(tau_p, tau_q - window_s, side="left")),
            np.maximum(hi, np.searchsorted(tau_p, tau_q + window_s, side="right")))
