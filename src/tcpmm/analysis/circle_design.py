"""The design matrix of a circle fit (:mod:`.circle_fit`): per arc its radius and centre,
the shared terms (:func:`.circle_model.term_columns`), the cyclic errors and the reversals'
tails. The first two do not change while a search tries cyclic errors or tails, and are
built apart from the others (:func:`base_columns`), for a fit to build them once."""

from __future__ import annotations

import numpy as np

from .circle_model import cyclic_columns, radial_weights, reversal_angle, term_columns
from .circle_reversal_tail import tail_block, tail_names

OWN = ("radius", "centre_X", "centre_Y")


def base_columns(arc, i, n_arcs, radius, shared, mu, angle, pos=None, centre=(0.0, 0.0),
                 widths=(0.0, 0.0)) -> tuple:
    """``(columns, w, pos, rev)``: the columns of arc ``i`` of ``n_arcs`` over ``angle`` of
    each arc's radius and centre and of the terms ``shared``; the axes' directions along the
    radius, its tool's position (``pos``, default on the nominal radius) and the angle its
    axes reverse at, which the other columns are built on (arguments of :func:`design`)
    [m/unit, -, m, rad]."""
    own = np.zeros((angle.size, 3 * n_arcs))
    w = radial_weights(angle, arc.s, arc.ratio, mu)
    own[:, 3 * i:3 * i + 3] = np.c_[np.ones_like(angle), *w]
    pos = pos if pos is not None else (radius * np.cos(angle), radius * np.sin(angle))
    rev = reversal_angle(pos, centre)
    cols = term_columns(shared, angle, arc.s, radius, arc.ratio, mu, rev, widths)
    return (np.column_stack([own, *cols]) if cols else own), w, pos, rev


def with_columns(base, arc, i, n_arcs, mu, waves, angle, tail=None) -> np.ndarray:
    """The columns ``base`` (:func:`base_columns` over ``angle``) with the cyclic errors'
    of ``waves`` and the reversals' tails ``tail`` after them (arguments of
    :func:`design`) [m/unit]."""
    columns, w, pos, rev = base
    cols = []
    for axis, k in enumerate(waves):
        if k is not None:
            cols += cyclic_columns(pos[axis], w[axis], k)
    if tail is not None:
        cols += list(tail_block(arc, i, n_arcs, mu, tail, angle, rev).T)
    return np.column_stack([columns, *cols]) if cols else columns


def design(arc, i, n_arcs, radius, shared, mu, waves, angle=None, pos=None,
           centre=(0.0, 0.0), tail=None, widths=(0.0, 0.0)):
    """Design matrix of arc ``i`` of ``n_arcs`` over ``angle`` (default its own), its
    tool at ``pos`` (default on the nominal radius), its axes reversing about ``centre``,
    the reversals' tails ``tail``, ``(decay, shape)`` (none for None), and each axis'
    backlash taken up over the travel ``widths`` after its reversal [m/unit]."""
    a = arc.angle if angle is None else angle
    base = base_columns(arc, i, n_arcs, radius, shared, mu, a, pos, centre, widths)
    return with_columns(base, arc, i, n_arcs, mu, waves, a, tail)


def column_names(n_arcs, shared, waves=(None, None), tail=None):
    """The fit's columns: per arc its radius and centre, the shared terms, the cyclic
    sine and cosine of each axis whose wavenumber is given, the reversals' tails where
    ``tail`` is given [-]."""
    names = [f"{o}_{i}" for i in range(n_arcs) for o in OWN] + list(shared)
    for axis, k in zip("XY", waves, strict=True):
        if k is not None:
            names += [f"cyclic_sin_{axis}", f"cyclic_cos_{axis}"]
    return names + (tail_names(n_arcs) if tail is not None else [])
