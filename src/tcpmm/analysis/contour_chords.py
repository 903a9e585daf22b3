"""Corners whose chords stray off the command: a feature shorter than the corner span (a
notch, a zig-zag's step-over, a small loop) lies within the straight lines from the corner
to the path a span before and after it, which give its turn and the direction its
overshoot is taken in, and makes them the feature's (docs/paths.md, *Corners*)."""

from __future__ import annotations

import numpy as np

from .._compiled import call

#: Share of the corner span by which the command may stray from a corner's chords (the
#: straight lines from the corner to the path a span before and after it, which give its
#: turn and the directions its overshoot is taken in) before the corner is said to be
#: measured over a feature shorter than the span (a notch, a step-over, a small loop): a
#: G64 blend the finder takes as a corner (within a quarter span) strays under 0.15 of it
#: from the chords of any vertex on it, an arc of radius R by span**2 / (8 R), under this
#: share for R over 0.75 span; a second bend of 90 deg within the span strays by more
#: (0.21 span at a 0.3 mm notch, 0.35 at a zig-zag's U-turn of a span's step-over) [-].
CHORD_STRAY = 1.0 / 6.0


def stray_corners(p, s, idx, off, span) -> dict:
    """Per corner at the command vertex ``idx`` (``off`` the first vertex ``p`` holds) whose
    chords over ``span`` stray from the command by more than :data:`CHORD_STRAY` of it
    (:func:`tcpmm.sim.cornerchords.chord_strays`): how far, and the path length over which
    the command runs straight from it on its shorter side (``inf``: the whole span). The
    command at hand holds the span on either side of each, as for their frames, so the
    pieces of a streamed run give the whole's [m]."""
    if not idx.size:
        return {}
    st = call("chord_strays", p, s, idx - off, span, CHORD_STRAY)
    return {int(idx[j]): (float(st[j, 0]), float(st[j, 1]))
            for j in np.flatnonzero(st[:, 0] > CHORD_STRAY * span).tolist()}


def off_chord(stream, kept) -> dict:
    """Per corner of ``kept`` (a :class:`~tcpmm.analysis.corner_rows.CornerRows`), by its
    number, whose chords stray off the command (``strayed`` of the
    :class:`~tcpmm.analysis.contour_corners.CornerStream` ``stream``): how far, and the
    path length over which the command runs straight from it on its shorter side
    (``inf``: over the whole span) [m]."""
    if not stream.strayed:
        return {}
    return {kept[k]["number"]: stream.strayed[i] for k, i in enumerate(kept.indices())
            if i in stream.strayed}
