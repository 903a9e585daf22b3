"""Which error terms an arc determines.

Over a full turn the terms' radial errors are nearly orthogonal; over an arc they are
not, and a term the columns still tell apart may yet carry the radial error that the
servo and the friction make along the arc and that no term describes. Bench circles
(`docs/circle_diagnostics.md`, "Arcs") cut to arcs read, in one direction, centre offsets
and bows of 10 to 170 um where their full turns read none, and as pairs of arcs shorter
than about 200 deg the same; pairs of 220 deg, a ballbar's partial arcs, come within
0.2 um of the full turns' centre, backlash, lateral play and bows on a machine of fine
sensors. So one direction over an arc, or a pair of arcs shorter than
:data:`MIN_TERMS_DEG`, gives no terms (its radial deviation, G and spikes it still
gives), and no arc shorter than :data:`CYCLIC_ARC_DEG` gives a cyclic error: over part
of a turn its columns are a centre and a bow. Full turns are fitted as they were.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .circle_display import rename_axes
from .circle_fit import Arc, column_names, fit_terms
from .circle_model import covers, fit_mask, is_full

#: shortest pair of arcs whose terms are fitted: a ballbar's partial arcs are 220 deg [deg]
MIN_TERMS_DEG = 210.0
#: shortest pair of arcs searched for cyclic errors, as full turns are: a turn cut short
#: by the settling at its ends (one programmed turn behind a 30 ms filter keeps 358 deg)
#: leaves a pitch error to the backlash and the spikes otherwise (0.8 um at 6 mm over
#: 352 deg read X's backlash 5.6 um for 4 and its spikes -2 um for +2) [deg]
CYCLIC_ARC_DEG = 350.0
#: Why an arc leaves a term undetermined
ARC_WHY = ("the arc does not determine it: its radial error there is nearly that of other "
           "terms, which take it over where it is present (what each would move per unit "
           "of it is said with the terms): measure the arcs from another start angle, or a "
           "full circle, to tell them apart")
#: why an arc reports no cyclic error
CYCLIC_WHY = ("an arc does not separate a cyclic error from the centre and the bows: over "
              "part of a turn its columns are theirs; a full circle does, or a pair of "
              f"arcs of {CYCLIC_ARC_DEG:g} deg or more")
#: why an arc that gives no terms gives no spikes after them either
SPIKES_WHY = ("the arc gives no terms to take off its radial error, so a spike after them "
              "would be the raw one and carry the terms (the raw spikes are spike_*_um of "
              "the circle)")
#: why an arc that gives no terms gives no residual after them
RESIDUAL_WHY = ("no term is fitted over the arc, so nothing is left after them: its rms would "
                "be the radial error itself, whose size the radial deviation and G give")
#: why one direction over an arc, or a pair of short arcs, reports no terms
SHORT_WHY = ("{what} does not separate the terms from the servo's and the friction's radial "
             "error along it (bench circles cut to such arcs read centre offsets and bows of "
             "10 um and more where their full turns read none): run the arc in both "
             "directions over {deg:.0f} deg or more, or a full circle")


def arc_fit(arcs, radius, shared, unseen=()):
    """:func:`tcpmm.analysis.circle_fit.fit_terms` of circles, or of arcs with the terms they
    do not determine left out (module docstring).

    Parameters
    ----------
    arcs : list of Arc
        The circles or arcs [-].
    radius : float
        Nominal radius [m].
    shared : sequence of str
        Terms common to the arcs [-].
    unseen : sequence of str
        Terms not fitted whose effect on the fitted ones is wanted
        (:func:`tcpmm.analysis.circle_fit.fit_terms`) [-].

    Returns
    -------
    fit : TermFit
        The fit [-].
    why : dict
        Per column left out, why, and ``reversal_spikes`` where no term is fitted at all
        (the spikes after them would be the raw ones); empty for full turns and for pairs
        of arcs long enough [-].
    """
    if all(is_full(a.angle) for a in arcs):
        # one direction leaves its lateral play, a step at the reversals, to them
        tail = "search" if len(arcs) >= 2 else None
        return fit_terms(arcs, radius, shared, unseen=unseen, tail=tail), {}
    deg = min(float(np.degrees(np.ptp(a.angle))) for a in arcs)
    if len(arcs) >= 2 and all(covers(a.angle, MIN_TERMS_DEG) for a in arcs):
        return fit_terms(arcs, radius, shared, cyclic=cyclic_on(arcs), unseen=unseen), {}
    # whole degrees, but 209.99 is no 210 in words either
    shown = f"{deg:.0f}" if round(deg) < MIN_TERMS_DEG else f"{np.floor(deg * 10) / 10:g}"
    what = (f"one direction over an arc of {shown} deg" if len(arcs) < 2 else
            f"a pair of arcs of {shown} deg")
    names = [n for n in column_names(len(arcs), shared) if not n.startswith("radius")]
    why = dict.fromkeys(names, SHORT_WHY.format(what=what, deg=MIN_TERMS_DEG))
    return (fit_terms([bridged(a) for a in arcs], radius, shared, cyclic=False,
                      drop=tuple(names)),
            {**why, "reversal_spikes": SPIKES_WHY})


@dataclass
class _Whole(Arc):
    """An arc fitted over all its steady samples, its reversals' windows bridged
    (:func:`bridged`); ``keep`` the samples fitted [-]."""

    keep: np.ndarray | None = None

    @property
    def mask(self):
        """The samples fitted [-]."""
        return self.keep

    def mask_for(self, mu: float):
        """The samples fitted, whatever the servo mismatch [-]."""
        return self.keep


def bridged(arc):
    """``arc`` with the samples of each reversal's window (the transient the fit leaves
    out) replaced by the radius the samples either side of it make, and fitted over all
    its samples: an arc that gives no terms fits its radius alone, whose value is then the
    arc's mean radius about the nominal centre over the whole arc, spikes aside. Left
    out, the windows would take that angle off the mean after the reversal in the
    direction of travel, so that the two directions read a mean over other angles (a
    centre 3 um off read 1.05 um CCW and 0.75 um CW on a 90 deg arc from 30 deg, for
    0.70 um over the arc) [-].

    A window is bridged from the samples within its length either side of it by the
    shapes the terms give the radius there (the first and second harmonics of the angle:
    a centre offset, the ellipses and a scale mismatch), with a step at its start where
    the axis reverses (a backlash); from one side alone by a line; a window with no steady
    samples beside it stays out.
    """
    a, e, ends = arc.angle, np.array(arc.e, float), arc.ends
    inside = ~fit_mask(a, arc.s, after_deg=(0.0, arc.after_deg)) & ends
    keep = ends.copy()
    span = np.radians(arc.after_deg)
    edges = np.flatnonzero(np.diff(np.r_[0, inside.astype(int), 0]))
    for i0, i1 in zip(edges[::2], edges[1::2], strict=True):
        t = arc.s * (a - a[i0])
        near = ends & ~inside & (t >= -span) & (t <= t[i1 - 1] + span)
        after = np.arange(a.size) >= i0
        fill = _bridge(t - t[i1 - 1] / 2, e, near & ~after, near & after, slice(i0, i1))
        if fill is None:
            keep[i0:i1] = False
        else:
            e[i0:i1] = fill
    return _Whole(a, e, arc.s, arc.ratio, arc.after_deg, keep)


def _bridge(t, e, before, after, window):
    """The radius over ``window`` from the samples ``before`` and ``after`` it (each a
    mask; :func:`bridged`), ``t`` the angle along the travel from the window's middle;
    None where neither side has two samples [m]."""
    nb, na = int(before.sum()), int(after.sum())
    if nb >= 4 and na >= 4:
        def cols(tt, step):
            return np.column_stack([np.ones_like(tt), np.cos(tt), np.sin(tt),
                                    np.cos(2 * tt), np.sin(2 * tt), step])
        m = before | after
        c = np.linalg.lstsq(cols(t[m], after[m].astype(float)), e[m], rcond=None)[0]
        return cols(t[window], np.ones_like(t[window])) @ c
    m = before if nb >= na else after
    if m.sum() < 2:
        return None
    return np.polyval(np.polyfit(t[m], e[m], 1), t[window])


def cyclic_on(arcs) -> bool:
    """Whether the arcs are searched for cyclic errors: a pair each of
    :data:`CYCLIC_ARC_DEG` or more (:func:`.circle_model.covers`), or full turns [-]."""
    return all(is_full(a.angle) for a in arcs) or (
        len(arcs) >= 2 and all(covers(a.angle, CYCLIC_ARC_DEG) for a in arcs))


def leave_open(why_out: dict, terms: dict, left: dict, arcs, axes, rename=None) -> None:
    """Say in ``why_out`` why the terms an arc's fit left out (``left``, :func:`arc_fit`)
    are open, and why an arc gives no cyclic error, by their reported names (``rename``
    maps a name to another, as ``squareness`` to ``squareness_or_servo``; axes renamed to
    the plane's); set those ``terms`` that are values of the fit's curves and not of its
    columns NaN: the cyclic error, and the spikes where no term is fitted. Nothing for
    full turns [-]."""
    if all(is_full(a.angle) for a in arcs):
        return
    reasons = {} if cyclic_on(arcs) else {
        f"cyclic_{q}_{a}": CYCLIC_WHY for a in "XY" for q in ("amplitude", "period")}
    for name, text in left.items():
        names = [name]
        if name.startswith("centre_"):
            names = [f"centre_offset_{name.split('_')[1]}"]
        elif name == "servo_angle":
            names = ["servo_mismatch", "servo_mismatch_angle"]
        reasons.update({(rename or {}).get(n, n): text for n in names})
    for k, text in reasons.items():
        why_out[rename_axes(k, axes)] = text
        if k.startswith("cyclic_"):
            terms[k] = (float("nan"), "m")
        if k == "reversal_spikes":
            terms.update({t: (float("nan"), "m") for t in terms if t.startswith("spike_")})
            terms["residual_rms"] = (float("nan"), "m")
            why_out["residual_rms"] = RESIDUAL_WHY
